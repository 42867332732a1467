#version 430 core
// SPDX-License-Identifier: Zlib
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 uv;
layout(location = 3) in vec2 physicsUv;
uniform mat4 model;
uniform mat3 normalMatrix;
uniform mat4 viewProjection;
uniform mat4 lightViewProjection;
out vec3 worldPosition;
out vec3 worldNormal;
out vec2 texCoord;
out vec2 wetCoord;
out vec4 lightClip;
void main() {
  vec4 world = model * vec4(position, 1.0);
  worldPosition = world.xyz;
  worldNormal = normalMatrix * normal;
  texCoord = uv;
  wetCoord = physicsUv;
  lightClip = lightViewProjection * world;
  gl_Position = viewProjection * world;
}
