// SPDX-License-Identifier: Zlib
// Mesh import/export: every format round-trips, UV seams merge, bad files give one-line errors.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>

#include "TestPaths.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"

using hydrotex::Mesh;
using hydrotex::test::outputPath;

namespace {

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// Unit cube as OBJ with per-face UVs: 8 positions, 24 UV vertices (each face its own cell of a
/// 3 x 2 grid), quads that assimp triangulates.
std::string cubeObjWithFaceUvs() {
  std::string obj = "# unit cube, one UV cell per face\n";
  obj += "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
  for (int face = 0; face < 6; ++face) {
    const double u0 = (face % 3) / 3.0 + 0.01, v0 = (face / 3) / 2.0 + 0.01;
    const double du = 1.0 / 3.0 - 0.02, dv = 0.5 - 0.02;
    obj += "vt " + std::to_string(u0) + " " + std::to_string(v0) + "\n";
    obj += "vt " + std::to_string(u0 + du) + " " + std::to_string(v0) + "\n";
    obj += "vt " + std::to_string(u0 + du) + " " + std::to_string(v0 + dv) + "\n";
    obj += "vt " + std::to_string(u0) + " " + std::to_string(v0 + dv) + "\n";
  }
  // Counter-clockwise seen from outside.
  const int faces[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 2, 6, 5}, {4, 8, 7, 3}, {1, 5, 8, 4}, {2, 3, 7, 6}};
  for (int f = 0; f < 6; ++f) {
    obj += "f";
    for (int c = 0; c < 4; ++c) {
      obj += ' ';
      obj += std::to_string(faces[f][c]);
      obj += '/';
      obj += std::to_string(4 * f + c + 1);
    }
    obj += "\n";
  }
  return obj;
}

/// Octahedron subdivided `levels` times and pushed onto the unit sphere, coordinates rounded to
/// float so that every format (all store 32-bit floats) can hold them exactly. UVs: each triangle
/// its own cell of a grid (a valid, if wasteful, atlas).
Mesh floatSphere(int levels) {
  Mesh mesh;
  mesh.sourceName = "sphere";
  mesh.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  mesh.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < levels; ++level) {
    std::vector<Eigen::Vector3i> finer;
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      mesh.positions.push_back((mesh.positions[a] + mesh.positions[b]).normalized());
      return midpoint[key] = static_cast<int>(mesh.positions.size() - 1);
    };
    for (const auto& t : mesh.triangles) {
      const int ab = middle(t[0], t[1]), bc = middle(t[1], t[2]), ca = middle(t[2], t[0]);
      finer.insert(finer.end(), {{t[0], ab, ca}, {ab, t[1], bc}, {ca, bc, t[2]}, {ab, bc, ca}});
    }
    mesh.triangles = finer;
  }
  // Round through a volatile float: with GCC 12 at -O3 the plain double -> float -> double round
  // trip in this loop was observed to leave a few coordinates unrounded.
  for (auto& p : mesh.positions)
    for (int k = 0; k < 3; ++k) {
      volatile float rounded = static_cast<float>(p[k]);
      p[k] = rounded;
    }
  const int cells = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(mesh.triangles.size()))));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const float u0 = static_cast<float>(t % static_cast<std::size_t>(cells)) / static_cast<float>(cells);
    const float v0 = static_cast<float>(t / static_cast<std::size_t>(cells)) / static_cast<float>(cells);
    const float step = 0.75f / static_cast<float>(cells);
    const int base = static_cast<int>(mesh.uv.uvs.size());
    mesh.uv.uvs.push_back({u0, v0});
    mesh.uv.uvs.push_back({u0 + step, v0});
    mesh.uv.uvs.push_back({u0, v0 + step});
    mesh.uv.uvTriangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

double uvArea(const Mesh& mesh) {
  double area = 0.0;
  for (const auto& t : mesh.uv.uvTriangles) {
    const Eigen::Vector2d e1 = mesh.uv.uvs[t[1]] - mesh.uv.uvs[t[0]], e2 = mesh.uv.uvs[t[2]] - mesh.uv.uvs[t[0]];
    area += 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
  }
  return area;
}

/// The message of a failed load; fails the test when the load succeeds.
std::string loadError(const std::string& path) {
  const auto loaded = hydrotex::loadMesh(path);
  REQUIRE_FALSE(loaded.ok());
  const std::string message = loaded.error().message;
  INFO(message);
  CHECK(message.rfind(path, 0) == 0);                 // begins with the file
  CHECK(message.find('\n') == std::string::npos);     // one line
  return message;
}

}  // namespace

