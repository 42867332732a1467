// SPDX-License-Identifier: Zlib
#pragma once
/// @file MeshDragPatches.hpp
/// Drag patches straight from a mesh's triangles, for bodies on the exact path (no bake needed):
/// the same DragPatch records as mergeTexelsIntoDragPatches (TexelDrag.hpp) makes from texels, with
/// the same two bounds (normals within a cosine of the patch's first element, centroids within a
/// radius of it), but exact areas and area vectors and no tile boundaries splitting flat faces: a
/// 1 x 0.5 x 1 m box at a radius of 0.2 m gets tens of patches where its 256^2 bake gives 337.

#include <limits>
#include <vector>

#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// The drag patches of `mesh` (body frame, m; outward triangles). Each triangle is split into
/// 4^k similar triangles (edge midpoints) until each piece reaches at most `maxPatchRadius` (m)
/// from its centroid; pieces then join the first patch whose first piece's unit normal lies
/// within `normalCosine` (0..1) of theirs and whose first centroid lies within `maxPatchRadius` of
/// theirs (pieces in the mesh's triangle order), as mergeTexelsIntoDragPatches merges texels.
/// A patch's area vector and area are its pieces' sums (exact), its position their area-weighted
/// centroid, its radius the farthest reach of a piece from there (so at most 2 maxPatchRadius).
/// Lids over openings (Mesh::openingTriangles) feel no drag and make no patch; degenerate
/// triangles are skipped. An infinite radius splits nothing and merges by normal alone.
std::vector<DragPatch> meshDragPatches(const Mesh& mesh, double normalCosine = 0.9,
                                       double maxPatchRadius = std::numeric_limits<double>::infinity());

}  // namespace hydrotex
