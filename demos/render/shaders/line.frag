#version 430 core
// SPDX-License-Identifier: Zlib
in vec3 lineColour;
out vec4 colour;
void main() { colour = vec4(lineColour, 1.0); }
