// SPDX-License-Identifier: Zlib
#pragma once
/// @file PolyhedralHydrostatics.hpp
/// The exact reference path (docs/design.md "Exact reference"): the closed triangle mesh is clipped
/// against the flat liquid surface in double precision and every quantity is integrated exactly
/// over the wetted part of the surface (divergence theorem with fields that vanish on the water
/// plane). Any closed mesh, convex or not. O(triangles).

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// Exact hydrostatics of `mesh` (body frame, m) posed by `query` in `surface`.
/// Surfaces: flat (exact), or a uniform medium (every triangle submerged; exact volume and centre
/// of buoyancy, force from the pressure at each triangle's centroid times its area vector, exact
/// when the density is constant). Errors: a surface that is neither (waves, height grids: use the
/// texture path), an invalid query (see validateHydrostaticsQuery), an empty or open mesh (an edge
/// not shared by exactly two triangles in opposite directions), or an index out of range.
/// The closedness check costs O(triangles log triangles); call polyhedralHydrostaticsUnchecked()
/// per step once the mesh is known to be closed.
Expected<HydrostaticsResult> polyhedralHydrostatics(const Mesh& mesh, const LiquidSurface& surface,
                                                    const HydrostaticsQuery& query);

/// As polyhedralHydrostatics() without the closedness check (the caller vouches for it; indices
/// are still range-checked). Allocation-free; under 20 ns per triangle is the goal
/// (bench_hydrostatics).
Expected<HydrostaticsResult> polyhedralHydrostaticsUnchecked(const Mesh& mesh, const LiquidSurface& surface,
                                                             const HydrostaticsQuery& query);

/// Status of the closedness check alone, MeshValidation's (validateMesh + requireClosed on the
/// topology): every edge used by exactly two triangles, once in each direction, and a positive
/// enclosed volume (not inside out). The message names the mesh and counts the offending edges.
Status checkClosedMesh(const Mesh& mesh);

}  // namespace hydrotex
