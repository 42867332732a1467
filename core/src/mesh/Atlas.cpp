// SPDX-License-Identifier: Zlib
/// @file Atlas.cpp
/// Chart growing by normal similarity with an overlap check inside each chart, area-preserving
/// chart scaling, and rectangle packing with stb_rect_pack (skyline bottom-left).

#include "hydrotex/mesh/Atlas.hpp"

#include <stb_rect_pack.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace hydrotex {
namespace {

constexpr std::uint32_t kNoNeighbour = std::numeric_limits<std::uint32_t>::max();
/// A triangle covering more cells than this in a chart's overlap grid starts a chart of its own
/// (keeps the overlap check local; such triangles are much larger than the chart's seed).
constexpr int kMaxCellsPerTriangle = 256;

/// Edge neighbours: across each of a triangle's three edges, the other triangle when exactly two
/// triangles share the edge (open and non-manifold edges separate charts).
std::vector<std::uint32_t> edgeNeighbours(const Mesh& mesh) {
  struct EdgeSlot {
    std::uint64_t key;
    std::uint32_t slot;  ///< triangle * 3 + edge
  };
  std::vector<EdgeSlot> slots;
  slots.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      const auto a = static_cast<std::uint32_t>(mesh.triangles[t][e]);
      const auto b = static_cast<std::uint32_t>(mesh.triangles[t][(e + 1) % 3]);
      if (a == b) continue;
      slots.push_back({(static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b),
                       static_cast<std::uint32_t>(t * 3 + static_cast<std::size_t>(e))});
    }
  std::sort(slots.begin(), slots.end(), [](const EdgeSlot& x, const EdgeSlot& y) { return x.key < y.key; });
  std::vector<std::uint32_t> neighbour(mesh.triangles.size() * 3, kNoNeighbour);
  for (std::size_t first = 0; first < slots.size();) {
    std::size_t last = first + 1;
    while (last < slots.size() && slots[last].key == slots[first].key) ++last;
    if (last - first == 2) {
      neighbour[slots[first].slot] = slots[first + 1].slot / 3;
      neighbour[slots[first + 1].slot] = slots[first].slot / 3;
    }
    first = last;
  }
  return neighbour;
}

