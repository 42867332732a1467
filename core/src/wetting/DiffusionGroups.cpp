// SPDX-License-Identifier: Zlib
// Merging of stiff texels for diffusion (DiffusionGroups.hpp says why). Union-find over the texel
// graph: each pass pairs every stiff group with its most strongly coupled neighbour group, each
// group joining at most one merge per pass, so groups grow by doubling, not by chains.
#include "hydrotex/wetting/DiffusionGroups.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hydrotex {

DiffusionGroups mergeStiffTexels(const TexelAdjacency& g, double mergeBelowFraction) {
  const std::size_t n = g.area.size(), pairs = g.pairCount();
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  if (mergeBelowFraction > 0.0 && pairs > 0) {
    // Bound per texel (s * D): A_i / sum_j g_ij; the merge threshold is a fraction of the median.
    std::vector<double> bounds;
    bounds.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
      if (g.area[i] > 0.0 && g.conductanceSum[i] > 0.0) bounds.push_back(g.area[i] / g.conductanceSum[i]);
    if (!bounds.empty()) {
      std::nth_element(bounds.begin(), bounds.begin() + static_cast<std::ptrdiff_t>(bounds.size() / 2), bounds.end());
      const double threshold = mergeBelowFraction * bounds[bounds.size() / 2];
      std::vector<double> area(n), conductance(n), strongest(n);
      std::vector<std::uint32_t> partner(n);
      std::vector<std::uint8_t> merged(n);
      // 32 passes allow groups of 2^32 texels, more than any texture holds.
      for (int pass = 0; pass < 32; ++pass) {
        std::fill(area.begin(), area.end(), 0.0);
        std::fill(conductance.begin(), conductance.end(), 0.0);
        std::fill(strongest.begin(), strongest.end(), 0.0);
        std::fill(merged.begin(), merged.end(), std::uint8_t{0});
        for (std::uint32_t i = 0; i < n; ++i) area[find(i)] += g.area[i];
        for (std::size_t p = 0; p < pairs; ++p) {
          const std::uint32_t a = find(g.first[p]), b = find(g.second[p]);
          if (a == b) continue;
          conductance[a] += g.conductance[p];
          conductance[b] += g.conductance[p];
          if (g.conductance[p] > strongest[a]) strongest[a] = g.conductance[p], partner[a] = b;
          if (g.conductance[p] > strongest[b]) strongest[b] = g.conductance[p], partner[b] = a;
        }
        bool any = false;
        for (std::uint32_t r = 0; r < n; ++r) {
          if (parent[r] != r || merged[r] || !(conductance[r] > 0.0) || area[r] >= threshold * conductance[r]) continue;
          const std::uint32_t other = partner[r];
          if (merged[other]) continue;
          // The larger group holds the union, so that the holding texel stays inside the bulk.
          const bool keep = area[r] >= area[other];
          parent[keep ? other : r] = keep ? r : other;
          merged[r] = merged[other] = 1;
          any = true;
        }
        if (!any) break;
      }
    }
  }
  DiffusionGroups out;
  // Groups: the holding texel is the root; members listed after it in increasing index.
  std::vector<std::uint32_t> count(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) ++count[find(i)];
  out.nodeArea.assign(n, 0.0);
  for (std::uint32_t i = 0; i < n; ++i) out.nodeArea[find(i)] += g.area[i];
  std::vector<std::uint32_t> slot(n, 0);
  for (std::uint32_t r = 0; r < n; ++r)
    if (parent[r] == r && count[r] > 1) {
      out.start.push_back(static_cast<std::uint32_t>(out.members.size()));
      slot[r] = static_cast<std::uint32_t>(out.members.size());
      out.members.resize(out.members.size() + count[r]);
      out.members[slot[r]++] = r;
    }
  if (!out.start.empty()) out.start.push_back(static_cast<std::uint32_t>(out.members.size()));
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t r = find(i);
    if (r != i && count[r] > 1) out.members[slot[r]++] = i;
  }
  // Pairs between groups, on their holding texels; internal pairs carry nothing (equal contents).
  std::vector<double> conductanceSum(n, 0.0);
  for (std::size_t p = 0; p < pairs; ++p) {
    const std::uint32_t a = find(g.first[p]), b = find(g.second[p]);
    if (a == b) continue;
    out.pairFirst.push_back(a);
    out.pairSecond.push_back(b);
    out.pairGeometric.push_back(g.conductance[p]);
    conductanceSum[a] += g.conductance[p];
    conductanceSum[b] += g.conductance[p];
  }
  for (std::size_t i = 0; i < n; ++i)
    if (conductanceSum[i] > 0.0)
      out.stableStepTimesDiffusivity = std::min(out.stableStepTimesDiffusivity, out.nodeArea[i] / conductanceSum[i]);
  return out;
}

int diffusionSubsteps(double dt, double stableStep, int maxExplicitSubsteps) {
  if (!(dt > 0.0) || !std::isfinite(stableStep)) return 0;
  const double substeps = std::ceil(dt / stableStep);
  return substeps <= maxExplicitSubsteps ? std::max(1, static_cast<int>(substeps)) : -1;
}

}  // namespace hydrotex
