// SPDX-License-Identifier: Zlib
#pragma once
/// @file SoftBodyMotion.hpp
/// The motion of a btSoftBody as a whole (its nodes' mass-weighted sums), for reports such as
/// `hydrotex simulate`'s CSV rows, which give rigid bodies a position, orientation and velocities.

#include <BulletSoftBody/btSoftBody.h>

namespace hydrotex::bullet {

/// A soft body's motion as a whole (world frame). Pinned nodes (zero inverse mass) are left out.
struct SoftBodyMotion {
  double mass = 0.0;                     ///< kg: sum of the node masses
  btVector3 centerOfMass{0, 0, 0};       ///< m: mass-weighted mean node position
  btVector3 linearVelocity{0, 0, 0};     ///< m/s: mass-weighted mean node velocity (momentum / mass)
  /// rad/s: I^-1 L about the centre of mass (L the nodes' angular momentum, I their inertia
  /// tensor); zero when I is singular (all nodes on a line).
  btVector3 angularVelocity{0, 0, 0};
  /// Rotation of the best-fit rigid frame (Bullet's pose matching, m_pose.m_rot) when the soft
  /// body tracks one (setPose(..., frame = true)); identity otherwise.
  btQuaternion orientation = btQuaternion::getIdentity();
};

/// The motion of `body` now; all zero (identity orientation) for a body without movable nodes.
SoftBodyMotion softBodyMotion(const btSoftBody& body);

}  // namespace hydrotex::bullet
