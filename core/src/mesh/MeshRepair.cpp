// SPDX-License-Identifier: Zlib
/// @file MeshRepair.cpp
/// Welding on a hash grid, edge counts by sorting, orientation by breadth-first search over
/// manifold edges, holes by walking boundary half-edges, outwardness by MeshParts.

#include "hydrotex/mesh/MeshRepair.hpp"

#include "hydrotex/mesh/MeshParts.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <map>
#include <sstream>
#include <unordered_map>
#include <utility>

namespace hydrotex {
namespace {

std::uint64_t edgeKey(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b)), hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

/// Undirected edge -> the triangles using it (sorted vector of (key, triangle)).
std::vector<std::pair<std::uint64_t, std::size_t>> edgeUses(const Mesh& mesh) {
  std::vector<std::pair<std::uint64_t, std::size_t>> uses;
  uses.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int e = 0; e < 3; ++e) uses.emplace_back(edgeKey(mesh.triangles[t][e], mesh.triangles[t][(e + 1) % 3]), t);
  std::sort(uses.begin(), uses.end());
  return uses;
}

std::string number(double value) {
  std::ostringstream out;
  out.precision(3);
  out << value;
  return out.str();
}

std::string metres(double value) { return number(value) + " m"; }

void flipTriangle(Mesh& mesh, std::size_t t, bool withUv) {
  std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
  if (withUv) std::swap(mesh.uv.uvTriangles[t][1], mesh.uv.uvTriangles[t][2]);
}

void removeTriangles(Mesh& mesh, const std::vector<bool>& drop, bool withUv) {
  // Lids of an earlier repair keep pointing at their triangles (a mesh repaired twice).
  std::vector<std::uint32_t> newIndex(mesh.triangles.size());
  std::size_t kept = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (drop[t]) continue;
    newIndex[t] = static_cast<std::uint32_t>(kept);
    mesh.triangles[kept] = mesh.triangles[t];
    if (withUv) mesh.uv.uvTriangles[kept] = mesh.uv.uvTriangles[t];
    ++kept;
  }
  mesh.triangles.resize(kept);
  if (withUv) mesh.uv.uvTriangles.resize(kept);
  std::vector<std::uint32_t> openings;
  for (std::uint32_t t : mesh.openingTriangles)
    if (t < drop.size() && !drop[t]) openings.push_back(newIndex[t]);
  mesh.openingTriangles = std::move(openings);
}

/// Merges vertices closer than `tolerance` (m) into the first one met; returns how many merged.
std::size_t weld(Mesh& mesh, const Eigen::Vector3d& lo, double tolerance) {
  if (!(tolerance > 0.0 && std::isfinite(tolerance))) return 0;
  struct CellHash {
    std::size_t operator()(const Eigen::Vector3i& c) const {
      return static_cast<std::size_t>(c.x()) * 73856093u ^ static_cast<std::size_t>(c.y()) * 19349663u ^
             static_cast<std::size_t>(c.z()) * 83492791u;
    }
  };
  struct CellEqual {
    bool operator()(const Eigen::Vector3i& a, const Eigen::Vector3i& b) const { return a == b; }
  };
  std::unordered_map<Eigen::Vector3i, std::vector<int>, CellHash, CellEqual> grid;
  std::vector<int> target(mesh.positions.size());
  std::vector<Eigen::Vector3d> kept;
  std::size_t merged = 0;
  const double inverseCell = 1.0 / tolerance;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Eigen::Vector3d& p = mesh.positions[v];
    // From the lower corner: cell indices stay below diagonal / tolerance (1e7 by default).
    const Eigen::Vector3d scaled = (p - lo) * inverseCell;
    const Eigen::Vector3i cell(static_cast<int>(std::floor(scaled.x())), static_cast<int>(std::floor(scaled.y())),
                               static_cast<int>(std::floor(scaled.z())));
    int found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          const auto it = grid.find(cell + Eigen::Vector3i(dx, dy, dz));
          if (it == grid.end()) continue;
          for (int k : it->second)
            if ((kept[static_cast<std::size_t>(k)] - p).norm() <= tolerance) {
              found = k;
              break;
            }
        }
    if (found >= 0) {
      target[v] = found;
      ++merged;
    } else {
      target[v] = static_cast<int>(kept.size());
      grid[cell].push_back(target[v]);
      kept.push_back(p);
    }
  }
  if (merged == 0) return 0;
  mesh.positions = std::move(kept);
  for (Eigen::Vector3i& t : mesh.triangles)
    for (int c = 0; c < 3; ++c) t[c] = target[static_cast<std::size_t>(t[c])];
  return merged;
}

