// One explicit diffusion sub-step of the liquid texture (core's Wetting::diffuseExplicit, Fick's
// law on the graph of diffusion groups): every holding texel gathers the fluxes of its own pairs
// from a CSR neighbour list and writes its new liquid to the other buffer (ping-pong); texels
// inside a merged group have no pairs and inverse area 0 and keep their contents. A pair's flux
// step c (phi_i - phi_j) is formed by both of its texels with the operands swapped, and IEEE
// subtraction is exactly antisymmetric, so the two sides move exactly opposite volumes: the total
// is conserved to the rounding of each texel's own sum, with no atomics. The pigment travels with
// the liquid at the concentration of the texel it leaves (upwind), the same texel seen from both
// sides, so it is conserved the same way.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer LiquidIn { float liquidIn[]; };
layout(std430, binding = 1) writeonly buffer LiquidOut { float liquidOut[]; };
layout(std430, binding = 2) readonly buffer RowStart { uint rowStart[]; };        // per texel + 1
layout(std430, binding = 3) readonly buffer Neighbour { uint neighbour[]; };      // per pair end
layout(std430, binding = 4) readonly buffer Conductance { float conductance[]; }; // D g_ij (m^2/s)
layout(std430, binding = 5) readonly buffer InverseArea { float inverseArea[]; }; // 1 / group area on the holder (1/m^2)
layout(std430, binding = 6) readonly buffer PigmentIn { float pigmentIn[]; };     // m of pigment per texel
layout(std430, binding = 7) writeonly buffer PigmentOut { float pigmentOut[]; };

uniform uint texelCount;
uniform float step;  // s
uniform bool withPigment;

void main() {
  uint i = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;
  if (i >= texelCount) return;
  float phi = liquidIn[i];
  float delta = 0.0;
  if (!withPigment) {
    for (uint k = rowStart[i]; k < rowStart[i + 1u]; ++k) delta -= step * conductance[k] * (phi - liquidIn[neighbour[k]]);
    liquidOut[i] = max(0.0, phi + delta * inverseArea[i]);
    return;
  }
  float own = pigmentIn[i], pigmentDelta = 0.0;
  for (uint k = rowStart[i]; k < rowStart[i + 1u]; ++k) {
    uint j = neighbour[k];
    float phiJ = liquidIn[j];
    float flux = step * conductance[k] * (phi - phiJ);  // m^3 from i to j
    float fromPhi = flux > 0.0 ? phi : phiJ, fromPigment = flux > 0.0 ? own : pigmentIn[j];
    delta -= flux;
    pigmentDelta -= flux * (fromPhi > 0.0 ? fromPigment / fromPhi : 0.0);
  }
  liquidOut[i] = max(0.0, phi + delta * inverseArea[i]);
  pigmentOut[i] = max(0.0, own + pigmentDelta * inverseArea[i]);
}
