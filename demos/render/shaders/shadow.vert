#version 430 core
// SPDX-License-Identifier: Zlib
layout(location = 0) in vec3 position;
uniform mat4 model;
uniform mat4 lightViewProjection;
void main() { gl_Position = lightViewProjection * model * vec4(position, 1.0); }
