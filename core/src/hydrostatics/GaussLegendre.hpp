// SPDX-License-Identifier: Zlib
#pragma once
/// @file GaussLegendre.hpp
/// Private to core: Gauss-Legendre rules on [0, 1], for the quadratures over a primitive's wetted
/// surface (a sphere's meridians, a box's faces: SphereHydrostaticsWaves.cpp,
/// BoxHydrostaticsWaves.cpp).

namespace hydrotex::detail {

/// Most nodes a rule has.
inline constexpr int kMaxGaussNodes = 48;

/// The K-point Gauss-Legendre rule on [0, 1]: nodes (ascending) and weights (summing to 1).
struct GaussRule {
  double node[kMaxGaussNodes], weight[kMaxGaussNodes];
};

/// The rule of `count` nodes (clamped to 1..kMaxGaussNodes), made once for all.
const GaussRule& gaussRule(int count);

}  // namespace hydrotex::detail
