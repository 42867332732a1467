// SPDX-License-Identifier: Zlib
#pragma once
/// @file PreparedPolyhedron.hpp
/// A closed mesh prepared once for the exact path's calls every step (issue 19: a simple body
/// costs no more than in a game engine's buoyancy): the checks that polyhedralHydrostatics makes
/// per call (closed, finite, indices in range) are made once, and each triangle's pose-independent
/// constants (area vector, area, centroid, second moments: 104 bytes) are kept, so that under a
/// flat surface a step costs per vertex one depth and per triangle a classification, plus 13
/// multiply-adds when it is wholly wet; only the triangles the water line cuts are clipped.
/// Results are bit for bit those of polyhedralHydrostaticsUnchecked on the same mesh.

#include <cstddef>
#include <memory>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

namespace detail {
struct TriangleConstants;  // core/src/hydrostatics/PolyhedralFlatSums.hpp
}

/// A closed mesh and its per-triangle constants (read-only once made; share it between bodies of
/// one mesh and between threads).
class PreparedPolyhedron {
 public:
  /// Prepares `mesh` (body frame, m). Errors: those of polyhedralHydrostatics' checks (an empty or
  /// open mesh, an index out of range, a vertex that is not finite).
  static Expected<PreparedPolyhedron> prepare(std::shared_ptr<const Mesh> mesh);
  /// The mesh it was made from.
  const Mesh& mesh() const { return *mesh_; }
  /// Heap held by the constants (bytes; the mesh is shared, not counted).
  std::size_t memoryBytes() const;

 private:
  friend Expected<HydrostaticsResult> polyhedralHydrostatics(const PreparedPolyhedron& body, const LiquidSurface& surface,
                                                             const HydrostaticsQuery& query);
  std::shared_ptr<const Mesh> mesh_;
  std::shared_ptr<const detail::TriangleConstants[]> constants_;  // one per triangle, in the mesh's order
};

/// Exact hydrostatics of a prepared mesh (as polyhedralHydrostatics, PolyhedralHydrostatics.hpp,
/// for every surface): under a flat surface from its constants (allocation-free once the thread's
/// scratch of one depth per vertex has grown); under waves, height grids and media the unprepared
/// path on its mesh. Errors: an invalid query (validateHydrostaticsQuery), a non-finite surface
/// height (waves, grids).
Expected<HydrostaticsResult> polyhedralHydrostatics(const PreparedPolyhedron& body, const LiquidSurface& surface,
                                                    const HydrostaticsQuery& query);

}  // namespace hydrotex
