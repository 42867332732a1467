// SPDX-License-Identifier: Zlib
#pragma once
/// @file PreparedPolyhedron.hpp
/// A closed mesh prepared once for the exact path's calls every step (issue 19: a simple body
/// costs no more than in a game engine's buoyancy): the checks that polyhedralHydrostatics makes
/// per call (closed, finite, indices in range) are made once, and each triangle's pose-independent
/// constants (area vector, area, centroid, second moments: 104 bytes) are kept, and a bounding-
/// volume hierarchy is built over the triangles with their constants summed per node, so that under
/// a flat surface a step costs per vertex one depth and per node visited a classification: a node
/// wholly under the water adds its sums (O(1)), one wholly above is skipped, and only the nodes the
/// water line crosses are opened, down to leaves of at most 8 triangles, which go triangle by
/// triangle, where the cut triangles are clipped. Results agree
/// with polyhedralHydrostaticsUnchecked on the same mesh to rounding (the same terms summed in
/// another order); under height grids and media they are its bits. Under surfaces with
/// smoothness bounds (Gerstner waves) the nodes are classified against local quadratic models
/// of the surface, as the texture path's tiles are, instead of taking the surface linear between
/// the mesh's vertices: see polyhedralHydrostatics below.

#include <cstddef>
#include <memory>
#include <optional>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

class PreparedPolyhedron;
struct ExactWaveWork;

namespace detail {
struct PreparedTriangles;  // core/src/hydrostatics/PolyhedralFlatSums.hpp
class SurfaceJetGrid;      // core/src/hydrostatics/SurfaceJetGrid.hpp
/// polyhedralHydrostatics (below) that, under waves, leaves the grid of surface jets its models
/// were interpolated from in `keep`: private to core, for the same body's drag after it
/// (RigidBodiesStep.cpp), which reads heights there instead of sampling a grid of its own.
Expected<HydrostaticsResult> polyhedralHydrostaticsKeepingJets(const PreparedPolyhedron& body,
                                                               const LiquidSurface& surface,
                                                               const HydrostaticsQuery& query,
                                                               std::optional<SurfaceJetGrid>& keep);
}  // namespace detail

/// What one exact query on a prepared mesh did under a surface with smoothness bounds (Gerstner
/// waves), counted: the work HydrostaticsMethod::Auto prices (modeledExactMicroseconds,
/// Advisor.hpp), the same on every machine. Under a flat surface only `nodes` (the flat-water
/// hierarchy's); all zero under surfaces the prepared path does not model (height grids, media).
struct ExactWaveWork {
  std::size_t nodes = 0;             ///< hierarchy nodes visited
  std::size_t models = 0;            ///< local surface models interpolated
  std::size_t pieces = 0;            ///< triangles and pieces of triangles classified one by one under a model
  std::size_t clippedTriangles = 0;  ///< triangles clipped against a model or the surface (after their split)
  std::size_t surfaceHeights = 0;    ///< heights asked of the surface itself (no model within the tolerance)
  std::size_t jets = 0;              ///< surface jets sampled for the models' interpolation grid
  std::size_t sampledPieces = 0;     ///< pieces of wholly wet triangles integrated from six interpolated heights each
};

/// A closed mesh, its per-triangle constants and their hierarchy (read-only once made; share it
/// between bodies of one mesh and between threads).
class PreparedPolyhedron {
 public:
  /// Prepares `mesh` (body frame, m). Errors: those of polyhedralHydrostatics' checks (an empty or
  /// open mesh, an index out of range, a vertex that is not finite).
  static Expected<PreparedPolyhedron> prepare(std::shared_ptr<const Mesh> mesh);
  /// The mesh it was made from.
  const Mesh& mesh() const { return *mesh_; }
  /// Nodes of the hierarchy the flat-surface sums walk (leaves of at most 8 triangles, halved at
  /// medians: 2 L - 1 nodes for L leaves).
  std::size_t nodeCount() const;
  /// Heap held by the constants (once), the nodes and the triangles in their order, for each of
  /// its two hierarchies where they differ (bytes; the mesh is shared, not counted).
  std::size_t memoryBytes() const;

 private:
  friend Expected<HydrostaticsResult> polyhedralHydrostatics(const PreparedPolyhedron& body, const LiquidSurface& surface,
                                                             const HydrostaticsQuery& query, ExactWaveWork* work);
  friend Expected<HydrostaticsResult> detail::polyhedralHydrostaticsKeepingJets(const PreparedPolyhedron& body,
                                                                                const LiquidSurface& surface,
                                                                                const HydrostaticsQuery& query,
                                                                                std::optional<detail::SurfaceJetGrid>& keep);
  std::shared_ptr<const Mesh> mesh_;
  // Every triangle once, in leaves' order, in two hierarchies: the one waves walk, halved across
  // the longest side, and the one flat water walks, halved across the height first
  // (PreparedPolyhedron.cpp, kFlatVerticalWeight), which holds the triangles' constants for
  // both; the same object where the two coincide.
  std::shared_ptr<const detail::PreparedTriangles> triangles_, flatTriangles_;
};

/// Exact hydrostatics of a prepared mesh (as polyhedralHydrostatics, PolyhedralHydrostatics.hpp,
/// for every surface): under a flat surface from its constants over a hierarchy halved across the height
/// first, the depths taken only at the corners of the leaves the water plane crosses; under a surface with smoothness bounds (Gerstner
/// waves) its nodes against local surface models within kExactSurfaceModelTolerance, wholly wet
/// ones adding their constants and the model's wave part, the triangles the water line crosses
/// clipped against the model after a split that keeps its linearization within
/// kExactWaveClipError (a 1 m box face sees waves shorter than itself; the plain path's depths,
/// linear between the mesh's vertices, do not: test_polyhedral_hydrostatics_waves); under height
/// grids and media the unprepared path on its mesh. Allocation-free. Errors: an invalid query
/// (validateHydrostaticsQuery), a non-finite surface height (waves, grids). `work`, when given,
/// receives what the query did under waves (ExactWaveWork).
Expected<HydrostaticsResult> polyhedralHydrostatics(const PreparedPolyhedron& body, const LiquidSurface& surface,
                                                    const HydrostaticsQuery& query, ExactWaveWork* work = nullptr);

}  // namespace hydrotex
