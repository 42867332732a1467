// SPDX-License-Identifier: Zlib
/// @file MeshValidation.cpp
/// Edge counting by sorting (O(n log n)), volume by the divergence theorem, UV overlap by a uniform
/// grid and the separating axis theorem.

#include "hydrotex/mesh/MeshValidation.hpp"

#include "hydrotex/mesh/MeshParts.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <vector>

namespace hydrotex {
namespace {

struct EdgeUse {
  std::uint64_t key;  ///< (smaller index << 32) | larger index
  bool forward;       ///< the triangle walks the edge from the smaller to the larger index
};

bool indicesValid(const Eigen::Vector3i& triangle, std::size_t count) {
  for (int c = 0; c < 3; ++c)
    if (triangle[c] < 0 || static_cast<std::size_t>(triangle[c]) >= count) return false;
  return true;
}

/// Twice the area is compared with the squared longest edge: a scale-free "is this a sliver".
bool isDegenerate(double twiceArea, double longestEdgeSquared) {
  return !(twiceArea > kDegenerateRelativeTolerance * longestEdgeSquared) || longestEdgeSquared == 0.0;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Uniform grid over the UV bounds holding each triangle in the cells its bounding box covers
/// (compressed rows: cellStart / entries).
class UvGrid {
 public:
  UvGrid(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int cellsPerSide)
      : lo_(lo), cells_(cellsPerSide) {
    const Eigen::Vector2d extent = (hi - lo).cwiseMax(Eigen::Vector2d::Constant(1e-300));
    inverseCell_ = Eigen::Vector2d(cells_ / extent.x(), cells_ / extent.y());
  }
  int cellsPerSide() const { return cells_; }
  int cellX(double u) const { return clampCell((u - lo_.x()) * inverseCell_.x()); }
  int cellY(double v) const { return clampCell((v - lo_.y()) * inverseCell_.y()); }

 private:
  int clampCell(double coordinate) const {
    if (!(coordinate > 0.0)) return 0;
    if (coordinate >= cells_) return cells_ - 1;
    return static_cast<int>(coordinate);
  }
  Eigen::Vector2d lo_;
  Eigen::Vector2d inverseCell_;
  int cells_;
};

struct UvBox {
  Eigen::Vector2d lo, hi;
  int x0, y0, x1, y1;  ///< covered cell range, inclusive
};

struct OverlapResult {
  std::size_t pairs = 0;
  bool complete = true;
};

/// Finds UV triangle pairs that overlap with positive area. Each candidate pair is tested once,
/// in the cell holding the lower corner of the intersection of their bounding boxes.
OverlapResult findUvOverlaps(const Mesh& mesh, const std::vector<std::uint32_t>& candidates) {
  OverlapResult result;
  if (candidates.size() < 2) return result;
  const auto& uvs = mesh.uv.uvs;
  const auto& uvTriangles = mesh.uv.uvTriangles;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (std::uint32_t t : candidates)
    for (int c = 0; c < 3; ++c) {
      lo = lo.cwiseMin(uvs[uvTriangles[t][c]]);
      hi = hi.cwiseMax(uvs[uvTriangles[t][c]]);
    }
  // Touching along an edge gives an overlap of exactly zero (same coordinates); the tolerance only
  // absorbs rounding between vertices that are meant to coincide but were stored twice.
  const double tolerance = 1e-9 * std::max((hi - lo).maxCoeff(), 1e-300);
  const std::size_t n = candidates.size();

  // About one triangle per cell; coarser when large triangles would fill too many cells.
  int cellsPerSide = std::clamp(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n)))), 1, 2048);
  std::vector<UvBox> boxes(n);
  std::size_t entryCount = 0;
  for (;;) {
    const UvGrid grid(lo, hi, cellsPerSide);
    entryCount = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const auto& tri = uvTriangles[candidates[i]];
      UvBox& box = boxes[i];
      box.lo = uvs[tri[0]].cwiseMin(uvs[tri[1]]).cwiseMin(uvs[tri[2]]);
      box.hi = uvs[tri[0]].cwiseMax(uvs[tri[1]]).cwiseMax(uvs[tri[2]]);
      box.x0 = grid.cellX(box.lo.x());
      box.y0 = grid.cellY(box.lo.y());
      box.x1 = grid.cellX(box.hi.x());
      box.y1 = grid.cellY(box.hi.y());
      entryCount += static_cast<std::size_t>(box.x1 - box.x0 + 1) * static_cast<std::size_t>(box.y1 - box.y0 + 1);
    }
    if (entryCount <= 16 * n + 4096 || cellsPerSide == 1) break;
    cellsPerSide = std::max(1, cellsPerSide / 2);
  }
  const UvGrid grid(lo, hi, cellsPerSide);
  const std::size_t cellCount = static_cast<std::size_t>(cellsPerSide) * static_cast<std::size_t>(cellsPerSide);
  std::vector<std::uint32_t> cellStart(cellCount + 1, 0);
  for (const UvBox& box : boxes)
    for (int y = box.y0; y <= box.y1; ++y)
      for (int x = box.x0; x <= box.x1; ++x) ++cellStart[static_cast<std::size_t>(y) * cellsPerSide + x + 1];
  for (std::size_t c = 0; c < cellCount; ++c) cellStart[c + 1] += cellStart[c];
  std::vector<std::uint32_t> entries(entryCount);
  std::vector<std::uint32_t> fill(cellStart.begin(), cellStart.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const UvBox& box = boxes[i];
    for (int y = box.y0; y <= box.y1; ++y)
      for (int x = box.x0; x <= box.x1; ++x)
        entries[fill[static_cast<std::size_t>(y) * cellsPerSide + x]++] = static_cast<std::uint32_t>(i);
  }

  // Work budget: normal layouts need a few tests per triangle; pathological ones (thousands of
  // slivers through one point) would otherwise be quadratic.
  std::uint64_t budget = 64 * static_cast<std::uint64_t>(n) + 20'000'000;
  for (std::size_t cell = 0; cell < cellCount; ++cell) {
    const int cellX = static_cast<int>(cell % static_cast<std::size_t>(cellsPerSide));
    const int cellY = static_cast<int>(cell / static_cast<std::size_t>(cellsPerSide));
    for (std::uint32_t a = cellStart[cell]; a < cellStart[cell + 1]; ++a) {
      const UvBox& boxA = boxes[entries[a]];
      for (std::uint32_t b = a + 1; b < cellStart[cell + 1]; ++b) {
        const UvBox& boxB = boxes[entries[b]];
        const Eigen::Vector2d overlapLo = boxA.lo.cwiseMax(boxB.lo);
        const Eigen::Vector2d overlapHi = boxA.hi.cwiseMin(boxB.hi);
        if (!(overlapHi.x() - overlapLo.x() > tolerance && overlapHi.y() - overlapLo.y() > tolerance)) continue;
        if (grid.cellX(overlapLo.x()) != cellX || grid.cellY(overlapLo.y()) != cellY) continue;
        if (budget-- == 0) {
          result.complete = false;
          return result;
        }
        const auto& ta = uvTriangles[candidates[entries[a]]];
        const auto& tb = uvTriangles[candidates[entries[b]]];
        const Eigen::Vector2d pa[3] = {uvs[ta[0]], uvs[ta[1]], uvs[ta[2]]};
        const Eigen::Vector2d pb[3] = {uvs[tb[0]], uvs[tb[1]], uvs[tb[2]]};
        if (uvTrianglesOverlap(pa, pb, tolerance) && ++result.pairs >= kMaxCountedUvOverlaps) return result;
      }
    }
  }
  return result;
}

