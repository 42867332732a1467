// SPDX-License-Identifier: Zlib
/// @file PrimitiveHydrostatics.cpp
/// A sphere under a flat surface in closed form. The submerged part is a spherical cap of height d:
/// volume pi d^2 (3 r - d) / 3, centroid 3 (2 r - d)^2 / (4 (3 r - d)) below the centre, zone area
/// 2 pi r d (Archimedes' hat-box theorem), cut by the plane in a disc of radius a = sqrt(d (2 r - d))
/// whose second moment about a diameter is pi a^4 / 4 (docs/references.md "Hydrostatics"; any
/// calculus text, e.g. Biran, "Ship Hydrostatics and Stability", ch. 2). The stiffness is
/// hydrostaticStiffness (Hydrostatics.hpp) of the disc's moments about O = (x_G, h, z_G), by the
/// parallel-axis theorem; force and torques as the exact path forms them under a flat surface
/// (HydrostaticSums.cpp, ForceModel::Archimedes).

#include "hydrotex/hydrostatics/PrimitiveHydrostatics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "hydrostatics/SphereHydrostaticsWaves.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"

namespace hydrotex {

SphericalCap sphericalCap(double radius, double planeAboveCenter) {
  SphericalCap cap;
  const double r = radius;
  const double d = std::clamp(r + planeAboveCenter, 0.0, 2.0 * r);
  cap.height = d;
  if (!(d > 0.0)) return cap;
  const double pi = std::numbers::pi;
  cap.volume = pi * d * d * (3.0 * r - d) / 3.0;
  const double rest = 2.0 * r - d;
  cap.centroidDepthBelowCenter = 3.0 * rest * rest / (4.0 * (3.0 * r - d));
  cap.waterplaneRadius = std::sqrt(std::max(d * rest, 0.0));
  cap.wettedArea = 2.0 * pi * r * d;
  return cap;
}

Expected<HydrostaticsResult> sphereHydrostatics(double radius, const Eigen::Vector3d& center,
                                                const LiquidSurface& surface, const HydrostaticsQuery& query) {
  if (Status valid = validateHydrostaticsQuery(surface, query); !valid) return valid.error();
  if (!(radius > 0.0) || !std::isfinite(radius))
    return Error{"sphere hydrostatics: radius " + std::to_string(radius) + " m is not positive and finite"};
  if (!center.allFinite()) return Error{"sphere hydrostatics: the sphere's centre is not finite"};
  const std::optional<double> flat = surface.flatHeight();
  if (!flat) {
    // The jets' grid per thread, reused (GCC zero-fills an empty local optional of its 60 KiB).
    static thread_local std::optional<detail::SurfaceJetGrid> grid;
    std::optional<Expected<HydrostaticsResult>> waves = detail::waveSphereHydrostatics(radius, center, surface, query, &grid);
    grid.reset();  // it refers to the surface
    if (waves) return std::move(*waves);
    return Error{"sphere hydrostatics: neither the closed form (the surface is not flat) nor the rule under waves "
                 "applies here (no smoothness bounds, the water line near a pole, or the sphere large against the waves): use "
                 "the exact or the texture path"};
  }

  HydrostaticsResult result;
  result.fluidDensity = surface.density();
  const double h = *flat;
  const Eigen::Vector3d c = query.pose.apply(center);
  const SphericalCap cap = sphericalCap(radius, h - c.y());
  if (!(cap.volume > 0.0)) return result;  // out of the liquid: zero, as the exact path answers

  const double rho = surface.density(), g = query.gravity, rhoG = rho * g;
  const double volume = cap.volume;
  result.submergedVolume = volume;
  result.centerOfBuoyancy = Eigen::Vector3d(c.x(), c.y() - cap.centroidDepthBelowCenter, c.z());
  result.buoyancyForce = Eigen::Vector3d(0.0, rhoG * volume, 0.0);
  const Eigen::Vector3d centerOfMass = query.pose.apply(query.centerOfMass);
  result.torqueAboutCenterOfMass = (result.centerOfBuoyancy - centerOfMass).cross(result.buoyancyForce);
  result.torqueAboutOrigin = (result.centerOfBuoyancy - query.pose.translation).cross(result.buoyancyForce);
  result.wettedArea = cap.wettedArea;

  const double a2 = cap.waterplaneRadius * cap.waterplaneRadius;
  const double area = std::numbers::pi * a2;
  result.waterplaneArea = area;
  result.waterplaneCentroid = area > 0.0 ? Eigen::Vector3d(c.x(), h, c.z()) : Eigen::Vector3d(centerOfMass.x(), h, centerOfMass.z());
  // The disc's moments about O = (x_G, h, z_G): its own pi a^4 / 4 about each diameter (none
  // across them) moved by the parallel-axis theorem to O.
  const double dx = c.x() - centerOfMass.x(), dz = c.z() - centerOfMass.z();
  const double ownSecondMoment = 0.25 * area * a2;
  const double mass = query.mass ? *query.mass : rho * volume;
  result.stiffness = hydrostaticStiffness(area, area * dx, area * dz, ownSecondMoment + area * dx * dx, area * dx * dz,
                                          ownSecondMoment + area * dz * dz, volume, result.centerOfBuoyancy.y() - h,
                                          centerOfMass.y() - h, rho, g, mass);
  return result;
}

}  // namespace hydrotex
