// SPDX-License-Identifier: Zlib
// Mesh repair: each defect real meshes bring (holes, flipped faces, inside-out parts, cavities,
// degenerate triangles, near-coincident vertices) is repaired to the closed form of the intact
// solid, and what cannot be repaired is named.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <string>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/MeshParts.hpp"
#include "hydrotex/mesh/MeshRepair.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using hydrotex::Mesh;
using hydrotex::RepairReport;
using hydrotex::RepairSettings;

namespace {

/// `b` appended to `a`, its vertices offset by `shift` (m), its winding reversed when `flip`.
Mesh joined(Mesh a, const Mesh& b, const Eigen::Vector3d& shift, bool flip) {
  const int base = static_cast<int>(a.positions.size());
  for (const Eigen::Vector3d& p : b.positions) a.positions.push_back(p + shift);
  for (Eigen::Vector3i t : b.triangles) {
    if (flip) std::swap(t[1], t[2]);
    a.triangles.push_back(t + Eigen::Vector3i::Constant(base));
  }
  a.uv = {};
  return a;
}

RepairReport repaired(Mesh& mesh, const RepairSettings& settings = {}) {
  auto report = hydrotex::repairMesh(mesh, settings);
  REQUIRE(report);
  return *report;
}

/// Box of extents e (kg, m) at density 1: I about its centre = V/12 diag(ey^2+ez^2, ...).
Eigen::Matrix3d boxInertia(const Eigen::Vector3d& e) {
  const double v = e.prod();
  return Eigen::Vector3d(v / 12 * (e.y() * e.y() + e.z() * e.z()), v / 12 * (e.x() * e.x() + e.z() * e.z()),
                         v / 12 * (e.x() * e.x() + e.y() * e.y()))
      .asDiagonal();
}

bool positiveDefinite(const Eigen::Matrix3d& m) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m).eigenvalues().minCoeff() > 0.0;
}

}  // namespace

TEST_CASE("a small hole is capped: the box's volume, mass and a generated atlas", "[repair]") {
  // 2 m cube, 32 x 32 quads a face; one quad (0.0625 m, perimeter 0.25 m = 0.072 of the 3.46 m
  // diagonal, under the default 0.1) removed from the top face.
  Mesh mesh = hydrotex::primitives::subdividedBox(Eigen::Vector3d(2, 2, 2), 32);
  const std::size_t intact = mesh.triangles.size();
  std::size_t removed = 0;
  for (std::size_t t = 0; t < mesh.triangles.size() && removed < 2; ++t) {
    bool top = true;
    for (int c = 0; c < 3; ++c) top = top && mesh.positions[mesh.triangles[t][c]].y() == 1.0;
    if (!top) continue;
    mesh.triangles.erase(mesh.triangles.begin() + static_cast<long>(t));
    mesh.uv.uvTriangles.erase(mesh.uv.uvTriangles.begin() + static_cast<long>(t));
    ++removed;
    --t;
  }
  REQUIRE(removed == 2);
  REQUIRE(hydrotex::validateMesh(mesh, false).boundaryEdges == 4);
  // The two triangles removed must be one quad (sharing their diagonal); else the loop has 6 edges.

  const RepairReport report = repaired(mesh);
  REQUIRE(report.holesClosed.size() == 1);
  CHECK(report.holesClosed[0].edges == 4);
  CHECK(report.holesClosed[0].perimeter == Approx(0.25).epsilon(1e-12));
  CHECK(report.holesClosed[0].area == Approx(0.0625 * 0.0625).epsilon(1e-12));
  CHECK(report.uvsDropped);
  CHECK(report.unrepaired.empty());
  CHECK(mesh.triangles.size() == intact - 2 + 4);  // a fan of four from the loop's centroid

  // The cap is flat in the face's plane: the volume is the cube's, exactly up to rounding (1e-12
  // relative: sums of a few thousand products of quarter-metre multiples).
  const hydrotex::MeshReport check = hydrotex::validateMesh(mesh, false);
  CHECK(check.outwardOriented);
  REQUIRE(check.volume);
  CHECK(*check.volume == Approx(8.0).epsilon(1e-12));
  const auto mass = hydrotex::polyhedralMassProperties(mesh, 1.0);
  REQUIRE(mass);
  CHECK(mass->volume == Approx(8.0).epsilon(1e-12));
  CHECK(mass->centerOfMass.norm() < 1e-12);
  CHECK((mass->inertia - boxInertia(Eigen::Vector3d(2, 2, 2))).norm() < 1e-10);

  // The artist's UVs went with the caps; the body gets a generated atlas and bakes.
  hydrotex::BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = 64;
  const auto body = hydrotex::prepareBodyGeometry(mesh, settings);
  REQUIRE(body);
  CHECK(body->atlas.generated);
}

