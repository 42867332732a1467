// SPDX-License-Identifier: Zlib
// Hydrostatics under a surface that is not a flat plane, the GPU form of the waves-and-grids and
// medium paths of core's TextureHydrostatics::query (core/src/hydrostatics/TextureHydrostatics.cpp): over the
// chunks hydrostatics_classify.comp listed (those not wholly above the surface's highest point),
// one workgroup per chunk of up to 256 texels of one body (4 per invocation). Each texel is the
// patch p + s eU + t eV under a locally level surface at the height h' the surface has above the
// texel's centre (the CPU's approximation: the slope over one texel is neglected), weighted by
// waterlineFractions; the pressure is integrated texel by texel. Frame: x' = R p + (0, t_y - o_y,
// 0), o = (t_x, h(centre of mass), t_z) for waves and grids, o = t for a medium. Compiled once per
// surface kind, one of:
//   SURFACE_GERSTNER  h' from GerstnerWaves::surfaceHeight's search (Newton, fixed-point steps
//                     where the Jacobian is nearly singular), in float about o; or, within
//                     its reach (modelReachSquared), from the chunk's local quadratic model
//                     about the centre of its box: one search and jet a chunk
//   SURFACE_GRID      h' bilinear in HeightGrid's samples, clamped at the edges as HeightGrid does
//   SURFACE_MEDIUM    no free surface: every texel wholly submerged (D = -y', Q = y'^2)
// Two float Partials per chunk: `partials` the 11 FlatWettedSums (sumYB as Sum (Q/2 - h' D) A_y),
// `headPartials` Sum e A' (0..2) and Sum e x' x A' (3..5), e the pressure head: the mean depth D
// under a free surface (pressure rho g D), H expm1(-y'/H) (or -y') in a medium, whose pressure is
// rho0 g exp(-(t_y - y0)/H) (H + e) (the host adds the constant part exactly: GlBackend.cpp).
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Texels { HydroTexel texels[]; };
layout(std430, binding = 1) readonly buffer Chunks { Chunk chunks[]; };
layout(std430, binding = 2) readonly buffer Poses { BodyPose poses[]; };
// Per chunk: `partials` at chunkIndex, `headPartials` at headBase + chunkIndex (one buffer, so
// that the shader stays within GL 4.3's guaranteed 8 storage blocks, bindings 0..7).
layout(std430, binding = 3) writeonly buffer Partials { Partial partials[]; };
layout(std430, binding = 4) readonly buffer Corrections { TexelCorrection corrections[]; };
layout(std430, binding = 6) readonly buffer Crossing { uint crossing[]; };

uniform uint listBase;  // this run's crossing list in Crossing; the dispatch has one group per entry
uniform uint headBase;  // where the pressure-head partials start in Partials

#if defined(SURFACE_GERSTNER)
layout(std430, binding = 5) readonly buffer Waves { GerstnerComponent waves[]; };
// Per body, waveCount + 2 floats: mean level - o_y (m), the crests' highest point - o_y (m), then
// each wave's phase at o and this time, k d . o - omega t + phase, reduced to [0, 2 pi) in double
// on the host.
layout(std430, binding = 7) readonly buffer BodyWaves { float bodyWaves[]; };
uniform uint waveCount;
uniform float horizontalSum;  // sum Q A (m): scale of the search's rounding
// Local models of the surface (issue 19 item 1, the GPU form of core's LocalSurfaceModel.hpp):
// the quadratic Taylor model of the height about a point, from one search and jet there, stands
// in for the search at points within modelReachSquared (m^2) of it, where its error bound
// M3 rho^3 / 6 (M3 the bound of the height's third directional derivative, GerstnerWaves::
// smoothness) is within the backend's tolerance (the host's figure). Negative: no models (every
// texel searched, the per-texel answer).
uniform float modelReachSquared;
#elif defined(SURFACE_GRID)
layout(std430, binding = 5) readonly buffer Heights { float gridHeights[]; };  // sample - reference (m)
layout(std430, binding = 7) readonly buffer Frames { GridFrame frames[]; };    // per body
uniform int countX;
uniform int countZ;
uniform float inverseSpacing;  // 1/m
#elif defined(SURFACE_MEDIUM)
uniform float inverseScaleHeight;  // 1/H (1/m); 0: constant density
#endif

