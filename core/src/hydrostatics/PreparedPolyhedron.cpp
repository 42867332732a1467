// SPDX-License-Identifier: Zlib
/// @file PreparedPolyhedron.cpp
/// Preparing a closed mesh for the exact path: the per-call checks made once, the triangles'
/// constants kept (PolyhedralFlatSums.hpp) and a bounding-volume hierarchy over them with their
/// constants summed per node, which the flat-surface sums walk instead of visiting every
/// triangle.

#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "hydrostatics/PolyhedralFlatSums.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex {

namespace {

/// Adds what the triangle with constants `k` brings to a node's sums.
void addToNode(detail::NodeSums& node, const detail::TriangleConstants& k) {
  node.area += k.area;
  for (int j = 0; j < 3; ++j) {
    node.areaVector[j] += k.areaVector[j];
    for (int i = 0; i < 3; ++i) node.firstMoments[i][j] += k.centroid[i] * k.areaVector[j];
    for (int pair = 0; pair < 6; ++pair) node.secondMoments[pair][j] += k.secondMoments[pair] * k.areaVector[j];
  }
}

/// Adds a child's sums to its parent's.
void addToNode(detail::NodeSums& node, const detail::NodeSums& child) {
  node.area += child.area;
  for (int j = 0; j < 3; ++j) {
    node.areaVector[j] += child.areaVector[j];
    for (int i = 0; i < 3; ++i) node.firstMoments[i][j] += child.firstMoments[i][j];
    for (int pair = 0; pair < 6; ++pair) node.secondMoments[pair][j] += child.secondMoments[pair][j];
  }
}

/// What building the hierarchy reads: the mesh, its triangles' constants by original index, and the
/// weight of the body's y axis against x and z when choosing the side to halve (kFlatVerticalWeight).
struct HierarchyInput {
  const Mesh& mesh;
  const std::vector<detail::TriangleConstants>& constants;
  double verticalWeight = 1.0;
};

/// The y axis's weight in the hierarchy that flat water walks. There a node costs O(1) unless the
/// water plane crosses it, which it does in proportion to the node's height for a body floating
/// near upright: halving tall nodes across their height first leaves low, wide leaves that lie
/// wholly under or over the plane. Under waves the same leaves are too wide for one surface model
/// each, so waves walk the plain hierarchy (halved across the longest side). Probe, 100 poses
/// tilted within 6 and 3 degrees at levels within 5 % of the height around mid height (2-core
/// reference machine, minimum of 6 passes), flat water, weights 1 / 2 / 4 / 8 / 16 / 64:
/// Wigley hull 16.2 / 12.3 / 14.0 / 11.8 / 11.3 / 11.4 us, the 17,160-face sphere 13.4 / 11.5 /
/// 11.2 / 11.3 / 10.8 / 11.3, the 162-vertex hull 1.30 / 1.09 / 1.04 / 1.04 / 1.01 / 0.98; the
/// same weights under waves: ship 596 / 810 / 867 / 1,040 us at 1 / 2 / 4 / 8.
constexpr double kFlatVerticalWeight = 8.0;

/// Appends the subtree over the triangles order[begin, end) to `nodes` (depth first) and returns
/// its bounds: a leaf for at most detail::kMaxLeafTriangles, otherwise the triangles halved at the median of
/// their centroids along the longest side of the centroids' bounds (nth_element reorders `order`
/// in place, so that each node's triangles end up contiguous) and a node over both halves.
void buildSubtree(const HierarchyInput& input, std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end,
                  std::vector<detail::TriangleNode>& nodes, std::vector<detail::NodeSums>& sums, Eigen::Vector3d& lower,
                  Eigen::Vector3d& upper) {
  const std::size_t index = nodes.size();
  nodes.emplace_back();
  sums.emplace_back();  // value-initialized: the sums start at zero
  lower = Eigen::Vector3d::Constant(INFINITY);
  upper = -lower;
  if (end - begin <= detail::kMaxLeafTriangles) {
    for (std::size_t t = begin; t < end; ++t) {
      const Eigen::Vector3i& tri = input.mesh.triangles[order[t]];
      for (int c = 0; c < 3; ++c) {
        lower = lower.cwiseMin(input.mesh.positions[std::size_t(tri[c])]);
        upper = upper.cwiseMax(input.mesh.positions[std::size_t(tri[c])]);
      }
      addToNode(sums[index], input.constants[order[t]]);
    }
  } else {
    Eigen::Vector3d centroidLower = Eigen::Vector3d::Constant(INFINITY), centroidUpper = -centroidLower;
    for (std::size_t t = begin; t < end; ++t) {
      const Eigen::Vector3d c(input.constants[order[t]].centroid);
      centroidLower = centroidLower.cwiseMin(c);
      centroidUpper = centroidUpper.cwiseMax(c);
    }
    int axis = 0;
    (centroidUpper - centroidLower).cwiseProduct(Eigen::Vector3d(1.0, input.verticalWeight, 1.0)).maxCoeff(&axis);
    const std::size_t middle = begin + (end - begin) / 2;
    const auto& constants = input.constants;
    std::nth_element(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(middle),
                     order.begin() + std::ptrdiff_t(end), [&](std::uint32_t a, std::uint32_t b) {
                       return constants[a].centroid[axis] < constants[b].centroid[axis] ||
                              (constants[a].centroid[axis] == constants[b].centroid[axis] && a < b);
                     });
    Eigen::Vector3d childLower, childUpper;
    const std::size_t first = nodes.size();
    buildSubtree(input, order, begin, middle, nodes, sums, childLower, childUpper);
    lower = childLower;
    upper = childUpper;
    const std::size_t second = nodes.size();
    buildSubtree(input, order, middle, end, nodes, sums, childLower, childUpper);
    lower = lower.cwiseMin(childLower);
    upper = upper.cwiseMax(childUpper);
    addToNode(sums[index], sums[first]);
    addToNode(sums[index], sums[second]);
  }
  detail::TriangleNode& node = nodes[index];
  for (int i = 0; i < 3; ++i) {
    node.center[i] = 0.5 * (lower[i] + upper[i]);
    // Widened by an ulp of the largest coordinate (the centre's and the half's rounding), so that
    // every corner lies within it.
    node.halfExtent[i] = 0.5 * (upper[i] - lower[i]) +
                         std::numeric_limits<double>::epsilon() * std::max(std::abs(lower[i]), std::abs(upper[i]));
  }
  node.begin = std::uint32_t(begin);
  node.end = std::uint32_t(end);
  node.next = std::uint32_t(nodes.size());
}

/// The order of the triangles of `mesh` (their constants `constants`, by original index) in a
/// hierarchy halved with the y axis weighted by `verticalWeight` (its leaves' order), and the
/// hierarchy into `layout`'s nodes and sums.
std::vector<std::uint32_t> buildHierarchy(const Mesh& mesh, const std::vector<detail::TriangleConstants>& constants,
                                          double verticalWeight, detail::PreparedTriangles& layout) {
  const std::size_t triangleCount = mesh.triangles.size();
  std::vector<std::uint32_t> order(triangleCount);
  std::iota(order.begin(), order.end(), 0u);
  Eigen::Vector3d lower, upper;
  buildSubtree(HierarchyInput{mesh, constants, verticalWeight}, order, 0, triangleCount, layout.nodes, layout.sums,
               lower, upper);
  layout.nodes.shrink_to_fit();
  layout.sums.shrink_to_fit();
  layout.triangles.reserve(triangleCount);
  for (std::uint32_t t : order) layout.triangles.push_back(mesh.triangles[t]);
  return order;
}

/// `layout`'s leaves' distinct vertices and its triangles' places among them
/// (PreparedTriangles::leafVertices), in the leaves' order.
void indexLeafVertices(detail::PreparedTriangles& layout) {
  const std::size_t nodeCount = layout.nodes.size();
  layout.vertexBegin.assign(nodeCount + 1, 0);
  layout.leafCorners.resize(layout.triangles.size());
  layout.leafVertices.reserve(layout.triangles.size() * 3);
  for (std::size_t i = 0; i < nodeCount; ++i) {
    const std::size_t first = layout.leafVertices.size();
    layout.vertexBegin[i] = std::uint32_t(first);
    const detail::TriangleNode& node = layout.nodes[i];
    if (node.next != i + 1) continue;  // an inner node
    for (std::uint32_t k = node.begin; k < node.end; ++k)
      for (int c = 0; c < 3; ++c) {
        const auto vertex = std::uint32_t(layout.triangles[k][c]);
        std::size_t place = first;
        while (place < layout.leafVertices.size() && layout.leafVertices[place] != vertex) ++place;
        if (place == layout.leafVertices.size()) layout.leafVertices.push_back(vertex);
        layout.leafCorners[k][std::size_t(c)] = std::uint8_t(place - first);
      }
  }
  layout.vertexBegin[nodeCount] = std::uint32_t(layout.leafVertices.size());
  layout.leafVertices.shrink_to_fit();
}

}  // namespace

