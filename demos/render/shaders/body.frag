#version 430 core
// SPDX-License-Identifier: Zlib
// Lambert sun with a 3x3 percentage-closer shadow lookup, hemispheric sky ambient, albedo texture,
// the wet look of the body's liquid texture (Lekner and Dorf, the library's own wet_shading.glsl)
// and an optional pseudo-colour overlay of a surface map or of the wetness.
#include "wet_shading.glsl"
in vec3 worldPosition;
in vec3 worldNormal;
in vec2 texCoord;
in vec2 wetCoord;
in vec4 lightClip;
out vec4 colour;
uniform sampler2D albedoMap;
uniform sampler2D overlayMap;
uniform sampler2DShadow shadowMap;
uniform vec3 sunDirection;   // towards the scene
uniform vec3 eye;
uniform float overlayOpacity;
uniform int palette;         // 0 heat, 1 viridis, 2 wetness
uniform sampler2D wetnessMap;   // r: saturation 0..1, g: pigment fraction 0..1, in the physics atlas (wetCoord)
uniform vec3 pigmentTransmittance; // per crossing of a film of pure pigment
uniform bool hasWetness;
uniform float wetnessViewOpacity; // 0: wet shading; 1: saturation in the wetness palette
const float kWaterIndex = 1.33;   // refractive index of water (the film)

vec3 heat(float x) { return clamp(vec3(3.0 * x, 3.0 * x - 1.0, 3.0 * x - 2.0), 0.0, 1.0); }
vec3 viridis(float x) {
  // Polynomial fit of matplotlib's viridis (Mattias Roberts' approximation, public domain).
  const vec3 c0 = vec3(0.2777, 0.0054, 0.3341), c1 = vec3(0.1051, 1.4046, 1.3846),
             c2 = vec3(-0.3309, 0.2148, 0.0951), c3 = vec3(-4.6342, -5.7991, -19.3324),
             c4 = vec3(6.2283, 14.1799, 56.6906), c5 = vec3(4.7764, -13.7451, -65.3530),
             c6 = vec3(-5.4355, 4.6459, 26.3124);
  return c0 + x * (c1 + x * (c2 + x * (c3 + x * (c4 + x * (c5 + x * c6)))));
}
vec3 wetness(float x) { return mix(vec3(0.95, 0.95, 0.9), vec3(0.05, 0.2, 0.7), x); }

void main() {
  vec3 n = normalize(worldNormal);
  vec3 toEye = normalize(eye - worldPosition);
  if (dot(n, toEye) < 0.0) n = -n;  // thin parts seen from behind
  vec3 albedo = texture(albedoMap, texCoord).rgb;
  if (overlayOpacity > 0.0) {
    float level = clamp(texture(overlayMap, texCoord).r, 0.0, 1.0);
    vec3 mapped = palette == 0 ? heat(level) : palette == 1 ? viridis(level) : wetness(level);
    float weight = palette == 0 ? overlayOpacity * smoothstep(0.0, 0.15, level) : overlayOpacity;
    albedo = mix(albedo, mapped, weight);
  }
  float saturation = 0.0;
  if (hasWetness) {
    vec2 wet = texture(wetnessMap, wetCoord).rg;
    saturation = clamp(wet.r, 0.0, 1.0);
    // Clear water transmits fully (darkening by internal reflection alone); a pigment absorbs:
    // T = exp(-alpha h) with the absorbing path growing with the pigment's fraction.
    vec3 transmittance = pow(pigmentTransmittance, vec3(clamp(wet.g, 0.0, 1.0)));
    albedo = hxWetSurfaceRgb(albedo, saturation, kWaterIndex, transmittance);
    albedo = mix(albedo, wetness(saturation), wetnessViewOpacity);
  }
  vec3 projected = lightClip.xyz / lightClip.w * 0.5 + 0.5;
  float lit = 0.0;
  vec2 texel = 1.0 / vec2(textureSize(shadowMap, 0));
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      lit += texture(shadowMap, vec3(projected.xy + vec2(dx, dy) * texel, projected.z - 0.0015));
  lit /= 9.0;
  if (any(lessThan(projected, vec3(0.0))) || any(greaterThan(projected, vec3(1.0)))) lit = 1.0;
  vec3 sun = -normalize(sunDirection);
  float diffuse = max(dot(n, sun), 0.0) * lit;
  vec3 ambient = mix(vec3(0.22, 0.20, 0.18), vec3(0.38, 0.45, 0.55), 0.5 + 0.5 * n.y);
  vec3 lightColour = vec3(1.0, 0.96, 0.88) * 0.85;
  float specular = pow(max(dot(reflect(-sun, n), toEye), 0.0), 32.0) * 0.08 * lit;
  // The film over the wet fraction of a texel is a smooth water surface, drawn as the sea is
  // (water.frag): it glints in the sun and, at oblique angles, mirrors the sky by Schlick's
  // Fresnel factor beyond its normal reflectance R1 (hxFilmReflectance, which the Lekner and Dorf
  // diffuse colour already leaves out); what it mirrors does not reach the surface below. Facing
  // the viewer the wet part is darker, towards the outline it gets a sky sheen: a dark hull
  // reads as wet by both. The dry rough surface has only its broad, faint highlight.
  float r1 = hxFilmReflectance(kWaterIndex);
  float fresnel = r1 + (1.0 - r1) * pow(1.0 - clamp(dot(n, toEye), 0.0, 1.0), 5.0);
  vec3 mirrored = reflect(-toEye, n);
  vec3 mirroredSky = mirrored.y >= 0.0 ? mix(vec3(0.78, 0.86, 0.93), vec3(0.25, 0.47, 0.80), pow(clamp(mirrored.y, 0.0, 1.0), 0.6))
                                       : ambient * albedo;  // below the horizon: the ground and the body itself
  float glint = pow(max(dot(mirrored, sun), 0.0), 120.0) * 2.0 * lit;
  vec3 film = saturation * ((fresnel - r1) * mirroredSky + vec3(1.0, 0.95, 0.85) * glint);
  colour = vec4(albedo * (ambient + lightColour * diffuse) * (1.0 - saturation * (fresnel - r1)) + specular + film, 1.0);
}
