// SPDX-License-Identifier: Zlib
/// @file PrimitiveMassProperties.cpp
/// A solid sphere's mass properties: V = 4/3 pi r^3, I = 2/5 m r^2 about any diameter (any
/// mechanics text, e.g. Goldstein, "Classical Mechanics", ch. 5).

#include "hydrotex/mass/PrimitiveMassProperties.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace hydrotex {

Expected<MassProperties> solidSphereMassProperties(double radius, double density, const Eigen::Vector3d& center) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    return Error{"sphere mass: radius " + std::to_string(radius) + " m is not positive and finite"};
  if (!(density > 0.0) || !std::isfinite(density))
    return Error{"sphere mass: density " + std::to_string(density) + " kg/m^3 is not positive and finite"};
  if (!center.allFinite()) return Error{"sphere mass: the centre is not finite"};
  MassProperties props;
  props.volume = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  props.mass = density * props.volume;
  props.centerOfMass = center;
  props.inertia = Eigen::Matrix3d::Identity() * (0.4 * props.mass * radius * radius);
  return props;
}

}  // namespace hydrotex
