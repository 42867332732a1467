// SPDX-License-Identifier: Zlib
// Flat-surface hydrostatics over the chunks that cross the surface (listed by
// hydrostatics_classify.comp; chunks wholly above or under it are done there), one workgroup per
// chunk of up to 256 texels of one body (4 per invocation): each texel is the planar patch
// p + s eU + t eV, weighted by the exact submerged fractions of that patch
// (core/src/hydrostatics/HydrostaticSums.hpp, waterlineFractions; the same sums as TextureHydrostatics' flat
// path; waterlineFractions in waterline.glsl), with the moment corrections of its texels of several
// pieces (addMomentCorrection, waterline.glsl), reduced in shared memory to one float Partial per
// chunk.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Texels { HydroTexel texels[]; };
layout(std430, binding = 1) readonly buffer Chunks { Chunk chunks[]; };
layout(std430, binding = 2) readonly buffer Poses { BodyPose poses[]; };
layout(std430, binding = 3) writeonly buffer Partials { Partial partials[]; };
layout(std430, binding = 6) readonly buffer Crossing { uint crossing[]; };
layout(std430, binding = 4) readonly buffer Corrections { TexelCorrection corrections[]; };

uniform uint listBase;  // this run's crossing list in Crossing; the dispatch has one group per entry

const uint kGroup = 64u;
const uint kTexelsPerInvocation = 4u;
const int kSums = 11;

shared float reduction[kSums][kGroup];

void main() {
  uint chunkIndex = crossing[listBase + gl_WorkGroupID.x];
  Chunk chunk = chunks[chunkIndex];
  BodyPose pose = poses[chunk.body];
  vec3 row1 = pose.row1.xyz;

  float sums[kSums];
  for (int k = 0; k < kSums; ++k) sums[k] = 0.0;
  for (uint n = 0u; n < kTexelsPerInvocation; ++n) {
    uint i = gl_LocalInvocationID.x + n * kGroup;
    if (i >= chunk.count) break;
    HydroTexel t = texels[chunk.begin + i];
    vec3 p = vec3(t.px, t.py, t.pz);
    float a = dot(row1, vec3(t.ux, t.uy, t.uz));
    float b = dot(row1, vec3(t.vx, t.vy, t.vz));
    float depth = -(dot(row1, p) + pose.row1.w);
    if (depth <= -0.5 * (abs(a) + abs(b))) continue;  // dry
    float x = dot(pose.row0.xyz, p) + pose.row0.w;
    float z = dot(pose.row2.xyz, p) + pose.row2.w;
    float ay = dot(row1, vec3(t.ax, t.ay, t.az));
    vec3 f = waterlineFractions(depth, a, b);
    float da = f.y * ay;
    float fay = f.x * ay;
    sums[0] += da;
    sums[1] += da * x;
    sums[2] += da * z;
    sums[3] += 0.5 * f.z * ay;
    sums[4] += fay;
    sums[5] += fay * x;
    sums[6] += fay * z;
    sums[7] += fay * x * x;
    sums[8] += fay * x * z;
    sums[9] += fay * z * z;
    sums[10] += f.x * t.area;
  }
  // The chunk's texels of several pieces add their moment corrections, weighted by the submerged
  // share of their pieces' span (correctionWeight).
  for (uint j = gl_LocalInvocationID.x; j < chunk.correctionCount; j += kGroup) {
    TexelCorrection c = corrections[chunk.correctionBegin + j];
    HydroTexel t = texels[chunk.begin + c.texel];
    vec3 p = vec3(t.px, t.py, t.pz);
    float a = dot(row1, vec3(t.ux, t.uy, t.uz));
    float b = dot(row1, vec3(t.vx, t.vy, t.vz));
    float depth = -(dot(row1, p) + pose.row1.w);
    float weight = correctionWeight(depth, 0.5 * (abs(a) + abs(b)), c.reach);
    if (weight == 0.0) continue;  // every piece dry
    float x = dot(pose.row0.xyz, p) + pose.row0.w;
    float z = dot(pose.row2.xyz, p) + pose.row2.w;
    vec3 d0, d1, d2;
    worldMoment(c, pose.row0.xyz, row1, pose.row2.xyz, d0, d1, d2);
    addMomentCorrection(sums, d0, d1, d2, x, -depth, z, weight, depth, 0.0, vec2(0.0));
  }

  uint lane = gl_LocalInvocationID.x;
  for (int k = 0; k < kSums; ++k) reduction[k][lane] = sums[k];
  barrier();
  // Two levels (8 lanes sum 8 values each, then one lane sums 8) instead of a tree of 6 barriers:
  // Quirk (llvmpipe): every barrier switches all the group's invocations' coroutines, which dominated the
  // pass; on a GPU the two levels cost about the same as the tree.
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
      partials[chunkIndex].value[k] = sum;
    }
    partials[chunkIndex].value[11] = 0.0;
  }
}
