// SPDX-License-Identifier: Zlib
// Mesh validation: topology defects, orientation, volume and area, UV overlap.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "hydrotex/mesh/MeshValidation.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using hydrotex::Mesh;

namespace {

/// Unit cube [0,1]^3, 8 vertices, 12 counter-clockwise (outward) triangles, no UVs.
Mesh unitCube() {
  Mesh mesh;
  mesh.sourceName = "cube";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

/// Gives every triangle of `mesh` UVs from `corner(t, c)`, one UV vertex per corner.
template <class CornerUv>
void setCornerUvs(Mesh& mesh, CornerUv corner) {
  mesh.uv = {};
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int base = static_cast<int>(mesh.uv.uvs.size());
    for (int c = 0; c < 3; ++c) mesh.uv.uvs.push_back(corner(t, c));
    mesh.uv.uvTriangles.emplace_back(base, base + 1, base + 2);
  }
}

/// The cube's faces in a 3 x 2 grid of cells (a valid atlas): each quad maps to its cell's square.
void setGridUvs(Mesh& cube, double inset = 0.0) {
  setCornerUvs(cube, [&](std::size_t t, int c) {
    const std::size_t face = t / 2;
    const Eigen::Vector2d cell(static_cast<double>(face % 3) / 3.0, static_cast<double>(face / 3) / 2.0);
    const Eigen::Vector2d square[4] = {{inset, inset}, {1 - inset, inset}, {1 - inset, 1 - inset}, {inset, 1 - inset}};
    const int quadCorner = (t % 2 == 0) ? c : (c == 0 ? 0 : c + 1);
    return Eigen::Vector2d(cell + square[quadCorner].cwiseProduct(Eigen::Vector2d(1.0 / 3.0, 0.5)));
  });
}

}  // namespace

TEST_CASE("A closed cube is watertight, outward, with exact volume and area", "[validation]") {
  const auto report = hydrotex::validateMesh(unitCube());
  CHECK(report.triangleCount == 12);
  CHECK(report.vertexCount == 8);
  CHECK(report.watertight);
  CHECK(report.outwardOriented);
  CHECK(report.boundaryEdges == 0);
  CHECK(report.nonManifoldEdges == 0);
  CHECK(report.inconsistentEdges == 0);
  CHECK(report.degenerateTriangles == 0);
  REQUIRE(report.volume.has_value());
  // Closed forms: volume 1, area 6; the sums have a dozen terms of exact binary values (1e-14).
  CHECK(*report.volume == Approx(1.0).epsilon(1e-14));
  CHECK(report.area == Approx(6.0).epsilon(1e-14));
  CHECK(report.boundsMin == Eigen::Vector3d(0, 0, 0));
  CHECK(report.boundsMax == Eigen::Vector3d(1, 1, 1));
  CHECK_FALSE(report.hasUv);
  CHECK(hydrotex::requireClosed(report, "cube.obj").ok());
  CHECK_FALSE(report.summary().empty());
}

TEST_CASE("Primitive meshes have the volume of their polyhedron and valid atlases", "[validation]") {
  // Icosphere: its volume is the sum of the tetrahedra from the origin; computed here per face
  // from the origin (a different reference point than validateMesh uses): agreement to 1e-12.
  const Mesh sphere = hydrotex::primitives::icosphere(2.0, 3);
  double expected = 0.0;
  for (const auto& t : sphere.triangles)
    expected += sphere.positions[t[0]].dot(sphere.positions[t[1]].cross(sphere.positions[t[2]])) / 6.0;
  const auto report = hydrotex::validateMesh(sphere);
  REQUIRE(report.watertight);
  CHECK(*report.volume == Approx(expected).epsilon(1e-12));
  // And it approaches the sphere's 4/3 pi r^3 from below (inscribed polyhedron, 1280 faces: < 2%).
  CHECK(*report.volume < 4.0 / 3.0 * M_PI * 8.0);
  CHECK(*report.volume > 0.98 * 4.0 / 3.0 * M_PI * 8.0);
  CHECK(report.hasUv);
  CHECK(report.uvUsableAsAtlas());
}

TEST_CASE("An open mesh reports its boundary edges and a clear message", "[validation]") {
  Mesh open = unitCube();
  open.triangles.pop_back();  // remove one triangle: a triangular hole with 3 boundary edges
  const auto report = hydrotex::validateMesh(open);
  CHECK(report.boundaryEdges == 3);
  CHECK_FALSE(report.watertight);
  CHECK_FALSE(report.outwardOriented);
  CHECK_FALSE(report.volume.has_value());
  CHECK(report.area == Approx(5.5).epsilon(1e-14));
  const auto closed = hydrotex::requireClosed(report, "ship.obj");
  REQUIRE_FALSE(closed.ok());
  CHECK(closed.error().message == "ship.obj: mesh is open (3 boundary edges); volume and buoyancy need a closed mesh");
}