void validateUvs(const Mesh& mesh, const std::vector<bool>& degenerate3d, MeshReport& report) {
  const auto& uvs = mesh.uv.uvs;
  std::vector<bool> uvUsed(uvs.size(), false);
  std::vector<std::uint32_t> candidates;
  candidates.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh.uv.uvTriangles[t];
    if (!indicesValid(tri, uvs.size())) {
      if (!degenerate3d[t]) ++report.zeroUvAreaTriangles;  // a UV triangle that does not exist has no area
      continue;
    }
    bool finite = true;
    for (int c = 0; c < 3; ++c) {
      uvUsed[tri[c]] = true;
      finite = finite && uvs[tri[c]].allFinite();
    }
    const Eigen::Vector2d e1 = uvs[tri[1]] - uvs[tri[0]];
    const Eigen::Vector2d e2 = uvs[tri[2]] - uvs[tri[0]];
    const Eigen::Vector2d e3 = uvs[tri[2]] - uvs[tri[1]];
    const double longest = std::max({e1.squaredNorm(), e2.squaredNorm(), e3.squaredNorm()});
    if (!finite || isDegenerate(std::abs(cross2(e1, e2)), longest)) {
      if (!degenerate3d[t]) ++report.zeroUvAreaTriangles;
      continue;
    }
    candidates.push_back(static_cast<std::uint32_t>(t));
  }
  for (std::size_t i = 0; i < uvs.size(); ++i) {
    if (!uvUsed[i]) continue;
    const Eigen::Vector2d& uv = uvs[i];
    if (!(uv.x() >= 0.0 && uv.x() <= 1.0 && uv.y() >= 0.0 && uv.y() <= 1.0)) ++report.uvsOutsideUnitSquare;
  }
  const OverlapResult overlaps = findUvOverlaps(mesh, candidates);
  report.uvOverlapPairs = overlaps.pairs;
  report.uvOverlap = overlaps.pairs > 0;
  report.uvOverlapCheckComplete = overlaps.complete;
}

}  // namespace

