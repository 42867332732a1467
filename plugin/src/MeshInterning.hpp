// SPDX-License-Identifier: Zlib
#pragma once
// The meshes the controller makes itself (from a body's collision shape, or loaded from a file),
// interned by content: bodies whose shapes are the same (one btBoxShape shared by many bodies, or
// many btBoxShapes of the same extents, or one OBJ file named by many bodies) get one mesh, so
// that they share one model (bake, texels, prepared triangles, drag patches: SharedBodyModel) as
// bodies handed one Mesh pointer do. Private to the plugin.

#include <cstddef>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::bullet {

/// Whether two meshes are the same to the bit: positions, triangles, texture coordinates,
/// openings, source name and file unit scale (a -0.0 and a 0.0 count as equal; a NaN never does).
bool sameMesh(const Mesh& a, const Mesh& b);

/// A hash of everything sameMesh() compares (raw bytes: equal meshes hash alike, except for the
/// sign of a zero, which only costs a missed share).
std::size_t meshContentHash(const Mesh& mesh);

/// Meshes by content, held weakly: a mesh is forgotten once no body holds it.
class InternedMeshes {
 public:
  /// The interned mesh equal to `mesh` (sameMesh), or `mesh` itself, now interned, when none is.
  /// O(size of the mesh) for the hash and, on a hit, the comparison.
  std::shared_ptr<const Mesh> intern(std::shared_ptr<const Mesh> mesh);

  /// The interned mesh made from a primitive shape of this key (primitiveShapeKey), or null.
  std::shared_ptr<const Mesh> findShape(const std::string& key) const;
  /// Remembers that a primitive shape of this key gave `mesh` (interned), for findShape().
  void rememberShape(const std::string& key, const std::shared_ptr<const Mesh>& mesh);

 private:
  std::unordered_map<std::size_t, std::vector<std::weak_ptr<const Mesh>>> byHash_;
  std::unordered_map<std::string, std::weak_ptr<const Mesh>> byShape_;
};

}  // namespace hydrotex::bullet