Expected<PreparedPolyhedron> PreparedPolyhedron::prepare(std::shared_ptr<const Mesh> mesh) {
  if (!mesh) return Error{"exact hydrostatics: no mesh to prepare"};
  if (mesh->triangles.empty()) return Error{"exact hydrostatics: the mesh has no triangles"};
  const std::string name = mesh->sourceName.empty() ? std::string("mesh") : mesh->sourceName;
  const auto count = static_cast<unsigned>(mesh->positions.size());
  for (const Eigen::Vector3i& t : mesh->triangles)
    for (int c = 0; c < 3; ++c)
      if (static_cast<unsigned>(t[c]) >= count) return Error{name + ": a triangle index is out of range"};
  for (std::size_t v = 0; v < mesh->positions.size(); ++v)
    if (!mesh->positions[v].allFinite()) return Error{name + ": vertex " + std::to_string(v) + " is not finite"};
  if (Status closed = checkClosedMesh(*mesh); !closed) return closed.error();
  if (mesh->triangles.size() >= std::numeric_limits<std::uint32_t>::max())
    return Error{name + ": more triangles than the exact path indexes (2^32 - 1)"};

  const std::size_t triangleCount = mesh->triangles.size();
  std::vector<detail::TriangleConstants> constants(triangleCount);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const Eigen::Vector3i& tri = mesh->triangles[t];
    constants[t] = detail::triangleConstants(mesh->positions[std::size_t(tri[0])].data(),
                                             mesh->positions[std::size_t(tri[1])].data(),
                                             mesh->positions[std::size_t(tri[2])].data());
  }
  // The flat-water layout keeps the constants in its order (its walk reads them leaf by leaf);
  // the waves layout reads them through an index, unless the two orders are one (a box: a leaf
  // or two), where one layout serves both.
  auto flat = std::make_shared<detail::PreparedTriangles>();
  const std::vector<std::uint32_t> flatOrder = buildHierarchy(*mesh, constants, kFlatVerticalWeight, *flat);
  flat->constants.reserve(triangleCount);
  for (std::uint32_t t : flatOrder) flat->constants.push_back(constants[t]);
  auto waves = std::make_shared<detail::PreparedTriangles>();
  const std::vector<std::uint32_t> wavesOrder = buildHierarchy(*mesh, constants, 1.0, *waves);
  PreparedPolyhedron body;
  body.flatTriangles_ = flat;
  // Only the walk under waves reads the leaves' vertices: its layout's.
  if (wavesOrder == flatOrder) {
    indexLeafVertices(*flat);
    body.triangles_ = flat;
  } else {
    indexLeafVertices(*waves);
    std::vector<std::uint32_t> flatPlace(triangleCount);
    for (std::size_t k = 0; k < triangleCount; ++k) flatPlace[flatOrder[k]] = std::uint32_t(k);
    waves->constantIndex.reserve(triangleCount);
    for (std::uint32_t t : wavesOrder) waves->constantIndex.push_back(flatPlace[t]);
    waves->constantsOf = flat;
    body.triangles_ = std::move(waves);
  }
  body.mesh_ = std::move(mesh);
  return body;
}