bool uvTrianglesOverlap(const Eigen::Vector2d a[3], const Eigen::Vector2d b[3], double tolerance) {
  // Separating axis theorem for convex polygons: their interiors are disjoint iff the projections
  // on one of the edge normals overlap by at most zero (Gottschalk et al., "OBBTree", SIGGRAPH
  // 1996, sec. 4). Overlaps up to `tolerance` count as touching.
  const Eigen::Vector2d* triangles[2] = {a, b};
  for (const Eigen::Vector2d* owner : triangles) {
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector2d edge = owner[(e + 1) % 3] - owner[e];
      const double length = edge.norm();
      if (!(length > 0.0)) continue;
      const Eigen::Vector2d axis(-edge.y() / length, edge.x() / length);
      double minA = std::numeric_limits<double>::infinity(), maxA = -minA;
      double minB = minA, maxB = -minA;
      for (int c = 0; c < 3; ++c) {
        const double pa = axis.dot(a[c]);
        const double pb = axis.dot(b[c]);
        minA = std::min(minA, pa);
        maxA = std::max(maxA, pa);
        minB = std::min(minB, pb);
        maxB = std::max(maxB, pb);
      }
      if (!(std::min(maxA, maxB) - std::max(minA, minB) > tolerance)) return false;
    }
  }
  return true;
}

MeshReport validateMesh(const Mesh& mesh, bool checkUvs) {
  MeshReport report;
  report.triangleCount = mesh.triangles.size();
  report.vertexCount = mesh.positions.size();
  if (!mesh.positions.empty()) {
    report.boundsMin = report.boundsMax = mesh.positions.front();
    for (const Eigen::Vector3d& p : mesh.positions) {
      report.boundsMin = report.boundsMin.cwiseMin(p);
      report.boundsMax = report.boundsMax.cwiseMax(p);
    }
  }
  // Volume about the bounds' centre: the divergence theorem holds for any reference point on a
  // closed surface, and a nearby one keeps the tetrahedra small (less cancellation).
  const Eigen::Vector3d reference = 0.5 * (report.boundsMin + report.boundsMax);

  std::vector<bool> degenerate(mesh.triangles.size(), false);
  double signedVolume = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    if (!indicesValid(tri, mesh.positions.size())) {
      degenerate[t] = true;
      ++report.degenerateTriangles;
      continue;
    }
    const Eigen::Vector3d a = mesh.positions[tri[0]] - reference;
    const Eigen::Vector3d b = mesh.positions[tri[1]] - reference;
    const Eigen::Vector3d c = mesh.positions[tri[2]] - reference;
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    const double twiceArea = normal.norm();
    report.area += 0.5 * twiceArea;
    // Signed tetrahedron volume against the reference point (divergence theorem, e.g. Zhang & Chen,
    // "Efficient feature extraction for 2D/3D objects in mesh representation", ICIP 2001).
    signedVolume += a.dot(b.cross(c)) / 6.0;
    const double longest = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    if (isDegenerate(twiceArea, longest)) {
      degenerate[t] = true;
      ++report.degenerateTriangles;
    }
  }
  const EdgeTopology topology = countEdgeTopology(mesh);
  report.boundaryEdges = topology.boundaryEdges;
  report.nonManifoldEdges = topology.nonManifoldEdges;
  report.inconsistentEdges = topology.inconsistentEdges;
  report.watertight = !mesh.triangles.empty() && topology.closed();
  const std::vector<MeshPart> parts = findMeshParts(mesh);
  report.parts = parts.size();
  for (const MeshPart& part : parts)
    if (part.insideOut()) {
      ++report.insideOutParts;
      report.insideOutVolume += std::abs(part.signedVolume);
    }
  if (report.watertight) {
    report.volume = signedVolume;
    report.outwardOriented = signedVolume > 0.0 && report.insideOutParts == 0;
  }

  if (!checkUvs) return report;
  report.hasUv = mesh.hasUvs();
  if (report.hasUv) validateUvs(mesh, degenerate, report);
  return report;
}

EdgeTopology countEdgeTopology(const Mesh& mesh) {
  std::vector<EdgeUse> edges;
  edges.reserve(mesh.triangles.size() * 3);
  for (const Eigen::Vector3i& tri : mesh.triangles) {
    if (!indicesValid(tri, mesh.positions.size())) continue;
    for (int e = 0; e < 3; ++e) {
      const auto from = static_cast<std::uint32_t>(tri[e]);
      const auto to = static_cast<std::uint32_t>(tri[(e + 1) % 3]);
      if (from == to) continue;  // a collapsed edge is no edge; the triangle is already degenerate
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(from, to)) << 32) | std::max(from, to);
      edges.push_back({key, from < to});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key; });
  EdgeTopology topology;
  for (std::size_t first = 0; first < edges.size();) {
    std::size_t last = first + 1;
    while (last < edges.size() && edges[last].key == edges[first].key) ++last;
    const std::size_t uses = last - first;
    if (uses == 1) ++topology.boundaryEdges;
    else if (uses > 2) ++topology.nonManifoldEdges;
    else if (edges[first].forward == edges[first + 1].forward) ++topology.inconsistentEdges;
    first = last;
  }
  return topology;
}

