// SPDX-License-Identifier: Zlib
/// @file PreparedPolyhedron.cpp
/// Preparing a closed mesh for the exact path: the per-call checks made once, the triangles'
/// constants kept (PolyhedralFlatSums.hpp) and the triangles grouped into clusters of nearby ones
/// with their constants summed, which the flat-surface sums then read instead of visiting every
/// triangle.

#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"

#include <algorithm>
#include <numeric>
#include <string>

#include "hydrostatics/PolyhedralFlatSums.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex {

namespace {

/// Triangles per cluster at most: the cost of a cluster the water line crosses against the
/// number of clusters classified (bench_peers, Wigley hull of 4,222 triangles: see the commit).
constexpr std::size_t kClusterTriangles = 16;

/// Splits `order` [begin, end) at the median of the triangles' centroids along the longest side of
/// their bounds until at most kClusterTriangles remain, appending one cluster per piece (the
/// pieces in order, so that clusters cover the order once).
void splitIntoClusters(std::vector<std::uint32_t>& order, std::size_t begin, std::size_t end,
                       const std::vector<detail::TriangleConstants>& constants, std::vector<std::size_t>& cuts) {
  if (end - begin <= kClusterTriangles) {
    cuts.push_back(end);
    return;
  }
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(INFINITY), upper = -lower;
  for (std::size_t i = begin; i < end; ++i) {
    const Eigen::Vector3d c(constants[order[i]].centroid);
    lower = lower.cwiseMin(c);
    upper = upper.cwiseMax(c);
  }
  int axis = 0;
  (upper - lower).maxCoeff(&axis);
  const std::size_t middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + std::ptrdiff_t(begin), order.begin() + std::ptrdiff_t(middle),
                   order.begin() + std::ptrdiff_t(end), [&](std::uint32_t a, std::uint32_t b) {
                     return constants[a].centroid[axis] < constants[b].centroid[axis] ||
                            (constants[a].centroid[axis] == constants[b].centroid[axis] && a < b);
                   });
  splitIntoClusters(order, begin, middle, constants, cuts);
  splitIntoClusters(order, middle, end, constants, cuts);
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

  const std::size_t triangleCount = mesh->triangles.size();
  std::vector<detail::TriangleConstants> constants(triangleCount);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const Eigen::Vector3i& tri = mesh->triangles[t];
    constants[t] = detail::triangleConstants(mesh->positions[std::size_t(tri[0])].data(),
                                             mesh->positions[std::size_t(tri[1])].data(),
                                             mesh->positions[std::size_t(tri[2])].data());
  }
  std::vector<std::uint32_t> order(triangleCount);
  std::iota(order.begin(), order.end(), 0u);
  std::vector<std::size_t> cuts;
  splitIntoClusters(order, 0, triangleCount, constants, cuts);

  auto layout = std::make_shared<detail::PreparedTriangles>();
  layout->triangles.reserve(triangleCount);
  layout->constants.reserve(triangleCount);
  for (std::uint32_t t : order) {
    layout->triangles.push_back(mesh->triangles[t]);
    layout->constants.push_back(constants[t]);
  }
  std::size_t begin = 0;
  for (std::size_t end : cuts) {
    detail::TriangleCluster cluster{};
    cluster.begin = std::uint32_t(begin);
    cluster.end = std::uint32_t(end);
    // The sphere: the centre of the corners' bounds, the farthest corner's distance.
    Eigen::Vector3d lower = Eigen::Vector3d::Constant(INFINITY), upper = -lower;
    for (std::size_t t = begin; t < end; ++t)
      for (int c = 0; c < 3; ++c) {
        lower = lower.cwiseMin(mesh->positions[std::size_t(layout->triangles[t][c])]);
        upper = upper.cwiseMax(mesh->positions[std::size_t(layout->triangles[t][c])]);
      }
    const Eigen::Vector3d center = 0.5 * (lower + upper);
    double radius = 0.0;
    for (std::size_t t = begin; t < end; ++t) {
      for (int c = 0; c < 3; ++c)
        radius = std::max(radius, (mesh->positions[std::size_t(layout->triangles[t][c])] - center).norm());
      const detail::TriangleConstants& k = layout->constants[t];
      cluster.area += k.area;
      for (int j = 0; j < 3; ++j) {
        cluster.areaVector[j] += k.areaVector[j];
        for (int i = 0; i < 3; ++i) cluster.firstMoments[i][j] += k.centroid[i] * k.areaVector[j];
        for (int pair = 0; pair < 6; ++pair) cluster.secondMoments[pair][j] += k.secondMoments[pair] * k.areaVector[j];
      }
    }
    for (int i = 0; i < 3; ++i) cluster.center[i] = center[i];
    cluster.radius = radius;
    layout->clusters.push_back(cluster);
    begin = end;
  }
  PreparedPolyhedron body;
  body.triangles_ = std::move(layout);
  body.mesh_ = std::move(mesh);
  return body;
}

std::size_t PreparedPolyhedron::clusterCount() const { return triangles_ ? triangles_->clusters.size() : 0; }

std::size_t PreparedPolyhedron::memoryBytes() const {
  if (!triangles_) return 0;
  return triangles_->triangles.capacity() * sizeof(Eigen::Vector3i) +
         triangles_->constants.capacity() * sizeof(detail::TriangleConstants) +
         triangles_->clusters.capacity() * sizeof(detail::TriangleCluster);
}

Expected<HydrostaticsResult> polyhedralHydrostatics(const PreparedPolyhedron& body, const LiquidSurface& surface,
                                                    const HydrostaticsQuery& query) {
  const std::optional<double> flat = surface.flatHeight();
  if (!flat) return polyhedralHydrostaticsUnchecked(*body.mesh_, surface, query);
  if (Status valid = validateHydrostaticsQuery(surface, query); !valid) return valid.error();
  return detail::flatPolyhedralHydrostatics(*body.mesh_, body.triangles_.get(), *flat, surface.density(), query);
}

}  // namespace hydrotex
