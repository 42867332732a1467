#version 430 core
// SPDX-License-Identifier: Zlib
// Transparent water: Schlick's Fresnel term (Schlick 1994, F0 = 0.02 for water) blends the body
// colour of the water with the reflected sky; a sun glint on top; more opaque at grazing angles.
in vec3 worldPosition;
in vec3 worldNormal;
out vec4 colour;
uniform vec3 eye;
uniform vec3 sunDirection;
uniform float fadeDistance;  // m: the grid's edge fades into the horizon colour
void main() {
  vec3 n = normalize(worldNormal);
  vec3 toEye = normalize(eye - worldPosition);
  if (dot(n, toEye) < 0.0) n = -n;
  float cosine = clamp(dot(n, toEye), 0.0, 1.0);
  float fresnel = 0.02 + 0.98 * pow(1.0 - cosine, 5.0);
  vec3 reflected = reflect(-toEye, n);
  vec3 sky = mix(vec3(0.78, 0.86, 0.93), vec3(0.25, 0.47, 0.80), pow(clamp(reflected.y, 0.0, 1.0), 0.6));
  vec3 body = vec3(0.06, 0.30, 0.38);
  vec3 sun = -normalize(sunDirection);
  float glint = pow(max(dot(reflected, sun), 0.0), 200.0) * 2.0;
  vec3 rgb = mix(body, 0.8 * sky, fresnel) + vec3(1.0, 0.95, 0.85) * glint;
  float alpha = mix(0.62, 0.97, fresnel);
  float distanceFade = smoothstep(0.7 * fadeDistance, fadeDistance, length(worldPosition.xz - eye.xz));
  colour = vec4(mix(rgb, vec3(0.42, 0.58, 0.66), distanceFade), mix(alpha, 1.0, distanceFade));
}
