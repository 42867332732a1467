// SPDX-License-Identifier: Zlib
// Physics atlas: artist UVs kept when valid; otherwise a generated atlas that covers every
// triangle, lies in [0,1]^2, has no overlap and a uniform texel density.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/mesh/Atlas.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using hydrotex::Mesh;

namespace {

double triangleArea3d(const Mesh& mesh, std::size_t t) {
  const auto& tri = mesh.triangles[t];
  return 0.5 * (mesh.positions[tri[1]] - mesh.positions[tri[0]]).cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]).norm();
}

double triangleAreaUv(const hydrotex::UvLayout& layout, std::size_t t) {
  const auto& tri = layout.uvTriangles[t];
  const Eigen::Vector2d e1 = layout.uvs[tri[1]] - layout.uvs[tri[0]], e2 = layout.uvs[tri[2]] - layout.uvs[tri[0]];
  return 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
}

/// Checks a generated atlas with the validator and returns max/min texel density
/// (UV area per 3D area) over the non-degenerate triangles.
double checkGeneratedAtlas(const Mesh& mesh, const hydrotex::PhysicsAtlas& atlas) {
  REQUIRE(atlas.generated);
  REQUIRE(atlas.layout.coversTriangles(mesh.triangles.size()));
  Mesh withAtlas = mesh;
  withAtlas.uv = atlas.layout;
  const auto report = hydrotex::validateMesh(withAtlas);
  CHECK(report.hasUv);
  CHECK_FALSE(report.uvOverlap);
  CHECK(report.uvOverlapCheckComplete);
  CHECK(report.uvsOutsideUnitSquare == 0);
  CHECK(report.zeroUvAreaTriangles == 0);
  CHECK(report.uvUsableAsAtlas());
  for (const auto& uv : atlas.layout.uvs) {
    CHECK(uv.x() >= 0.0);
    CHECK(uv.x() <= 1.0);
    CHECK(uv.y() >= 0.0);
    CHECK(uv.y() <= 1.0);
  }
  double lowest = std::numeric_limits<double>::infinity(), highest = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const double area = triangleArea3d(mesh, t);
    if (area <= 0.0) continue;
    const double density = triangleAreaUv(atlas.layout, t) / area;
    lowest = std::min(lowest, density);
    highest = std::max(highest, density);
  }
  return highest / lowest;
}

/// Within a chart, projection scales a triangle's area by cos(angle to the chart normal), in
/// [kChartNormalCosine, 1]; each chart is scaled to the same mean density, so over the atlas the
/// density varies at most by 1 / kChartNormalCosine^2 (plus float-free rounding: 1e-9).
const double kDensityBound = 1.0 / (hydrotex::kChartNormalCosine * hydrotex::kChartNormalCosine) + 1e-9;

/// A flat ramp winding twice around the y axis: nearly every normal is +y, so a chart grown by
/// normals alone would lay the second turn on top of the first in projection.
Mesh doubleSpiralRamp(int segments) {
  Mesh mesh;
  mesh.sourceName = "ramp";
  for (int i = 0; i <= segments; ++i) {
    const double angle = 4.0 * M_PI * i / segments;
    const double height = 0.02 * angle;
    mesh.positions.emplace_back(std::cos(angle), height, -std::sin(angle));
    mesh.positions.emplace_back(2.0 * std::cos(angle), height, -2.0 * std::sin(angle));
  }
  for (int i = 0; i < segments; ++i) {
    const int a = 2 * i;
    mesh.triangles.emplace_back(a, a + 3, a + 1);
    mesh.triangles.emplace_back(a, a + 2, a + 3);
  }
  return mesh;
}

}  // namespace

TEST_CASE("Valid artist UVs are used as they are", "[atlas]") {
  const Mesh torus = hydrotex::primitives::torus(1.0, 0.25, 32, 16);
  const auto report = hydrotex::validateMesh(torus);
  REQUIRE(report.uvUsableAsAtlas());
  const auto atlas = hydrotex::physicsAtlas(torus, report);
  CHECK_FALSE(atlas.generated);
  CHECK(atlas.layout.uvs == torus.uv.uvs);
  CHECK(atlas.layout.uvTriangles == torus.uv.uvTriangles);
}

TEST_CASE("A mesh without UVs gets a generated atlas", "[atlas]") {
  Mesh sphere = hydrotex::primitives::icosphere(1.5, 4);  // 5120 triangles
  sphere.uv = {};
  const auto report = hydrotex::validateMesh(sphere);
  const auto atlas = hydrotex::physicsAtlas(sphere, report);
  CHECK(atlas.reason.find("no UVs") != std::string::npos);
  const double densitySpread = checkGeneratedAtlas(sphere, atlas);
  CHECK(densitySpread <= kDensityBound);
  // Charts are far fewer than triangles (a sphere needs about a dozen 37-degree caps).
  CHECK(atlas.chartCount < sphere.triangles.size() / 20);
}

