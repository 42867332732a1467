// SPDX-License-Identifier: Zlib
/// @file MeshDragPatches.cpp
/// Drag patches from a mesh's triangles: large triangles split by edge midpoints (4^k similar
/// pieces, each reaching half as far per level), pieces merged in the cells of a grid that tiles
/// their bounds (the first patch of the cell with a close normal): O(pieces).

#include "hydrotex/hydrostatics/MeshDragPatches.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace hydrotex {

namespace {

/// At most 4^kMaxLevels pieces a triangle, whatever the radius asked.
constexpr int kMaxLevels = 6;

struct Piece {
  Eigen::Vector3d centroid, areaVector;
  double area, reach;
};

struct Accumulator {
  Eigen::Vector3d normal, areaVector = Eigen::Vector3d::Zero(), weightedPosition = Eigen::Vector3d::Zero();
  double area = 0.0;
  std::vector<std::uint32_t> members;  // pieces
};

/// The farthest corner of triangle (a, b, c) from its centroid (m).
double reachOf(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& centroid) {
  return std::sqrt(std::max({(a - centroid).squaredNorm(), (b - centroid).squaredNorm(), (c - centroid).squaredNorm()}));
}

std::int64_t cellKey(std::int64_t i, std::int64_t j, std::int64_t k) {
  // 21 bits per axis (cells of one radius: +-10^6 radii), enough for any body.
  constexpr std::int64_t kMask = (std::int64_t(1) << 21) - 1;
  return ((i & kMask) << 42) | ((j & kMask) << 21) | (k & kMask);
}

}  // namespace

std::vector<DragPatch> meshDragPatches(const Mesh& mesh, double normalCosine, double maxPatchRadius) {
  std::vector<DragPatch> patches;
  if (!(maxPatchRadius > 0.0)) return patches;
  const bool bounded = std::isfinite(maxPatchRadius);
  std::vector<bool> lid(mesh.triangles.size(), false);
  for (std::uint32_t t : mesh.openingTriangles)
    if (t < lid.size()) lid[t] = true;

  // Pieces: every triangle split until each piece reaches at most the radius; the bounds of the
  // triangles they come from (the merge's grid tiles them).
  std::vector<Piece> pieces;
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(INFINITY), upper = Eigen::Vector3d::Constant(-INFINITY);
  const auto count = static_cast<unsigned>(mesh.positions.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    if (lid[t] || unsigned(tri[0]) >= count || unsigned(tri[1]) >= count || unsigned(tri[2]) >= count) continue;
    const Eigen::Vector3d a = mesh.positions[std::size_t(tri[0])], b = mesh.positions[std::size_t(tri[1])],
                          c = mesh.positions[std::size_t(tri[2])];
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
    lower = lower.cwiseMin(a).cwiseMin(b).cwiseMin(c);
    upper = upper.cwiseMax(a).cwiseMax(b).cwiseMax(c);
    const double reach = reachOf(a, b, c, (a + b + c) / 3.0);
    int levels = 0;
    while (bounded && levels < kMaxLevels && std::ldexp(reach, -levels) > maxPatchRadius) ++levels;
    const int n = 1 << levels;
    const Eigen::Vector3d u = (b - a) / n, v = (c - a) / n;
    auto corner = [&](int i, int j) { return Eigen::Vector3d(a + double(i) * u + double(j) * v); };
    auto add = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
      const Eigen::Vector3d areaVector = 0.5 * (q - p).cross(r - p);
      const double area = areaVector.norm();
      if (!(area > 0.0)) return;  // degenerate
      const Eigen::Vector3d centroid = (p + q + r) / 3.0;
      pieces.push_back({centroid, areaVector, area, reachOf(p, q, r, centroid)});
    };
    // The barycentric grid of n^2 pieces: upright (i, j), (i+1, j), (i, j+1) and inverted
    // (i+1, j), (i+1, j+1), (i, j+1), both counter-clockwise as (a, b, c).
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        add(corner(i, j), corner(i + 1, j), corner(i, j + 1));
        if (i + j + 1 < n) add(corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1));
      }
  }

  // Merge on a grid laid over the triangles' bounds, 2^m cells an axis with each cell at most twice
  // the radius wide: a piece joins the first open patch of its cell whose normal lies within the
  // cosine of its own. The cells tile the bounds exactly, so a box's faces (whose pieces pair
  // into small squares of the same powers of two) get centred, mirror-symmetric patches, and a
  // heaving box feels no torque from its patch layout (a first-come merge left it lopsided).
  Eigen::Vector3d cellSize = Eigen::Vector3d::Constant(INFINITY);
  for (int axis = 0; axis < 3 && bounded && !pieces.empty(); ++axis) {
    const double extent = upper[axis] - lower[axis];
    int cells = 1;
    while (cells < (1 << 20) && extent / cells > 2.0 * maxPatchRadius) cells *= 2;
    cellSize[axis] = extent / cells;
  }
  std::vector<Accumulator> open;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells;  // patches by cell, in creation order
  auto cellOf = [&](const Eigen::Vector3d& p, int axis) {
    return bounded && cellSize[axis] > 0.0 ? std::int64_t(std::floor((p[axis] - lower[axis]) / cellSize[axis]))
                                           : std::int64_t(0);
  };
  for (std::uint32_t index = 0; index < pieces.size(); ++index) {
    const Piece& piece = pieces[index];
    const Eigen::Vector3d normal = piece.areaVector / piece.area;
    std::vector<std::uint32_t>& cell =
        cells[cellKey(cellOf(piece.centroid, 0), cellOf(piece.centroid, 1), cellOf(piece.centroid, 2))];
    std::uint32_t chosen = std::uint32_t(-1);
    for (std::uint32_t patch : cell)
      if (open[patch].normal.dot(normal) >= normalCosine) {
        chosen = patch;
        break;
      }
    if (chosen == std::uint32_t(-1)) {
      chosen = std::uint32_t(open.size());
      Accumulator acc;
      acc.normal = normal;
      open.push_back(std::move(acc));
      cell.push_back(chosen);
    }
    Accumulator& acc = open[chosen];
    acc.areaVector += piece.areaVector;
    acc.weightedPosition += piece.area * piece.centroid;
    acc.area += piece.area;
    acc.members.push_back(index);
  }

  patches.reserve(open.size());
  for (const Accumulator& acc : open) {
    const Eigen::Vector3d centroid = acc.weightedPosition / acc.area;
    double radius = 0.0;
    for (std::uint32_t member : acc.members)
      radius = std::max(radius, (pieces[member].centroid - centroid).norm() + pieces[member].reach);
    DragPatch patch;
    patch.position = centroid.cast<float>();
    patch.areaVector = acc.areaVector.cast<float>();
    patch.area = static_cast<float>(acc.area);
    patch.radius = static_cast<float>(radius);
    patches.push_back(patch);
  }
  return patches;
}

}  // namespace hydrotex