const uint kGroup = 64u;
const uint kTexelsPerInvocation = 4u;
const int kSums = 11;
const int kHeads = 6;

shared float reduction[kSums + kHeads][kGroup];

#if defined(SURFACE_GERSTNER)
// GerstnerWaves::surfaceHeight about o: the rest point x0 with x0 + H(x0) = x, then the height of
// its displaced point. Same iteration, same switch to fixed-point steps (determinant <= 0.1), same
// 24 iterations at most; the stopping step is float's (8 ulps of the coordinates) instead of
// 1e-9 m, a height error of at most sum(k A) times that.
float dryLevelOf(uint body) { return bodyWaves[body * (waveCount + 2u) + 1u]; }

// The rest point (x0, z0) whose displaced point lies above (x, z), its height (returned) and
// `slope` (d h / dx, d h / dz) from the same iterate: the height's gradient in the rest point
// through the inverse of the (symmetric) Jacobian of x0 -> x, as GerstnerWaves::heightJet;
// `jacobian` (xx, xz, zz) is that Jacobian at `rest`.
float restPointOf(float x, float z, uint body, out vec2 rest, out vec2 slope, out vec3 jacobian) {
  uint base = body * (waveCount + 2u);
  float tolerance = 1.0e-6 * (abs(x) + abs(z) + horizontalSum) + 1.0e-12;
  float x0 = x, z0 = z, height = 0.0;
  slope = vec2(0.0);
  for (int iteration = 0; iteration < 24; ++iteration) {
    float hx = 0.0, hz = 0.0, jxx = 1.0, jxz = 0.0, jzz = 1.0, gx = 0.0, gz = 0.0;
    height = 0.0;
    for (uint w = 0u; w < waveCount; ++w) {
      GerstnerComponent c = waves[w];
      float theta = c.waveNumber * (c.dirX * x0 + c.dirZ * z0) + bodyWaves[base + 2u + w];
      float sine = sin(theta), cosine = cos(theta);
      hx -= c.horizontal * sine * c.dirX;
      hz -= c.horizontal * sine * c.dirZ;
      height += c.amplitude * cosine;
      gx -= c.amplitude * c.waveNumber * sine * c.dirX;
      gz -= c.amplitude * c.waveNumber * sine * c.dirZ;
      float steepness = c.horizontal * c.waveNumber * cosine;
      jxx -= steepness * c.dirX * c.dirX;
      jxz -= steepness * c.dirX * c.dirZ;
      jzz -= steepness * c.dirZ * c.dirZ;
    }
    float rx = x0 + hx - x, rz = z0 + hz - z;
    float determinant = jxx * jzz - jxz * jxz;
    if (determinant != 0.0) slope = vec2(jzz * gx - jxz * gz, jxx * gz - jxz * gx) / determinant;
    float stepX = rx, stepZ = rz;
    if (determinant > 0.1) {
      stepX = (jzz * rx - jxz * rz) / determinant;
      stepZ = (jxx * rz - jxz * rx) / determinant;
    }
    rest = vec2(x0, z0);  // the point the height, slope and Jacobian belong to
    jacobian = vec3(jxx, jxz, jzz);
    if (abs(stepX) + abs(stepZ) < tolerance) break;
    x0 -= stepX;
    z0 -= stepZ;
  }
  return bodyWaves[base] + height;
}

float surfaceHeightAt(float x, float z, uint body, out vec2 slope) {
  vec2 rest;
  vec3 jacobian;
  return restPointOf(x, z, body, rest, slope, jacobian);
}