/// Drops triangles with repeated corners, and zero-area triangles whose every edge is used by 0
/// or 2 other triangles (removing them opens nothing). A zero-area triangle filling a slit is kept.
std::size_t dropDegenerate(Mesh& mesh, bool withUv) {
  std::vector<bool> drop(mesh.triangles.size(), false);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    drop[t] = tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2];
  }
  std::map<std::uint64_t, int> uses;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    if (!drop[t])
      for (int e = 0; e < 3; ++e) ++uses[edgeKey(mesh.triangles[t][e], mesh.triangles[t][(e + 1) % 3])];
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (drop[t]) continue;
    const Eigen::Vector3i& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    const double longest = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    if ((b - a).cross(c - a).norm() > kDegenerateRelativeTolerance * longest) continue;
    bool harmless = true;
    for (int e = 0; e < 3; ++e) {
      const int others = uses[edgeKey(tri[e], tri[(e + 1) % 3])] - 1;
      harmless = harmless && (others == 0 || others == 2);
    }
    if (!harmless) continue;
    drop[t] = true;
    for (int e = 0; e < 3; ++e) --uses[edgeKey(tri[e], tri[(e + 1) % 3])];
  }
  const auto dropped = static_cast<std::size_t>(std::count(drop.begin(), drop.end(), true));
  if (dropped > 0) removeTriangles(mesh, drop, withUv);
  return dropped;
}

/// Makes neighbours across manifold edges walk their shared edge oppositely, part by part,
/// keeping each part's majority orientation. Returns the triangles flipped; `nonOrientable`
/// counts parts where no orientation agrees everywhere (a Moebius band).
std::size_t orientConsistently(Mesh& mesh, bool withUv, std::size_t& nonOrientable) {
  const auto uses = edgeUses(mesh);
  const std::size_t n = mesh.triangles.size();
  // Neighbour across each manifold edge.
  std::vector<std::vector<std::size_t>> neighbours(n);
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t last = first + 1;
    while (last < uses.size() && uses[last].first == uses[first].first) ++last;
    if (last - first == 2 && uses[first].second != uses[first + 1].second) {
      neighbours[uses[first].second].push_back(uses[first + 1].second);
      neighbours[uses[first + 1].second].push_back(uses[first].second);
    }
    first = last;
  }
  // Does triangle t walk the edge a->b (true) or b->a?
  const auto walks = [&](std::size_t t, int a, int b) {
    for (int e = 0; e < 3; ++e)
      if (mesh.triangles[t][e] == a && mesh.triangles[t][(e + 1) % 3] == b) return true;
    return false;
  };
  std::vector<int> state(n, -1);  // -1 unvisited, 0 keep, 1 flip
  std::size_t flipped = 0;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (state[seed] >= 0) continue;
    std::vector<std::size_t> part{seed};
    std::deque<std::size_t> queue{seed};
    state[seed] = 0;
    bool conflict = false;
    while (!queue.empty()) {
      const std::size_t t = queue.front();
      queue.pop_front();
      for (std::size_t u : neighbours[t]) {
        // The shared edge, as t walks it (after t's own flip).
        int a = -1, b = -1;
        for (int e = 0; e < 3 && a < 0; ++e) {
          const int p = mesh.triangles[t][e], q = mesh.triangles[t][(e + 1) % 3];
          if (walks(u, p, q) || walks(u, q, p)) {
            a = p;
            b = q;
          }
        }
        if (state[t] == 1) std::swap(a, b);
        // u must walk b->a; if it walks a->b as stored, it needs a flip.
        const int wanted = walks(u, a, b) ? 1 : 0;
        if (state[u] < 0) {
          state[u] = wanted;
          part.push_back(u);
          queue.push_back(u);
        } else if (state[u] != wanted) {
          conflict = true;
        }
      }
    }
    if (conflict) {
      ++nonOrientable;
      continue;  // left as it is: no orientation fits
    }
    std::size_t toFlip = 0;
    for (std::size_t t : part) toFlip += static_cast<std::size_t>(state[t]);
    const bool invert = 2 * toFlip > part.size();  // keep the majority as it is
    for (std::size_t t : part)
      if ((state[t] == 1) != invert) {
        flipTriangle(mesh, t, withUv);
        ++flipped;
      }
  }
  return flipped;
}