/// Orthonormal in-plane axes (t1, t2) with t1 x t2 = normal, so counter-clockwise stays counter-clockwise.
void planeAxes(const Eigen::Vector3d& normal, Eigen::Vector3d& t1, Eigen::Vector3d& t2) {
  Eigen::Index smallest = 0;
  normal.cwiseAbs().minCoeff(&smallest);
  t1 = normal.cross(Eigen::Vector3d::Unit(smallest)).normalized();
  t2 = normal.cross(t1);
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// The triangles of the chart being grown, bucketed by grid cell (linked lists in one vector), to
/// test a candidate only against placed triangles near it.
class ChartGrid {
 public:
  explicit ChartGrid(double cellSize) : inverseCell_(1.0 / cellSize) {}

  /// Cell range of a bounding box, or false when it covers too many cells.
  bool cellRange(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, std::int64_t range[4]) const {
    range[0] = static_cast<std::int64_t>(std::floor(lo.x() * inverseCell_));
    range[1] = static_cast<std::int64_t>(std::floor(lo.y() * inverseCell_));
    range[2] = static_cast<std::int64_t>(std::floor(hi.x() * inverseCell_));
    range[3] = static_cast<std::int64_t>(std::floor(hi.y() * inverseCell_));
    return (range[2] - range[0] + 1) * (range[3] - range[1] + 1) <= kMaxCellsPerTriangle;
  }
  template <class Visit>
  bool anyInRange(const std::int64_t range[4], Visit&& visit) const {
    for (std::int64_t y = range[1]; y <= range[3]; ++y)
      for (std::int64_t x = range[0]; x <= range[2]; ++x) {
        const auto found = heads_.find(key(x, y));
        if (found == heads_.end()) continue;
        for (std::uint32_t entry = found->second; entry != kNoNeighbour; entry = entries_[entry].next)
          if (visit(entries_[entry].triangle)) return true;
      }
    return false;
  }
  void insert(const std::int64_t range[4], std::uint32_t triangle) {
    for (std::int64_t y = range[1]; y <= range[3]; ++y)
      for (std::int64_t x = range[0]; x <= range[2]; ++x) {
        const auto [it, inserted] = heads_.try_emplace(key(x, y), kNoNeighbour);
        entries_.push_back({triangle, it->second});
        it->second = static_cast<std::uint32_t>(entries_.size() - 1);
      }
  }

 private:
  static std::uint64_t key(std::int64_t x, std::int64_t y) {
    return (static_cast<std::uint64_t>(x) << 32) ^ (static_cast<std::uint64_t>(y) & 0xFFFFFFFFULL);
  }
  struct Entry {
    std::uint32_t triangle;
    std::uint32_t next;
  };
  double inverseCell_;
  std::unordered_map<std::uint64_t, std::uint32_t> heads_;
  std::vector<Entry> entries_;
};

struct Chart {
  std::vector<std::uint32_t> triangles;
  Eigen::Vector2d lo, hi;   ///< bounds of the projected (and then scaled) chart
  double area3d = 0.0;      ///< m^2
  double areaProjected = 0.0;
};

struct ChartBuilder {
  const Mesh& mesh;
  std::vector<Eigen::Vector3d> normals;           ///< unit, zero for degenerate triangles
  std::vector<std::uint32_t> neighbour;
  std::vector<std::uint32_t> chartOf;
  std::vector<Eigen::Vector2d> corners;           ///< per triangle corner, projected
  double typicalEdge = 0.0;

  explicit ChartBuilder(const Mesh& m) : mesh(m) {
    const std::size_t n = mesh.triangles.size();
    normals.resize(n);
    std::vector<double> longestEdges(n);
    for (std::size_t t = 0; t < n; ++t) {
      const Eigen::Vector3d& a = mesh.positions[mesh.triangles[t][0]];
      const Eigen::Vector3d& b = mesh.positions[mesh.triangles[t][1]];
      const Eigen::Vector3d& c = mesh.positions[mesh.triangles[t][2]];
      const Eigen::Vector3d normal = (b - a).cross(c - a);
      const double length = normal.norm();
      normals[t] = length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
      longestEdges[t] = std::sqrt(std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()}));
    }
    std::nth_element(longestEdges.begin(), longestEdges.begin() + static_cast<std::ptrdiff_t>(n / 2), longestEdges.end());
    typicalEdge = longestEdges[n / 2];
    neighbour = edgeNeighbours(mesh);
    chartOf.assign(n, kNoNeighbour);
    corners.resize(n * 3);
  }

  void project(std::uint32_t t, const Eigen::Vector3d& t1, const Eigen::Vector3d& t2) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d& p = mesh.positions[mesh.triangles[t][c]];
      corners[t * 3 + static_cast<std::uint32_t>(c)] = Eigen::Vector2d(p.dot(t1), p.dot(t2));
    }
  }

  Chart grow(std::uint32_t seed, std::uint32_t chartId) {
    Chart chart;
    const Eigen::Vector3d normal = normals[seed];
    Eigen::Vector3d t1, t2;
    planeAxes(normal.squaredNorm() > 0.0 ? normal : Eigen::Vector3d::UnitZ(), t1, t2);
    project(seed, t1, t2);
    const Eigen::Vector2d* seedCorners = &corners[seed * 3];
    const Eigen::Vector2d seedLo = seedCorners[0].cwiseMin(seedCorners[1]).cwiseMin(seedCorners[2]);
    const Eigen::Vector2d seedHi = seedCorners[0].cwiseMax(seedCorners[1]).cwiseMax(seedCorners[2]);
    const double cellSize = std::max({(seedHi - seedLo).maxCoeff(), typicalEdge, 1e-300});
    const double tolerance = 1e-9 * cellSize;
    ChartGrid grid(cellSize);

    chart.lo = seedLo;
    chart.hi = seedHi;
    std::vector<std::uint32_t> queue{seed};
    chartOf[seed] = chartId;
    std::int64_t range[4];
    // A degenerate seed (no normal) or one that is huge for the grid stays alone: a single
    // triangle is always a valid chart.
    const bool canGrow = normal.squaredNorm() > 0.0 && grid.cellRange(seedLo, seedHi, range);
    if (canGrow) grid.insert(range, seed);
    for (std::size_t next = 0; next < queue.size(); ++next) {
      const std::uint32_t current = queue[next];
      chart.triangles.push_back(current);
      if (!canGrow) break;
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t candidate = neighbour[current * 3 + static_cast<std::uint32_t>(e)];
        if (candidate == kNoNeighbour || chartOf[candidate] != kNoNeighbour) continue;
        if (normals[candidate].dot(normal) < kChartNormalCosine) continue;
        project(candidate, t1, t2);
        const Eigen::Vector2d* p = &corners[candidate * 3];
        if (!(cross2(p[1] - p[0], p[2] - p[0]) > 0.0)) continue;  // must keep its orientation
        const Eigen::Vector2d lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
        const Eigen::Vector2d hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
        if (!grid.cellRange(lo, hi, range)) continue;
        const bool overlaps = grid.anyInRange(range, [&](std::uint32_t placed) {
          return uvTrianglesOverlap(p, &corners[placed * 3], tolerance);
        });
        if (overlaps) continue;
        grid.insert(range, candidate);
        chartOf[candidate] = chartId;
        chart.lo = chart.lo.cwiseMin(lo);
        chart.hi = chart.hi.cwiseMax(hi);
        queue.push_back(candidate);
      }
    }
    for (std::uint32_t t : chart.triangles) {
      const Eigen::Vector2d* p = &corners[t * 3];
      chart.areaProjected += 0.5 * std::abs(cross2(p[1] - p[0], p[2] - p[0]));
      const Eigen::Vector3d& a = mesh.positions[mesh.triangles[t][0]];
      chart.area3d += 0.5 * (mesh.positions[mesh.triangles[t][1]] - a).cross(mesh.positions[mesh.triangles[t][2]] - a).norm();
    }
    return chart;
  }
};