TEST_CASE("a flipped triangle is turned to agree with its neighbours", "[repair]") {
  Mesh mesh = hydrotex::primitives::box(Eigen::Vector3d(1, 2, 3));
  std::swap(mesh.triangles[5][1], mesh.triangles[5][2]);
  std::swap(mesh.uv.uvTriangles[5][1], mesh.uv.uvTriangles[5][2]);
  REQUIRE_FALSE(hydrotex::validateMesh(mesh, false).watertight);
  const RepairReport report = repaired(mesh);
  CHECK(report.trianglesReoriented == 1);
  CHECK(report.partsFlipped == 0);
  CHECK_FALSE(report.uvsDropped);  // no cap: the artist's UVs stay, flipped with their triangle
  CHECK(mesh.hasUvs());
  const hydrotex::MeshReport check = hydrotex::validateMesh(mesh);
  CHECK(check.outwardOriented);
  CHECK(check.uvUsableAsAtlas());
  CHECK(*check.volume == Approx(6.0).epsilon(1e-12));
}

TEST_CASE("a part inside out is found per part and turned; mass matches the closed form", "[repair][parts]") {
  // A 2 m cube at the origin and an inside-out 1 m cube 3 m along x: the total signed volume is
  // 8 - 1 = 7 > 0, which a whole-mesh sign test calls outward (the RexROV case).
  const Mesh big = hydrotex::primitives::box(Eigen::Vector3d(2, 2, 2));
  Mesh mesh = joined(big, hydrotex::primitives::box(Eigen::Vector3d(1, 1, 1)), Eigen::Vector3d(3, 0, 0), true);
  const hydrotex::MeshReport before = hydrotex::validateMesh(mesh, false);
  CHECK(before.watertight);
  CHECK(*before.volume == Approx(7.0).epsilon(1e-12));
  CHECK(before.parts == 2);
  CHECK(before.insideOutParts == 1);
  CHECK_FALSE(before.outwardOriented);
  const auto refused = hydrotex::polyhedralMassProperties(mesh, 1.0);
  REQUIRE_FALSE(refused);
  CHECK(refused.error().message.find("inside out") != std::string::npos);

  const RepairReport report = repaired(mesh);
  CHECK(report.partsFlipped == 1);
  CHECK(report.flippedVolume == Approx(1.0).epsilon(1e-12));
  CHECK(hydrotex::validateMesh(mesh, false).outwardOriented);
  const auto mass = hydrotex::polyhedralMassProperties(mesh, 1.0);
  REQUIRE(mass);
  // Closed form: V = 9, x_c = (8*0 + 1*3)/9; parallel axis theorem for each cube about x_c.
  CHECK(mass->volume == Approx(9.0).epsilon(1e-12));
  const double xc = 3.0 / 9.0;
  CHECK((mass->centerOfMass - Eigen::Vector3d(xc, 0, 0)).norm() < 1e-12);
  Eigen::Matrix3d expected = boxInertia(Eigen::Vector3d(2, 2, 2)) + boxInertia(Eigen::Vector3d(1, 1, 1));
  const double d2 = xc * xc * 8.0 + (3.0 - xc) * (3.0 - xc) * 1.0;  // sum of m d^2 off the x axis
  expected(1, 1) += d2;
  expected(2, 2) += d2;
  CHECK((mass->inertia - expected).norm() < 1e-10);
  CHECK(positiveDefinite(mass->inertia));
}

TEST_CASE("a part inside another keeps the sign of a cavity", "[repair][parts]") {
  const Mesh outer = hydrotex::primitives::box(Eigen::Vector3d(4, 4, 4));
  const Mesh inner = hydrotex::primitives::box(Eigen::Vector3d(2, 2, 2));
  const Eigen::Vector3d shift(0.5, 0.0, 0.0);
  SECTION("an inward cavity is correct as it is") {
    Mesh mesh = joined(outer, inner, shift, true);
    const RepairReport report = repaired(mesh);
    CHECK(report.partsFlipped == 0);
    CHECK(hydrotex::validateMesh(mesh, false).insideOutParts == 0);
    CHECK(*hydrotex::validateMesh(mesh, false).volume == Approx(64.0 - 8.0).epsilon(1e-12));
  }
  SECTION("an outward inner part is turned into a cavity") {
    Mesh mesh = joined(outer, inner, shift, false);
    CHECK(hydrotex::validateMesh(mesh, false).insideOutParts == 1);
    const RepairReport report = repaired(mesh);
    CHECK(report.partsFlipped == 1);
    const auto mass = hydrotex::polyhedralMassProperties(mesh, 1.0);
    REQUIRE(mass);
    // Closed form: V = 64 - 8; x_c = (64*0 - 8*0.5)/56.
    CHECK(mass->volume == Approx(56.0).epsilon(1e-12));
    CHECK((mass->centerOfMass - Eigen::Vector3d(-4.0 / 56.0, 0, 0)).norm() < 1e-12);
    CHECK(positiveDefinite(mass->inertia));
  }
  SECTION("both inside out: both turned") {
    Mesh mesh = joined(joined(Mesh{}, outer, Eigen::Vector3d::Zero(), true), inner, shift, false);
    const RepairReport report = repaired(mesh);
    CHECK(report.partsFlipped == 2);
    CHECK(*hydrotex::validateMesh(mesh, false).volume == Approx(56.0).epsilon(1e-12));
  }
}

