// SPDX-License-Identifier: Zlib
#pragma once
/// @file WettedNode.hpp
/// Private to core: a node of a quadrature rule on a primitive's wetted surface (a sphere's,
/// SphereHydrostaticsWaves.hpp; a box's, BoxHydrostaticsWaves.hpp), on which the body's drag sums
/// its law instead of on mesh patches (RigidBodyDragWithJets.hpp: rigidBodyDragOnNodes).

#include <Eigen/Core>

namespace hydrotex::detail {

/// A node of the rule on the wetted surface (world frame): where it lies, its outward area vector
/// (its weight times the unit normal, m^2), its weight (m^2) and the surface's height above it (m).
struct WettedNode {
  Eigen::Vector3d position;    ///< m, world
  Eigen::Vector3d areaVector;  ///< m^2, world, outward
  double area = 0.0;           ///< m^2
  double surfaceHeight = 0.0;  ///< m, world
};

}  // namespace hydrotex::detail
