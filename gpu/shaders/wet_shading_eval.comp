// SPDX-License-Identifier: Zlib
// Evaluates wet_shading.glsl (appended before this file) for a batch of samples, one invocation
// each: what WetShadingGl.cpp runs to check the GLSL against the C++ reference.
layout(local_size_x = 64) in;

// Per sample: dry RGB and saturation; film transmittance RGB and refractive index.
layout(std430, binding = 0) readonly buffer Samples { vec4 samples[]; };
// Per sample: wet surface RGB and p; R_bar, R1, diffuse and total wet albedo of the red channel.
layout(std430, binding = 1) writeonly buffer Results { vec4 results[]; };

uniform uint sampleCount;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= sampleCount) return;
  vec4 dry = samples[2u * i];
  vec4 film = samples[2u * i + 1u];
  float n = film.w;
  vec2 red = hxWetAlbedo(dry.r, n, film.r);
  results[2u * i] = vec4(hxWetSurfaceRgb(dry.rgb, dry.w, n, film.rgb), hxInternalReflectionProbability(n));
  results[2u * i + 1u] = vec4(hxAverageInternalReflectance(n), hxFilmReflectance(n), red.x, red.y);
}
