// SPDX-License-Identifier: Zlib
// Primitives: closed, outward, merged vertices, valid UV atlases, and volumes against the
// polyhedra's own closed forms.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

constexpr double kPi = std::numbers::pi;

struct NamedMesh {
  std::string name;
  Mesh mesh;
};

std::vector<NamedMesh> allPrimitives() {
  return {{"box", prim::box({1.0, 2.0, 3.0})},
          {"subdivided box", prim::subdividedBox({2.0, 1.0, 1.5}, 5)},
          {"uv sphere", prim::uvSphere(1.5, 24, 12)},
          {"icosphere", prim::icosphere(1.0, 3)},
          {"cylinder", prim::cylinder(0.5, 2.0, 20)},
          {"cone", prim::cone(1.0, 2.0, 24)},
          {"capsule", prim::capsule(0.5, 1.2, 24, 6)},
          {"capsule without cylinder", prim::capsule(0.5, 0.0, 24, 6)},
          {"torus", prim::torus(1.0, 0.3, 32, 12)},
          {"hemisphere up", prim::hemisphere(1.0, 24, 8, true)},
          {"hemisphere down", prim::hemisphere(1.0, 24, 8, false)},
          {"wigley", prim::wigleyHull(4.0, 0.4, 0.25, 20, 8)}};
}

// Independent closedness check: every directed edge has exactly one opposite twin.
bool everyEdgeHasOneTwin(const Mesh& mesh) {
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++count[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, n] : count) {
    if (n != 1) return false;
    auto twin = count.find({edge.second, edge.first});
    if (twin == count.end() || twin->second != 1) return false;
  }
  return true;
}

// Signed volume by the divergence theorem (sum of tetrahedra from the origin).
double signedVolume(const Mesh& mesh) {
  double v = 0.0;
  for (const auto& t : mesh.triangles)
    v += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]])) / 6.0;
  return v;
}

}  // namespace

TEST_CASE("primitives are closed, outward, merged, with UV atlases inside the unit square") {
  for (const auto& [name, mesh] : allPrimitives()) {
    INFO(name);
    REQUIRE(mesh.hasUvs());
    CHECK(everyEdgeHasOneTwin(mesh));
    CHECK(signedVolume(mesh) > 0.0);  // outward winding gives a positive volume
    // Merged: no two vertices share a position (exact comparison: merging is by index).
    std::vector<std::array<double, 3>> sorted;
    for (const auto& p : mesh.positions) sorted.push_back({p.x(), p.y(), p.z()});
    std::sort(sorted.begin(), sorted.end());
    CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    // UVs inside [0,1]^2 and no UV triangle degenerate (relative to the atlas: 1e-12).
    for (const auto& uv : mesh.uv.uvs) CHECK((uv.minCoeff() >= 0.0 && uv.maxCoeff() <= 1.0));
    for (const auto& t : mesh.uv.uvTriangles) {
      const Eigen::Vector2d a = mesh.uv.uvs[t[1]] - mesh.uv.uvs[t[0]], b = mesh.uv.uvs[t[2]] - mesh.uv.uvs[t[0]];
      CHECK(std::abs(a.x() * b.y() - a.y() * b.x()) > 1e-12);
    }
  }
}

TEST_CASE("primitive UV atlases do not overlap") {
  // An overlap shows in the bake as a texel covered by more UV area than the texel has. The
  // covered area per texel is summed in double from float fractions: 1e-5 texel of slack.
  for (const auto& [name, mesh] : allPrimitives()) {
    INFO(name);
    BakeSettings settings;
    settings.width = settings.height = 256;
    auto bake = bakeSurface(mesh, mesh.uv, settings);
    REQUIRE(bake.ok());
    std::vector<double> uvArea(mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.uv.uvTriangles[t];
      const Eigen::Vector2d a = mesh.uv.uvs[tri[1]] - mesh.uv.uvs[tri[0]], b = mesh.uv.uvs[tri[2]] - mesh.uv.uvs[tri[0]];
      uvArea[t] = 0.5 * std::abs(a.x() * b.y() - a.y() * b.x()) * 256.0 * 256.0;  // in texels
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < bake->coveredCount(); ++i) {
      double covered = 0.0;
      for (auto k = bake->pieceStart[i]; k < bake->pieceStart[i + 1]; ++k)
        covered += bake->pieces[k].areaFraction * uvArea[bake->pieces[k].triangle];
      worst = std::max(worst, covered);
    }
    CHECK(worst <= 1.0 + 1e-5);
  }
}

TEST_CASE("primitive volumes match the polyhedra's closed forms") {
  SECTION("box: exact") {
    // Eberly's sums on 12 triangles: rounding only, 1e-12 relative.
    const auto mp = polyhedralMassProperties(prim::box({1.0, 2.0, 3.0}), 1.0);
    REQUIRE(mp.ok());
    CHECK(mp->volume == Approx(6.0).epsilon(1e-12));
    const auto sub = polyhedralMassProperties(prim::subdividedBox({1.0, 2.0, 3.0}, 7), 1.0);
    REQUIRE(sub.ok());
    CHECK(sub->volume == Approx(6.0).epsilon(1e-12));
  }
  SECTION("cylinder and cone: polygon prism and pyramid") {
    const int n = 20;
    const double polygon = 0.5 * n * 0.25 * std::sin(2.0 * kPi / n);  // regular n-gon of radius 0.5
    CHECK(signedVolume(prim::cylinder(0.5, 2.0, n)) == Approx(polygon * 2.0).epsilon(1e-12));
    const double base = 0.5 * n * std::sin(2.0 * kPi / n);  // radius 1
    CHECK(signedVolume(prim::cone(1.0, 2.0, n)) == Approx(base * 2.0 / 3.0).epsilon(1e-12));
  }
  SECTION("smooth shapes converge to their analytic volumes at second order") {
    // The inscribed polyhedron's volume error shrinks like 1/n^2: doubling the segments must
    // cut it by about 4 (between 3 and 5).
    auto ratio = [](double coarseErr, double fineErr) { return coarseErr / fineErr; };
    const double sphere = 4.0 / 3.0 * kPi;
    const double e1 = std::abs(signedVolume(prim::uvSphere(1.0, 32, 16)) - sphere);
    const double e2 = std::abs(signedVolume(prim::uvSphere(1.0, 64, 32)) - sphere);
    CHECK(ratio(e1, e2) == Approx(4.0).margin(1.0));
    const double torus = 2.0 * kPi * kPi * 1.0 * 0.09;
    const double t1 = std::abs(signedVolume(prim::torus(1.0, 0.3, 32, 16)) - torus);
    const double t2 = std::abs(signedVolume(prim::torus(1.0, 0.3, 64, 32)) - torus);
    CHECK(ratio(t1, t2) == Approx(4.0).margin(1.0));
    const double wigley = 4.0 / 9.0 * 4.0 * 0.4 * 0.25;
    const double w1 = std::abs(signedVolume(prim::wigleyHull(4.0, 0.4, 0.25, 16, 8)) - wigley);
    const double w2 = std::abs(signedVolume(prim::wigleyHull(4.0, 0.4, 0.25, 32, 16)) - wigley);
    CHECK(ratio(w1, w2) == Approx(4.0).margin(1.0));
    CHECK(w2 / wigley < 0.01);
    const double ico = std::abs(signedVolume(prim::icosphere(1.0, 4)) - sphere) / sphere;
    CHECK(ico < 0.01);
    const double hemi = std::abs(signedVolume(prim::hemisphere(1.0, 64, 16, true)) - sphere / 2) / (sphere / 2);
    CHECK(hemi < 0.01);
  }
}
