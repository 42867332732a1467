// SPDX-License-Identifier: Zlib
// Backward Euler diffusion of the liquid texture on the GPU (core's Wetting::diffuseImplicit):
// (M + dt L) x = M phi, M the groups' areas (1 where a texel holds no group), L the conductance
// graph's Laplacian with D g_ij, solved by conjugate gradients with a Jacobi preconditioner, in
// double as on the CPU: the pair fluxes dt D g_ij (x_i - x_j) that wetting_diffuse.comp then
// applies to phi (so that the volume is conserved whatever the residual) multiply x's error by
// dt D g / A, a million at long steps, which float x would turn into errors of the contents'
// size. One program, one texel per invocation, in modes; the dot products are summed per work
// group and finished by wetting_implicit_reduce.comp, which keeps the solver's scalars on the GPU.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Liquid { float liquid[]; };         // phi (m)
layout(std430, binding = 1) buffer Solution { double x[]; };                     // x (m)
layout(std430, binding = 2) readonly buffer Graph { uint graph[]; };             // row starts (texelCount + 1), then neighbours
layout(std430, binding = 3) readonly buffer Conductance { float conductance[]; }; // D g_ij (m^2/s)
layout(std430, binding = 4) readonly buffer InverseArea { float inverseArea[]; }; // 1 / group area, 0 off holders
layout(std430, binding = 5) buffer Work { double work[]; };  // r, z, p, Ap: four arrays of texelCount
layout(std430, binding = 6) buffer Scalars { double scalars[]; };  // rz, pAp, alpha, beta, rz0, then per-group partials

const uint kStart = 0u, kApply = 1u, kUpdate = 2u, kDirection = 3u;
uniform uint mode;
uniform uint texelCount;
uniform float dt;  // s
const uint kPartials = 8u;  // partials follow the scalars

shared double partial[64];

double massOf(uint i) { return inverseArea[i] > 0.0 ? 1.0LF / double(inverseArea[i]) : 1.0LF; }

void main() {
  uint local = gl_LocalInvocationID.x;
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint i = group * 64u + local;
  uint n = texelCount;
  double sum = 0.0LF;
  if (i < n) {
    double m = massOf(i), diagonal = m, laplacian = 0.0LF, step = double(dt);
    if (mode == kStart) {
      // x = phi, r = M phi - (M + dt L) phi = -dt L phi.
      double phi = double(liquid[i]);
      for (uint k = graph[i]; k < graph[i + 1u]; ++k) {
        diagonal += step * double(conductance[k]);
        laplacian += double(conductance[k]) * (phi - double(liquid[graph[n + 1u + k]]));
      }
      double r = -step * laplacian, z = r / diagonal;
      x[i] = phi;
      work[i] = r;
      work[n + i] = z;
      work[2u * n + i] = z;
      sum = r * z;
    } else if (mode == kApply) {
      double p = work[2u * n + i];
      for (uint k = graph[i]; k < graph[i + 1u]; ++k)
        laplacian += double(conductance[k]) * (p - work[2u * n + graph[n + 1u + k]]);
      double ap = m * p + step * laplacian;
      work[3u * n + i] = ap;
      sum = p * ap;
    } else if (mode == kUpdate) {
      for (uint k = graph[i]; k < graph[i + 1u]; ++k) diagonal += step * double(conductance[k]);
      double alpha = scalars[2];
      x[i] += alpha * work[2u * n + i];
      double r = work[i] - alpha * work[3u * n + i];
      double z = r / diagonal;
      work[i] = r;
      work[n + i] = z;
      sum = r * z;
    } else {
      work[2u * n + i] = work[n + i] + scalars[3] * work[2u * n + i];
    }
  }
  if (mode == kDirection) return;
  partial[local] = sum;
  barrier();
  for (uint stride = 32u; stride > 0u; stride >>= 1u) {
    if (local < stride) partial[local] += partial[local + stride];
    barrier();
  }
  if (local == 0u) scalars[kPartials + group] = partial[0];
}