/// Packs chart rectangles (sizes in metres after scaling) into the unit square; returns each
/// chart's lower-left corner in UV and the UV units per metre.
struct Packing {
  std::vector<Eigen::Vector2d> origin;
  double uvPerMetre = 0.0;
};

/// Packs the charts into [0,1]^2 with `gutter` packing cells of a grid of `side` cells between
/// them (an empty packing when they do not fit at any scale).
Packing packCharts(const std::vector<Chart>& charts, int side, int gutter) {
  const std::size_t count = charts.size();
  double sizeSum = 0.0;
  double largestSide = 0.0;
  for (const Chart& chart : charts) {
    const Eigen::Vector2d size = chart.hi - chart.lo;
    sizeSum += size.x() * size.y();
    largestSide = std::max(largestSide, size.maxCoeff());
  }
  double cellsPerMetre = sizeSum > 0.0 ? std::sqrt(0.7 * side * static_cast<double>(side) / sizeSum) : 1.0;
  if (largestSide > 0.0) cellsPerMetre = std::min(cellsPerMetre, (side - 2.0 * gutter) / largestSide);

  std::vector<stbrp_rect> rects(count);
  std::vector<stbrp_node> nodes(static_cast<std::size_t>(side));
  auto tryPack = [&](double scale) {
    for (std::size_t c = 0; c < count; ++c) {
      const Eigen::Vector2d size = (charts[c].hi - charts[c].lo) * scale;
      rects[c].id = static_cast<int>(c);
      rects[c].w = std::max(static_cast<stbrp_coord>(std::ceil(size.x())), 1) + gutter;
      rects[c].h = std::max(static_cast<stbrp_coord>(std::ceil(size.y())), 1) + gutter;
    }
    stbrp_context context;
    stbrp_init_target(&context, side, side, nodes.data(), side);
    return stbrp_pack_rects(&context, rects.data(), static_cast<int>(count)) == 1;
  };
  // Largest scale that packs: bracket it (grow or shrink by 10%), then bisect a few times.
  // Every attempt is one O(n log n) pack; many-chart atlases get fewer refinements.
  const int refinements = count < 20'000 ? 6 : 2;
  double good = 0.0, bad = 0.0;
  if (tryPack(cellsPerMetre)) {
    good = cellsPerMetre;
    for (int i = 0; i < refinements && bad == 0.0; ++i) {
      if (tryPack(good * 1.1)) good *= 1.1;
      else bad = good * 1.1;
    }
  } else {
    bad = cellsPerMetre;
    for (int i = 0; i < 200 && good == 0.0; ++i) {
      if (tryPack(bad * 0.9)) good = bad * 0.9;
      else bad *= 0.9;
    }
  }
  for (int i = 0; i < refinements && bad > 0.0 && good > 0.0; ++i) {
    const double middle = 0.5 * (good + bad);
    if (tryPack(middle)) good = middle;
    else bad = middle;
  }
  Packing packing;
  packing.origin.assign(count, Eigen::Vector2d::Zero());
  if (good == 0.0 || !tryPack(good)) return packing;
  for (const stbrp_rect& rect : rects)
    packing.origin[static_cast<std::size_t>(rect.id)] = Eigen::Vector2d(rect.x, rect.y) / side;
  packing.uvPerMetre = good / side;
  return packing;
}

