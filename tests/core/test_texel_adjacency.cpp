// SPDX-License-Identifier: Zlib
// The texel graph: exact interface lengths inside charts and across seams, connectivity across
// every seam of closed primitives.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <queue>

#include "TestSurfaces.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/bake/TexelAdjacency.hpp"

using namespace hydrotex;

namespace {

// A flat square plate of side `side` in the plane y = 0 whose UVs fill [0,1]^2 (u along x, v
// along z); two triangles, so the diagonal crosses texels.
Mesh plate(double side) { return test::squarePlate(side); }

TexelAdjacency build(const Mesh& mesh, int resolution) {
  auto graph = buildTexelAdjacency(test::bakeOf(mesh, resolution), mesh, mesh.uv);
  REQUIRE(graph.ok());
  return std::move(graph).value();
}

// Texels with area reachable from the first such texel through pairs.
std::size_t reachable(const TexelAdjacency& graph) {
  std::vector<std::vector<std::uint32_t>> next(graph.area.size());
  for (std::size_t p = 0; p < graph.pairCount(); ++p) {
    next[graph.first[p]].push_back(graph.second[p]);
    next[graph.second[p]].push_back(graph.first[p]);
  }
  std::vector<char> seen(graph.area.size(), 0);
  std::size_t start = 0;
  while (start < graph.area.size() && graph.area[start] <= 0.0) ++start;
  std::queue<std::uint32_t> queue;
  queue.push(static_cast<std::uint32_t>(start));
  seen[start] = 1;
  std::size_t count = 0;
  while (!queue.empty()) {
    const auto i = queue.front();
    queue.pop();
    ++count;
    for (auto j : next[i])
      if (!seen[j]) seen[j] = 1, queue.push(j);
  }
  return count;
}

std::size_t texelsWithArea(const TexelAdjacency& graph) {
  std::size_t count = 0;
  for (double a : graph.area) count += a > 0.0;
  return count;
}

// Sum of the 3D lengths of the mesh edges whose two triangles have different UV edges.
double seamEdgeLength(const Mesh& mesh) {
  std::map<std::pair<int, int>, std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>> edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& f = mesh.triangles[t];
    const double area = (mesh.positions[f[1]] - mesh.positions[f[0]]).cross(mesh.positions[f[2]] - mesh.positions[f[0]]).norm();
    if (area <= 1e-14) continue;
    for (int k = 0; k < 3; ++k) {
      int a = f[k], b = f[(k + 1) % 3];
      Eigen::Vector2d ua = mesh.uv.uvs[mesh.uv.uvTriangles[t][k]], ub = mesh.uv.uvs[mesh.uv.uvTriangles[t][(k + 1) % 3]];
      if (a > b) std::swap(a, b), std::swap(ua, ub);
      edges[{a, b}].push_back({ua, ub});
    }
  }
  double total = 0.0;
  for (const auto& [key, sides] : edges)
    if (sides.size() == 2 && (sides[0].first != sides[1].first || sides[0].second != sides[1].second))
      total += (mesh.positions[key.second] - mesh.positions[key.first]).norm();
  return total;
}

}  // namespace

TEST_CASE("A flat plate's graph is the regular grid with unit conductances", "[adjacency]") {
  const int n = 64;
  const TexelAdjacency graph = build(plate(2.0), n);
  // Every texel is covered; the pairs are the grid's 2 n (n - 1) edges, none across a seam.
  REQUIRE(graph.area.size() == static_cast<std::size_t>(n * n));
  CHECK(graph.pairCount() == static_cast<std::size_t>(2 * n * (n - 1)));
  CHECK(graph.seamPairCount() == 0);
  // A square texel of side h: interface h, centroid distance h, so g = 1 exactly; the diagonal
  // crossing texels must not change that (lengths from both triangles add). Lengths are clipped in
  // double: 1e-9.
  for (std::size_t p = 0; p < graph.pairCount(); ++p) {
    // (the centroids come from the bake's float barycentrics: 1e-5)
    REQUIRE(graph.conductance[p] == Approx(1.0).epsilon(1e-5));
    REQUIRE(graph.interfaceLength[p] == Approx(2.0 / n).epsilon(1e-9));
  }
  // Explicit bound A / (D sum g) = h^2 / (4 D) for interior texels (docs/references.md).
  const double h = 2.0 / n, diffusivity = 1e-3;
  CHECK(graph.stableTimeStep(diffusivity) == Approx(h * h / (4.0 * diffusivity)).epsilon(1e-5));  // float centroids
}

TEST_CASE("UV sphere: seams are paired along their whole 3D length and the graph is connected", "[adjacency]") {
  const Mesh sphere = primitives::uvSphere(1.0, 32, 16);
  const TexelAdjacency graph = build(sphere, 128);
  CHECK(graph.seamPairCount() > 0);
  double seamLength = 0.0;
  for (std::size_t p = 0; p < graph.pairCount(); ++p)
    if (graph.acrossSeam[p]) seamLength += graph.interfaceLength[p];
  // Every stretch of every seam edge lies in one covered texel on each side, so the paired lengths
  // (plus stretches whose two sides share one texel) add up to the seam edges' total 3D length;
  // only rounding of the breakpoints differs (1e-9).
  CHECK(graph.seamLengthUncovered == 0.0);
  CHECK(seamLength + graph.seamLengthInOneTexel == Approx(seamEdgeLength(sphere)).epsilon(1e-9));
  CHECK(reachable(graph) == texelsWithArea(graph));
}

TEST_CASE("Box and icosphere: charts joined across every border", "[adjacency]") {
  for (const Mesh& mesh : {primitives::box(Eigen::Vector3d(1.0, 0.5, 2.0)), primitives::icosphere(1.0, 2)}) {
    const TexelAdjacency graph = build(mesh, 128);
    double seamLength = 0.0;
    for (std::size_t p = 0; p < graph.pairCount(); ++p)
      if (graph.acrossSeam[p]) seamLength += graph.interfaceLength[p];
    CAPTURE(mesh.sourceName);
    CHECK(graph.seamLengthUncovered == 0.0);
    CHECK(seamLength + graph.seamLengthInOneTexel == Approx(seamEdgeLength(mesh)).epsilon(1e-9));
    CHECK(reachable(graph) == texelsWithArea(graph));
    // Texel areas add up to the surface area (the bake's pieces are exact; float fractions: 1e-5).
    double area = 0.0, exact = 0.0;
    for (double a : graph.area) area += a;
    for (const auto& f : mesh.triangles)
      exact += 0.5 * (mesh.positions[f[1]] - mesh.positions[f[0]]).cross(mesh.positions[f[2]] - mesh.positions[f[0]]).norm();
    CHECK(area == Approx(exact).epsilon(1e-5));
  }
}

TEST_CASE("Mismatched bake and mesh are refused", "[adjacency]") {
  const Mesh mesh = plate(1.0);
  BakeSettings settings;
  settings.width = settings.height = 16;
  auto bake = bakeSurface(mesh, mesh.uv, settings);
  REQUIRE(bake.ok());
  UvLayout empty;
  CHECK_FALSE(buildTexelAdjacency(*bake, mesh, empty).ok());
  Mesh fewer = mesh;
  fewer.triangles.pop_back();
  fewer.uv.uvTriangles.pop_back();
  auto result = buildTexelAdjacency(*bake, fewer, fewer.uv);
  REQUIRE_FALSE(result.ok());
  CHECK(result.error().message.find("triangle") != std::string::npos);
}
