// SPDX-License-Identifier: Zlib
/// @file MeshParts.cpp
/// Parts by union-find over manifold edges (edges sorted, O(n log n)); nesting by winding numbers.

#include "hydrotex/mesh/MeshParts.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace hydrotex {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool usable(const Eigen::Vector3i& t, std::size_t count) {
  for (int c = 0; c < 3; ++c)
    if (t[c] < 0 || static_cast<std::size_t>(t[c]) >= count) return false;
  return t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
}

struct HalfEdge {
  std::uint64_t key;  ///< (smaller << 32) | larger
  std::size_t triangle;
  bool forward;  ///< walked from the smaller index to the larger
};

std::size_t findRoot(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

double windingNumber(const Mesh& mesh, const std::vector<std::size_t>& triangles, const Eigen::Vector3d& point) {
  double total = 0.0;
  for (std::size_t t : triangles) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.positions[tri[0]] - point;
    const Eigen::Vector3d b = mesh.positions[tri[1]] - point;
    const Eigen::Vector3d c = mesh.positions[tri[2]] - point;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * kPi);
}

std::vector<MeshPart> findMeshParts(const Mesh& mesh) {
  const std::size_t n = mesh.triangles.size();
  std::vector<HalfEdge> edges;
  edges.reserve(3 * n);
  std::vector<bool> valid(n, false);
  for (std::size_t t = 0; t < n; ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    if (!usable(tri, mesh.positions.size())) continue;
    valid[t] = true;
    for (int e = 0; e < 3; ++e) {
      const auto from = static_cast<std::uint32_t>(tri[e]), to = static_cast<std::uint32_t>(tri[(e + 1) % 3]);
      edges.push_back({(static_cast<std::uint64_t>(std::min(from, to)) << 32) | std::max(from, to), t, from < to});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) { return x.key < y.key; });
  std::vector<std::size_t> parent(n);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  std::vector<bool> open(n, false);  // the triangle has a boundary, non-manifold or inconsistent edge
  for (std::size_t first = 0; first < edges.size();) {
    std::size_t last = first + 1;
    while (last < edges.size() && edges[last].key == edges[first].key) ++last;
    if (last - first == 2) {
      const std::size_t a = findRoot(parent, edges[first].triangle), b = findRoot(parent, edges[first + 1].triangle);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
      if (edges[first].forward == edges[first + 1].forward) open[edges[first].triangle] = open[edges[first + 1].triangle] = true;
    } else {
      for (std::size_t i = first; i < last; ++i) open[edges[i].triangle] = true;
    }
    first = last;
  }

  std::vector<MeshPart> parts;
  std::vector<std::size_t> partOfRoot(n, n);
  for (std::size_t t = 0; t < n; ++t) {
    if (!valid[t]) continue;
    const std::size_t root = findRoot(parent, t);
    if (partOfRoot[root] == n) {
      partOfRoot[root] = parts.size();
      parts.emplace_back();
      parts.back().closed = true;
    }
    MeshPart& part = parts[partOfRoot[root]];
    part.triangles.push_back(t);
    if (open[t]) part.closed = false;
  }

  // Volume, bounds and a probe point (the centroid of the largest triangle) per part.
  struct Extent {
    Eigen::Vector3d lo, hi, probe;
  };
  std::vector<Extent> extents(parts.size());
  for (std::size_t p = 0; p < parts.size(); ++p) {
    MeshPart& part = parts[p];
    Extent& extent = extents[p];
    extent.lo = extent.hi = mesh.positions[mesh.triangles[part.triangles.front()][0]];
    for (std::size_t t : part.triangles)
      for (int c = 0; c < 3; ++c) {
        extent.lo = extent.lo.cwiseMin(mesh.positions[mesh.triangles[t][c]]);
        extent.hi = extent.hi.cwiseMax(mesh.positions[mesh.triangles[t][c]]);
      }
    // About the part's own centre: small tetrahedra, little cancellation (as validateMesh).
    const Eigen::Vector3d reference = 0.5 * (extent.lo + extent.hi);
    double largest = -1.0;
    for (std::size_t t : part.triangles) {
      const Eigen::Vector3d a = mesh.positions[mesh.triangles[t][0]] - reference;
      const Eigen::Vector3d b = mesh.positions[mesh.triangles[t][1]] - reference;
      const Eigen::Vector3d c = mesh.positions[mesh.triangles[t][2]] - reference;
      part.signedVolume += a.dot(b.cross(c)) / 6.0;
      const double area = (b - a).cross(c - a).norm();
      if (area > largest) {
        largest = area;
        extent.probe = reference + (a + b + c) / 3.0;
      }
    }
  }
  // Nesting: a part is inside a closed part when its probe point has a winding number of about
  // +-1 there (0 outside; 0.5 separates the two robustly against rounding and small gaps).
  for (std::size_t p = 0; p < parts.size(); ++p) {
    for (std::size_t q = 0; q < parts.size(); ++q) {
      if (q == p || !parts[q].closed) continue;
      const Extent& inner = extents[p];
      const Extent& outer = extents[q];
      if ((inner.probe.array() < outer.lo.array()).any() || (inner.probe.array() > outer.hi.array()).any()) continue;
      if (std::abs(windingNumber(mesh, parts[q].triangles, inner.probe)) > 0.5) ++parts[p].enclosingParts;
    }
  }
  return parts;
}

}  // namespace hydrotex
