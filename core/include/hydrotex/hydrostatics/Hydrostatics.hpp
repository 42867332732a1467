// SPDX-License-Identifier: Zlib
#pragma once
/// @file Hydrostatics.hpp
/// What a hydrostatics query asks and what it answers; shared by the texture path
/// (TextureHydrostatics.hpp) and the exact polyhedral path (PolyhedralHydrostatics.hpp).
///
/// Stiffness convention (meshmagick's hydrostatic stiffness, translated from its z-up frame to our
/// y-up frame by x_m = x, y_m = -z, z_m = y): the generalized displacement is
/// q = (heave: translation along +y (m), roll: rotation about +x (rad), pitch: rotation about +z
/// (rad)), the rotations taken about axes through the reference point O = (x_G, h, z_G) (the centre
/// of mass projected vertically onto the water plane y = h), and the restoring generalized force is
/// -K q (N, N m). With the water-plane integrals taken about O:
///   K(0,0) = rho g A_wp
///   K(0,1) = K(1,0) = -rho g Int(z) dA          K(0,2) = K(2,0) = rho g Int(x) dA
///   K(1,1) = rho g (Int(z^2) dA + V (y_B - h)) - m g (y_G - h)
///   K(2,2) = rho g (Int(x^2) dA + V (y_B - h)) - m g (y_G - h)
///   K(1,2) = K(2,1) = -rho g Int(x z) dA
/// m is HydrostaticsQuery::mass, or rho V (floating in equilibrium) when not given.

#include <Eigen/Core>
#include <optional>

#include "hydrotex/Expected.hpp"
#include "hydrotex/Pose.hpp"

namespace hydrotex {

class LiquidSurface;

/// One hydrostatics question: where the body is and what pulls it down.
struct HydrostaticsQuery {
  Pose pose;                                                  ///< body to world
  double gravity = 9.81;                                      ///< m/s^2 along -y (> 0)
  Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();     ///< m, body frame (torque and stiffness reference)
  double time = 0.0;                                          ///< s, passed to the liquid surface
  /// kg, for the gravity term of the stiffness; empty: the body floats in equilibrium (m = rho V).
  std::optional<double> mass;
};

/// The answer, in the world frame unless stated. Everything is zero for a body out of the liquid.
struct HydrostaticsResult {
  double submergedVolume = 0.0;                                     ///< m^3
  Eigen::Vector3d centerOfBuoyancy = Eigen::Vector3d::Zero();       ///< m, centroid of the submerged volume (world)
  Eigen::Vector3d buoyancyForce = Eigen::Vector3d::Zero();          ///< N, pressure force on the wetted surface (world)
  Eigen::Vector3d torqueAboutCenterOfMass = Eigen::Vector3d::Zero();///< N m, about the world centre of mass
  Eigen::Vector3d torqueAboutOrigin = Eigen::Vector3d::Zero();      ///< N m, about the body origin (pose.translation)
  double waterplaneArea = 0.0;                                      ///< m^2, area cut by the surface inside the body
  Eigen::Vector3d waterplaneCentroid = Eigen::Vector3d::Zero();     ///< m, centroid of that area (world; y = surface height)
  double wettedArea = 0.0;                                          ///< m^2, submerged surface area
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();              ///< heave/roll/pitch, see the file comment (N/m, N, N m/rad)
  double fluidDensity = 0.0;                                        ///< kg/m^3 used (nominal density of the surface)
};

/// Checks a query and a surface before any work: finite pose with an orthonormal rotation,
/// positive finite gravity, finite centre of mass, non-negative mass, and the surface's own
/// validate(). The one-line message names the value at fault.
Status validateHydrostaticsQuery(const LiquidSurface& surface, const HydrostaticsQuery& query);

/// Hydrostatic stiffness (see the file comment) from water-plane integrals about the reference
/// point O: `waterplaneArea` (m^2), `firstMomentX` = Int(x - x_O) dA, `firstMomentZ` (m^3),
/// `secondMomentXX` = Int((x - x_O)^2) dA, `secondMomentXZ`, `secondMomentZZ` (m^4), the
/// submerged volume (m^3), heights of the centre of buoyancy and of mass above the water plane
/// (m), density (kg/m^3), gravity (m/s^2) and mass (kg).
Eigen::Matrix3d hydrostaticStiffness(double waterplaneArea, double firstMomentX, double firstMomentZ,
                                     double secondMomentXX, double secondMomentXZ, double secondMomentZZ,
                                     double submergedVolume, double buoyancyHeightAboveSurface,
                                     double massHeightAboveSurface, double density, double gravity, double mass);

}  // namespace hydrotex
