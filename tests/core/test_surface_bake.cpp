// SPDX-License-Identifier: Zlib
// The exact texel bake: closure, areas and enclosed volume against the polyhedral reference at
// several resolutions, re-evaluation from moved vertices, layout order, and bad input.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <string>

#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

BakeSettings square(int resolution, int tile = 16) {
  BakeSettings s;
  s.width = s.height = resolution;
  s.tileSize = tile;
  return s;
}

double meshArea(const Mesh& mesh) {
  double a = 0.0;
  for (const auto& t : mesh.triangles)
    a += 0.5 * (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]).norm();
  return a;
}

struct TextureSums {
  Eigen::Vector3d areaVector = Eigen::Vector3d::Zero();
  double area = 0.0;
  double volume = 0.0;  // sum p . A / 3 (divergence theorem with the field x / 3)
};

TextureSums sums(const SurfaceTextures& tex) {
  TextureSums s;
  for (std::size_t i = 0; i < tex.size(); ++i) {
    s.areaVector += tex.areaVector[i].cast<double>();
    s.area += tex.area[i];
    s.volume += tex.position[i].cast<double>().dot(tex.areaVector[i].cast<double>()) / 3.0;
  }
  return s;
}

}  // namespace

TEST_CASE("texel sums are exact: closure, area and enclosed volume at any resolution") {
  const std::vector<std::pair<std::string, Mesh>> meshes = {
      {"box", prim::box({1.0, 2.0, 3.0})},
      {"uv sphere", prim::uvSphere(1.0, 32, 16)},
      {"cylinder", prim::cylinder(0.5, 2.0, 24)},
      {"torus (non-convex)", prim::torus(1.0, 0.3, 48, 16)},
      {"wigley (non-convex deck corners)", prim::wigleyHull(4.0, 0.4, 0.25, 24, 8)},
      {"icosphere", prim::icosphere(1.0, 2)}};
  for (const auto& [name, mesh] : meshes) {
    const auto exact = polyhedralMassProperties(mesh, 1.0);
    REQUIRE(exact.ok());
    const double area = meshArea(mesh);
    for (int resolution : {16, 64, 256, 1000}) {
      INFO(name << " at " << resolution);
      const auto bake = bakeSurface(mesh, mesh.uv, square(resolution));
      REQUIRE(bake.ok());
      const SurfaceTextures tex = evaluateSurface(*bake, mesh, mesh.uv);
      const TextureSums s = sums(tex);
      // Float storage: each texel's numbers carry ~6e-8 relative rounding; summed over up to 1e6
      // texels with random signs that stays well below 1e-6 of the totals.
      CHECK(s.areaVector.norm() / area < 1e-6);
      CHECK(s.area == Approx(area).epsilon(1e-6));
      CHECK(s.volume == Approx(exact->volume).epsilon(1e-6));
    }
  }
}

TEST_CASE("re-evaluation from moved vertices needs no new bake") {
  const Mesh mesh = prim::torus(1.0, 0.3, 32, 12);
  const auto bake = bakeSurface(mesh, mesh.uv, square(128));
  REQUIRE(bake.ok());
  const double volume = sums(evaluateSurface(*bake, mesh, mesh.uv)).volume;
  Mesh scaled = mesh;
  for (auto& p : scaled.positions) p *= 2.0;
  const TextureSums s = sums(evaluateSurface(*bake, scaled, mesh.uv));
  // Scaling by 2 multiplies the volume by 8 and the area by 4, to float rounding (1e-6).
  CHECK(s.volume == Approx(8.0 * volume).epsilon(1e-6));
  CHECK(s.area == Approx(4.0 * meshArea(mesh)).epsilon(1e-6));
  // A non-uniform deformation: the texel volume follows the polyhedral one of the moved mesh.
  Mesh sheared = mesh;
  for (auto& p : sheared.positions) p = Eigen::Vector3d(p.x() + 0.3 * p.y(), 1.5 * p.y(), p.z() - 0.2 * p.x());
  const auto exact = polyhedralMassProperties(sheared, 1.0);
  REQUIRE(exact.ok());
  CHECK(sums(evaluateSurface(*bake, sheared, mesh.uv)).volume == Approx(exact->volume).epsilon(1e-6));
}

