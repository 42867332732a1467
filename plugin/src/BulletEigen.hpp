// SPDX-License-Identifier: Zlib
#pragma once
// Conversions between Bullet's btScalar types and the core's Eigen doubles, in one place.

#include <btBulletDynamicsCommon.h>

#include <Eigen/Core>

#include "hydrotex/Pose.hpp"

namespace hydrotex::bullet {

/// Bullet vector to Eigen (m, m/s, N: whatever the vector holds).
inline Eigen::Vector3d toEigen(const btVector3& v) { return {double(v.x()), double(v.y()), double(v.z())}; }

/// Eigen vector to Bullet (narrowed to btScalar).
inline btVector3 toBullet(const Eigen::Vector3d& v) {
  return {btScalar(v.x()), btScalar(v.y()), btScalar(v.z())};
}

/// Bullet 3x3 matrix to Eigen.
inline Eigen::Matrix3d toEigen(const btMatrix3x3& m) {
  Eigen::Matrix3d out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out(r, c) = double(m[r][c]);
  return out;
}

/// Eigen 3x3 matrix to Bullet.
inline btMatrix3x3 toBulletBasis(const Eigen::Matrix3d& m) {
  return btMatrix3x3(btScalar(m(0, 0)), btScalar(m(0, 1)), btScalar(m(0, 2)), btScalar(m(1, 0)), btScalar(m(1, 1)),
                     btScalar(m(1, 2)), btScalar(m(2, 0)), btScalar(m(2, 1)), btScalar(m(2, 2)));
}

/// Bullet transform to the core's Pose.
inline Pose toPose(const btTransform& t) {
  Pose pose;
  pose.rotation = toEigen(t.getBasis());
  pose.translation = toEigen(t.getOrigin());
  return pose;
}

}  // namespace hydrotex::bullet
