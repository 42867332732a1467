// SPDX-License-Identifier: Zlib
#pragma once
/// @file TexelAdjacency.hpp
/// The texel graph that liquid diffuses on: which covered texels exchange liquid and how easily.
/// Built from the mesh, not from UV neighbours alone: neighbours inside a chart share a texel edge
/// that a UV-continuous piece of surface crosses, and texels on the two sides of a UV seam (or a
/// chart border of a generated atlas) are paired through the shared 3D edge (González and Patow
/// 2009, "Continuity Mapping for Multi-Chart Textures"). Built once per bake.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// Pairs of covered texels (indices into SurfaceBake::texelIndex) with their geometric
/// conductance l_ij / d_ij: l_ij the 3D length of the interface they share (m), d_ij the 3D
/// distance between their centroids (m). Fick's law on the graph is then
/// A_i dphi_i/dt = sum_j D g_ij (phi_j - phi_i), with antisymmetric pair fluxes.
struct TexelAdjacency {
  std::vector<std::uint32_t> first;      ///< per pair: one texel (covered index)
  std::vector<std::uint32_t> second;     ///< per pair: the other texel (covered index, != first)
  std::vector<double> conductance;       ///< per pair: l_ij / d_ij (dimensionless, > 0)
  std::vector<double> interfaceLength;   ///< per pair: l_ij, 3D length of the shared interface (m)
  std::vector<std::uint8_t> acrossSeam;  ///< per pair: 1 when paired through a UV seam or chart border
  std::vector<double> area;              ///< per covered texel: exact surface area of its pieces (m^2)
  std::vector<Eigen::Vector3d> centroid; ///< per covered texel: area-weighted centroid of its pieces (m, body frame)
  std::vector<double> conductanceSum;    ///< per covered texel: sum of g_ij over its pairs (dimensionless)
  double seamLengthInOneTexel = 0.0;     ///< seam stretches (m) whose two sides fall in the same texel: nothing to exchange
  double seamLengthUncovered = 0.0;      ///< seam stretches (m) with a side in no covered texel (0 for a sound bake)

  /// Number of pairs.
  std::size_t pairCount() const { return first.size(); }
  /// Number of pairs across seams or chart borders.
  std::size_t seamPairCount() const;
  /// Largest explicit (forward Euler) time step (s) that keeps every texel's liquid non-negative
  /// for diffusivity D (m^2/s): min_i A_i / (D sum_j g_ij) over texels with pairs (docs/references.md).
  /// +infinity when there are no pairs or D = 0.
  double stableTimeStep(double diffusivity) const;
};

/// Builds the graph for `bake` of `mesh` with `layout` (the layout the bake was made from).
/// Texels whose pieces have zero 3D area (degenerate triangles at a pole) get no pairs.
/// Errors: a bake that does not match the mesh (piece naming a missing triangle, texel index out
/// of range), a layout that does not cover the mesh's triangles.
Expected<TexelAdjacency> buildTexelAdjacency(const SurfaceBake& bake, const Mesh& mesh, const UvLayout& layout);

}  // namespace hydrotex
