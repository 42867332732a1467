#version 430 core
// SPDX-License-Identifier: Zlib
// A triangle that covers the screen; the fragment shader turns its position into a view ray.
out vec2 clipPosition;
void main() {
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
  clipPosition = corner;
  gl_Position = vec4(corner, 1.0, 1.0);
}
