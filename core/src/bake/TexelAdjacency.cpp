// SPDX-License-Identifier: Zlib
// The texel graph for surface diffusion. Two kinds of pairs:
//  - inside a chart: texels that share a texel edge; the interface length is the 3D length of the
//    part of that edge covered on both sides by UV-continuous triangles (the same triangle, or
//    triangles sharing a UV vertex), found by clipping the edge against the triangles;
//  - across a UV seam or chart border: a mesh edge whose two triangles have different UV edges is
//    walked on both sides at once (González and Patow 2009, continuity mapping); every stretch of
//    it that lies in one texel on each side pairs those two texels with the stretch's 3D length.
// Conductance g_ij = l_ij / d_ij is the two-point flux approximation of Fick's law (finite
// volumes), exact for orthogonal texel grids (docs/references.md "Fick").
// Work is in texel coordinates: X = u * width, Y = (1 - v) * height, texel (row, column) is the
// square [column, column + 1] x [row, row + 1] (Mesh.hpp's row convention).
#include "hydrotex/bake/TexelAdjacency.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <utility>

namespace hydrotex {

std::size_t TexelAdjacency::seamPairCount() const {
  return static_cast<std::size_t>(std::count(acrossSeam.begin(), acrossSeam.end(), std::uint8_t{1}));
}

double TexelAdjacency::stableTimeStep(double diffusivity) const {
  double best = std::numeric_limits<double>::infinity();
  if (!(diffusivity > 0.0)) return best;
  for (std::size_t i = 0; i < area.size(); ++i)
    if (conductanceSum[i] > 0.0) best = std::min(best, area[i] / (diffusivity * conductanceSum[i]));
  return best;
}

namespace {

constexpr std::uint32_t kUncovered = std::numeric_limits<std::uint32_t>::max();

// Per triangle: UV corners in texel coordinates, the affine map texel coordinates -> 3D (its
// linear part), and whether it carries area in 3D.
struct TriangleMap {
  Eigen::Vector2d q[3];
  Eigen::Matrix<double, 3, 2> jacobian = Eigen::Matrix<double, 3, 2>::Zero();
  double orientation = 1.0;  // sign of the UV area
  bool hasArea = false;
};

// Interval [t0, t1] of a segment inside one triangle.
struct Span {
  double t0, t1;
  std::uint32_t triangle;
};

// Clips the segment a + t (b - a), t in [0, 1], against a UV triangle; false when nothing is left.
bool clipSegment(const TriangleMap& tri, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d& p = tri.q[k];
    const Eigen::Vector2d e = tri.q[(k + 1) % 3] - p;
    auto inside = [&](const Eigen::Vector2d& x) { return tri.orientation * (e.x() * (x.y() - p.y()) - e.y() * (x.x() - p.x())); };
    const double fa = inside(a), fb = inside(b);
    if (fa < 0.0 && fb < 0.0) return false;
    if (fa < 0.0) t0 = std::max(t0, fa / (fa - fb));
    if (fb < 0.0) t1 = std::min(t1, fa / (fa - fb));
  }
  return t1 > t0;
}

bool shareUvVertex(const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) return true;
  return false;
}

}  // namespace