TEST_CASE("OBJ cube with per-face UVs merges to 8 vertices and is watertight", "[meshio]") {
  const std::string path = outputPath("cube_face_uvs.obj");
  writeText(path, cubeObjWithFaceUvs());
  const auto loaded = hydrotex::loadMesh(path);
  REQUIRE(loaded.ok());
  const Mesh& mesh = *loaded;
  CHECK(mesh.positions.size() == 8);
  CHECK(mesh.triangles.size() == 12);
  CHECK(mesh.hasUvs());
  CHECK(mesh.uv.uvs.size() == 24);
  CHECK(mesh.sourceName == "cube_face_uvs.obj");
  const auto report = hydrotex::validateMesh(mesh);
  CHECK(report.watertight);
  CHECK(report.outwardOriented);
  REQUIRE(report.volume.has_value());
  // Unit cube: exact volume 1 and area 6; only rounding of 12 small sums (1e-14).
  CHECK(*report.volume == Approx(1.0).epsilon(1e-14));
  CHECK(report.area == Approx(6.0).epsilon(1e-14));
  CHECK_FALSE(report.uvOverlap);
  CHECK(report.uvUsableAsAtlas());
}

TEST_CASE("Every written format reads back with the same triangles, volume, area and UVs", "[meshio]") {
  const Mesh original = floatSphere(3);  // 512 triangles
  const auto originalReport = hydrotex::validateMesh(original);
  REQUIRE(originalReport.watertight);
  const double originalUvArea = uvArea(original);
  for (const std::string extension : {".obj", ".glb", ".gltf", ".ply", ".stl"}) {
    SECTION(extension) {
      const std::string path = outputPath("roundtrip_sphere" + extension);
      const auto saved = hydrotex::saveMesh(original, path);
      INFO((saved.ok() ? std::string("saved") : saved.error().message));
      REQUIRE(saved.ok());
      const auto loaded = hydrotex::loadMesh(path);
      INFO((loaded.ok() ? std::string("loaded") : loaded.error().message));
      REQUIRE(loaded.ok());
      const auto report = hydrotex::validateMesh(*loaded);
      CHECK(report.triangleCount == original.triangles.size());
      CHECK(report.vertexCount == original.positions.size());
      REQUIRE(report.watertight);
      CHECK(report.outwardOriented);
      // Positions are float-exact in every format, so only the summation order differs: 1e-12.
      CHECK(*report.volume == Approx(*originalReport.volume).epsilon(1e-12));
      CHECK(report.area == Approx(originalReport.area).epsilon(1e-12));
      if (extension != ".stl") {  // STL has no texture coordinates
        REQUIRE(loaded->hasUvs());
        CHECK(report.uvUsableAsAtlas());
        // OBJ and PLY store the float UVs exactly (1e-12); glTF's exporter and importer each
        // compute v -> 1 - v in float, so there the UV area agrees to float rounding (1e-6).
        const double uvTolerance = (extension == ".obj" || extension == ".ply") ? 1e-12 : 1e-6;
        CHECK(uvArea(*loaded) == Approx(originalUvArea).epsilon(uvTolerance));
        Eigen::Vector2d lo = loaded->uv.uvs[0], hi = lo;
        for (const auto& uv : loaded->uv.uvs) { lo = lo.cwiseMin(uv); hi = hi.cwiseMax(uv); }
        CHECK(lo.x() == Approx(0.0).margin(1e-7));
        CHECK(lo.y() == Approx(0.0).margin(1e-7));
      }
    }
  }
}

TEST_CASE("glTF keeps the OBJ UV convention (v up) through assimp", "[meshio]") {
  // One triangle whose UVs are distinct per corner; after a glTF round trip, the corner at the
  // top of UV space must still be at the top (assimp flips glTF's v on export and back on import).
  Mesh triangle;
  triangle.sourceName = "tri";
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.triangles = {{0, 1, 2}};
  triangle.uv.uvs = {{0.125, 0.25}, {0.75, 0.25}, {0.125, 0.875}};
  triangle.uv.uvTriangles = {{0, 1, 2}};
  for (const std::string extension : {".glb", ".obj", ".ply"}) {
    const std::string path = outputPath("uv_convention" + extension);
    REQUIRE(hydrotex::saveMesh(triangle, path).ok());
    const auto loaded = hydrotex::loadMesh(path);
    REQUIRE(loaded.ok());
    REQUIRE(loaded->hasUvs());
    for (int c = 0; c < 3; ++c) {
      const int position = loaded->triangles[0][c];
      const Eigen::Vector2d uv = loaded->uv.uvs[loaded->uv.uvTriangles[0][c]];
      // Which original corner is this? Match by position; then its UV must be unchanged.
      for (int k = 0; k < 3; ++k)
        if (loaded->positions[position] == triangle.positions[k]) {
          INFO(extension << " corner " << k);
          CHECK(uv.x() == Approx(triangle.uv.uvs[k].x()).margin(1e-7));
          CHECK(uv.y() == Approx(triangle.uv.uvs[k].y()).margin(1e-7));
        }
    }
  }
}

