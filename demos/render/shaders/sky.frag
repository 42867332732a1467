#version 430 core
// SPDX-License-Identifier: Zlib
// Sky gradient above the horizon, deep water colour below it (seen through the transparent
// water surface), and a soft sun disc.
in vec2 clipPosition;
out vec4 colour;
uniform mat4 inverseViewProjection;
uniform vec3 sunDirection;  // towards the scene
void main() {
  vec4 far = inverseViewProjection * vec4(clipPosition, 1.0, 1.0);
  vec4 near = inverseViewProjection * vec4(clipPosition, -1.0, 1.0);
  vec3 ray = normalize(far.xyz / far.w - near.xyz / near.w);
  float up = ray.y;
  vec3 horizon = vec3(0.78, 0.86, 0.93);
  vec3 zenith = vec3(0.25, 0.47, 0.80);
  vec3 sky = mix(horizon, zenith, pow(clamp(up, 0.0, 1.0), 0.6));
  float sun = pow(max(dot(ray, -normalize(sunDirection)), 0.0), 400.0);
  sky += vec3(1.0, 0.95, 0.8) * sun;
  // Below the horizon: hazy far water at the horizon, deep water looking down.
  vec3 deep = mix(vec3(0.42, 0.58, 0.66), vec3(0.02, 0.10, 0.15), clamp(pow(-up * 6.0, 0.5), 0.0, 1.0));
  colour = vec4(up >= 0.0 ? sky : deep, 1.0);
}