/// Turns a chart in its plane to the angle (of 32 tried over 90 degrees) with the smallest
/// bounding rectangle: rectangles are what gets packed, so this is texture space regained.
void rotateToSmallestBounds(Chart& chart, std::vector<Eigen::Vector2d>& corners) {
  constexpr int kAngles = 32;
  double bestArea = std::numeric_limits<double>::infinity();
  double bestAngle = 0.0;
  for (int a = 0; a < kAngles; ++a) {
    const double angle = 0.5 * M_PI * a / kAngles;
    const Eigen::Vector2d axisU(std::cos(angle), std::sin(angle)), axisV(-std::sin(angle), std::cos(angle));
    double loU = std::numeric_limits<double>::infinity(), hiU = -loU, loV = loU, hiV = -loU;
    for (std::uint32_t t : chart.triangles)
      for (std::uint32_t c = 0; c < 3; ++c) {
        const Eigen::Vector2d& p = corners[t * 3 + c];
        const double u = axisU.dot(p), v = axisV.dot(p);
        loU = std::min(loU, u); hiU = std::max(hiU, u);
        loV = std::min(loV, v); hiV = std::max(hiV, v);
      }
    const double area = (hiU - loU) * (hiV - loV);
    if (area < bestArea) { bestArea = area; bestAngle = angle; }
  }
  if (bestAngle == 0.0) return;
  const Eigen::Rotation2Dd rotation(-bestAngle);  // coordinates on the rotated axes
  chart.lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  chart.hi = -chart.lo;
  for (std::uint32_t t : chart.triangles)
    for (std::uint32_t c = 0; c < 3; ++c) {
      Eigen::Vector2d& p = corners[t * 3 + c];
      p = rotation * p;
      chart.lo = chart.lo.cwiseMin(p);
      chart.hi = chart.hi.cwiseMax(p);
    }
}

}  // namespace

/// The charts packed as generateAtlas documents: one packing cell between charts, or, for a bake
/// of `texels` per side, more than one texel, unless that costs more than a fifth of the charts'
/// scale (many small charts), where the texel gutter would cost more resolution than the mixed
/// texels it avoids.
Packing packChartsFor(const std::vector<Chart>& charts, int texels) {
  // Packing grid: about 12 cells per chart at least (each rectangle takes >= 2 x 2 with its
  // gutter), 1024 to 16384 cells per side.
  const int side = static_cast<int>(
      std::clamp(std::ceil(std::sqrt(12.0 * static_cast<double>(charts.size()))) * 2.0, 1024.0, 16384.0));
  // At the last shrink every chart is a 2 x 2 cell rectangle, which always fits: a positive scale.
  Packing tight = packCharts(charts, side, 1);  // positive, so charts never touch
  if (texels <= 0) return tight;
  // A gap of more than 1 / texels in u and v: no texel reaches two charts.
  const int texelGutter = side / texels + 2;
  if (texelGutter <= 1) return tight;
  Packing apart = packCharts(charts, side, texelGutter);
  return apart.uvPerMetre >= 0.8 * tight.uvPerMetre ? apart : tight;
}

