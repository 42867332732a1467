// SPDX-License-Identifier: Zlib
// Wet appearance of a rough absorbent surface under a liquid film (paper section 4.3), after
// Lekner and Dorf 1988, "Why some things are darker when wet", Applied Optics 27(7), 1278-1280.
// The GLSL twin of core/include/hydrotex/wetting/WetShading.hpp (the C++ reference, same names with an
// hx prefix); tests/gpu/test_wet_shading_glsl.cpp runs it on llvmpipe and compares the two to
// 1e-3. For users' engines: paste or include it into a fragment or compute shader (GLSL 1.30 or
// later, no version line here) and feed it the liquid texture's saturation (liquid / capacity).
// Float precision: the closed form of R_bar cancels terms about 40 times larger than the result
// at n = 1.33 (error about 1e-5); keep n >= 1.1.

// R_bar(n): reflectance of the liquid's surface for isotropic light from inside, relative index
// n > 1 (Lekner and Dorf's closed form). Water (n = 1.33): 0.065931.
float hxAverageInternalReflectance(float n) {
  float n2 = n * n;
  float n3 = n2 * n;
  float np1 = n + 1.0;
  float n2p1 = n2 + 1.0;
  float n2m1 = n2 - 1.0;
  return (3.0 * n2 + 2.0 * n + 1.0) / (3.0 * np1 * np1) - 2.0 * n3 * (n2 + 2.0 * n - 1.0) / (n2p1 * n2p1 * n2m1) +
         n2 * n2p1 * log(n) / (n2m1 * n2m1) - n2 * n2m1 * n2m1 / (n2p1 * n2p1 * n2p1) * log(n * np1 / (n - 1.0));
}

// p = 1 - (1 - R_bar(n)) / n^2: probability that light leaving the rough surface into the film is
// sent back to it. Water: 0.471949.
float hxInternalReflectionProbability(float n) { return 1.0 - (1.0 - hxAverageInternalReflectance(n)) / (n * n); }

// R1 = ((n - 1) / (n + 1))^2: the film's own (normal incidence) reflection. Water: 0.020059.
float hxFilmReflectance(float n) {
  float r = (n - 1.0) / (n + 1.0);
  return r * r;
}

// Wet albedo of a surface of dry albedo a in [0, 1] under a film of index n and transmittance T
// per crossing (1 clear; e^(-alpha h) for a coloured liquid): x = diffuse
// (1 - R1) a (1 - p) T^2 / (1 - p a T^2), y = total = diffuse + R1.
vec2 hxWetAlbedo(float dryAlbedo, float n, float filmTransmittance) {
  float a = clamp(dryAlbedo, 0.0, 1.0);
  float t2 = filmTransmittance * filmTransmittance;
  float p = hxInternalReflectionProbability(n);
  float r1 = hxFilmReflectance(n);
  float diffuse = (1.0 - r1) * a * (1.0 - p) * t2 / (1.0 - p * a * t2);
  return vec2(diffuse, diffuse + r1);
}

// Diffuse wet colour per channel; dry (0.6, 0.4, 0.2) under water: (0.433, 0.255, 0.114).
vec3 hxWetDiffuseRgb(vec3 dryRgb, float n, vec3 filmTransmittance) {
  return vec3(hxWetAlbedo(dryRgb.r, n, filmTransmittance.r).x, hxWetAlbedo(dryRgb.g, n, filmTransmittance.g).x,
              hxWetAlbedo(dryRgb.b, n, filmTransmittance.b).x);
}

// Diffuse colour of a partly wet texel: the dry colour blended towards the wet one by the
// saturation (0 dry .. 1 wet, clamped), the fraction of its area under a film.
vec3 hxWetSurfaceRgb(vec3 dryRgb, float saturation, float n, vec3 filmTransmittance) {
  return mix(dryRgb, hxWetDiffuseRgb(dryRgb, n, filmTransmittance), clamp(saturation, 0.0, 1.0));
}
