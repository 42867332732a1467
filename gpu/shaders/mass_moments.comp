// SPDX-License-Identifier: Zlib
// Mass pass, one workgroup per block of 256 texels of one body (TextureMassIntegrator's blocks):
// cone masses w = rho v, their first moments w d and second moments w d d^T about the reference
// point (core/src/mass/TextureMassProperties.cpp), the density-weighted |v| and the lowest density,
// reduced in shared memory to one float Partial per block.
layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Texels { MassTexel texels[]; };
layout(std430, binding = 1) readonly buffer Chunks { Chunk chunks[]; };
layout(std430, binding = 2) readonly buffer Ranges { BodyRange ranges[]; };
layout(std430, binding = 3) writeonly buffer Partials { Partial partials[]; };
layout(std430, binding = 4) readonly buffer Densities { float densities[]; };

uniform uint chunkBase;
uniform uint chunkCount;

const uint kGroup = 256u;
shared float reduction[12][kGroup];

void main() {
  uint local = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (local >= chunkCount) return;  // the same for the whole workgroup
  uint chunkIndex = chunkBase + local;
  Chunk chunk = chunks[chunkIndex];
  BodyRange range = ranges[chunk.body];
  if (range.mode == 2u) return;  // body not asked this call: its partials are not read

  uint lane = gl_LocalInvocationID.x;
  float s[12];
  for (int k = 0; k < 12; ++k) s[k] = 0.0;
  s[11] = range.mode == 1u ? 3.0e38 : range.uniformDensity;
  if (lane < chunk.count) {
    vec4 texel = texels[chunk.begin + lane].offsetAndVolume;
    float rho = range.mode == 1u ? densities[chunk.begin + lane] : range.uniformDensity;
    float w = rho * texel.w;
    vec3 wd = w * texel.xyz;
    s[0] = w;
    s[1] = wd.x;
    s[2] = wd.y;
    s[3] = wd.z;
    s[4] = wd.x * texel.x;
    s[5] = wd.y * texel.y;
    s[6] = wd.z * texel.z;
    s[7] = wd.x * texel.y;
    s[8] = wd.x * texel.z;
    s[9] = wd.y * texel.z;
    s[10] = rho * abs(texel.w);
    if (range.mode == 1u) s[11] = rho;
  }
  for (int k = 0; k < 12; ++k) reduction[k][lane] = s[k];
  barrier();
  // Two levels, as in hydrostatics_flat.comp (llvmpipe's barrier cost). The lowest density is not
  // taken with min(): a NaN density must not vanish (min's NaN result is undefined); the NaN also
  // reaches the mass, which the host checks.
  if (lane < 32u) {
    for (int k = 0; k < 11; ++k) {
      float sum = 0.0;
      for (uint j = 0u; j < 8u; ++j) sum += reduction[k][lane + 32u * j];
      reduction[k][lane] = sum;
    }
    float lowest = reduction[11][lane];
    for (uint j = 1u; j < 8u; ++j) {
      float other = reduction[11][lane + 32u * j];
      if (!(other >= lowest)) lowest = other;
    }
    reduction[11][lane] = lowest;
  }
  barrier();
  if (lane == 0u) {
    for (int k = 0; k < 11; ++k) {
      float sum = 0.0;
      for (uint j = 0u; j < 32u; ++j) sum += reduction[k][j];
      partials[chunkIndex].value[k] = sum;
    }
    float lowest = reduction[11][0];
    for (uint j = 1u; j < 32u; ++j) {
      float other = reduction[11][j];
      if (!(other >= lowest)) lowest = other;
    }
    partials[chunkIndex].value[11] = lowest;
  }
}
