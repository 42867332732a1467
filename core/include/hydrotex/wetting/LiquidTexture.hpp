// SPDX-License-Identifier: Zlib
#pragma once
/// @file LiquidTexture.hpp
/// The liquid texture (LT, paper section 4.1): liquid held per unit area in every covered texel,
/// with the per-texel material that bounds and drives it (capacity from porosity, permeability),
/// and optionally a pigment carried by the liquid (coloured liquids, paper figure 17).

#include <vector>

#include "hydrotex/Expected.hpp"

namespace hydrotex {

/// Material of an absorbent surface layer; defaults are those of a porous fabric or sandstone skin.
struct WettingMaterial {
  double porosity = 0.3;          ///< void fraction of the layer (0..1); capacity = porosity * layerThickness
  double layerThickness = 0.005;  ///< thickness of the absorbent layer (m), also Darcy's flow length L
  double permeability = 1e-12;    ///< intrinsic permeability k (m^2); sandstone 1e-13..1e-11
  /// One-line reason when a value is out of range (negative, NaN, porosity above 1).
  Status validate() const;
};

/// Per covered texel state and material, same order as SurfaceBake::texelIndex.
struct LiquidTexture {
  std::vector<float> liquid;        ///< liquid volume per area (m) held in the texel, 0..capacity
  std::vector<float> capacity;      ///< most liquid per area the texel holds (m) = porosity * thickness
  std::vector<float> permeability;  ///< k (m^2)
  std::vector<float> pigment;       ///< pigment volume per area (m); empty when the liquid is clear
  double layerThickness = 0.005;    ///< Darcy flow length L (m)

  /// Number of texels.
  std::size_t size() const { return liquid.size(); }
  /// Saturation of texel i (0..1): liquid / capacity, 0 where the capacity is 0.
  float saturation(std::size_t i) const { return capacity[i] > 0.0f ? liquid[i] / capacity[i] : 0.0f; }
  /// Liquid held (m^3): sum of liquid * area, in double. `area` per texel (m^2).
  double heldVolume(const std::vector<double>& area) const;
  /// Pigment held (m^3), as heldVolume.
  double heldPigment(const std::vector<double>& area) const;
};

/// A dry liquid texture for `texelCount` texels of `material`. `porosityMap` and
/// `permeabilityMap`, when not empty, give per texel values in [0,1] (ImageMap resampled with
/// resampleToTexels) that scale the material's porosity and permeability. `withPigment` keeps a
/// pigment channel. Errors: a bad material, a map whose size is not `texelCount`, a map value
/// outside [0,1] or NaN.
Expected<LiquidTexture> makeLiquidTexture(std::size_t texelCount, const WettingMaterial& material,
                                          const std::vector<float>& porosityMap = {},
                                          const std::vector<float>& permeabilityMap = {}, bool withPigment = false);

}  // namespace hydrotex