TEST_CASE("Hand-written PLY and ASCII STL load, node transforms are applied", "[meshio]") {
  const std::string ply = outputPath("tetra.ply");
  writeText(ply,
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
            "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const auto tetra = hydrotex::loadMesh(ply);
  REQUIRE(tetra.ok());
  auto report = hydrotex::validateMesh(*tetra);
  CHECK(report.watertight);
  // Unit corner tetrahedron: volume 1/6, exact in double up to rounding.
  CHECK(*report.volume == Approx(1.0 / 6.0).epsilon(1e-14));

  // The tightest ASCII body (one-character values, one entry a line, no newline after the last)
  // is not taken for counts beyond the data (PlyGuard): it reaches assimp, whose verdict here is
  // "Mesh contains no faces".
  const std::string tight = outputPath("tight.ply");
  writeText(tight, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n2\n3");
  const auto points = hydrotex::loadMesh(tight);
  REQUIRE_FALSE(points.ok());
  CHECK(points.error().message.find("more than the file") == std::string::npos);
  CHECK(points.error().message.find("no faces") != std::string::npos);

  const std::string stl = outputPath("tetra_ascii.stl");
  writeText(stl,
            "solid t\n"
            "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
            "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
            "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
            "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
            "endsolid t\n");
  const auto fromStl = hydrotex::loadMesh(stl);
  REQUIRE(fromStl.ok());
  CHECK(fromStl->positions.size() == 4);  // STL repeats vertices per facet; merged by position
  report = hydrotex::validateMesh(*fromStl);
  CHECK(report.watertight);
  CHECK(*report.volume == Approx(1.0 / 6.0).epsilon(1e-14));

  // glTF with a node that scales by 2 and mirrors x: volume x 8 and still outward (the mirror
  // flips the winding, which the loader undoes).
  const std::string gltf = outputPath("tetra_node.gltf");
  const std::string buffer = outputPath("tetra_node.bin");
  {
    const float vertices[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const std::uint16_t indices[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    std::ofstream out(buffer, std::ios::binary);
    out.write(reinterpret_cast<const char*>(vertices), sizeof vertices);
    out.write(reinterpret_cast<const char*>(indices), sizeof indices);
  }
  writeText(gltf, R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
  "nodes":[{"mesh":0,"matrix":[-2,0,0,0, 0,2,0,0, 0,0,2,0, 5,0,0,1]}],
  "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
  "buffers":[{"uri":"tetra_node.bin","byteLength":72}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":24}],
  "accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,1]},
               {"bufferView":1,"componentType":5123,"count":12,"type":"SCALAR"}]})");
  const auto transformed = hydrotex::loadMesh(gltf);
  INFO((transformed.ok() ? std::string() : transformed.error().message));
  REQUIRE(transformed.ok());
  report = hydrotex::validateMesh(*transformed);
  REQUIRE(report.watertight);
  CHECK(report.outwardOriented);
  CHECK(*report.volume == Approx(8.0 / 6.0).epsilon(1e-14));
  CHECK(report.boundsMin.x() == Approx(3.0));  // x' = 5 - 2x
  CHECK(report.boundsMax.x() == Approx(5.0));
}

TEST_CASE("Bad mesh files give a one-line error naming the file", "[meshio]") {
  SECTION("missing") { CHECK(loadError(outputPath("no_such_mesh.obj")).find("not found") != std::string::npos); }
  SECTION("empty") {
    const std::string path = outputPath("empty.obj");
    writeText(path, "");
    CHECK(loadError(path).find("empty") != std::string::npos);
  }
  SECTION("garbage bytes") {
    const std::string path = outputPath("garbage.glb");
    std::string bytes;
    for (int i = 0; i < 4096; ++i) bytes.push_back(static_cast<char>((i * 7919 + 13) % 251));
    writeText(path, bytes);
    loadError(path);
  }
  SECTION("unknown format") {
    const std::string path = outputPath("notes.xyzmesh");
    writeText(path, "this is not a mesh\n");
    loadError(path);
  }
  SECTION("truncated binary STL") {
    const std::string full = outputPath("truncated_source.stl");
    REQUIRE(hydrotex::saveMesh(floatSphere(1), full).ok());
    std::ifstream in(full, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string path = outputPath("truncated.stl");
    writeText(path, bytes.substr(0, bytes.size() / 2));
    loadError(path);
  }
  SECTION("truncated GLB") {
    const std::string full = outputPath("truncated_source.glb");
    REQUIRE(hydrotex::saveMesh(floatSphere(1), full).ok());
    std::ifstream in(full, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string path = outputPath("truncated.glb");
    writeText(path, bytes.substr(0, bytes.size() * 2 / 3));
    loadError(path);
  }
  SECTION("NaN vertex") {
    const std::string path = outputPath("nan_vertex.obj");
    writeText(path, "v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    const std::string message = loadError(path);
    CHECK(message.find("NaN") != std::string::npos);
    CHECK(message.find("vertex") != std::string::npos);
  }
  SECTION("infinite vertex") {
    const std::string path = outputPath("inf_vertex.ply");
    writeText(path,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n");
    CHECK(loadError(path).find("infinite") != std::string::npos);
  }
  SECTION("absurd coordinates") {
    const std::string path = outputPath("far_vertex.obj");
    writeText(path, "v 0 0 0\nv 1e13 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(loadError(path).find("1e12") != std::string::npos);
  }
  SECTION("no triangles") {
    const std::string path = outputPath("lines_only.obj");
    writeText(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
    loadError(path);
  }
  SECTION("a directory") { loadError(outputPath("")); }
}

TEST_CASE("saveMesh rejects unknown extensions and broken meshes", "[meshio]") {
  const Mesh sphere = floatSphere(0);
  CHECK_FALSE(hydrotex::saveMesh(sphere, outputPath("x.unknownext")).ok());
  Mesh broken = sphere;
  broken.triangles[0][1] = 99;
  const auto saved = hydrotex::saveMesh(broken, outputPath("broken.obj"));
  REQUIRE_FALSE(saved.ok());
  CHECK(saved.error().message.find("broken.obj") != std::string::npos);
}

TEST_CASE("A million-triangle mesh loads", "[meshio][large]") {
  // The input-size guard must not refuse ordinary large meshes: a 708 x 708 quad grid (1,002,528
  // triangles) with float-exact coordinates.
  Mesh grid;
  grid.sourceName = "grid";
  const int n = 708;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) grid.positions.emplace_back(x * 0.25, y * 0.25, 0.0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x;
      grid.triangles.emplace_back(a, a + 1, a + n + 2);
      grid.triangles.emplace_back(a, a + n + 2, a + n + 1);
    }
  const std::string path = outputPath("big_grid.stl");
  REQUIRE(hydrotex::saveMesh(grid, path).ok());
  const auto loaded = hydrotex::loadMesh(path);
  REQUIRE(loaded.ok());
  CHECK(loaded->triangles.size() == grid.triangles.size());
  CHECK(loaded->positions.size() == grid.positions.size());
  const auto report = hydrotex::validateMesh(*loaded);
  CHECK(report.boundaryEdges == 4 * n);
  // Area 177 x 177 m^2; sums of exact quarter-metre squares: exact in double.
  CHECK(report.area == Approx(177.0 * 177.0).epsilon(1e-12));
}

TEST_CASE("loadMesh with MeshLoadSettings: a z-up file equals its y-up twin, --scale scales", "[mesh_io][axes]") {
  // The same box (0..1, 0..2, 0..3 in y-up metres) written twice: y up as it is, and z up in
  // centimetres, i.e. a y-up point (x, y, z) stored as (x, -z, y) * 100.
  const std::string yUp = outputPath("axes_y_up.obj");
  const std::string zUpCm = outputPath("axes_z_up_cm.obj");
  const double xs[2] = {0, 1}, ys[2] = {0, 2}, zs[2] = {0, 3};
  std::string objY, objZ;
  for (int i = 0; i < 8; ++i) {
    const double x = xs[i & 1], y = ys[(i >> 1) & 1], z = zs[(i >> 2) & 1];
    objY += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + "\n";
    objZ += "v " + std::to_string(100 * x) + " " + std::to_string(-100 * z) + " " + std::to_string(100 * y) + "\n";
  }
  // Counter-clockwise from outside in the y-up frame (corner i = x + 2y + 4z, 1-based in OBJ).
  const std::string faces = "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  writeText(yUp, objY + faces);
  writeText(zUpCm, objZ + faces);

  const auto reference = hydrotex::loadMesh(yUp, hydrotex::MeshLoadSettings{});
  REQUIRE(reference);
  hydrotex::MeshLoadSettings settings;
  settings.up = hydrotex::UpAxis::Z;
  settings.scale = 0.01;
  const auto converted = hydrotex::loadMesh(zUpCm, settings);
  REQUIRE(converted);
  REQUIRE(converted->positions.size() == reference->positions.size());
  REQUIRE(converted->triangles == reference->triangles);
  // Tolerance: the OBJ stores 6 decimals of centimetres, i.e. 1e-8 m, times 0.01 in doubles.
  for (std::size_t i = 0; i < reference->positions.size(); ++i)
    CHECK((converted->positions[i] - reference->positions[i]).norm() < 1e-9);
  // The rotation keeps the winding outward: the converted box encloses +6 m^3 (closed form 1*2*3).
  const hydrotex::MeshReport report = hydrotex::validateMesh(*converted, false);
  REQUIRE(report.volume);
  CHECK(*report.volume == Approx(6.0).epsilon(1e-12));

  SECTION("bad settings are one line naming the value") {
    settings.scale = 0.0;
    const auto refused = hydrotex::loadMesh(zUpCm, settings);
    REQUIRE_FALSE(refused);
    CHECK(refused.error().message.find("scale") != std::string::npos);
    CHECK(refused.error().message.find('\n') == std::string::npos);
    CHECK_FALSE(hydrotex::upAxisFromName("x"));
    CHECK(*hydrotex::upAxisFromName("Z") == hydrotex::UpAxis::Z);
  }
}

namespace {

/// A closed cube of side `side` file units in COLLADA 1.4, declaring `metersPerUnit` (issue 20).
std::string colladaCube(double side, const std::string& metersPerUnit) {
  std::ostringstream positions, indices;
  for (int i = 0; i < 8; ++i) positions << (i & 4 ? side : 0.0) << ' ' << (i & 2 ? side : 0.0) << ' ' << (i & 1 ? side : 0.0) << ' ';
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& q : quads) indices << q[0] << ' ' << q[1] << ' ' << q[2] << ' ' << q[0] << ' ' << q[2] << ' ' << q[3] << ' ';
  std::ostringstream doc;
  doc << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset>)" << (metersPerUnit.empty() ? "" : "<unit meter=\"" + metersPerUnit + "\"/>") << R"(<up_axis>Y_UP</up_axis></asset>
  <library_geometries><geometry id="box"><mesh>
    <source id="p"><float_array id="pa" count="24">)" << positions.str() << R"(</float_array>
      <technique_common><accessor source="#pa" count="8" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="12"><input semantic="VERTEX" source="#v" offset="0"/><p>)" << indices.str() << R"(</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#box"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>)";
  return doc.str();
}

}  // namespace

TEST_CASE("a unit the file declares (COLLADA) is applied and reported", "[meshio][units]") {
  // 100 units of a centimetre: a 1 m cube, whose volume is exact (1 m^3 to float rounding of
  // the file's coordinates, 1e-6 relative).
  for (const auto& [unit, side, scale] : {std::tuple<std::string, double, double>{"0.01", 100.0, 0.01},
                                          {"1", 1.0, 1.0}, {"", 1.0, 1.0}}) {
    CAPTURE(unit);
    const std::string path = outputPath("units_cube_" + (unit.empty() ? std::string("none") : unit) + ".dae");
    std::ofstream(path) << colladaCube(side, unit);
    const hydrotex::Expected<Mesh> mesh = hydrotex::loadMesh(path);
    REQUIRE(mesh);
    CHECK(mesh->fileUnitScale == Approx(scale).epsilon(1e-7));  // assimp keeps the scale in float
    const hydrotex::MeshReport report = hydrotex::validateMesh(*mesh);
    REQUIRE(report.volume);
    CHECK(*report.volume == Approx(1.0).epsilon(1e-6));
  }
}