/// Boundary loops as walked by their triangles (each loop closed: last vertex joins the first).
/// `untraced` counts boundary edges that could not be chained into a loop.
std::vector<std::vector<int>> boundaryLoops(const Mesh& mesh, std::size_t& untraced) {
  const auto uses = edgeUses(mesh);
  std::multimap<int, int> next;  // boundary half-edge from -> to
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t last = first + 1;
    while (last < uses.size() && uses[last].first == uses[first].first) ++last;
    if (last - first == 1) {
      const Eigen::Vector3i& tri = mesh.triangles[uses[first].second];
      const int lo = static_cast<int>(uses[first].first >> 32), hi = static_cast<int>(uses[first].first & 0xffffffffu);
      for (int e = 0; e < 3; ++e) {
        const int a = tri[e], b = tri[(e + 1) % 3];
        if (std::min(a, b) == lo && std::max(a, b) == hi) {
          next.emplace(a, b);
          break;
        }
      }
    }
    first = last;
  }
  std::vector<std::vector<int>> loops;
  untraced = 0;
  while (!next.empty()) {
    const int start = next.begin()->first;
    std::vector<int> loop{start};
    int at = start;
    bool closed = false;
    while (true) {
      const auto it = next.find(at);
      if (it == next.end()) break;
      at = it->second;
      next.erase(it);
      if (at == start) {
        closed = true;
        break;
      }
      loop.push_back(at);
    }
    if (closed && loop.size() >= 3) loops.push_back(std::move(loop));
    else untraced += loop.size();
  }
  return loops;
}

/// A closed loop split where it passes a vertex again (a rim pinched at one vertex) into simple
/// loops, each visiting its vertices once: a fan over a pinched loop would use the edge from the
/// pinch to the apex four times. Pieces of fewer than three vertices (an edge walked there and
/// back) enclose nothing and are left out.
std::vector<std::vector<int>> simpleLoops(const std::vector<int>& loop) {
  std::vector<std::vector<int>> loops;
  std::vector<int> stack;
  std::unordered_map<int, std::size_t> at;  // vertex -> its place on the stack
  for (int v : loop) {
    const auto seen = at.find(v);
    if (seen == at.end()) {
      at.emplace(v, stack.size());
      stack.push_back(v);
      continue;
    }
    const std::size_t from = seen->second;
    if (stack.size() - from >= 3) loops.emplace_back(stack.begin() + std::ptrdiff_t(from), stack.end());
    for (std::size_t i = from + 1; i < stack.size(); ++i) at.erase(stack[i]);
    stack.resize(from + 1);
  }
  if (stack.size() >= 3) loops.push_back(std::move(stack));
  return loops;
}

}  // namespace

