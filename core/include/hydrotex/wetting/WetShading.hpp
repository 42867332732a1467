// SPDX-License-Identifier: Zlib
#pragma once
/// @file WetShading.hpp
/// Wet appearance of a rough absorbent surface under a liquid film (paper section 4.3), after
/// Lekner and Dorf 1988 (Applied Optics 27, 1278): light that leaves the rough surface is partly
/// reflected back by the film's upper side (probability p), so more of it is absorbed: the
/// surface darkens, darker channels more, so saturation rises. This is the C++ reference; the same
/// model in GLSL is gpu/shaders/wet_shading.glsl.

#include <Eigen/Core>

namespace hydrotex {

/// R_bar(n): reflectance of the liquid's surface for isotropic light from inside, relative index
/// n > 1 (Lekner and Dorf 1988, closed form). Water (n = 1.33): 0.065931.
double averageInternalReflectance(double n);

/// p = 1 - (1 - R_bar(n)) / n^2: probability that light leaving the rough surface into the film
/// is sent back to it. Water: 0.471949.
double internalReflectionProbability(double n);

/// R1 = ((n - 1) / (n + 1))^2: the film's own (normal incidence) reflection. Water: 0.020059.
double filmReflectance(double n);

/// Wet albedo of a surface of dry albedo (1 - a).
struct WetAlbedo {
  double total = 0.0;    ///< including the film's own reflection R1
  double diffuse = 0.0;  ///< the light that reached the rough surface and came back out
};

/// Wet albedo for a dry albedo in [0, 1], film index n (> 1) and film transmittance per crossing
/// (1 for a clear liquid; e^(-alpha h) for a coloured one, alpha its absorption coefficient and h
/// the film thickness): diffuse = (1 - R1)(1 - a)(1 - p) T^2 / (1 - p (1 - a) T^2), total =
/// diffuse + R1. Water over dry albedo 0.5: total 0.35870, diffuse 0.33864.
WetAlbedo wetAlbedo(double dryAlbedo, double n, double filmTransmittance = 1.0);

/// wetAlbedo(...).diffuse per RGB channel; dry (0.6, 0.4, 0.2) under water: (0.433, 0.255, 0.114).
Eigen::Vector3d wetDiffuseRgb(const Eigen::Vector3d& dryRgb, double n,
                              const Eigen::Vector3d& filmTransmittance = Eigen::Vector3d::Ones());

/// Diffuse colour of a partly wet texel: the dry colour blended towards wetDiffuseRgb by the
/// texel's saturation (0 dry .. 1 wet, clamped), as the fraction of its area under a film.
Eigen::Vector3d wetSurfaceRgb(const Eigen::Vector3d& dryRgb, double saturation, double n,
                              const Eigen::Vector3d& filmTransmittance = Eigen::Vector3d::Ones());

}  // namespace hydrotex
