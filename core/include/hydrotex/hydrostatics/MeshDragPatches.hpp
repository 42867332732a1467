// SPDX-License-Identifier: Zlib
#pragma once
/// @file MeshDragPatches.hpp
/// Drag patches straight from a mesh's triangles, for bodies on the exact path (no bake needed):
/// the same DragPatch records as mergeTexelsIntoDragPatches (TexelDrag.hpp) makes from texels, with
/// normals within a cosine of the patch's first element and a bounded size, but exact areas and
/// area vectors: a 1 x 0.5 x 1 m box at a radius of 0.2 m gets tens of patches where its 256^2
/// bake gives 337. The controller gives them to bodies on the exact path.

#include <limits>
#include <vector>

#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// The drag patches of `mesh` (body frame, m; outward triangles). Each triangle is split into
/// 4^k similar triangles (edge midpoints) until each piece reaches at most `maxPatchRadius` (m)
/// from its centroid; pieces are then merged in the cells of a grid laid over their bounds (2^m
/// cells an axis, each at most 2 maxPatchRadius wide): a piece joins the first patch of its cell
/// whose first unit normal lies within `normalCosine` (0..1) of its own (pieces in the mesh's
/// triangle order). The cells tile the bounds exactly, so an axis-aligned box's faces, whose
/// pieces pair into small rectangles of the same powers of two, get centred, mirror-symmetric
/// patches (a layout that is lopsided makes a heaving body turn). A patch's area vector and area
/// are its pieces' sums (exact), its position their area-weighted centroid, its radius the
/// farthest reach of a piece from there. Lids over openings (Mesh::openingTriangles) feel no drag
/// and make no patch; degenerate triangles are skipped. An infinite radius splits nothing and
/// merges by normal alone.
std::vector<DragPatch> meshDragPatches(const Mesh& mesh, double normalCosine = 0.9,
                                       double maxPatchRadius = std::numeric_limits<double>::infinity());

}  // namespace hydrotex
