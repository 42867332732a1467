// SPDX-License-Identifier: Zlib
#pragma once
/// @file MassMoments.hpp
/// Private to core: from mass, first and second moments about a reference point to MassProperties
/// (centre of mass, inertia about it), shared by the texel path (TextureMassProperties.cpp) and
/// the triangle path (TriangleMassIntegrator.cpp). Central second moment S = second - m o o^T with
/// o = first / m the centre relative to the reference point; inertia I = trace(S) Id - S.

#include <Eigen/Core>

#include "hydrotex/MassProperties.hpp"

namespace hydrotex::detail {

/// Mass (kg), first (kg m) and second (kg m^2) moments about a reference point, and the volume.
struct MassMoments {
  double mass = 0.0;                                  ///< kg
  Eigen::Vector3d first = Eigen::Vector3d::Zero();    ///< kg m, about the reference point
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();   ///< kg m^2, about the reference point
  double volume = 0.0;                                ///< m^3
};

/// The mass properties of `moments` taken about `referencePoint` (m). A body of zero (or not
/// positive) mass gets its centre at the reference point and zero inertia.
inline MassProperties massPropertiesFromMoments(const MassMoments& moments, const Eigen::Vector3d& referencePoint) {
  MassProperties result;
  result.mass = moments.mass;
  result.volume = moments.volume;
  if (!(moments.mass > 0.0)) {
    result.centerOfMass = referencePoint;
    return result;
  }
  const Eigen::Vector3d offset = moments.first / moments.mass;  // centre relative to the reference point
  result.centerOfMass = referencePoint + offset;
  const Eigen::Matrix3d central = moments.second - moments.mass * offset * offset.transpose();
  result.inertia = central.trace() * Eigen::Matrix3d::Identity() - central;
  return result;
}

}  // namespace hydrotex::detail