TEST_CASE("bake layout: tiles, texel order, pieces and texel geometry") {
  const Mesh mesh = prim::uvSphere(1.0, 24, 12);
  const int resolution = 100, tile = 16;  // 100 is not a multiple of 16: partial edge tiles
  const auto bake = bakeSurface(mesh, mesh.uv, square(resolution, tile));
  REQUIRE(bake.ok());
  const int tilesX = bake->tilesX();
  CHECK(tilesX == 7);
  REQUIRE(bake->tileStart.size() == static_cast<std::size_t>(tilesX * bake->tilesY() + 1));
  CHECK(bake->tileStart.back() == bake->coveredCount());
  CHECK(bake->pieceStart.size() == bake->coveredCount() + 1);
  CHECK(bake->pieceStart.back() == bake->pieces.size());
  // Every covered texel lies in its tile's range, tiles are in row-major order, and texels within
  // a tile in row-major order.
  for (int t = 0; t + 1 < static_cast<int>(bake->tileStart.size()); ++t) {
    std::uint32_t previous = 0;
    for (auto i = bake->tileStart[t]; i < bake->tileStart[t + 1]; ++i) {
      const int row = static_cast<int>(bake->texelIndex[i]) / resolution;
      const int column = static_cast<int>(bake->texelIndex[i]) % resolution;
      CHECK((row / tile) * tilesX + column / tile == t);
      if (i > bake->tileStart[t]) CHECK(bake->texelIndex[i] > previous);
      previous = bake->texelIndex[i];
      CHECK(bake->pieceStart[i + 1] > bake->pieceStart[i]);  // covered texels have pieces
    }
  }
  for (const auto& piece : bake->pieces) {
    CHECK((piece.areaFraction > 0.0f && piece.areaFraction <= 1.0f + 1e-6f));
    // The centroid of a piece lies inside its triangle (barycentrics in [0,1], float slack).
    CHECK((piece.centroidBary1 >= -1e-6f && piece.centroidBary2 >= -1e-6f &&
           piece.centroidBary1 + piece.centroidBary2 <= 1.0f + 1e-6f));
  }
  // A texel wholly inside one triangle has area |edgeU x edgeV| and its edges lie in the
  // triangle's plane; every single-triangle texel's position lies on that plane (float: 1e-6 m).
  const SurfaceTextures tex = evaluateSurface(*bake, mesh, mesh.uv);
  int whole = 0;
  for (std::size_t i = 0; i < tex.size(); ++i) {
    const auto first = bake->pieceStart[i];
    if (bake->pieceStart[i + 1] - first != 1) continue;
    const auto& tri = mesh.triangles[bake->pieces[first].triangle];
    const Eigen::Vector3d a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    const Eigen::Vector3f span = tex.edgeU[i].cross(tex.edgeV[i]);
    // One piece of area < a whole texel's only when it is cut; a whole texel has area |eu x ev|.
    if (std::abs(span.norm() - tex.area[i]) < 1e-4f * span.norm()) {
      ++whole;
      // edges lie in the triangle's plane
      CHECK(std::abs(tex.edgeU[i].cast<double>().dot(normal)) < 1e-6);
      CHECK(std::abs(tex.edgeV[i].cast<double>().dot(normal)) < 1e-6);
    }
    CHECK(std::abs((tex.position[i].cast<double>() - a).dot(normal)) < 1e-6);  // on the plane
  }
  CHECK(whole > 100);
}

TEST_CASE("bad settings and layouts are errors") {
  const Mesh mesh = prim::box({1.0, 1.0, 1.0});
  CHECK_FALSE(bakeSurface(mesh, mesh.uv, square(15)).ok());
  CHECK_FALSE(bakeSurface(mesh, mesh.uv, square(4097)).ok());
  CHECK_FALSE(bakeSurface(mesh, mesh.uv, square(0)).ok());
  CHECK_FALSE(bakeSurface(mesh, mesh.uv, square(100000)).ok());
  CHECK_FALSE(bakeSurface(mesh, mesh.uv, square(64, 0)).ok());
  CHECK_FALSE(bakeSurface(mesh, mesh.uv, square(64, 257)).ok());
  CHECK(bakeSurface(mesh, mesh.uv, square(16, 1)).ok());
  CHECK(bakeSurface(mesh, mesh.uv, square(4096, 256)).ok());

  UvLayout missing = mesh.uv;
  missing.uvTriangles.pop_back();
  const auto notCovered = bakeSurface(mesh, missing, square(64));
  REQUIRE_FALSE(notCovered.ok());
  CHECK(notCovered.error().message.find("UV") != std::string::npos);

  CHECK_FALSE(bakeSurface(mesh, UvLayout{}, square(64)).ok());

  UvLayout outside = mesh.uv;
  outside.uvs[0].x() = 1.5;
  CHECK_FALSE(bakeSurface(mesh, outside, square(64)).ok());

  UvLayout notFinite = mesh.uv;
  notFinite.uvs[1].y() = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(bakeSurface(mesh, notFinite, square(64)).ok());

  Mesh nanMesh = mesh;
  nanMesh.positions[2].z() = std::numeric_limits<double>::infinity();
  CHECK_FALSE(bakeSurface(nanMesh, mesh.uv, square(64)).ok());

  UvLayout collapsed = mesh.uv;  // a UV triangle of zero area under a real 3D triangle
  const auto t = collapsed.uvTriangles[0];
  collapsed.uvs.push_back(collapsed.uvs[t[0]]);
  collapsed.uvTriangles[0] = Eigen::Vector3i(t[0], t[0], static_cast<int>(collapsed.uvs.size()) - 1);
  const auto degenerate = bakeSurface(mesh, collapsed, square(64));
  REQUIRE_FALSE(degenerate.ok());
  CHECK(degenerate.error().message.find("zero UV area") != std::string::npos);

  UvLayout badIndex = mesh.uv;
  badIndex.uvTriangles[3][1] = 1000;
  CHECK_FALSE(bakeSurface(mesh, badIndex, square(64)).ok());

  CHECK_FALSE(bakeSurface(Mesh{}, UvLayout{}, square(64)).ok());
}
