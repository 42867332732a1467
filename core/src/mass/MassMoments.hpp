// SPDX-License-Identifier: Zlib
#pragma once
/// @file MassMoments.hpp
/// Private to core: from mass, first and second moments about a reference point to MassProperties
/// (centre of mass, inertia about it), shared by the texel path (TextureMassProperties.cpp) and
/// the triangle path (TriangleMassIntegrator.cpp). Central second moment S = second - m o o^T with
/// o = first / m the centre relative to the reference point; inertia I = trace(S) Id - S.

#include <Eigen/Core>

#include "hydrotex/mass/MassProperties.hpp"

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

/// The corner sums of a triangle with corners d0, d1, d2 (m, about a reference point) from which
/// its area and cone moments follow (Eberly, "Polyhedral Mass Properties"; the triangle path and
/// the lids of open hulls share them): s = d0 + d1 + d2 and q = s s^T + sum of d_i d_i^T (xx yy
/// zz xy xz yz). A triangle of area a has first area moment a s / 3 and second a q / 12; its cone
/// from the reference point, of height-times-area h (volume h / 3), h s / 12 and h q / 60.
inline void triangleCornerSums(const double d0[3], const double d1[3], const double d2[3], double s[3], double q[6]) {
  for (int c = 0; c < 3; ++c) s[c] = d0[c] + d1[c] + d2[c];
  q[0] = s[0] * s[0] + d0[0] * d0[0] + d1[0] * d1[0] + d2[0] * d2[0];
  q[1] = s[1] * s[1] + d0[1] * d0[1] + d1[1] * d1[1] + d2[1] * d2[1];
  q[2] = s[2] * s[2] + d0[2] * d0[2] + d1[2] * d1[2] + d2[2] * d2[2];
  q[3] = s[0] * s[1] + d0[0] * d0[1] + d1[0] * d1[1] + d2[0] * d2[1];
  q[4] = s[0] * s[2] + d0[0] * d0[2] + d1[0] * d1[2] + d2[0] * d2[2];
  q[5] = s[1] * s[2] + d0[1] * d0[2] + d1[1] * d1[2] + d2[1] * d2[2];
}

}  // namespace hydrotex::detail
