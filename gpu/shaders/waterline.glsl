// SPDX-License-Identifier: Zlib
// Shared by the hydrostatics texel passes (hydrostatics_flat.comp, hydrostatics_surface.comp):
// the waterline inside a texel and the moment corrections of texels of several pieces.

// E[1(d > X)], E[(d - X)+], E[(d - X)+^2] - frac (a^2 + b^2) / 12 for X = a U1 + b U2, U uniform
// on [-1/2, 1/2]: second differences of the antiderivatives (HydrostaticSums.hpp). In float the
// 2-D form loses eps a/b of its value to cancellation, so it hands over to the 1-D limit below
// b = 1e-3 a (whose own error is O((b/a)^2), 1e-6) instead of the CPU's 1e-6 a.
vec3 waterlineFractions(float d, float a, float b) {
  a = abs(a);
  b = abs(b);
  if (a < b) { float swapped = a; a = b; b = swapped; }
  float halfSpan = 0.5 * (a + b);
  float variance = (a * a + b * b) / 12.0;
  if (d >= halfSpan) return vec3(1.0, d, d * d);
  if (d <= -halfSpan) return vec3(0.0);
  float frac, mean, meanSq;
  if (b > 1e-3 * a) {
    vec4 z = max(vec4(d + halfSpan, d + 0.5 * (a - b), d - 0.5 * (a - b), d - halfSpan), vec4(0.0));
    vec4 sign = vec4(1.0, -1.0, -1.0, 1.0);
    vec4 z2 = z * z;
    float inv = 1.0 / (a * b);
    frac = dot(sign, z2) * 0.5 * inv;
    mean = dot(sign, z2 * z) / 6.0 * inv;
    meanSq = dot(sign, z2 * z2) / 12.0 * inv;
  } else if (a > 0.0) {
    float hi = max(d + 0.5 * a, 0.0), lo = max(d - 0.5 * a, 0.0);
    float inv = 1.0 / a;
    frac = (hi - lo) * inv;
    mean = 0.5 * (hi * hi - lo * lo) * inv;
    meanSq = (hi * hi * hi - lo * lo * lo) / 3.0 * inv;
  } else {
    frac = d > 0.0 ? 1.0 : 0.0;
    mean = max(d, 0.0);
    meanSq = mean * mean;
  }
  return vec3(frac, mean, meanSq - frac * variance);
}

// The rows of R dM R^T (m^3, world axes) of a texel's moment correction dM (TexelCorrection,
// body frame), R the pose's rotation given by its rows.
void worldMoment(TexelCorrection c, vec3 r0, vec3 r1, vec3 r2, out vec3 d0, out vec3 d1, out vec3 d2) {
  vec3 m0 = vec3(c.moment[0], c.moment[1], c.moment[2]);
  vec3 m1 = vec3(c.moment[3], c.moment[4], c.moment[5]);
  vec3 m2 = vec3(c.moment[6], c.moment[7], c.moment[8]);
  vec3 rm0 = r0.x * m0 + r0.y * m1 + r0.z * m2;  // rows of R dM
  vec3 rm1 = r1.x * m0 + r1.y * m1 + r1.z * m2;
  vec3 rm2 = r2.x * m0 + r2.y * m1 + r2.z * m2;
  d0 = vec3(dot(rm0, r0), dot(rm0, r1), dot(rm0, r2));
  d1 = vec3(dot(rm1, r0), dot(rm1, r1), dot(rm1, r2));
  d2 = vec3(dot(rm2, r0), dot(rm2, r1), dot(rm2, r2));
}

// The weight of a texel's moment correction (core's correctionWeight): the submerged share of the
// vertical segment y' +- s, s the larger of the patch's half span and the pieces' reach.
float correctionWeight(float depth, float halfSpan, float reach) {
  float s = max(halfSpan, reach);
  if (depth >= s) return 1.0;
  if (depth <= -s) return 0.0;
  return 0.5 * (depth + s) / s;
}

// A texel's moment correction in the 11 FlatWettedSums, weighted by its submerged fraction
// `weight`, at x' = (x, y, z) with the depth D = h' - y' at its centre, the local height h' and the
// surface's slope there (core's detail::MomentCorrectionSums: the sums' first-order term over
// the texel's pieces, grad D = (slope.x, -1, slope.y)).
void addMomentCorrection(inout float sums[11], vec3 d0, vec3 d1, vec3 d2, float x, float y, float z, float weight,
                         float depth, float localHeight, vec2 slope) {
  float along = slope.x * d0.y - d1.y + slope.y * d2.y;  // grad D . dM'(:, y)
  sums[0] += weight * along;
  sums[1] += weight * (depth * d0.y + x * along);
  sums[2] += weight * (depth * d2.y + z * along);
  sums[3] += weight * (y * d1.y - localHeight * (slope.x * d0.y + slope.y * d2.y));
  sums[5] += weight * d0.y;
  sums[6] += weight * d2.y;
  sums[7] += weight * 2.0 * x * d0.y;
  sums[8] += weight * (x * d2.y + z * d0.y);
  sums[9] += weight * 2.0 * z * d2.y;
}
