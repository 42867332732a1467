// SPDX-License-Identifier: Zlib
#pragma once
/// @file DiffusionGroups.hpp
/// The control volumes the liquid diffuses between: the texel graph with its stiff texels merged.
/// The explicit stability bound is set by the smallest A_i / sum_j g_ij; slivers at chart borders
/// and the squeezed texels near a UV sphere's poles make it tiny, so they are merged with their
/// most strongly coupled neighbour into one control volume (the finite-volume "cell agglomeration"
/// of cut-cell methods) until every group meets a fraction of the median texel's bound. A group's
/// liquid is pooled into its holding texel, diffused there with the group's area, and copied back
/// to every member; volume is conserved. Built once per graph; the CPU (Wetting) and the GPU
/// (gpu::GlWettingDiffusion) take the same groups, so that they give the same results.

#include <cstdint>
#include <limits>
#include <vector>

#include "hydrotex/bake/TexelAdjacency.hpp"

namespace hydrotex {

/// Merged diffusion groups and the pairs between them.
struct DiffusionGroups {
  std::vector<std::uint32_t> start;    ///< CSR ranges into `members`, one per group of two or more texels (+1); empty when none
  std::vector<std::uint32_t> members;  ///< texels of each group; the first of a range holds the group
  std::vector<double> nodeArea;        ///< per texel: its group's area on the holder, its own area when alone, 0 on other members (m^2)
  std::vector<std::uint32_t> pairFirst;   ///< per pair between holding texels (pairs inside a group are dropped): one texel
  std::vector<std::uint32_t> pairSecond;  ///< the other texel
  std::vector<double> pairGeometric;      ///< g_ij of the pair (dimensionless), from the texel graph
  /// min over holding texels of nodeArea / sum_j g_ij (m^2): the explicit stability bound times D;
  /// +infinity without pairs.
  double stableStepTimesDiffusivity = std::numeric_limits<double>::infinity();

  /// Number of groups of two or more texels.
  std::size_t groupCount() const { return start.empty() ? 0 : start.size() - 1; }
  /// Largest stable explicit step (s) for diffusivity D (m^2/s); +infinity for D = 0 or no pairs.
  double stableTimeStep(double diffusivity) const {
    return diffusivity > 0.0 ? stableStepTimesDiffusivity / diffusivity : std::numeric_limits<double>::infinity();
  }
};

/// Merges the texels of `graph` whose bound A_i / sum_j g_ij is below `mergeBelowFraction` times
/// the median texel's (0: no merging; each texel is then its own node). Groups grow by pairing
/// each stiff group with its most strongly coupled neighbour, the larger one holding the union.
/// `graph` must be consistent, as buildTexelAdjacency makes it (Wetting::create and
/// gpu::GlWettingDiffusion::create check it before they call this).
DiffusionGroups mergeStiffTexels(const TexelAdjacency& graph, double mergeBelowFraction);

/// How a diffusion step of `dt` (s) runs under the stable explicit step `stableStep` (s,
/// DiffusionGroups::stableTimeStep): 0 when nothing diffuses (dt <= 0, or an infinite bound: no
/// pairs or D = 0), ceil(dt / stableStep) explicit sub-steps while that is at most
/// `maxExplicitSubsteps`, -1 beyond (one backward Euler step). The CPU and the GPU both ask this.
int diffusionSubsteps(double dt, double stableStep, int maxExplicitSubsteps);

}  // namespace hydrotex
