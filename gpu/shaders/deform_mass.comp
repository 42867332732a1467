// SPDX-License-Identifier: Zlib
// Deforming bodies, mass texels: one workgroup per 256-texel mass block of one body (64
// invocations, 4 texels each). Each texel is evaluated from the moved triangles' frames
// (deform_texel.glsl, as deform_texels.comp does for the hydrostatics texels) and written as the
// mass pass's MassTexel (cone apex-to-base vector d = p - c and cone volume v = d . A / 3), where
// mass_moments.comp reads it; the block's geometry sums (MassBlock) are those of
// TextureMassIntegrator::update (core/src/mass/TextureMassProperties.cpp): the cone covariance
// 3/5 v C with C = min(1, |A| / |eu x ev|) (eu eu^T + ev ev^T) / 12, sum |v|, sum v and the shell
// sums. So the mass properties of a body deformed on the GPU come from GPU-side texels.
layout(local_size_x = 64) in;

layout(std430, binding = 0) writeonly buffer Texels { MassTexel texels[]; };  // the buffer of the body's mass run
layout(std430, binding = 1) readonly buffer Chunks { Chunk chunks[]; };       // mass chunks
layout(std430, binding = 5) writeonly buffer Blocks { MassBlock blocks[]; };  // per body block
// Bindings 2..4: deform_texel.glsl.

uniform uint bodyChunkBegin;  // global index of the body's first mass chunk
uniform uint chunkBase;       // body-local index of this dispatch's first block
uniform uint chunkCount;      // blocks in this dispatch
uniform vec3 referencePoint;  // c (m, body frame)

const uint kGroup = 64u;
const uint kPerInvocation = 4u;
const int kSums = 18;
shared float reduction[kSums][kGroup];

void main() {
  uint local = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (local >= chunkCount) return;  // the same for the whole workgroup
  uint block = chunkBase + local;
  Chunk chunk = chunks[bodyChunkBegin + block];
  uint lane = gl_LocalInvocationID.x;

  float s[kSums];
  for (int k = 0; k < kSums; ++k) s[k] = 0.0;
  for (uint n = 0u; n < kPerInvocation; ++n) {
    uint i = lane + n * kGroup;
    if (i >= chunk.count) break;
    vec3 p, a, eu, ev;
    float area;
    evaluateTexel(block * 256u + i, p, a, area, eu, ev);
    vec3 d = p - referencePoint;
    float v = dot(d, a) * (1.0 / 3.0);
    texels[chunk.begin + i].offsetAndVolume = vec4(d, v);
    float spanned = length(cross(eu, ev));
    float k = (spanned > 0.0 ? min(area / spanned, 1.0) : 0.0) * (1.0 / 12.0);
    float c[6] = float[6](k * (eu.x * eu.x + ev.x * ev.x), k * (eu.y * eu.y + ev.y * ev.y), k * (eu.z * eu.z + ev.z * ev.z),
                          k * (eu.x * eu.y + ev.x * ev.y), k * (eu.x * eu.z + ev.x * ev.z), k * (eu.y * eu.z + ev.y * ev.z));
    float pairs[6] = float[6](d.x * d.x, d.y * d.y, d.z * d.z, d.x * d.y, d.x * d.z, d.y * d.z);
    for (int m = 0; m < 6; ++m) {
      s[m] += 0.6 * v * c[m];
      s[12 + m] += area * (pairs[m] + c[m]);
    }
    s[6] += abs(v);
    s[7] += v;
    s[8] += area;
    s[9] += area * d.x;
    s[10] += area * d.y;
    s[11] += area * d.z;
  }

  for (int k = 0; k < kSums; ++k) reduction[k][lane] = s[k];
  barrier();
  // Two levels, as hydrostatics_flat.comp (llvmpipe's barrier cost).
  if (lane < 8u)
    for (int k = 0; k < kSums; ++k) {
      float sum = 0.0;
      for (uint j = 0u; j < 8u; ++j) sum += reduction[k][lane + 8u * j];
      reduction[k][lane] = sum;
    }
  barrier();
  if (lane == 0u) {
    for (int k = 0; k < kSums; ++k) {
      float sum = 0.0;
      for (uint j = 0u; j < 8u; ++j) sum += reduction[k][j];
      blocks[block].value[k] = sum;
    }
    blocks[block].value[18] = 0.0;
    blocks[block].value[19] = 0.0;
  }
}