TEST_CASE("A flipped triangle makes its three edges inconsistent", "[validation]") {
  Mesh flipped = unitCube();
  std::swap(flipped.triangles[4][1], flipped.triangles[4][2]);
  const auto report = hydrotex::validateMesh(flipped);
  CHECK(report.inconsistentEdges == 3);
  CHECK(report.boundaryEdges == 0);
  CHECK_FALSE(report.watertight);
  CHECK_FALSE(hydrotex::requireClosed(report, "cube").ok());
}

TEST_CASE("An inverted mesh is watertight but not outward", "[validation]") {
  Mesh inverted = unitCube();
  for (auto& t : inverted.triangles) std::swap(t[1], t[2]);
  const auto report = hydrotex::validateMesh(inverted);
  CHECK(report.watertight);
  CHECK_FALSE(report.outwardOriented);
  REQUIRE(report.volume.has_value());
  CHECK(*report.volume == Approx(-1.0).epsilon(1e-14));
  const auto closed = hydrotex::requireClosed(report, "cube");
  REQUIRE_FALSE(closed.ok());
  CHECK(closed.error().message.find("inside out") != std::string::npos);
}

TEST_CASE("Degenerate triangles are counted, scale-free", "[validation]") {
  for (const double scale : {1e-6, 1.0, 1e6}) {
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {scale, 0, 0}, {2 * scale, 0, 0}, {0, scale, 0}, {scale, 1e-12 * scale, 0}};
    mesh.triangles = {{0, 1, 3}, {0, 2, 1}, {0, 0, 3}, {0, 2, 4}};  // good, collinear, repeated index, sliver
    const auto report = hydrotex::validateMesh(mesh);
    INFO("scale " << scale);
    // The sliver's height is 1e-12 of its base, below the 1e-10 relative tolerance.
    CHECK(report.degenerateTriangles == 3);
  }
  Mesh outOfRange = unitCube();
  outOfRange.triangles[0][0] = 42;
  CHECK(hydrotex::validateMesh(outOfRange).degenerateTriangles == 1);  // no crash either
}

TEST_CASE("An edge shared by three triangles is non-manifold", "[validation]") {
  Mesh fin = unitCube();
  fin.positions.emplace_back(0.5, 2.0, 0.5);
  fin.triangles.emplace_back(2, 3, 8);  // a fin standing on the cube's edge 2-3
  const auto report = hydrotex::validateMesh(fin);
  CHECK(report.nonManifoldEdges == 1);
  CHECK(report.boundaryEdges == 2);  // the fin's two free edges
  CHECK_FALSE(report.watertight);
}