Expected<TexelAdjacency> buildTexelAdjacency(const SurfaceBake& bake, const Mesh& mesh, const UvLayout& layout) {
  const std::size_t triangleCount = mesh.triangles.size();
  if (!layout.coversTriangles(triangleCount))
    return Error{mesh.sourceName + ": UV layout has " + std::to_string(layout.uvTriangles.size()) +
                 " triangles for " + std::to_string(triangleCount) + " mesh triangles"};
  const std::size_t pixelCount = static_cast<std::size_t>(bake.width) * static_cast<std::size_t>(bake.height);
  if (bake.pieceStart.size() != bake.coveredCount() + 1)
    return Error{mesh.sourceName + ": bake piece ranges do not match its covered texels"};
  const auto positionCount = static_cast<int>(mesh.positions.size());
  const auto uvCount = static_cast<int>(layout.uvs.size());
  for (std::size_t t = 0; t < triangleCount; ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[t][k] < 0 || mesh.triangles[t][k] >= positionCount || layout.uvTriangles[t][k] < 0 ||
          layout.uvTriangles[t][k] >= uvCount)
        return Error{mesh.sourceName + ": triangle " + std::to_string(t) + " has an index out of range"};

  // Triangle maps (texel coordinates -> body frame).
  std::vector<TriangleMap> maps(triangleCount);
  double largestArea = 0.0;
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const auto& f = mesh.triangles[t];
    largestArea = std::max(largestArea, 0.5 * (mesh.positions[f[1]] - mesh.positions[f[0]])
                                                  .cross(mesh.positions[f[2]] - mesh.positions[f[0]])
                                                  .norm());
  }
  for (std::size_t t = 0; t < triangleCount; ++t) {
    TriangleMap& m = maps[t];
    const auto& f = mesh.triangles[t];
    const auto& g = layout.uvTriangles[t];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d& uv = layout.uvs[g[k]];
      m.q[k] = Eigen::Vector2d(uv.x() * bake.width, (1.0 - uv.y()) * bake.height);
    }
    Eigen::Matrix2d uvEdges;
    uvEdges << m.q[1] - m.q[0], m.q[2] - m.q[0];
    const double det = uvEdges.determinant();
    const Eigen::Vector3d e1 = mesh.positions[f[1]] - mesh.positions[f[0]];
    const Eigen::Vector3d e2 = mesh.positions[f[2]] - mesh.positions[f[0]];
    // A triangle with no 3D area (a collapsed pole quad) carries no liquid and no interface.
    m.hasArea = 0.5 * e1.cross(e2).norm() > 1e-12 * largestArea && det != 0.0;
    if (!m.hasArea) continue;
    m.orientation = det > 0.0 ? 1.0 : -1.0;
    Eigen::Matrix<double, 3, 2> edges3;
    edges3 << e1, e2;
    m.jacobian = edges3 * uvEdges.inverse();
  }

  TexelAdjacency graph;
  const std::size_t covered = bake.coveredCount();
  graph.area.assign(covered, 0.0);
  graph.centroid.assign(covered, Eigen::Vector3d::Zero());
  std::vector<std::uint32_t> coveredAt(pixelCount, kUncovered);
  for (std::size_t i = 0; i < covered; ++i) {
    if (bake.texelIndex[i] >= pixelCount)
      return Error{mesh.sourceName + ": bake texel " + std::to_string(i) + " lies outside the texture"};
    coveredAt[bake.texelIndex[i]] = static_cast<std::uint32_t>(i);
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    double total = 0.0;
    for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k) {
      const TexelPiece& piece = bake.pieces[k];
      if (piece.triangle >= triangleCount)
        return Error{mesh.sourceName + ": bake piece names triangle " + std::to_string(piece.triangle) +
                     " of " + std::to_string(triangleCount)};
      const auto& f = mesh.triangles[piece.triangle];
      const Eigen::Vector3d& p0 = mesh.positions[f[0]];
      const Eigen::Vector3d& p1 = mesh.positions[f[1]];
      const Eigen::Vector3d& p2 = mesh.positions[f[2]];
      const double area = piece.areaFraction * 0.5 * (p1 - p0).cross(p2 - p0).norm();
      const double b1 = piece.centroidBary1, b2 = piece.centroidBary2;
      weighted += area * ((1.0 - b1 - b2) * p0 + b1 * p1 + b2 * p2);
      total += area;
    }
    graph.area[i] = total;
    if (total > 0.0) graph.centroid[i] = weighted / total;
  }
  double meanSide = 0.0;
  for (double a : graph.area) meanSide += std::sqrt(a);
  meanSide /= static_cast<double>(std::max<std::size_t>(covered, 1));
  // Centroids closer than this are kept apart, so that two slivers facing each other across a seam
  // do not get an unbounded conductance.
  const double minimumDistance = 1e-3 * meanSide;

  auto addPair = [&](std::uint32_t i, std::uint32_t j, double length, bool seam) {
    if (i == j || length <= 0.0 || graph.area[i] <= 0.0 || graph.area[j] <= 0.0) return;
    const double distance = std::max((graph.centroid[i] - graph.centroid[j]).norm(), minimumDistance);
    graph.first.push_back(std::min(i, j));
    graph.second.push_back(std::max(i, j));
    graph.conductance.push_back(length / distance);
    graph.interfaceLength.push_back(length);
    graph.acrossSeam.push_back(seam ? 1 : 0);
  };

  // Inside charts: the right and lower texel edges of every covered texel.
  std::vector<Span> spansI, spansJ;
  auto spansOn = [&](std::uint32_t texel, const Eigen::Vector2d& a, const Eigen::Vector2d& b, std::vector<Span>& out) {
    out.clear();
    for (std::uint32_t k = bake.pieceStart[texel]; k < bake.pieceStart[texel + 1]; ++k) {
      const std::uint32_t t = bake.pieces[k].triangle;
      if (!maps[t].hasArea) continue;
      bool seen = false;
      for (const Span& s : out) seen = seen || s.triangle == t;
      double t0 = 0.0, t1 = 0.0;
      if (!seen && clipSegment(maps[t], a, b, t0, t1)) out.push_back({t0, t1, t});
    }
  };
  // The edge is nudged this far (texels) into each side so that a triangle edge lying exactly on
  // the texel edge is counted on its own side only.
  constexpr double kNudge = 1e-7;
  for (std::uint32_t i = 0; i < covered; ++i) {
    const int row = static_cast<int>(bake.texelIndex[i] / static_cast<std::uint32_t>(bake.width));
    const int column = static_cast<int>(bake.texelIndex[i] % static_cast<std::uint32_t>(bake.width));
    for (int direction = 0; direction < 2; ++direction) {
      const int nRow = row + direction, nColumn = column + 1 - direction;
      if (nRow >= bake.height || nColumn >= bake.width) continue;
      const std::uint32_t j = coveredAt[static_cast<std::size_t>(nRow) * bake.width + nColumn];
      if (j == kUncovered) continue;
      // Shared edge: x = column + 1 (direction 0) or y = row + 1 (direction 1).
      const Eigen::Vector2d a = direction == 0 ? Eigen::Vector2d(column + 1.0, row) : Eigen::Vector2d(column, row + 1.0);
      const Eigen::Vector2d b = direction == 0 ? Eigen::Vector2d(column + 1.0, row + 1.0)
                                               : Eigen::Vector2d(column + 1.0, row + 1.0);
      const Eigen::Vector2d normal = direction == 0 ? Eigen::Vector2d(1.0, 0.0) : Eigen::Vector2d(0.0, 1.0);
      spansOn(i, a - kNudge * normal, b - kNudge * normal, spansI);
      spansOn(j, a + kNudge * normal, b + kNudge * normal, spansJ);
      double length = 0.0;
      for (const Span& si : spansI)
        for (const Span& sj : spansJ) {
          const double overlap = std::min(si.t1, sj.t1) - std::max(si.t0, sj.t0);
          if (overlap <= 0.0) continue;
          if (si.triangle != sj.triangle &&
              !shareUvVertex(layout.uvTriangles[si.triangle], layout.uvTriangles[sj.triangle]))
            continue;
          length += overlap * (maps[si.triangle].jacobian * (b - a)).norm();
        }
      addPair(i, j, length, false);
    }
  }

  // Across seams: mesh edges shared by two triangles (with area) whose UV edges differ.
  std::map<std::pair<int, int>, std::vector<std::pair<std::uint32_t, int>>> edges;
  for (std::size_t t = 0; t < triangleCount; ++t) {
    if (!maps[t].hasArea) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back({static_cast<std::uint32_t>(t), k});
    }
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> seamLength;
  std::vector<double> breaks;
  for (const auto& [key, users] : edges) {
    // Only manifold edges pair up; a border edge of an open mesh has no other side.
    if (users.size() != 2) continue;
    const auto [tA, kA] = users[0];
    const auto [tB, kB] = users[1];
    // UV corners of the edge's endpoints (key.first, key.second) on each side.
    auto cornerOf = [&](std::uint32_t t, int k, int position) {
      return mesh.triangles[t][k] == position ? k : (k + 1) % 3;
    };
    const int aFirst = cornerOf(tA, kA, key.first), aSecond = cornerOf(tA, kA, key.second);
    const int bFirst = cornerOf(tB, kB, key.first), bSecond = cornerOf(tB, kB, key.second);
    const TriangleMap& mA = maps[tA];
    const TriangleMap& mB = maps[tB];
    if (mA.q[aFirst] == mB.q[bFirst] && mA.q[aSecond] == mB.q[bSecond]) continue;  // UV-continuous
    const Eigen::Vector2d a0 = mA.q[aFirst], a1 = mA.q[aSecond], b0 = mB.q[bFirst], b1 = mB.q[bSecond];
    const double length3d = (mesh.positions[key.second] - mesh.positions[key.first]).norm();
    breaks.assign({0.0, 1.0});
    auto addGridCrossings = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
      for (int axis = 0; axis < 2; ++axis) {
        const double lo = std::min(p[axis], q[axis]), hi = std::max(p[axis], q[axis]);
        for (double line = std::ceil(lo); line <= hi; line += 1.0)
          if (q[axis] != p[axis]) breaks.push_back((line - p[axis]) / (q[axis] - p[axis]));
      }
    };
    addGridCrossings(a0, a1);
    addGridCrossings(b0, b1);
    std::sort(breaks.begin(), breaks.end());
    const Eigen::Vector2d centreA = (mA.q[0] + mA.q[1] + mA.q[2]) / 3.0;
    const Eigen::Vector2d centreB = (mB.q[0] + mB.q[1] + mB.q[2]) / 3.0;
    auto texelAt = [&](const Eigen::Vector2d& point, const Eigen::Vector2d& centre) {
      // One thousandth of a texel towards the triangle's inside picks the texel on its side.
      const Eigen::Vector2d inward = (centre - point).normalized();
      const Eigen::Vector2d x = point + 1e-3 * inward;
      const int column = std::clamp(static_cast<int>(std::floor(x.x())), 0, bake.width - 1);
      const int row = std::clamp(static_cast<int>(std::floor(x.y())), 0, bake.height - 1);
      return coveredAt[static_cast<std::size_t>(row) * bake.width + column];
    };
    for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
      const double t0 = std::clamp(breaks[k], 0.0, 1.0), t1 = std::clamp(breaks[k + 1], 0.0, 1.0);
      if (t1 - t0 <= 1e-12) continue;
      const double t = 0.5 * (t0 + t1);
      const std::uint32_t i = texelAt(a0 + t * (a1 - a0), centreA);
      const std::uint32_t j = texelAt(b0 + t * (b1 - b0), centreB);
      if (i == kUncovered || j == kUncovered) {
        graph.seamLengthUncovered += (t1 - t0) * length3d;
        continue;
      }
      if (i == j) {
        graph.seamLengthInOneTexel += (t1 - t0) * length3d;
        continue;
      }
      seamLength[{std::min(i, j), std::max(i, j)}] += (t1 - t0) * length3d;
    }
  }
  for (const auto& [pair, length] : seamLength) addPair(pair.first, pair.second, length, true);

  graph.conductanceSum.assign(covered, 0.0);
  for (std::size_t p = 0; p < graph.pairCount(); ++p) {
    graph.conductanceSum[graph.first[p]] += graph.conductance[p];
    graph.conductanceSum[graph.second[p]] += graph.conductance[p];
  }
  return graph;
}

}  // namespace hydrotex
