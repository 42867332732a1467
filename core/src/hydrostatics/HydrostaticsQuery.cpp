// SPDX-License-Identifier: Zlib
/// @file HydrostaticsQuery.cpp
/// Up-front checks shared by both hydrostatics paths, so that neither path sees NaN input.

#include <cmath>
#include <string>

#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"

namespace hydrotex {

Status validateHydrostaticsQuery(const LiquidSurface& surface, const HydrostaticsQuery& query) {
  if (!query.pose.isFinite()) return Error{"hydrostatics query: pose has a NaN or infinite entry"};
  // A rotation that is not orthonormal would scale volumes; 1e-6 admits float-built rotations.
  const double orthogonalityError =
      (query.pose.rotation.transpose() * query.pose.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthogonalityError > 1e-6 || query.pose.rotation.determinant() < 0.0)
    return Error{"hydrostatics query: pose rotation is not a proper rotation (error " + std::to_string(orthogonalityError) + ")"};
  if (!std::isfinite(query.gravity) || query.gravity <= 0.0)
    return Error{"hydrostatics query: gravity " + std::to_string(query.gravity) + " m/s^2 is not positive"};
  if (!query.centerOfMass.allFinite()) return Error{"hydrostatics query: centre of mass is not finite"};
  if (!std::isfinite(query.time)) return Error{"hydrostatics query: time is not finite"};
  if (query.mass && (!std::isfinite(*query.mass) || *query.mass < 0.0))
    return Error{"hydrostatics query: mass " + std::to_string(*query.mass) + " kg is negative or not finite"};
  return surface.validate();
}

}  // namespace hydrotex