TEST_CASE("UV overlap: a correct atlas passes, stacked and mirrored UVs are caught", "[validation]") {
  Mesh cube = unitCube();
  setGridUvs(cube);  // faces touch along cell borders: touching is not overlapping
  auto report = hydrotex::validateMesh(cube);
  REQUIRE(report.hasUv);
  CHECK_FALSE(report.uvOverlap);
  CHECK(report.uvOverlapCheckComplete);
  CHECK(report.uvsOutsideUnitSquare == 0);
  CHECK(report.zeroUvAreaTriangles == 0);
  CHECK(report.uvUsableAsAtlas());

  SECTION("stacked: every face on the same square") {
    setCornerUvs(cube, [](std::size_t t, int c) {
      const Eigen::Vector2d square[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      return square[(t % 2 == 0) ? c : (c == 0 ? 0 : c + 1)];
    });
    report = hydrotex::validateMesh(cube);
    CHECK(report.uvOverlap);
    // 6 faces of 2 triangles each on one square: each lower triangle overlaps the 5 other lower
    // ones, likewise the upper ones: 2 * C(6,2) = 30 pairs (lower/upper only share the diagonal).
    CHECK(report.uvOverlapPairs == 30);
    CHECK_FALSE(report.uvUsableAsAtlas());
  }
  SECTION("mirrored: one face's cell reused mirrored by another face") {
    // Face 1 (triangles 2, 3) gets face 0's cell mirrored in u: reversed orientation, same area.
    setGridUvs(cube);
    for (int t = 2; t < 4; ++t)
      for (int c = 0; c < 3; ++c) {
        Eigen::Vector2d& uv = cube.uv.uvs[cube.uv.uvTriangles[t][c]];
        uv = cube.uv.uvs[cube.uv.uvTriangles[t - 2][c]];
        uv.x() = 1.0 / 3.0 - uv.x();
      }
    report = hydrotex::validateMesh(cube);
    CHECK(report.uvOverlap);
    CHECK(report.uvOverlapPairs >= 2);
  }
  SECTION("folded: one triangle flipped inside its own chart") {
    // Triangle 1 of face 0 reflected across the shared diagonal lands on triangle 0.
    Eigen::Vector2d& corner = cube.uv.uvs[cube.uv.uvTriangles[1][2]];  // quad corner 3 -> corner 1
    corner = cube.uv.uvs[cube.uv.uvTriangles[0][1]];
    corner.y() += 1e-3;
    report = hydrotex::validateMesh(cube);
    CHECK(report.uvOverlap);
  }
  SECTION("zero-area UV triangles and UVs outside [0,1]") {
    cube.uv.uvs[cube.uv.uvTriangles[0][1]] = cube.uv.uvs[cube.uv.uvTriangles[0][0]];
    cube.uv.uvs[cube.uv.uvTriangles[5][2]] = Eigen::Vector2d(1.5, -0.25);
    report = hydrotex::validateMesh(cube);
    CHECK(report.zeroUvAreaTriangles == 1);
    CHECK(report.uvsOutsideUnitSquare == 1);
    CHECK_FALSE(report.uvUsableAsAtlas());
  }
}

TEST_CASE("The pairwise overlap test: shared edges and vertices touch, they do not overlap", "[validation]") {
  const Eigen::Vector2d a[3] = {{0, 0}, {1, 0}, {0, 1}};
  const Eigen::Vector2d acrossEdge[3] = {{1, 0}, {1, 1}, {0, 1}};
  const Eigen::Vector2d atVertex[3] = {{1, 0}, {2, 0}, {2, 1}};
  const Eigen::Vector2d inside[3] = {{0.1, 0.1}, {0.3, 0.1}, {0.1, 0.3}};
  const Eigen::Vector2d crossing[3] = {{0.4, 0.4}, {2, 0.4}, {0.4, 2}};
  const Eigen::Vector2d apart[3] = {{0.6, 0.6}, {2, 0.6}, {0.6, 2}};
  CHECK_FALSE(hydrotex::uvTrianglesOverlap(a, acrossEdge, 1e-12));
  CHECK_FALSE(hydrotex::uvTrianglesOverlap(a, atVertex, 1e-12));
  CHECK(hydrotex::uvTrianglesOverlap(a, inside, 1e-12));
  CHECK(hydrotex::uvTrianglesOverlap(inside, a, 1e-12));
  CHECK(hydrotex::uvTrianglesOverlap(a, crossing, 1e-12));
  CHECK_FALSE(hydrotex::uvTrianglesOverlap(a, apart, 1e-12));
  CHECK(hydrotex::uvTrianglesOverlap(a, a, 1e-12));
}

TEST_CASE("Overlap search over many triangles agrees with brute force", "[validation]") {
  // A torus atlas (valid) with a few triangles copied onto others: the grid search must find
  // exactly the pairs a brute-force all-pairs search finds.
  Mesh torus = hydrotex::primitives::torus(1.0, 0.3, 24, 12);
  REQUIRE(torus.hasUvs());
  for (std::size_t t : {std::size_t{5}, std::size_t{100}, std::size_t{300}}) {
    const std::size_t target = (t * 7 + 11) % torus.triangles.size();
    for (int c = 0; c < 3; ++c) torus.uv.uvs.push_back(torus.uv.uvs[torus.uv.uvTriangles[target][c]]);
    const int base = static_cast<int>(torus.uv.uvs.size()) - 3;
    torus.uv.uvTriangles[t] = Eigen::Vector3i(base, base + 1, base + 2);
  }
  std::size_t bruteForce = 0;
  const double tolerance = 1e-9;  // the validator's: 1e-9 of the UV extent (about 1 here)
  for (std::size_t i = 0; i < torus.triangles.size(); ++i)
    for (std::size_t j = i + 1; j < torus.triangles.size(); ++j) {
      Eigen::Vector2d pa[3], pb[3];
      for (int c = 0; c < 3; ++c) {
        pa[c] = torus.uv.uvs[torus.uv.uvTriangles[i][c]];
        pb[c] = torus.uv.uvs[torus.uv.uvTriangles[j][c]];
      }
      if (hydrotex::uvTrianglesOverlap(pa, pb, tolerance)) ++bruteForce;
    }
  const auto report = hydrotex::validateMesh(torus);
  CHECK(bruteForce >= 3);
  CHECK(report.uvOverlapPairs == bruteForce);
}
