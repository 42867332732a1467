// SPDX-License-Identifier: Zlib
#pragma once
/// @file WetShadingGl.hpp
/// Runs gpu/shaders/wet_shading.glsl (the Lekner and Dorf wet appearance for users' engines) on
/// the GPU of a headless context, so that the GLSL can be checked against the C++ reference
/// hydrotex/WetShading.hpp and timed.

#include <Eigen/Core>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/gpu/EglContext.hpp"

namespace hydrotex::gpu {

/// One texel to shade.
struct WetShadingSample {
  Eigen::Vector3f dryRgb = Eigen::Vector3f::Constant(0.5f);             ///< dry diffuse albedo per channel (0..1)
  float saturation = 1.0f;                                              ///< liquid / capacity (0 dry .. 1 wet)
  float refractiveIndex = 1.33f;                                        ///< liquid's n (> 1; water 1.33)
  Eigen::Vector3f filmTransmittance = Eigen::Vector3f::Ones();          ///< per crossing of the film (1: clear)
};

/// What the GLSL returned for one sample.
struct WetShadingResult {
  Eigen::Vector3f surfaceRgb = Eigen::Vector3f::Zero();  ///< hxWetSurfaceRgb: the texel's diffuse colour
  float internalReflection = 0.0f;                       ///< hxInternalReflectionProbability: p
  float averageInternalReflectance = 0.0f;               ///< hxAverageInternalReflectance: R_bar
  float filmReflectance = 0.0f;                          ///< hxFilmReflectance: R1
  float redDiffuse = 0.0f;                               ///< hxWetAlbedo(red).x: diffuse wet albedo of the red channel
  float redTotal = 0.0f;                                 ///< hxWetAlbedo(red).y: including the film's reflection
};

/// Compiles wet_shading.glsl with a small compute kernel on `context` (made current here) and
/// evaluates every sample on the GPU. Errors: the context cannot be made current, the shader does
/// not compile (the driver's log), a sample with a refractive index not above 1 or a NaN.
Expected<std::vector<WetShadingResult>> evaluateWetShading(const EglContext& context,
                                                           const std::vector<WetShadingSample>& samples);

}  // namespace hydrotex::gpu