TEST_CASE("degenerate triangles are dropped and near-coincident vertices welded", "[repair]") {
  Mesh mesh = hydrotex::primitives::box(Eigen::Vector3d(1, 1, 1));
  mesh.uv = {};
  // A collapsed triangle, and a loose zero-area sliver of three collinear new vertices.
  mesh.triangles.emplace_back(0, 0, 1);
  const int s = static_cast<int>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {{5, 0, 0}, {6, 0, 0}, {7, 0, 0}});
  mesh.triangles.emplace_back(s, s + 1, s + 2);
  // A copy of vertex 0 moved by 1e-9 m (under 1e-7 of the 1.7 m diagonal) used by one triangle.
  mesh.positions.push_back(mesh.positions[0] + Eigen::Vector3d(1e-9, 0, 0));
  const int copy = static_cast<int>(mesh.positions.size()) - 1;
  for (int c = 0; c < 3; ++c)
    if (mesh.triangles[0][c] == 0) mesh.triangles[0][c] = copy;
  REQUIRE(mesh.triangles[0].maxCoeff() == copy);  // the box's first triangle uses vertex 0
  REQUIRE(hydrotex::validateMesh(mesh, false).boundaryEdges > 0);

  const RepairReport report = repaired(mesh);
  CHECK(report.verticesWelded == 1);
  CHECK(report.trianglesDropped == 2);
  CHECK(report.unrepaired.empty());
  CHECK(mesh.triangles.size() == 12);
  const hydrotex::MeshReport check = hydrotex::validateMesh(mesh, false);
  CHECK(check.outwardOriented);
  CHECK(check.degenerateTriangles == 0);
  CHECK(*check.volume == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("what repair cannot fix is named, and disabled repair changes nothing", "[repair][refusal]") {
  SECTION("a hole larger than the limit") {
    Mesh mesh = hydrotex::primitives::box(Eigen::Vector3d(1, 1, 1));
    mesh.uv = {};
    // Drop one face: a 4 m loop against a 1.73 m diagonal.
    std::vector<Eigen::Vector3i> kept;
    for (const Eigen::Vector3i& t : mesh.triangles) {
      bool top = true;
      for (int c = 0; c < 3; ++c) top = top && mesh.positions[t[c]].y() == 0.5;
      if (!top) kept.push_back(t);
    }
    REQUIRE(kept.size() == 10);
    mesh.triangles = kept;
    const RepairReport report = repaired(mesh);
    CHECK(report.holesClosed.empty());
    REQUIRE(report.unrepaired.size() == 1);
    const hydrotex::Status status = report.requireRepaired("box.obj");
    REQUIRE_FALSE(status);
    CHECK(status.error().message.rfind("box.obj: open hull: a boundary loop of 4 m (4 edges)", 0) == 0);
    CHECK(status.error().message.find('\n') == std::string::npos);
    // Raising the limit closes it.
    RepairSettings wide;
    wide.maxHoleFraction = 3.0;
    CHECK(repaired(mesh, wide).unrepaired.empty());
    CHECK(*hydrotex::validateMesh(mesh, false).volume == Approx(1.0).epsilon(1e-12));
  }
  SECTION("a non-manifold fan") {
    Mesh mesh = hydrotex::primitives::box(Eigen::Vector3d(1, 1, 1));
    mesh.uv = {};
    // A fin on one of the box's edges: that edge is shared by three triangles.
    const Eigen::Vector3i& t = mesh.triangles[0];
    mesh.positions.emplace_back(3, 3, 3);
    mesh.triangles.emplace_back(t[0], t[1], static_cast<int>(mesh.positions.size()) - 1);
    const RepairReport report = repaired(mesh);
    const hydrotex::Status status = report.requireRepaired("fin.obj");
    REQUIRE_FALSE(status);
    CHECK(status.error().message.rfind("fin.obj: non-manifold: 1 edges", 0) == 0);
  }
  SECTION("repair off") {
    Mesh mesh = hydrotex::primitives::box(Eigen::Vector3d(1, 1, 1));
    std::swap(mesh.triangles[0][1], mesh.triangles[0][2]);
    const Mesh before = mesh;
    RepairSettings off;
    off.enabled = false;
    const RepairReport report = repaired(mesh, off);
    CHECK_FALSE(report.changed());
    CHECK(mesh.triangles == before.triangles);
    CHECK_FALSE(hydrotex::checkClosed(mesh, "box"));
  }
  SECTION("bad settings") {
    Mesh mesh = hydrotex::primitives::box(Eigen::Vector3d(1, 1, 1));
    RepairSettings bad;
    bad.maxHoleFraction = -1.0;
    CHECK_FALSE(hydrotex::repairMesh(mesh, bad));
  }
}
