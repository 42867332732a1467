// SPDX-License-Identifier: Zlib
#pragma once
// What a primitive collision shape's mesh (meshFromCollisionShape) is made from, as a key, so
// that the controller tessellates each kind of primitive once (InternedMeshes::findShape): a
// 1e-3 sphere is 17,160 triangles, about 0.6 ms to make and weld. Private to the plugin;
// defined in ShapeMesh.cpp beside the tessellation it keys.

#include <btBulletCollisionCommon.h>

#include <optional>
#include <string>

#include "hydrotex/bullet/ShapeMesh.hpp"

namespace hydrotex::bullet {

/// The bytes of every value meshFromCollisionShape(shape, tessellation) reads, with the shape's
/// type, for a box, sphere, capsule, cylinder or cone (their meshes are functions of these alone);
/// nothing for any other shape (hulls, triangle meshes, compounds: their meshes are made anew).
std::optional<std::string> primitiveShapeKey(const btCollisionShape& shape, const ShapeTessellation& tessellation);

}  // namespace hydrotex::bullet
