// SPDX-License-Identifier: Zlib
/// @file HydrostaticStiffness.cpp
/// Heave/roll/pitch hydrostatic stiffness. Source: meshmagick, meshmagick/hydrostatics.py
/// (compute_hydrostatics: k33 = rho g S_wp, k34 = rho g Int(y), k35 = -rho g Int(x),
/// k44 = rho g (Int(y^2) + V z_B) - m g z_G, k55 = rho g (Int(x^2) + V z_B) - m g z_G,
/// k45 = -rho g Int(x y)), with heights measured from the water plane; mapped from its z-up
/// frame to ours by x_m = x, y_m = -z, z_m = y (pitch about y_m is minus pitch about z).

#include "hydrotex/hydrostatics/Hydrostatics.hpp"

namespace hydrotex {

Eigen::Matrix3d hydrostaticStiffness(double waterplaneArea, double firstMomentX, double firstMomentZ,
                                     double secondMomentXX, double secondMomentXZ, double secondMomentZZ,
                                     double submergedVolume, double buoyancyHeightAboveSurface,
                                     double massHeightAboveSurface, double density, double gravity, double mass) {
  const double rhoG = density * gravity;
  const double restoringHeights = rhoG * submergedVolume * buoyancyHeightAboveSurface - mass * gravity * massHeightAboveSurface;
  Eigen::Matrix3d k;
  k(0, 0) = rhoG * waterplaneArea;
  k(0, 1) = k(1, 0) = -rhoG * firstMomentZ;
  k(0, 2) = k(2, 0) = rhoG * firstMomentX;
  k(1, 1) = rhoG * secondMomentZZ + restoringHeights;
  k(2, 2) = rhoG * secondMomentXX + restoringHeights;
  k(1, 2) = k(2, 1) = -rhoG * secondMomentXZ;
  return k;
}

}  // namespace hydrotex