Status RepairSettings::validate() const {
  if (!(std::isfinite(weldFraction) && weldFraction >= 0.0 && weldFraction < 0.01))
    return Error{"repair weld fraction " + std::to_string(weldFraction) + " must lie in [0, 0.01)"};
  if (!(std::isfinite(maxHoleFraction) && maxHoleFraction >= 0.0))
    return Error{"max hole fraction " + std::to_string(maxHoleFraction) + " must be a finite number >= 0"};
  if (!(std::isfinite(maxHoleAreaFraction) && maxHoleAreaFraction >= 0.0 && maxHoleAreaFraction <= 1.0))
    return Error{"max hole area fraction " + std::to_string(maxHoleAreaFraction) + " must lie in [0, 1]"};
  return Ok{};
}

Expected<RepairReport> repairMesh(Mesh& mesh, const RepairSettings& settings) {
  if (Status valid = settings.validate(); !valid) return valid.error();
  RepairReport report;
  if (!settings.enabled || mesh.triangles.empty()) return report;
  for (const Eigen::Vector3i& t : mesh.triangles)
    for (int c = 0; c < 3; ++c)
      if (t[c] < 0 || static_cast<std::size_t>(t[c]) >= mesh.positions.size())
        return Error{"a triangle indexes a missing vertex; nothing to repair from"};
  for (const Eigen::Vector3d& p : mesh.positions)
    if (!p.allFinite()) return Error{"a vertex is not finite; nothing to repair from"};
  const bool withUv = mesh.hasUvs();
  Eigen::Vector3d lo = mesh.positions.front(), hi = lo;
  for (const Eigen::Vector3d& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = (hi - lo).norm();

  report.verticesWelded = weld(mesh, lo, settings.weldFraction * diagonal);
  report.trianglesDropped = dropDegenerate(mesh, withUv);
  std::size_t nonOrientable = 0;
  report.trianglesReoriented = orientConsistently(mesh, withUv, nonOrientable);

  std::size_t untraced = 0;
  const double maxPerimeter = settings.maxHoleFraction * diagonal;
  double surfaceArea = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles)
    surfaceArea += 0.5 * (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]).norm();
  const double maxCapArea = settings.maxHoleAreaFraction * surfaceArea;
  for (const std::vector<int>& loop : boundaryLoops(mesh, untraced)) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    double perimeter = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      centroid += mesh.positions[loop[i]];
      perimeter += (mesh.positions[loop[(i + 1) % loop.size()]] - mesh.positions[loop[i]]).norm();
    }
    centroid /= static_cast<double>(loop.size());
    double capArea = 0.0;
    for (std::size_t i = 0; i < loop.size(); ++i)
      capArea += 0.5 * (mesh.positions[loop[i]] - centroid).cross(mesh.positions[loop[(i + 1) % loop.size()]] - centroid).norm();
    const bool opening = perimeter > maxPerimeter && capArea > maxCapArea;
    if (opening && !settings.openHull) {
      report.unrepaired.push_back("open hull: a boundary loop of " + metres(perimeter) + " (" +
                                  std::to_string(loop.size()) + " edges) is longer than the " + metres(maxPerimeter) +
                                  " holes repair closes (max hole fraction " + number(settings.maxHoleFraction) +
                                  " of the " + metres(diagonal) +
                                  " bounding-box diagonal); raise it (--max-hole-fraction, scene key "
                                  "\"max_hole_fraction\"), close the opening in the file, or cap it as the "
                                  "opening of an open hull (--open-hull, scene key \"open_hull\")");
      continue;
    }
    // Cap triangles walk each loop edge backwards, so they agree with the part's orientation.
    // A lid is capped as a hole is; only its triangles are listed as an opening.
    ClosedHole hole{loop.size(), perimeter, 0.0};
    const auto addCap = [&](int a, int b, int c) {
      if (opening) mesh.openingTriangles.push_back(static_cast<std::uint32_t>(mesh.triangles.size()));
      mesh.triangles.emplace_back(a, b, c);
      hole.area += 0.5 * (mesh.positions[b] - mesh.positions[a]).cross(mesh.positions[c] - mesh.positions[a]).norm();
    };
    for (const std::vector<int>& simple : simpleLoops(loop)) {
      if (simple.size() == 3) {
        addCap(simple[2], simple[1], simple[0]);
        continue;
      }
      Eigen::Vector3d apex = Eigen::Vector3d::Zero();
      for (int v : simple) apex += mesh.positions[v];
      const int apexIndex = static_cast<int>(mesh.positions.size());
      mesh.positions.push_back(apex / static_cast<double>(simple.size()));
      for (std::size_t i = 0; i < simple.size(); ++i) addCap(simple[(i + 1) % simple.size()], simple[i], apexIndex);
    }
    (opening ? report.lids : report.holesClosed).push_back(hole);
  }
  if ((!report.holesClosed.empty() || !report.lids.empty()) && withUv) {
    // Caps have no artist UVs; a partial layout cannot be an atlas, so the atlas is generated.
    mesh.uv = UvLayout{};
    report.uvsDropped = true;
  }
  const bool uvNow = mesh.hasUvs();

  for (const MeshPart& part : findMeshParts(mesh)) {
    if (!part.insideOut()) continue;
    for (std::size_t t : part.triangles) flipTriangle(mesh, t, uvNow);
    ++report.partsFlipped;
    report.flippedVolume += std::abs(part.signedVolume);
  }

  const EdgeTopology topology = countEdgeTopology(mesh);
  if (topology.nonManifoldEdges > 0)
    report.unrepaired.push_back("non-manifold: " + std::to_string(topology.nonManifoldEdges) +
                                " edges shared by more than two triangles (touching solids, fins or doubled faces); "
                                "repair cannot tell which surface is the hull: separate or remove them in the file");
  if (nonOrientable > 0)
    report.unrepaired.push_back("non-orientable: " + std::to_string(nonOrientable) +
                                " parts have no consistent side (a Moebius band); fix the surface in the file");
  if (untraced > 0)
    report.unrepaired.push_back("open hull: " + std::to_string(untraced) +
                                " boundary edges do not form loops (they meet at non-manifold vertices); fix the "
                                "rim in the file");
  return report;
}

