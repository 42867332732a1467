#version 430 core
// SPDX-License-Identifier: Zlib
layout(location = 0) in vec3 position;  // world
layout(location = 1) in vec3 colourIn;
uniform mat4 viewProjection;
out vec3 lineColour;
void main() {
  lineColour = colourIn;
  gl_Position = viewProjection * vec4(position, 1.0);
}
