// SPDX-License-Identifier: Zlib
// Pair fluxes of the liquid texture's diffusion (core's Wetting, Fick's law on the graph of
// diffusion groups): every holding texel gathers the fluxes of its own pairs from a CSR neighbour
// list and writes its new liquid to the other buffer (ping-pong); texels inside a merged group
// have no pairs and inverse area 0 and keep their contents. The flux of pair (i, j) is
// step c (u_i - u_j) with u the potential: the liquid itself for an explicit sub-step
// (Wetting::diffuseExplicit), backward Euler's solution for the implicit step
// (Wetting::applyPairFluxes). It is formed by both texels with the operands swapped, and IEEE
// subtraction is exactly antisymmetric, so the two sides move exactly opposite volumes: the total
// is conserved to the rounding of each texel's own sum, with no atomics. The pigment travels with
// the liquid at the concentration of the texel it leaves (upwind), the same texel seen from both
// sides, so it is conserved the same way. Compiled twice: `real` is float for the explicit
// sub-steps, double for the implicit step (its solution is double, wetting_implicit.comp says why).
#ifndef real
#define real float
#endif
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer LiquidIn { float liquidIn[]; };
layout(std430, binding = 1) writeonly buffer LiquidOut { float liquidOut[]; };
layout(std430, binding = 2) readonly buffer Graph { uint graph[]; };             // row starts (texelCount + 1), then neighbours
layout(std430, binding = 3) readonly buffer Conductance { float conductance[]; }; // D g_ij (m^2/s)
layout(std430, binding = 4) readonly buffer InverseArea { float inverseArea[]; }; // 1 / group area on the holder (1/m^2)
layout(std430, binding = 5) readonly buffer PigmentIn { float pigmentIn[]; };     // m of pigment per texel
layout(std430, binding = 6) writeonly buffer PigmentOut { float pigmentOut[]; };
layout(std430, binding = 7) readonly buffer Potential { real potential[]; };      // u (m): the liquid, or the implicit solution

uniform uint texelCount;
uniform float step;  // s
uniform bool withPigment;

void main() {
  uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;
  if (i >= texelCount) return;
  uint first = graph[i], last = graph[i + 1u], neighbours = texelCount + 1u;
  float phi = liquidIn[i];
  real u = potential[i], zero = real(0.0), delta = zero, dt = real(step);
  if (!withPigment) {
    for (uint k = first; k < last; ++k) delta -= dt * real(conductance[k]) * (u - potential[graph[neighbours + k]]);
    liquidOut[i] = float(max(zero, real(phi) + delta * real(inverseArea[i])));
    return;
  }
  float own = pigmentIn[i];
  real pigmentDelta = zero;
  for (uint k = first; k < last; ++k) {
    uint j = graph[neighbours + k];
    real flux = dt * real(conductance[k]) * (u - potential[j]);  // m^3 from i to j
    float fromPhi = flux > zero ? phi : liquidIn[j], fromPigment = flux > zero ? own : pigmentIn[j];
    delta -= flux;
    pigmentDelta -= flux * real(fromPhi > 0.0 ? fromPigment / fromPhi : 0.0);
  }
  liquidOut[i] = float(max(zero, real(phi) + delta * real(inverseArea[i])));
  pigmentOut[i] = float(max(zero, real(own) + pigmentDelta * real(inverseArea[i])));
}
