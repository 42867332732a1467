// SPDX-License-Identifier: Zlib
// Bad mesh files, through the API (loadMesh, loadMeshFromMemory, loadBodyGeometry) and the tool
// (inspect, mass, hydrostatics, bake): each gives one line naming the file and a non-zero exit,
// never a crash, a hang or a silently wrong number. Meshes that are imperfect but usable (no UVs,
// overlapping UVs, UVs outside the unit square, a million triangles) give the right numbers.

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "TestPaths.hpp"
#include "ToolRun.hpp"
#include "hydrotex/mesh/Atlas.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;
using hydrotex::test::outputPath;
using hydrotex::test::readFile;
using hydrotex::test::writeScratch;

namespace {

/// The unit cube as OBJ text with the UVs given per triangle corner (`uvOf(t, corner)`), or none.
template <class UvOf>
std::string cubeObj(UvOf uvOf, bool withUvs) {
  const Mesh cube = primitives::box(Eigen::Vector3d::Ones());
  std::ostringstream obj;
  obj.precision(17);
  for (const Eigen::Vector3d& p : cube.positions) obj << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (std::size_t t = 0; t < cube.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d uv = uvOf(t, c);
      if (withUvs) obj << "vt " << uv.x() << ' ' << uv.y() << '\n';
    }
  for (std::size_t t = 0; t < cube.triangles.size(); ++t) {
    obj << 'f';
    for (int c = 0; c < 3; ++c) {
      obj << ' ' << cube.triangles[t][c] + 1;
      if (withUvs) obj << '/' << 3 * t + static_cast<std::size_t>(c) + 1;
    }
    obj << '\n';
  }
  return obj.str();
}

/// The cube with its own (valid) atlas.
std::string validCubeObj() {
  const Mesh cube = primitives::box(Eigen::Vector3d::Ones());
  return cubeObj([&](std::size_t t, int c) { return cube.uv.uvs[std::size_t(cube.uv.uvTriangles[t][c])]; }, true);
}

/// A tetrahedron (outward) with its four vertices given as OBJ text.
std::string tetrahedronObj(const std::string& vertices) { return vertices + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"; }

struct BadMesh {
  std::string file;     ///< scratch file name (its extension picks assimp's reader)
  std::string content;  ///< bytes
  std::string reason;   ///< a word the message must contain (besides the file name)
  bool loads;           ///< loadMesh accepts it (the problem is found later: topology, volume)
};

/// The text cut in the middle of its face lines (half the faces kept, the last one cut short).
std::string cutInFaces(const std::string& text) {
  const std::size_t firstFace = text.find("\nf ");
  return text.substr(0, firstFace + (text.size() - firstFace) / 2);
}

std::vector<BadMesh> badMeshes() {
  const std::string unitTet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  std::string garbage;
  for (int i = 0; i < 2048; ++i) garbage.push_back(static_cast<char>((i * 7919 + 13) % 251));
  // A binary STL of the cube, cut in the middle of its triangles.
  const std::string stlPath = outputPath("robust_source_cube.stl");
  REQUIRE(saveMesh(primitives::box(Eigen::Vector3d::Ones()), stlPath).ok());
  const std::string stl = readFile(stlPath);
  // A binary PLY triangle whose face list (uint count) declares 4e9 corners.
  std::string binaryHugeList =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uint int vertex_indices\nend_header\n";
  binaryHugeList += std::string(9 * sizeof(float), '\0');
  const std::uint32_t hugeCount = 4000000000u;  // little-endian on every platform the tests run on
  binaryHugeList.append(reinterpret_cast<const char*>(&hugeCount), sizeof hugeCount);
  binaryHugeList += std::string(3 * sizeof(std::int32_t), '\0');
  return {
      {"robust_empty.obj", "", "empty", false},
      {"robust_garbage.ply", garbage, "not a readable mesh", false},
      {"robust_garbage.stl", garbage, "", false},
      {"robust_unsupported.hdxmesh", "solid nothing here\n", "not a readable mesh", false},
      {"robust_truncated.stl", stl.substr(0, 84 + 50 * 5 + 17), "", false},
      // An OBJ cut inside a face ("f 8/"): assimp's validation refuses the half face.
      {"robust_truncated.obj", cutInFaces(validCubeObj()), "not a readable mesh", false},
      // assimp 5.2's PLY reader loops forever without "end_header" (fuzz_mesh): refused first.
      {"robust_ply_no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n0\n1\n2\n",
       "end_header", false},
      {"robust_ply_end_header_not_a_line.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty end_headerfloat x\nend_header1 2 3\n0\n1\n2\n",
       "end_header", false},
      // Counts beyond the data: assimp would allocate for them first (11 GB for this list).
      {"robust_ply_huge_list.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
       "33333333333333333333 0 1 2\n",
       "more than the file", false},
      // A token that is not a number makes assimp's reader split the body otherwise than a
      // reader of whole tokens: it took the last line's value for a list count (11 GB; fuzz_mesh).
      {"robust_ply_not_a_number.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
       "3]0 1 2\n33333333333333333333 0 1 2\n",
       "'3]0' where a list count belongs", false},
      {"robust_ply_word_for_number.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 y\n3 0 1 2\n",
       "'vertex' entry 2 holds 'y' where a number belongs", false},
      // assimp's reader takes one entry a line: a short vertex line shifted a later value into a
      // face's list count (4 billion values; fuzz_mesh in CI's run). Likewise a short last line,
      // an entry with values to spare, a count that is not a whole number, a file that ends early.
      {"robust_ply_short_line.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 000\n0 1 0\n"
       "3333333333 0 1 2\n",
       "entry 1 has 2 values on its line, fewer", false},
      {"robust_ply_short_face.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
       "'face' entry 0 has 3 values on its line, fewer", false},
      {"robust_ply_long_line.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "'vertex' entry 0 has 4 values on its line, more", false},
      {"robust_ply_fractional_count.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3.5 0 1 2\n",
       "'3.5' where a list count belongs", false},
      {"robust_ply_ends_early.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "has 1 of its 2 entries", false},
      // A garbled header line: assimp's lenient reader saw other elements than a strict one
      // (a list count of 3e33 then got through; fuzz_mesh in CI's run). Refused at the line.
      {"robust_ply_garbled_header.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float xJproperty float y\nproperty float z\n"
       "element faceelement vertex 3\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n",
       "PLY header line 4 ('property float xJproperty float y') is not 'property <type> <name>'", false},
      {"robust_ply_binary_huge_list.ply", binaryHugeList, "declares a list of 4000000000 values, more than the file holds",
       false},
      // assimp's OFF reader allocates for its counts first (a face count of 1e25 wrapped to 2.3e9
      // asked for 37 GB; fuzz_mesh).
      {"robust_off_huge_count.off", "OFF\n3 10000000000000000000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "OFF header declares 10000000000000000000000000 faces, more than the file's", false},
      {"robust_off_count_with_tail.off", "OFF\n3 1000000000$0 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "OFF header declares 1000000000$0 faces", false},
      {"robust_off_huge_vertices.off", "OFF\n4000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "OFF header declares 4000000000 vertices", false},
      // The reader goes on right after the keyword: digits glued to it are the vertex count
      // ("OFF02": 2, then a face count of 1e17), and '#' glued to it starts a comment (fuzz_mesh
      // in CI's runs).
      {"robust_off_glued_count.off", "OFF02 \n100000000000000000(1 2 3\n",
       "OFF header declares 100000000000000000(1 faces", false},
      {"robust_off_glued_comment.off", "OFF#\n2 100000000000000000000\n3 03\n3!0sho4\n3(1 2 3\n",
       "OFF header declares 100000000000000000000 faces", false},
      // An element without properties costs assimp an instance per entry, and the guard's binary
      // walk one turn: 2^64 - 1 of them are refused, not walked.
      {"robust_ply_empty_element.ply",
       "ply\nformat binary_little_endian 1.0\nelement nothing 18446744073709551615\nend_header\n",
       "declares 18446744073709551615 entries, more than the file's", false},
      {"robust_ply_huge_count.ply",
       "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n0000",
       "more than the file", false},
      {"robust_points_only.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n", "no triangles", false},
      {"robust_lines_only.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n", "no triangles", false},
      {"robust_nan.obj", tetrahedronObj("v 0 0 0\nv 1 0 0\nv 0 nan 0\nv 0 0 1\n"), "NaN", false},
      {"robust_inf.obj", tetrahedronObj("v 0 0 0\nv 1 0 0\nv 0 inf 0\nv 0 0 1\n"), "infinite", false},
      {"robust_1e30.obj", tetrahedronObj("v 0 0 0\nv 1e30 0 0\nv 0 1 0\nv 0 0 1\n"), "1e12", false},
      {"robust_collinear.obj", tetrahedronObj("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\n"), "", true},
      {"robust_flat.obj", tetrahedronObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"), "no volume", true},
      {"robust_inverted.obj", unitTet + "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n", "inside out", true},
      {"robust_open.obj", unitTet + "f 1 3 2\nf 1 2 4\nf 1 4 3\n", "open", true},
      {"robust_one_flipped.obj", unitTet + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 4 3\n", "", true},
      // Two tetrahedra sharing one edge: no boundary, but an edge used by four triangles.
      {"robust_non_manifold.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nv 0 0 -1\n"
       "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 1 2 5\nf 1 6 2\nf 1 5 6\nf 2 6 5\n",
       "manifold", true},
  };
}

/// The message is one line that names the file.
void checkMessage(const std::string& message, const std::string& file, const std::string& reason) {
  INFO(message);
  CHECK(message.find(file) != std::string::npos);
  CHECK(message.find('\n') == std::string::npos);
  if (!reason.empty()) CHECK(message.find(reason) != std::string::npos);
}

}  // namespace

TEST_CASE("bad mesh files: the API returns one line naming the file", "[robustness][bad-input][mesh]") {
  for (const BadMesh& bad : badMeshes()) {
    CAPTURE(bad.file);
    const std::string path = writeScratch(bad.file, bad.content);
    const Expected<Mesh> mesh = loadMesh(path);
    CHECK(mesh.ok() == bad.loads);
    if (!mesh) checkMessage(mesh.error().message, bad.file, bad.reason);

    // The same bytes from memory: the same verdict, named by the given name.
    const std::string extension = bad.file.substr(bad.file.rfind('.') + 1);
    const Expected<Mesh> fromMemory = loadMeshFromMemory(bad.content.data(), bad.content.size(), extension, bad.file);
    CHECK(fromMemory.ok() == mesh.ok());
    if (!fromMemory) checkMessage(fromMemory.error().message, bad.file, "");

    // Everything that needs a volume refuses it as it is (repair off; repairs: the next cases),
    // naming the file.
    BodyGeometrySettings settings;
    settings.bake.width = settings.bake.height = 32;
    settings.load.repair.enabled = false;
    const Expected<BodyGeometry> body = loadBodyGeometry(path, settings);
    REQUIRE_FALSE(body.ok());
    checkMessage(body.error().message, bad.file, bad.reason);
    if (mesh) {
      const Expected<MassProperties> exact = polyhedralMassProperties(*mesh, 1000.0);
      REQUIRE_FALSE(exact.ok());
      checkMessage(exact.error().message, bad.file, "");
    }
  }
}

TEST_CASE("loadMeshFromMemory reads what loadMesh reads, and refuses bad hints", "[robustness][mesh]") {
  const std::string obj = validCubeObj();
  const Expected<Mesh> mesh = loadMeshFromMemory(obj.data(), obj.size(), "obj", "cube.obj");
  REQUIRE(mesh.ok());
  CHECK(mesh->triangles.size() == 12);
  CHECK(mesh->hasUvs());
  const Expected<MassProperties> mass = polyhedralMassProperties(*mesh, 1000.0);
  REQUIRE(mass.ok());
  // Coordinates +-0.5 are exact in every format: the unit cube's mass is exact.
  CHECK(mass->mass == Approx(1000.0).epsilon(1e-12));
  CHECK_FALSE(loadMeshFromMemory(obj.data(), obj.size(), ".obj", "cube.obj").ok());
  CHECK_FALSE(loadMeshFromMemory(obj.data(), obj.size(), "../../x", "cube.obj").ok());
  CHECK_FALSE(loadMeshFromMemory(nullptr, 0, "obj", "nothing.obj").ok());
}

// Regression (fuzz_mesh, issue 11): assimp 5.2's MTL parser writes through a wild pointer on binary
// garbage (seen under ASan; silent or a crash elsewhere). ReadFileFromMemory handed it the mesh
// bytes themselves as the OBJ's fallback material library; on disk, a corrupt .mtl beside the OBJ
// reached it. hydrotex reads no material library at all, so both load the triangles cleanly.
TEST_CASE("a corrupt material library is never parsed", "[robustness][bad-input][mesh]") {
  // The fuzzer's input: one byte picking the "obj" hint, binary garbage, then an OBJ cube.
  const std::string input = readFile(hydrotex::test::sourcePath("fuzz/corpus/mesh/obj-garbage-mtl-fallback.bin"));
  REQUIRE(input.size() > 1);
  const Expected<Mesh> fromMemory = loadMeshFromMemory(input.data() + 1, input.size() - 1, "obj", "fuzz.obj");
  // The leading garbage is not OBJ: a clean error naming the file (no crash is the point).
  REQUIRE_FALSE(fromMemory.ok());
  checkMessage(fromMemory.error().message, "fuzz.obj", "not a readable mesh");

  // On disk: a valid cube whose material library is those garbage bytes.
  writeScratch("robust_corrupt_materials.mtl", input);
  const std::string path = writeScratch("robust_corrupt_materials.obj", "mtllib robust_corrupt_materials.mtl\nusemtl hull\n" + validCubeObj());
  const Expected<Mesh> fromDisk = loadMesh(path);
  REQUIRE(fromDisk.ok());
  CHECK(fromDisk->triangles.size() == 12);
  // The same text from memory: nothing else is opened (no .mtl looked up in the working directory).
  const std::string text = readFile(path);
  const Expected<Mesh> textFromMemory = loadMeshFromMemory(text.data(), text.size(), "obj", "cube.obj");
  REQUIRE(textFromMemory.ok());
  CHECK(textFromMemory->triangles.size() == 12);
}

// Regression (fuzz_mesh, issue 11): Debian's assimp 5.2 keeps its assertions, and its
// triangulation aborted the process when the PLY reader, failing to parse a face, kept it with no
// corners while flagging the mesh as holding polygons.
TEST_CASE("a PLY face the reader skips does not abort the import", "[robustness][bad-input][mesh]") {
  const std::string input =
      readFile(hydrotex::test::sourcePath("fuzz/corpus/mesh/ply-skipped-face-triangulate-assert.bin"));
  REQUIRE(input.size() > 1);
  const std::string bytes = input.substr(1);  // the first byte picked the "ply" hint
  const std::string path = writeScratch("robust_skipped_face.ply", bytes);
  const Expected<Mesh> fromDisk = loadMesh(path);
  const Expected<Mesh> fromMemory = loadMeshFromMemory(bytes.data(), bytes.size(), "ply", "robust_skipped_face.ply");
  // The reader kept the face it could not parse as one with no corners (a short vertex line set
  // it off; the import refuses such faces too). The guard now refuses the file at that line.
  REQUIRE_FALSE(fromDisk.ok());
  checkMessage(fromDisk.error().message, "robust_skipped_face.ply", "'vertex' entry 2 has 2 values on its line");
  REQUIRE_FALSE(fromMemory.ok());
  checkMessage(fromMemory.error().message, "robust_skipped_face.ply", "'vertex' entry 2 has 2 values on its line");
}

#ifdef HYDROTEX_TOOL_PATH
TEST_CASE("with repair on, flipped tetrahedra load and the rest is refused naming the defect", "[robustness][bad-input][mesh][repair]") {
  using hydrotex::test::requireCleanFailure;
  using hydrotex::test::runTool;
  for (const BadMesh& bad : badMeshes()) {
    if (!bad.loads) continue;
    CAPTURE(bad.file);
    const std::string path = writeScratch(bad.file, bad.content);
    BodyGeometrySettings settings;
    settings.bake.width = settings.bake.height = 32;
    const Expected<BodyGeometry> body = loadBodyGeometry(path, settings);
    if (bad.file == "robust_inverted.obj" || bad.file == "robust_one_flipped.obj") {
      // The unit tetrahedron (corners at the origin and the unit axes): volume 1/6, exact in doubles
      // up to rounding of a few products (1e-12 relative).
      REQUIRE(body.ok());
      CHECK(*body->report.volume == Approx(1.0 / 6.0).epsilon(1e-12));
      CHECK(body->repairs.changed());
      continue;
    }
    REQUIRE_FALSE(body.ok());
    checkMessage(body.error().message, bad.file, "");
    // The repair names what it could not fix; the flat and collinear ones are caught after it.
    if (bad.file == "robust_open.obj") checkMessage(body.error().message, bad.file, "open hull: a boundary loop of");
    if (bad.file == "robust_non_manifold.obj") checkMessage(body.error().message, bad.file, "non-manifold");
    requireCleanFailure(runTool("mass --method exact " + path, 120), bad.file);
  }
}

TEST_CASE("bad mesh files: the tool exits non-zero with one line naming the file", "[robustness][bad-input][mesh][tool]") {
  using hydrotex::test::requireCleanFailure;
  using hydrotex::test::runTool;
  const std::string bakeOut = outputPath("robust_bake_out");
  for (const BadMesh& bad : badMeshes()) {
    CAPTURE(bad.file);
    const std::string path = writeScratch(bad.file, bad.content);
    for (const std::string verb :
         {"mass --resolution 32 --no-repair", "mass --method exact --no-repair", "hydrostatics --resolution 32 --no-repair",
          "hydrostatics --method exact --no-repair"}) {
      CAPTURE(verb);
      const test::ToolRun run = runTool(verb + " " + path, 120);
      requireCleanFailure(run, bad.file);
      // Prefixed once: "x.obj: x.obj: ..." reads like two files (assimp's own text may name it too).
      CHECK(run.err.find(bad.file + ":") == run.err.rfind(bad.file + ":"));
    }
    // A bake is a surface quantity: open, inverted or flat meshes bake; unreadable ones must not.
    const test::ToolRun bake = runTool("bake --resolution 32 --out " + bakeOut + " " + path, 120);
    if (!bad.loads || bake.exitCode != 0) requireCleanFailure(bake, bad.file);
    // inspect reports what it can: files that load are described (not refused), others fail cleanly.
    const test::ToolRun inspect = runTool("inspect " + path + " --json --no-repair", 120);
    if (bad.loads) {
      REQUIRE(inspect.exitCode == 0);
      const auto json = nlohmann::json::parse(inspect.out);
      CHECK((json["watertight"] == false || json["volume"].get<double>() <= 0.0));
    } else {
      requireCleanFailure(inspect, bad.file);
    }
  }
}

TEST_CASE("unusable UVs fall back to a generated atlas and the mass stays exact", "[robustness][mesh][atlas][tool]") {
  using hydrotex::test::runTool;
  const Mesh cube = primitives::box(Eigen::Vector3d::Ones());
  struct Case {
    std::string file;
    std::string content;
  };
  const std::vector<Case> cases = {
      {"robust_no_uvs.obj", cubeObj([](std::size_t, int) { return Eigen::Vector2d::Zero(); }, false)},
      // Every triangle on the same UV triangle: maximal overlap.
      {"robust_stacked_uvs.obj",
       cubeObj([](std::size_t, int c) { return Eigen::Vector2d(c == 1 ? 1.0 : 0.0, c == 2 ? 1.0 : 0.0); }, true)},
      // A valid layout shifted out of the unit square.
      {"robust_uvs_outside.obj",
       cubeObj([&](std::size_t t, int c) {
         return Eigen::Vector2d(cube.uv.uvs[std::size_t(cube.uv.uvTriangles[t][c])] + Eigen::Vector2d(3.0, -2.0));
       },
               true)},
      // Every UV at one point (zero UV area everywhere).
      {"robust_collapsed_uvs.obj", cubeObj([](std::size_t, int) { return Eigen::Vector2d(0.5, 0.5); }, true)},
  };
  for (const Case& c : cases) {
    CAPTURE(c.file);
    const std::string path = writeScratch(c.file, c.content);
    const Expected<Mesh> mesh = loadMesh(path);
    REQUIRE(mesh.ok());
    const MeshReport report = validateMesh(*mesh);
    CHECK_FALSE(report.uvUsableAsAtlas());
    const PhysicsAtlas atlas = physicsAtlas(*mesh, report);
    CHECK(atlas.generated);
    CHECK_FALSE(atlas.reason.empty());
    const test::ToolRun run = runTool("mass " + path + " --resolution 64 --json", 120);
    INFO(run.err);
    REQUIRE(run.exitCode == 0);
    // Unit cube of 1000 kg/m^3: texel volumes are exact up to float storage of PT and VAT (1e-5).
    CHECK(nlohmann::json::parse(run.out)["mass"].get<double>() == Approx(1000.0).epsilon(1e-5));
  }
}
#endif

TEST_CASE("a million-triangle mesh goes through validation, atlas, bake and mass", "[robustness][mesh][large]") {
  // A UV sphere of 1000 x 500 cells: 998,000 triangles (the pole rows are single triangles).
  const Mesh sphere = primitives::uvSphere(1.0, 1000, 500);
  REQUIRE(sphere.triangles.size() > 990'000);
  const std::string path = outputPath("robust_million.stl");
  REQUIRE(saveMesh(sphere, path).ok());
  const Expected<Mesh> loaded = loadMesh(path);  // binary STL: no UVs, so the atlas is generated
  REQUIRE(loaded.ok());
  CHECK(loaded->triangles.size() == sphere.triangles.size());
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = 512;
  const Expected<BodyGeometry> body = prepareBodyGeometry(*loaded, settings);
  INFO((body ? std::string() : body.error().message));
  REQUIRE(body.ok());
  CHECK(body->atlas.generated);
  const Expected<MassProperties> exact = polyhedralMassProperties(*loaded, 1000.0);
  REQUIRE(exact.ok());
  const MassProperties texture = textureMassProperties(body->textures, TextureMassModel{});
  // The texel volume sum is exact for the polyhedron up to float storage of PT and VAT (1e-5);
  // the polyhedron's volume is within (pi / 500)^2 of the sphere's (chord error of the cells).
  CHECK(texture.mass == Approx(exact->mass).epsilon(1e-5));
  CHECK(exact->volume == Approx(4.0 / 3.0 * std::numbers::pi).epsilon(1e-4));
}
