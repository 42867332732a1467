// SPDX-License-Identifier: Zlib
// Darcy through the surface of a flooding body under a flat level: per node of its liquid graph,
// the five float sums LiquidGraph::step makes over the node's permeable texels
// (core/src/flooding/LiquidGraph.cpp, flatNodeSums; FloodingNodeSums in LiquidGraph.hpp). One
// work group per node; heights along `up` in the body frame from the body origin.
layout(local_size_x = 128) in;

layout(std430, binding = 0) readonly buffer Texels { vec4 texels[]; };        // x, y, z (m, body frame), T (m^3)
layout(std430, binding = 1) readonly buffer NodeStart { uint nodeStart[]; };  // per node + 1
layout(std430, binding = 2) readonly buffer Levels { vec2 levels[]; };        // per node: inside level, wet level (m)
layout(std430, binding = 3) writeonly buffer Sums { float sums[]; };          // per node: the five sums

uniform vec3 up;
uniform float outsideLevel;

shared float partial[5][128];

void main() {
  uint node = gl_WorkGroupID.x;
  uint lane = gl_LocalInvocationID.x;
  vec2 level = levels[node];
  float netHead = 0.0, pushedHead = 0.0, all = 0.0, inside = 0.0, either = 0.0;
  for (uint t = nodeStart[node] + lane; t < nodeStart[node + 1u]; t += 128u) {
    vec4 texel = texels[t];
    float y = up.x * texel.x + up.y * texel.y + up.z * texel.z;
    float outsideHead = max(outsideLevel - y, 0.0);
    float insideHead = max(level.x - y, 0.0);
    float c = texel.w;
    netHead += c * (outsideHead - insideHead);
    pushedHead += c * outsideHead;
    all += c;
    bool wetInside = y <= level.y;
    inside += wetInside ? c : 0.0;
    either += (wetInside || outsideHead > 0.0) ? c : 0.0;
  }
  partial[0][lane] = netHead;
  partial[1][lane] = pushedHead;
  partial[2][lane] = all;
  partial[3][lane] = inside;
  partial[4][lane] = either;
  barrier();
  for (uint stride = 64u; stride > 0u; stride >>= 1u) {
    if (lane < stride)
      for (int k = 0; k < 5; ++k) partial[k][lane] += partial[k][lane + stride];
    barrier();
  }
  if (lane == 0u)
    for (int k = 0; k < 5; ++k) sums[node * 5u + uint(k)] = partial[k][0];
}
