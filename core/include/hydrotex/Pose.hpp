// SPDX-License-Identifier: Zlib
#pragma once
/// @file Pose.hpp
/// A rigid placement of a body in the world: x_world = rotation * x_body + translation.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hydrotex {

/// Rigid pose. Rotation is orthonormal; translation in metres.
struct Pose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< body to world rotation
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();   ///< body origin in the world (m)

  /// Maps a body-frame point to the world.
  Eigen::Vector3d apply(const Eigen::Vector3d& bodyPoint) const { return rotation * bodyPoint + translation; }

  /// Pose from three angles in degrees, extrinsic X then Y then Z (R = Rz*Ry*Rx, docs/design.md), then
  /// the translation.
  static Pose fromDegreesXYZ(const Eigen::Vector3d& degrees, const Eigen::Vector3d& translation) {
    const double k = 3.14159265358979323846 / 180.0;
    Pose pose;
    pose.rotation = (Eigen::AngleAxisd(degrees.z() * k, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(degrees.y() * k, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(degrees.x() * k, Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    pose.translation = translation;
    return pose;
  }

  /// True when every entry is finite (NaN or infinite poses are rejected by every query).
  bool isFinite() const { return rotation.allFinite() && translation.allFinite(); }
};

}  // namespace hydrotex
