// SPDX-License-Identifier: Zlib
// Shared by the hydrostatics texel passes (hydrostatics_flat.comp, hydrostatics_surface.comp).

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