TEST_CASE("Overlapping artist UVs are replaced, and left untouched", "[atlas]") {
  Mesh box = hydrotex::primitives::subdividedBox(Eigen::Vector3d(3.0, 1.0, 0.5), 4);
  // Stack every triangle's UVs on one triangle: the worst artist layout.
  box.uv.uvs = {{0.1, 0.1}, {0.9, 0.1}, {0.1, 0.9}};
  box.uv.uvTriangles.assign(box.triangles.size(), Eigen::Vector3i(0, 1, 2));
  const hydrotex::UvLayout artist = box.uv;
  const auto report = hydrotex::validateMesh(box);
  REQUIRE(report.uvOverlap);
  const auto atlas = hydrotex::physicsAtlas(box, report);
  CHECK(atlas.reason.find("overlap") != std::string::npos);
  const double densitySpread = checkGeneratedAtlas(box, atlas);
  // Flat faces: every triangle lies in its chart's plane, so density is uniform to rounding
  // (rounding of positions to UV: 1e-9 relative).
  CHECK(densitySpread == Approx(1.0).epsilon(1e-9));
  CHECK(atlas.chartCount == 6);  // one chart per box face
  CHECK(box.uv.uvs == artist.uvs);
  CHECK(box.uv.uvTriangles == artist.uvTriangles);
}

TEST_CASE("Charts do not overlap themselves where the surface winds over itself", "[atlas]") {
  const Mesh ramp = doubleSpiralRamp(400);
  const auto report = hydrotex::validateMesh(ramp);
  const auto atlas = hydrotex::physicsAtlas(ramp, report);
  const double densitySpread = checkGeneratedAtlas(ramp, atlas);
  CHECK(densitySpread <= kDensityBound);
  CHECK(atlas.chartCount >= 2);  // one chart cannot hold both turns
}

TEST_CASE("Degenerate triangles and open, non-manifold meshes still get an atlas", "[atlas]") {
  Mesh mesh = hydrotex::primitives::box(Eigen::Vector3d(1, 1, 1));
  mesh.uv = {};
  mesh.positions.emplace_back(0.5, 0.5, 0.5);
  mesh.positions.emplace_back(0.5, 0.5, 0.5);
  mesh.triangles.emplace_back(0, static_cast<int>(mesh.positions.size()) - 1, static_cast<int>(mesh.positions.size()) - 2);
  mesh.triangles.erase(mesh.triangles.begin());  // open as well
  const auto atlas = hydrotex::physicsAtlas(mesh, hydrotex::validateMesh(mesh));
  checkGeneratedAtlas(mesh, atlas);
}

TEST_CASE("A curved mesh of 80k triangles gets an overlap-free atlas", "[atlas][large]") {
  Mesh torus = hydrotex::primitives::torus(2.0, 0.5, 400, 100);  // 80,000 triangles
  torus.uv = {};
  const auto atlas = hydrotex::physicsAtlas(torus, hydrotex::validateMesh(torus));
  CHECK(checkGeneratedAtlas(torus, atlas) <= kDensityBound);
}

TEST_CASE("For a known bake resolution, no texel holds pieces of two charts", "[atlas][bake]") {
  // A texel's pieces of two charts may lie on faces far apart (a box's floor and a side), which
  // its one position cannot stand for where the waterline passes between them (the open hull's
  // draft, test_open_hull). With the bake's texels per side, the gutter is more than a texel, so
  // every texel's pieces lie on one face of the box: their triangles' normals agree (to rounding).
  // (At 16 texels a side a texel gutter would shrink the six charts by more than a fifth, so the
  // one-cell gutter stays there: generateAtlas.)
  Mesh box = hydrotex::primitives::subdividedBox(Eigen::Vector3d(2.0, 0.5, 1.0), 4);
  box.uv = {};
  const auto report = hydrotex::validateMesh(box);
  auto mixedTexels = [&](int atlasTexels, int bakeTexels) {
    const auto atlas = hydrotex::physicsAtlas(box, report, atlasTexels);
    checkGeneratedAtlas(box, atlas);
    hydrotex::BakeSettings settings;
    settings.width = settings.height = bakeTexels;
    const auto bake = hydrotex::bakeSurface(box, atlas.layout, settings);
    REQUIRE(bake);
    auto normalOf = [&](std::uint32_t t) {
      const auto& tri = box.triangles[t];
      return Eigen::Vector3d((box.positions[tri[1]] - box.positions[tri[0]]).cross(box.positions[tri[2]] - box.positions[tri[0]]).normalized());
    };
    int mixed = 0;
    for (std::size_t i = 0; i + 1 < bake->pieceStart.size(); ++i) {
      const Eigen::Vector3d first = normalOf(bake->pieces[bake->pieceStart[i]].triangle);
      for (std::uint32_t k = bake->pieceStart[i] + 1; k < bake->pieceStart[i + 1]; ++k)
        if (normalOf(bake->pieces[k].triangle).dot(first) < 1.0 - 1e-9) {
          ++mixed;
          break;
        }
    }
    return mixed;
  };
  for (int texels : {32, 64, 256}) {
    CAPTURE(texels);
    CHECK(mixedTexels(texels, texels) == 0);
  }
  // Without the resolution, the one-cell gutter lets texels of a coarse bake reach two charts:
  // the case above is not vacuous.
  CHECK(mixedTexels(0, 64) > 0);
}
