// One explicit diffusion sub-step of the liquid texture (core's Wetting::diffuseExplicit, Fick's
// law on the texel graph): every texel gathers the fluxes of its own pairs from a CSR neighbour
// list and writes its new liquid to the other buffer (ping-pong). A pair's flux
// step c (phi_i - phi_j) is formed by both of its texels with the operands swapped, and IEEE
// subtraction is exactly antisymmetric, so the two sides move exactly opposite volumes: the total
// is conserved to the rounding of each texel's own sum, with no atomics.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer LiquidIn { float liquidIn[]; };
layout(std430, binding = 1) writeonly buffer LiquidOut { float liquidOut[]; };
layout(std430, binding = 2) readonly buffer RowStart { uint rowStart[]; };        // per texel + 1
layout(std430, binding = 3) readonly buffer Neighbour { uint neighbour[]; };      // per pair end
layout(std430, binding = 4) readonly buffer Conductance { float conductance[]; }; // D g_ij (m^2/s)
layout(std430, binding = 5) readonly buffer InverseArea { float inverseArea[]; }; // 1 / A_i (1/m^2)

uniform uint texelCount;
uniform float step;  // s

void main() {
  uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;
  if (i >= texelCount) return;
  float phi = liquidIn[i];
  float delta = 0.0;
  for (uint k = rowStart[i]; k < rowStart[i + 1u]; ++k) delta -= step * conductance[k] * (phi - liquidIn[neighbour[k]]);
  liquidOut[i] = max(0.0, phi + delta * inverseArea[i]);
}
