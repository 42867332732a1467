// SPDX-License-Identifier: Zlib
#pragma once
/// @file ShapeMesh.hpp
/// A closed triangle mesh from a body's own Bullet collision shape, so that a Bullet user's boxes,
/// capsules, hulls and compounds float with no mesh file (FloatingBodySettings with neither mesh
/// nor meshPath).
///
/// The mesh is the shape as constructed, in the shape's own frame (local scaling included), and
/// without Bullet's collision margin: a btBoxShape or btCylinderShape is the size it was given
/// (Bullet stores it shrunk by the margin, getHalfExtentsWithoutMargin, and grows it back by the
/// margin in contacts; the mesh uses getHalfExtentsWithMargin, with sharp edges); a cone, convex
/// hull, multi-sphere or triangle mesh is its points as given (Bullet's margin, 0.04 m by
/// default, rounds it outwards in contacts; the mesh does not add it).

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"

class btCollisionShape;

namespace hydrotex::bullet {

/// How finely round shapes are tessellated.
struct ShapeTessellation {
  /// Largest relative volume error of a round shape's mesh (sphere, capsule, cylinder, cone,
  /// multi-sphere), 1e-5..0.1. The meshes are inscribed, so their volume is smaller by at most
  /// this fraction: segment counts come from the closed-form volume of the inscribed polygons
  /// (a regular n-gon holds n sin(2 pi / n) / (2 pi) of its circle's area; a sphere's meridian is
  /// summed as frusta; a multi-sphere's from the hulls of its spheres' inscribed and
  /// circumscribed meshes, between which it lies). 1e-3 gives 84 segments around a cylinder or cone and a sphere of 132 x 66
  /// (17,160 triangles); 1e-4 gives 260 and 408 x 204 (165,648 triangles). Boxes, hulls and
  /// triangle meshes are exact.
  double maxRelativeVolumeError = 1.0e-3;
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// The closed mesh of `shape` (m, the shape's frame, counter-clockwise seen from outside):
/// btBoxShape, btSphereShape, btCapsuleShape (X, Y, Z), btCylinderShape (X, Y, Z), btConeShape
/// (X, Y, Z; centred on its bounding box as Bullet centres it, apex towards +axis),
/// btConvexHullShape (its hull), btMultiSphereShape (the hull of its spheres; uniform scaling
/// only), btUniformScalingShape, btScaledBvhTriangleMeshShape, btBvhTriangleMeshShape and
/// btGImpactMeshShape (their triangles, vertices at the same position merged; the mesh must be
/// closed and outward for addBody to take it), and btCompoundShape of these (child transforms
/// applied). A compound's children are merged into one mesh of separate closed parts without
/// computing their union, so children that overlap are refused, naming them: their common volume
/// would count twice, and the mesh checks read a part inside another as a cavity. Two children
/// are taken as apart when their meshes are separated along one of the compound's axes, their
/// own axes or the cross products of these (exact for two boxes; for round children it may
/// refuse two that are apart but close, never accept two that overlap). Touching is apart.
/// Primitives keep their UV atlas; merged children get a generated one.
/// Errors: an unsupported shape (one line naming its type), a degenerate hull, overlapping
/// compound children (naming them), invalid tessellation settings.
Expected<Mesh> meshFromCollisionShape(const btCollisionShape& shape, const ShapeTessellation& tessellation = {});

}  // namespace hydrotex::bullet
