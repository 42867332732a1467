// SPDX-License-Identifier: Zlib
#pragma once
/// @file Atlas.hpp
/// The UV layout used for physics: the artist's UVs when they are a valid atlas, otherwise a
/// generated private atlas (the artist's UVs stay untouched for rendering).

#include <cstddef>
#include <string>

#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"

namespace hydrotex {

/// Charts grow only over triangles whose normal is within this cosine of the chart's normal
/// (about 37 degrees). Projection shrinks a triangle's area by this cosine at most, so within a
/// generated atlas texel density (UV area per 3D area) varies by at most 1 / 0.8^2 = 1.5625.
inline constexpr double kChartNormalCosine = 0.8;

/// The layout handed to the bake.
struct PhysicsAtlas {
  UvLayout layout;         ///< one UV triangle per mesh triangle, inside [0,1]^2, no overlap
  bool generated = false;  ///< true when generated here; false when the artist's UVs are used
  std::string reason;      ///< one line: why these UVs (e.g. "no UVs in the file")
  std::size_t chartCount = 0;  ///< charts of a generated atlas (0 when the artist's UVs are used)
};

/// Chooses the physics atlas: the mesh's own UVs when `report.uvUsableAsAtlas()` (present,
/// inside [0,1]^2, bijective, no zero-area UV triangle), otherwise generateAtlas(mesh, texels).
/// `report` must come from validateMesh(mesh); `texels`: the bake's texels per side (0: unknown).
PhysicsAtlas physicsAtlas(const Mesh& mesh, const MeshReport& report, int texels = 0);

/// Generates a private atlas: charts of edge-connected triangles with similar normals (within
/// kChartNormalCosine of the chart's first triangle) projected on the chart's plane, grown only
/// while a new triangle does not overlap the chart's triangles already placed; each chart scaled
/// so its UV area per 3D area is the same for every chart; packed without overlap into [0,1]^2
/// with a gutter of at least one packing cell. With `texels` > 0 (the bake's texels per side) the
/// gutter is more than one texel, so that no texel holds pieces of two charts (faces that may lie
/// far apart, which one texel position cannot stand for at the waterline), unless that shrinks
/// the charts' scale by more than a fifth (many small charts), when the one-cell gutter is kept.
/// O(n log n); about a second per million triangles. `chartCount`, when given, receives the
/// number of charts. Returns an empty layout for a mesh with indices out of range or non-finite
/// positions (loadMesh rejects those).
UvLayout generateAtlas(const Mesh& mesh, std::size_t* chartCount = nullptr, int texels = 0);

}  // namespace hydrotex