std::string RepairReport::summary() const {
  std::ostringstream out;
  out.precision(4);
  if (!changed() && unrepaired.empty()) return "repairs: none\n";
  out << "repairs:\n";
  if (verticesWelded > 0) out << "  vertices welded: " << verticesWelded << "\n";
  if (trianglesDropped > 0) out << "  degenerate triangles dropped: " << trianglesDropped << "\n";
  if (trianglesReoriented > 0) out << "  triangles flipped to agree with their neighbours: " << trianglesReoriented << "\n";
  for (const ClosedHole& hole : holesClosed)
    out << "  hole closed: " << hole.edges << " edges, perimeter " << hole.perimeter << " m, cap area " << hole.area
        << " m^2\n";
  for (const ClosedHole& lid : lids)
    out << "  opening capped by a lid (open hull): " << lid.edges << " edges, loop length " << lid.perimeter
        << " m, lid area " << lid.area << " m^2 (no mass; open to liquid with flooding)\n";
  if (partsFlipped > 0) out << "  parts turned right side out: " << partsFlipped << " (" << flippedVolume << " m^3)\n";
  if (uvsDropped) out << "  artist UVs dropped (caps have none): the physics atlas is generated\n";
  for (const std::string& left : unrepaired) out << "  not repaired: " << left << "\n";
  return out.str();
}

Status RepairReport::requireRepaired(const std::string& what) const {
  if (unrepaired.empty()) return Ok{};
  return Error{what + ": " + unrepaired.front()};
}

}  // namespace hydrotex