// The height with its slope and `curvature` (d2 h / dx2, dx dz, dz2) at (x, z): GerstnerWaves::
// jetAt's sum over the waves of (-A k^2 cos - Q A k^2 sin (slope . d)) e e^T, e = J^-1 d, at the
// search's rest point. A map that folds there (det J <= 0) gives no curvature: `valid` false.
float surfaceJetAt(float x, float z, uint body, out vec2 slope, out vec3 curvature, out bool valid) {
  vec2 rest;
  vec3 j;
  float height = restPointOf(x, z, body, rest, slope, j);
  uint base = body * (waveCount + 2u);
  float jxx = j.x, jxz = j.y, jzz = j.z;
  float determinant = jxx * jzz - jxz * jxz;
  curvature = vec3(0.0);
  valid = determinant > 0.0;
  if (!valid) return height;
  float ixx = jzz / determinant, ixz = -jxz / determinant, izz = jxx / determinant;
  for (uint w = 0u; w < waveCount; ++w) {
    GerstnerComponent c = waves[w];
    float theta = c.waveNumber * (c.dirX * rest.x + c.dirZ * rest.y) + bodyWaves[base + 2u + w];
    float k2 = c.waveNumber * c.waveNumber;
    float weight = -c.amplitude * k2 * cos(theta) - c.horizontal * k2 * sin(theta) * (slope.x * c.dirX + slope.y * c.dirZ);
    float ex = ixx * c.dirX + ixz * c.dirZ, ez = ixz * c.dirX + izz * c.dirZ;
    curvature += weight * vec3(ex * ex, ex * ez, ez * ez);
  }
  return height;
}
#elif defined(SURFACE_GRID)
// HeightGrid::surfaceHeight about o: the grid coordinate (x - originX) / spacing split into the
// body's cell (exact integer) and a small float part, clamped to [0, count - 1] as HeightGrid
// clamps it.
float dryLevelOf(uint body) { return frames[body].dryLevel; }

// `slope`: 0, as on the CPU (HeightGrid gives no height jets).
float surfaceHeightAt(float x, float z, uint body, out vec2 slope) {
  slope = vec2(0.0);
  GridFrame frame = frames[body];
  float gx = x * inverseSpacing + frame.fracX, gz = z * inverseSpacing + frame.fracZ;
  float cellX = floor(gx), cellZ = floor(gz);
  int ix = int(cellX) + frame.cellX, iz = int(cellZ) + frame.cellZ;
  float fx = gx - cellX, fz = gz - cellZ;
  if (ix < 0) { ix = 0; fx = 0.0; }
  else if (ix >= countX - 1) { ix = countX - 2; fx = 1.0; }
  if (iz < 0) { iz = 0; fz = 0.0; }
  else if (iz >= countZ - 1) { iz = countZ - 2; fz = 1.0; }
  int i00 = iz * countX + ix;
  float h00 = gridHeights[i00], h10 = gridHeights[i00 + 1];
  float h01 = gridHeights[i00 + countX], h11 = gridHeights[i00 + countX + 1];
  return frame.heightOffset + ((1.0 - fz) * ((1.0 - fx) * h00 + fx * h10) + fz * ((1.0 - fx) * h01 + fx * h11));
}
#endif

#if defined(SURFACE_MEDIUM)
// H expm1(-y/H): the medium's pressure head about o relative to o's own (series where exp(x) - 1
// would cancel in float; its first left-out term is below float rounding for |x| < 1e-2).
float mediumHead(float y) {
  if (inverseScaleHeight == 0.0) return -y;
  float x = -y * inverseScaleHeight;
  float expm1 = abs(x) < 1.0e-2 ? x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0)))) : exp(x) - 1.0;
  return expm1 / inverseScaleHeight;
}
#endif

#if defined(SURFACE_GERSTNER)
// A local model: its reach squared (m^2; 0: none), centre (x, z) (m), height there (m), slope,
// and curvature (xx, xz, zz; 1/m).
struct LocalModel {
  float reachSquared;
  vec2 center;
  float height;
  vec2 slope;
  vec3 curvature;
};

// The model's height at (x, z) and its slope there, when (x, z) lies within its reach.
bool modelHeightAt(LocalModel m, float x, float z, out float height, out vec2 slope) {
  float dx = x - m.center.x, dz = z - m.center.y;
  if (!(dx * dx + dz * dz < m.reachSquared)) return false;
  slope = vec2(m.slope.x + m.curvature.x * dx + m.curvature.y * dz, m.slope.y + m.curvature.y * dx + m.curvature.z * dz);
  height = m.height + m.slope.x * dx + m.slope.y * dz +
           0.5 * (m.curvature.x * dx * dx + 2.0 * m.curvature.y * dx * dz + m.curvature.z * dz * dz);
  return true;
}

// The model about (x, z): its height and slope there are the search's (surfaceHeightAt's); no
// reach where models are off or the map folds there.
LocalModel modelAbout(float x, float z, uint body) {
  LocalModel m;
  bool valid;
  m.height = surfaceJetAt(x, z, body, m.slope, m.curvature, valid);
  m.center = vec2(x, z);
  m.reachSquared = valid && modelReachSquared > 0.0 ? modelReachSquared : 0.0;
  return m;
}

