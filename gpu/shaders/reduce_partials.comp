// SPDX-License-Identifier: Zlib
// Final pass in double, one workgroup per body: sums the body's float chunk partials into
// BodySums. Mass mode also adds each block's cone covariance weighted by the block's mean density
// and scales the moments (first by 3/4, second by 3/5), as TextureMassIntegrator::evaluate does.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Partials { Partial partials[]; };
layout(std430, binding = 1) readonly buffer Ranges { BodyRange ranges[]; };
layout(std430, binding = 2) readonly buffer Blocks { BlockGeometry blocks[]; };
layout(std430, binding = 3) writeonly buffer Results { BodySums results[]; };
layout(std430, binding = 4) readonly buffer Chunks { Chunk chunks[]; };  // mass chunks (massMode): their BlockGeometry entry

uniform uint bodyBase;   // first body of this dispatch
uniform uint bodyCount;  // bodies in this dispatch
uniform bool massMode;
uniform uint partialBase;  // where this dispatch's partials start in Partials (the pressure heads' region or 0)

const uint kGroup = 64u;
shared double reduction[12][kGroup];

void main() {
  uint local = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  if (local >= bodyCount) return;
  uint body = bodyBase + local;
  BodyRange range = ranges[body];
  if (massMode && range.mode == 2u) return;
  uint lane = gl_LocalInvocationID.x;
  double s[12];
  for (int k = 0; k < 12; ++k) s[k] = 0.0LF;
  if (massMode) s[10] = 3.0e38LF;
  for (uint c = range.chunkBegin + lane; c < range.chunkEnd; c += kGroup) {
    if (!massMode) {
      for (int k = 0; k < 11; ++k) s[k] += double(partials[partialBase + c].value[k]);
      continue;
    }
    BlockGeometry block = blocks[chunks[c].table];
    double meanDensity = double(range.uniformDensity);
    if (range.mode == 1u)
      meanDensity = block.absVolume > 0.0LF ? double(partials[c].value[10]) / block.absVolume : 0.0LF;
    s[0] += double(partials[c].value[0]);
    for (int k = 1; k < 4; ++k) s[k] += 0.75LF * double(partials[c].value[k]);
    for (int k = 4; k < 10; ++k) s[k] += 0.6LF * double(partials[c].value[k]) + meanDensity * block.covariance[k - 4];
    double lowest = double(partials[c].value[11]);
    if (!(lowest >= s[10])) s[10] = lowest;
  }
  for (int k = 0; k < 12; ++k) reduction[k][lane] = s[k];
  barrier();
  for (uint stride = kGroup / 2u; stride > 0u; stride >>= 1u) {
    if (lane < stride) {
      for (int k = 0; k < 10; ++k) reduction[k][lane] += reduction[k][lane + stride];
      if (massMode) {
        double other = reduction[10][lane + stride];
        if (!(other >= reduction[10][lane])) reduction[10][lane] = other;
      } else {
        reduction[10][lane] += reduction[10][lane + stride];
      }
    }
    barrier();
  }
  if (lane == 0u)
    for (int k = 0; k < 12; ++k) results[body].value[k] = reduction[k][0];
}
