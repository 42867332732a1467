// SPDX-License-Identifier: Zlib
#pragma once
/// @file Camera.hpp
/// A perspective camera looking from an eye point at a target, y up (world frame, metres).

#include <Eigen/Core>

namespace hydrotex::render {

/// Where the camera is and what it sees.
struct Camera {
  Eigen::Vector3d eye{8.0, 4.0, 10.0};    ///< m, world
  Eigen::Vector3d target{0.0, 0.0, 0.0};  ///< m, world point at the centre of the picture
  double verticalFovDegrees = 40.0;       ///< degrees
  double nearPlane = 0.1;                 ///< m
  double farPlane = 500.0;                ///< m

  /// World-to-view matrix (right-handed, looking down -z).
  Eigen::Matrix4f view() const;
  /// View-to-clip matrix for a picture of `aspect` = width / height (OpenGL clip space).
  Eigen::Matrix4f projection(double aspect) const;
};

/// Orthographic view-projection of a directional light shining along `direction` (world, towards
/// the scene) that covers a sphere of `radius` (m) around `centre`: the shadow map's matrix.
Eigen::Matrix4f lightViewProjection(const Eigen::Vector3d& direction, const Eigen::Vector3d& centre, double radius);

}  // namespace hydrotex::render