UvLayout generateAtlas(const Mesh& mesh, std::size_t* chartCount, int texels) {
  UvLayout layout;
  if (chartCount != nullptr) *chartCount = 0;
  const std::size_t n = mesh.triangles.size();
  if (n == 0) return layout;
  // loadMesh never yields these; a hand-built mesh might, and must not crash the generator.
  for (const Eigen::Vector3i& triangle : mesh.triangles)
    for (int c = 0; c < 3; ++c)
      if (triangle[c] < 0 || static_cast<std::size_t>(triangle[c]) >= mesh.positions.size()) return layout;
  for (const Eigen::Vector3d& position : mesh.positions)
    if (!position.allFinite()) return layout;
  ChartBuilder builder(mesh);
  std::vector<Chart> charts;
  for (std::uint32_t t = 0; t < n; ++t)
    if (builder.chartOf[t] == kNoNeighbour) charts.push_back(builder.grow(t, static_cast<std::uint32_t>(charts.size())));

  // Equal UV area per 3D area for every chart: scale each chart by sqrt(3D area / projected area).
  std::vector<double> chartScale(charts.size(), 1.0);
  for (std::size_t c = 0; c < charts.size(); ++c) {
    Chart& chart = charts[c];
    if (chart.triangles.size() > 1) rotateToSmallestBounds(chart, builder.corners);
    if (chart.areaProjected > 0.0) chartScale[c] = std::sqrt(chart.area3d / chart.areaProjected);
    chart.lo *= chartScale[c];
    chart.hi *= chartScale[c];
  }
  const Packing packing = packChartsFor(charts, texels);

  layout.uvs.reserve(n * 3);
  layout.uvTriangles.resize(n);
  // UV vertices are shared inside a chart (same mesh vertex, same chart), never across charts.
  std::vector<std::uint32_t> uvOfPosition(mesh.positions.size(), 0);
  std::vector<std::uint32_t> stampOfPosition(mesh.positions.size(), kNoNeighbour);
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const Chart& chart = charts[c];
    for (std::uint32_t t : chart.triangles) {
      for (int corner = 0; corner < 3; ++corner) {
        const auto position = static_cast<std::size_t>(mesh.triangles[t][corner]);
        if (stampOfPosition[position] != c) {
          stampOfPosition[position] = static_cast<std::uint32_t>(c);
          uvOfPosition[position] = static_cast<std::uint32_t>(layout.uvs.size());
          const Eigen::Vector2d local = builder.corners[t * 3 + static_cast<std::uint32_t>(corner)] * chartScale[c] - chart.lo;
          const Eigen::Vector2d uv = packing.origin[c] + local * packing.uvPerMetre;
          layout.uvs.push_back(uv.cwiseMax(Eigen::Vector2d::Zero()).cwiseMin(Eigen::Vector2d::Ones()));
        }
        layout.uvTriangles[t][corner] = static_cast<int>(uvOfPosition[position]);
      }
    }
  }
  if (chartCount != nullptr) *chartCount = charts.size();
  return layout;
}

PhysicsAtlas physicsAtlas(const Mesh& mesh, const MeshReport& report, int texels) {
  PhysicsAtlas atlas;
  if (report.uvUsableAsAtlas()) {
    atlas.layout = mesh.uv;
    atlas.reason = "the file's UVs are a valid atlas (inside [0,1], no overlap, no zero-area UV triangle)";
    return atlas;
  }
  if (!report.hasUv) atlas.reason = "no UVs in the file";
  else if (report.uvOverlap) atlas.reason = "the file's UVs overlap (" + std::to_string(report.uvOverlapPairs) + " pairs)";
  else if (!report.uvOverlapCheckComplete) atlas.reason = "the file's UVs could not be checked for overlap";
  else if (report.zeroUvAreaTriangles > 0)
    atlas.reason = std::to_string(report.zeroUvAreaTriangles) + " triangles have zero UV area";
  else atlas.reason = std::to_string(report.uvsOutsideUnitSquare) + " UVs lie outside [0,1]";
  atlas.reason += "; generated a physics atlas";
  atlas.layout = generateAtlas(mesh, &atlas.chartCount, texels);
  atlas.generated = true;
  return atlas;
}

}  // namespace hydrotex