std::size_t PreparedPolyhedron::nodeCount() const { return flatTriangles_ ? flatTriangles_->nodes.size() : 0; }

std::size_t PreparedPolyhedron::memoryBytes() const {
  const auto bytes = [](const detail::PreparedTriangles& t) {
    return t.triangles.capacity() * sizeof(Eigen::Vector3i) + t.constants.capacity() * sizeof(detail::TriangleConstants) +
           t.constantIndex.capacity() * sizeof(std::uint32_t) + t.nodes.capacity() * sizeof(detail::TriangleNode) +
           t.sums.capacity() * sizeof(detail::NodeSums) + t.leafVertices.capacity() * sizeof(std::uint32_t) +
           t.vertexBegin.capacity() * sizeof(std::uint32_t) + t.leafCorners.capacity() * sizeof(std::array<std::uint8_t, 3>);
  };
  if (!triangles_) return 0;
  return bytes(*triangles_) + (flatTriangles_ != triangles_ ? bytes(*flatTriangles_) : 0);
}

namespace {
// polyhedralHydrostatics, keeping the jets of a query under waves in `keep` when given.
Expected<HydrostaticsResult> preparedHydrostatics(const Mesh& mesh, const detail::PreparedTriangles& triangles,
                                                  const detail::PreparedTriangles* flatTriangles,
                                                  const LiquidSurface& surface, const HydrostaticsQuery& query,
                                                  ExactWaveWork* work, std::optional<detail::SurfaceJetGrid>* keep) {
  if (work) *work = ExactWaveWork{};
  const std::optional<double> flat = surface.flatHeight();
  if (Status valid = validateHydrostaticsQuery(surface, query); !valid) return valid.error();
  if (!flat && surface.hasFreeSurface())
    if (std::optional<Expected<HydrostaticsResult>> waves =
            detail::wavePolyhedralHydrostatics(mesh, triangles, surface, query, work, keep))
      return std::move(*waves);
  if (!flat) return polyhedralHydrostaticsUnchecked(mesh, surface, query);
  return detail::flatPolyhedralHydrostatics(mesh, flatTriangles, *flat, surface.density(), query,
                                            work ? &work->nodes : nullptr);
}
}  // namespace

Expected<HydrostaticsResult> detail::polyhedralHydrostaticsKeepingJets(const PreparedPolyhedron& body,
                                                                       const LiquidSurface& surface,
                                                                       const HydrostaticsQuery& query,
                                                                       std::optional<SurfaceJetGrid>& keep) {
  return preparedHydrostatics(*body.mesh_, *body.triangles_, body.flatTriangles_.get(), surface, query, nullptr, &keep);
}

Expected<HydrostaticsResult> polyhedralHydrostatics(const PreparedPolyhedron& body, const LiquidSurface& surface,
                                                    const HydrostaticsQuery& query, ExactWaveWork* work) {
  return preparedHydrostatics(*body.mesh_, *body.triangles_, body.flatTriangles_.get(), surface, query, work, nullptr);
}

}  // namespace hydrotex
