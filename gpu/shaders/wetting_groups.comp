// SPDX-License-Identifier: Zlib
// Merged diffusion groups (core's DiffusionGroups, Wetting::poolGroup / spreadGroups), one group
// per invocation. Pooling: the members' volumes (contents times areas) summed onto the holding
// texel as the group's mean content; spreading, after the diffusion: the holder's content copied
// to every member. The group's volume is unchanged by either.
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Liquid { float liquid[]; };                  // m
layout(std430, binding = 1) buffer Pigment { float pigment[]; };                // m of pigment
layout(std430, binding = 2) readonly buffer GroupStart { uint groupStart[]; };  // per group + 1
layout(std430, binding = 3) readonly buffer Members { uint members[]; };        // holder first
layout(std430, binding = 4) readonly buffer Area { float area[]; };             // per texel (m^2)
layout(std430, binding = 5) readonly buffer InverseArea { float inverseArea[]; }; // 1 / group area on the holder

uniform uint groupCount;
uniform bool spreading;  // false: pool
uniform bool withPigment;

void main() {
  uint g = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationID.x;
  if (g >= groupCount) return;
  uint holder = members[groupStart[g]];
  if (spreading) {
    for (uint m = groupStart[g] + 1u; m < groupStart[g + 1u]; ++m) {
      liquid[members[m]] = liquid[holder];
      if (withPigment) pigment[members[m]] = pigment[holder];
    }
    return;
  }
  float volume = 0.0, pigmentVolume = 0.0;
  for (uint m = groupStart[g]; m < groupStart[g + 1u]; ++m) {
    uint i = members[m];
    volume += liquid[i] * area[i];
    if (withPigment) pigmentVolume += pigment[i] * area[i];
  }
  liquid[holder] = volume * inverseArea[holder];
  if (withPigment) pigment[holder] = pigmentVolume * inverseArea[holder];
}