namespace {
/// The one wording of "not closed", shared by checkClosed and requireClosed.
Status describeClosedness(const EdgeTopology& topology, std::size_t triangleCount, const std::string& what) {
  const std::string suffix = "; volume and buoyancy need a closed mesh";
  if (triangleCount == 0) return Error{what + ": mesh has no triangles" + suffix};
  if (topology.boundaryEdges > 0)
    return Error{what + ": mesh is open (" + std::to_string(topology.boundaryEdges) + " boundary edges)" + suffix};
  if (topology.nonManifoldEdges > 0)
    return Error{what + ": mesh is not a closed manifold (" + std::to_string(topology.nonManifoldEdges) +
                 " edges shared by more than two triangles)" + suffix};
  if (topology.inconsistentEdges > 0)
    return Error{what + ": mesh is inconsistently oriented (" + std::to_string(topology.inconsistentEdges) +
                 " edges walked the same way by both triangles)" + suffix};
  return Ok{};
}
}  // namespace

Status checkClosed(const Mesh& mesh, const std::string& what) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (!indicesValid(mesh.triangles[t], mesh.positions.size()))
      return Error{what + ": triangle " + std::to_string(t) + " has a vertex index out of range"};
  return describeClosedness(countEdgeTopology(mesh), mesh.triangles.size(), what);
}

std::string MeshReport::summary() const {
  std::ostringstream out;
  out << "triangles: " << triangleCount << ", vertices: " << vertexCount << "\n";
  out << "degenerate triangles: " << degenerateTriangles << "\n";
  out << "watertight: " << (watertight ? "yes" : "no") << " (boundary edges " << boundaryEdges
      << ", non-manifold edges " << nonManifoldEdges << ", inconsistently oriented edges " << inconsistentEdges << ")\n";
  out << "outward oriented: " << (outwardOriented ? "yes" : "no") << " (parts " << parts << ", inside out "
      << insideOutParts << ")\n";
  out << "area: " << area << " m^2\n";
  out << "volume: ";
  if (volume) out << *volume << " m^3\n";
  else out << "none (open mesh)\n";
  out << "bounds: [" << boundsMin.x() << ", " << boundsMin.y() << ", " << boundsMin.z() << "] .. [" << boundsMax.x()
      << ", " << boundsMax.y() << ", " << boundsMax.z() << "] m\n";
  out << "UVs: " << (hasUv ? "yes" : "no");
  if (hasUv) {
    out << ", overlap: " << (uvOverlap ? "yes" : "no") << " (" << uvOverlapPairs
        << (uvOverlapPairs >= kMaxCountedUvOverlaps ? "+" : "") << " pairs"
        << (uvOverlapCheckComplete ? "" : ", search stopped early") << ")"
        << ", zero-area UV triangles: " << zeroUvAreaTriangles << ", UVs outside [0,1]: " << uvsOutsideUnitSquare
        << ", usable as physics atlas: " << (uvUsableAsAtlas() ? "yes" : "no");
  }
  out << "\n";
  return out.str();
}

Status requireClosed(const MeshReport& report, const std::string& what) {
  const EdgeTopology topology{report.boundaryEdges, report.nonManifoldEdges, report.inconsistentEdges};
  if (Status closed = describeClosedness(topology, report.triangleCount, what); !closed) return closed;
  if (!report.outwardOriented) {
    // A closed but flat (or collinear) mesh has a volume of zero up to rounding, of either sign:
    // calling it inside out would send the user flipping triangles that are not the problem.
    const double extent = (report.boundsMax - report.boundsMin).norm();
    const double volume = report.volume.value_or(0.0);
    if (std::abs(volume) <= kDegenerateRelativeTolerance * extent * extent * extent)
      return Error{what + ": mesh encloses no volume (" + std::to_string(volume) +
                   " m^3: flat or degenerate); volume and buoyancy need a solid"};
    if (report.insideOutParts > 0 && volume > 0.0)
      return Error{what + ": " + std::to_string(report.insideOutParts) + " of the mesh's " + std::to_string(report.parts) +
                   " parts are inside out (" + std::to_string(report.insideOutVolume) +
                   " m^3 counted negative); load it with repair on (drop --no-repair) or flip those parts"};
    return Error{what + ": mesh is inside out (negative volume); flip the winding of every triangle"};
  }
  return Ok{};
}

}  // namespace hydrotex