// The chunk's model, about the centre of its box (body frame), made by its first invocation.
shared LocalModel chunkModel;

// The surface's height above (x, z) and its slope: the chunk's model within its reach (the
// Taylor bound holds pointwise, so a chunk wider than the reach still models its texels near its
// centre), else the search. (A model per invocation, about its last searched texel, made the
// step slower: invocations run in lockstep, and one that searches holds up the others.)
float modeledHeightAt(float x, float z, uint body, out vec2 slope) {
  float height;
  if (modelHeightAt(chunkModel, x, z, height, slope)) return height;
  return surfaceHeightAt(x, z, body, slope);
}
#endif

void main() {
  uint chunkIndex = crossing[listBase + gl_WorkGroupID.x];
  Chunk chunk = chunks[chunkIndex];
  BodyPose pose = poses[chunk.body];
  vec3 row0 = pose.row0.xyz, row1 = pose.row1.xyz, row2 = pose.row2.xyz;
#if defined(SURFACE_GERSTNER)
  if (gl_LocalInvocationID.x == 0u) {
    vec3 boxCenter = vec3(chunk.centerX, chunk.centerY, chunk.centerZ);
    chunkModel = LocalModel(0.0, vec2(0.0), 0.0, vec2(0.0), vec3(0.0));  // none
    if (modelReachSquared > 0.0)
      chunkModel = modelAbout(dot(row0, boxCenter) + pose.row0.w, dot(row2, boxCenter) + pose.row2.w, chunk.body);
  }
  barrier();
#endif

  float sums[kSums];
  float heads[kHeads];
  for (int k = 0; k < kSums; ++k) sums[k] = 0.0;
  for (int k = 0; k < kHeads; ++k) heads[k] = 0.0;
  for (uint n = 0u; n < kTexelsPerInvocation; ++n) {
    uint i = gl_LocalInvocationID.x + n * kGroup;
    if (i >= chunk.count) break;
    HydroTexel t = texels[chunk.begin + i];
    vec3 p = vec3(t.px, t.py, t.pz), area = vec3(t.ax, t.ay, t.az);
    float x = dot(row0, p) + pose.row0.w;
    float y = dot(row1, p) + pose.row1.w;
    float z = dot(row2, p) + pose.row2.w;
    vec3 a = vec3(dot(row0, area), dot(row1, area), dot(row2, area));
#if defined(SURFACE_MEDIUM)
    float localHeight = 0.0;
    vec3 f = vec3(1.0, -y, y * y);
    float head = mediumHead(y);
#else
    float ea = dot(row1, vec3(t.ux, t.uy, t.uz));
    float eb = dot(row1, vec3(t.vx, t.vy, t.vz));
    float halfSpan = 0.5 * (abs(ea) + abs(eb));
    // Wholly above the surface's highest point: dry without the surface's look-up (as the CPU).
    if (y - halfSpan >= dryLevelOf(chunk.body)) continue;
    vec2 unusedSlope;
#if defined(SURFACE_GERSTNER)
    float localHeight = modeledHeightAt(x, z, chunk.body, unusedSlope);
#else
    float localHeight = surfaceHeightAt(x, z, chunk.body, unusedSlope);
#endif
    float depth = localHeight - y;
    if (!(depth > -halfSpan)) continue;  // dry (or a NaN height)
    vec3 f = waterlineFractions(depth, ea, eb);
    float head = f.y;
#endif
    float da = f.y * a.y;
    float fay = f.x * a.y;
    sums[0] += da;
    sums[1] += da * x;
    sums[2] += da * z;
    sums[3] += (0.5 * f.z - localHeight * f.y) * a.y;
    sums[4] += fay;
    sums[5] += fay * x;
    sums[6] += fay * z;
    sums[7] += fay * x * x;
    sums[8] += fay * x * z;
    sums[9] += fay * z * z;
    sums[10] += f.x * t.area;
    heads[0] += head * a.x;
    heads[1] += head * a.y;
    heads[2] += head * a.z;
    heads[3] += head * (y * a.z - z * a.y);
    heads[4] += head * (z * a.x - x * a.z);
    heads[5] += head * (x * a.y - y * a.x);
  }
  // The chunk's texels of several pieces add their moment corrections (waterline.glsl), weighted
  // by the submerged share of their pieces' span (correctionWeight); the head's share is its first-order term too, with the head e at the centre and
  // grad e = (slope.x, -1, slope.y) under a free surface (e = D), (0, e', 0) with
  // e' = -exp(-y'/H) in a medium.
  for (uint j = gl_LocalInvocationID.x; j < chunk.correctionCount; j += kGroup) {
    TexelCorrection c = corrections[chunk.correctionBegin + j];
    HydroTexel t = texels[chunk.begin + c.texel];
    vec3 p = vec3(t.px, t.py, t.pz);
    float x = dot(row0, p) + pose.row0.w;
    float y = dot(row1, p) + pose.row1.w;
    float z = dot(row2, p) + pose.row2.w;
#if defined(SURFACE_MEDIUM)
    float weight = 1.0;
    float depth = -y;
    float localHeight = 0.0;
    vec2 slope = vec2(0.0);
    float head = mediumHead(y);
    vec3 gradient = vec3(0.0, -1.0 - head * inverseScaleHeight, 0.0);  // e' = -exp(-y/H) = -(1 + e/H)
#else
    float ea = dot(row1, vec3(t.ux, t.uy, t.uz));
    float eb = dot(row1, vec3(t.vx, t.vy, t.vz));
    float halfSpan = 0.5 * (abs(ea) + abs(eb));
    float span = max(halfSpan, c.reach);  // the pieces may reach beyond the patch
    if (y - span >= dryLevelOf(chunk.body)) continue;
    vec2 slope;
#if defined(SURFACE_GERSTNER)
    float localHeight = modeledHeightAt(x, z, chunk.body, slope);
#else
    float localHeight = surfaceHeightAt(x, z, chunk.body, slope);
#endif
    float depth = localHeight - y;
    if (!(depth > -span)) continue;
    float weight = correctionWeight(depth, halfSpan, c.reach);
    float head = depth;
    vec3 gradient = vec3(slope.x, -1.0, slope.y);
#endif
    vec3 d0, d1, d2;
    worldMoment(c, row0, row1, row2, d0, d1, d2);
    addMomentCorrection(sums, d0, d1, d2, x, y, z, weight, depth, localHeight, slope);
    // grad e . dM'(:, k) over k, then moment(i, k) = e dM'(i, k) + x_i grad e . dM'(:, k); the
    // torque's components of its x_i A_k.
    vec3 along = gradient.x * d0 + gradient.y * d1 + gradient.z * d2;
    vec3 m0 = head * d0 + x * along;
    vec3 m1 = head * d1 + y * along;
    vec3 m2 = head * d2 + z * along;
    heads[0] += weight * along.x;
    heads[1] += weight * along.y;
    heads[2] += weight * along.z;
    heads[3] += weight * (m1.z - m2.y);
    heads[4] += weight * (m2.x - m0.z);
    heads[5] += weight * (m0.y - m1.x);
  }

  uint lane = gl_LocalInvocationID.x;
  for (int k = 0; k < kSums; ++k) reduction[k][lane] = sums[k];
  for (int k = 0; k < kHeads; ++k) reduction[kSums + k][lane] = heads[k];
  barrier();
  // Two levels, as hydrostatics_flat.comp (llvmpipe's barrier cost).
  if (lane < 8u)
    for (int k = 0; k < kSums + kHeads; ++k) {
      float sum = 0.0;
      for (uint j = 0u; j < 8u; ++j) sum += reduction[k][lane + 8u * j];
      reduction[k][lane] = sum;
    }
  barrier();
  if (lane == 0u) {
    float total[kSums + kHeads];
    for (int k = 0; k < kSums + kHeads; ++k) {
      total[k] = 0.0;
      for (uint j = 0u; j < 8u; ++j) total[k] += reduction[k][j];
    }
    for (int k = 0; k < kSums; ++k) partials[chunkIndex].value[k] = total[k];
    partials[chunkIndex].value[11] = 0.0;
    for (int k = 0; k < 12; ++k) partials[headBase + chunkIndex].value[k] = k < kHeads ? total[kSums + k] : 0.0;
  }
}
