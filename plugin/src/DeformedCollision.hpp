// SPDX-License-Identifier: Zlib
#pragma once
// How a body moved by a deformation callback keeps its collision shape in step with its vertices
// (issue 5): the shape hydrotex updates every step, and the map from its points to the mesh's
// vertices. Private to the plugin; BodyDeformation.cpp fills and follows it.

#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>

#include <memory>
#include <vector>

namespace hydrotex::bullet {

/// The collision shape a deformation callback moves, and how.
struct DeformedCollision {
  /// A convex hull whose points follow mesh vertices: the user's (points matched to vertices at
  /// registration) or one hydrotex made of every vertex (DeformedCollisionShape::ConvexHull).
  btConvexHullShape* hull = nullptr;
  std::vector<int> hullVertex;                     ///< per hull point, the mesh vertex it follows
  std::unique_ptr<btConvexHullShape> ownedHull;    ///< the hull hydrotex made, when it made one
  /// A triangle mesh shape over a vertex array whose vertices are the mesh's, in order: the
  /// vertices are rewritten in place and the shape refitted.
  btGImpactMeshShape* gimpact = nullptr;
  btBvhTriangleMeshShape* bvh = nullptr;
  btStridingMeshInterface* meshInterface = nullptr;  ///< the array under gimpact or bvh
};

}  // namespace hydrotex::bullet
