// SPDX-License-Identifier: Zlib
// The `hydrotex` tool as a user meets it: JSON keys and values on good input; a one-line message
// naming the file or value and a non-zero exit on bad input, never a crash.

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "TestPaths.hpp"
#include "ToolRun.hpp"
#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/Version.hpp"

namespace {

using hydrotex::test::requireCleanFailure;
using hydrotex::test::runTool;
using hydrotex::test::ToolRun;
using hydrotex::test::writeScratch;

const std::string kBox = hydrotex::test::sourcePath("data/meshes/box.obj");

}  // namespace

TEST_CASE("--version prints versionString(), the version CMake installs the package under", "[tool]") {
  // versionString() is written by hand in core/src/Version.cpp; find_package(hydrotex) takes
  // project(VERSION) from CMakeLists.txt. They must not drift apart.
  CHECK(std::string(hydrotex::versionString()) == HYDROTEX_PROJECT_VERSION);
  const ToolRun run = runTool("--version");
  CHECK(run.exitCode == 0);
  CHECK(run.out == std::string(hydrotex::versionString()) + "\n");
}

TEST_CASE("inspect reports the bundled unit box", "[tool]") {
  const ToolRun run = runTool("inspect " + kBox + " --json");
  REQUIRE(run.exitCode == 0);
  const auto json = nlohmann::json::parse(run.out);
  CHECK(json["triangles"] == 12);
  CHECK(json["vertices"] == 8);
  CHECK(json["watertight"] == true);
  CHECK(json["has_uv"] == true);
  CHECK(json["uv_overlap"] == false);
  CHECK(json["degenerate_triangles"] == 0);
  // The OBJ stores float32 coordinates of +-0.5, which are exact: area and volume are exact too.
  CHECK(json["area"].get<double>() == Approx(6.0).epsilon(1e-12));
  CHECK(json["volume"].get<double>() == Approx(1.0).epsilon(1e-12));
  CHECK(json["bounds_min"][0].get<double>() == -0.5);
  CHECK(json["bounds_max"][1].get<double>() == 0.5);
}

TEST_CASE("mass: exact and texture agree with the closed form of a unit cube", "[tool]") {
  // Unit cube, 1000 kg/m^3: mass 1000 kg, inertia m (a^2 + a^2) / 12 = 1000/6 kg m^2 about each axis.
  const ToolRun exact = runTool("mass " + kBox + " --method exact --json");
  REQUIRE(exact.exitCode == 0);
  const auto e = nlohmann::json::parse(exact.out);
  CHECK(e["mass"].get<double>() == Approx(1000.0).epsilon(1e-12));
  CHECK(e["inertia"][0][0].get<double>() == Approx(1000.0 / 6.0).epsilon(1e-12));
  CHECK(e["method"] == "exact");

  const ToolRun texture = runTool("mass " + kBox + " --method texture --resolution 128 --json");
  REQUIRE(texture.exitCode == 0);
  const auto t = nlohmann::json::parse(texture.out);
  // The texel cones of a cube's flat faces are exact up to float storage of PT and VAT: measured
  // mass 5e-8 off, centre 6e-9 m, inertia 2.3e-7 relative at 128^2. Bounds about 4 times those.
  CHECK(t["mass"].get<double>() == Approx(1000.0).epsilon(2e-7));
  CHECK(t["resolution"] == 128);
  for (int c = 0; c < 3; ++c) CHECK(std::abs(t["center_of_mass"][c].get<double>()) < 3e-8);
  for (int c = 0; c < 3; ++c) CHECK(t["inertia"][c][c].get<double>() == Approx(1000.0 / 6.0).epsilon(1e-6));
}

TEST_CASE("mass with a density map", "[tool]") {
  // A white map with --density-range 0,300 gives 300 kg/m^3 everywhere: 300 kg for the unit cube,
  // to float storage of the texel cones (1e-5); a black map with range 200,900 gives 200 kg.
  const std::string white = hydrotex::test::outputPath("white.png"), black = hydrotex::test::outputPath("black.png");
  REQUIRE(hydrotex::writePng(white, 8, 8, 1, std::vector<std::uint8_t>(64, 255)).ok());
  REQUIRE(hydrotex::writePng(black, 8, 8, 1, std::vector<std::uint8_t>(64, 0)).ok());
  const ToolRun w = runTool("mass " + kBox + " --resolution 64 --density-map " + white + " --density-range 0,300 --json");
  REQUIRE(w.exitCode == 0);
  CHECK(nlohmann::json::parse(w.out)["mass"].get<double>() == Approx(300.0).epsilon(1e-5));
  const ToolRun b = runTool("mass " + kBox + " --resolution 64 --density-map " + black + " --density-range 200,900 --json");
  REQUIRE(b.exitCode == 0);
  CHECK(nlohmann::json::parse(b.out)["mass"].get<double>() == Approx(200.0).epsilon(1e-5));
  requireCleanFailure(runTool("mass " + kBox + " --density-map " + white), "density-range");
  requireCleanFailure(runTool("mass " + kBox + " --method exact --density-map " + white + " --density-range 1,2"),
                      "density-map");
}

TEST_CASE("hydrostatics of the unit box half under water", "[tool]") {
  for (const char* method : {"exact", "texture"}) {
    const ToolRun run = runTool("hydrostatics " + kBox + " --method " + method + " --water-level 0 --json");
    REQUIRE(run.exitCode == 0);
    const auto json = nlohmann::json::parse(run.out);
    // Half the cube under: V = 0.5 m^3, B at y = -0.25, F = rho g V, A_wp = 1 m^2. The texture
    // path is exact for a flat face cut by a flat surface up to float storage (1e-5).
    CHECK(json["submerged_volume"].get<double>() == Approx(0.5).epsilon(1e-5));
    CHECK(json["center_of_buoyancy"][1].get<double>() == Approx(-0.25).epsilon(1e-4));
    CHECK(json["buoyancy_force"][1].get<double>() == Approx(1000.0 * 9.81 * 0.5).epsilon(1e-5));
    CHECK(json["waterplane_area"].get<double>() == Approx(1.0).epsilon(1e-4));
    CHECK(json["method"] == method);
  }
}

TEST_CASE("--backend gpu gives the CPU backend's answer and says what ran it", "[tool][gpu]") {
  const std::string pose = " --resolution 128 --rotate-deg 10,20,30 --translate 0,0.1,0 --json";
  const ToolRun cpu = runTool("hydrostatics " + kBox + " --backend cpu" + pose);
  REQUIRE(cpu.exitCode == 0);
  const auto c = nlohmann::json::parse(cpu.out);
  CHECK(c["backend"] == "cpu");
  CHECK(c["renderer"] == "CPU");
  const ToolRun gpu = runTool("hydrostatics " + kBox + " --backend gpu" + pose);
  if (gpu.exitCode != 0 && gpu.err.find("without the GPU backend") != std::string::npos) {
    WARN("hydrotex was built without hydrotex::gpu: " << gpu.err);
    return;
  }
  INFO(gpu.err);
  REQUIRE(gpu.exitCode == 0);
  const auto g = nlohmann::json::parse(gpu.out);
  CHECK(g["backend"] == "gpu");
  CHECK(!g["renderer"].get<std::string>().empty());
  // Issue 7's parity tolerance: 1e-5 relative on volume and force.
  CHECK(g["submerged_volume"].get<double>() == Approx(c["submerged_volume"].get<double>()).epsilon(1e-5));
  CHECK(g["buoyancy_force"][1].get<double>() == Approx(c["buoyancy_force"][1].get<double>()).epsilon(1e-5));
  const ToolRun mass = runTool("mass " + kBox + " --backend gpu --resolution 64 --json");
  REQUIRE(mass.exitCode == 0);
  CHECK(nlohmann::json::parse(mass.out)["mass"].get<double>() == Approx(1000.0).epsilon(1e-5));
}

TEST_CASE("bake writes pictures and float data", "[tool]") {
  const std::string out = hydrotex::test::outputPath("bake_box");
  std::filesystem::remove_all(out);
  const ToolRun run = runTool("bake " + kBox + " --resolution 64 --out " + out);
  REQUIRE(run.exitCode == 0);
  for (const char* file : {"position.png", "normal.png", "area.png", "coverage.png", "position.pfm", "area_vector.pfm"})
    CHECK(std::filesystem::file_size(out + "/" + file) > 0);
  // 64 x 64 texels of 3 floats, plus the PFM header.
  CHECK(std::filesystem::file_size(out + "/position.pfm") > 64u * 64u * 12u);
}

TEST_CASE("bad input gets one line and a non-zero exit", "[tool][bad-input]") {
  const std::string missing = hydrotex::test::outputPath("does_not_exist.obj");
  requireCleanFailure(runTool("inspect " + missing), "does_not_exist.obj");
  requireCleanFailure(runTool("mass " + writeScratch("empty.obj", "")), "empty.obj");
  requireCleanFailure(runTool("mass " + writeScratch("garbage.stl", std::string("\x01\x02garbage\xff\x00\x13", 12))),
                      "garbage.stl");
  requireCleanFailure(runTool("mass " + writeScratch("no_triangles.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n")),
                      "no_triangles.obj");
  requireCleanFailure(runTool("mass " + writeScratch("nan_vertex.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 1\n"
                                                                       "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")),
                      "nan_vertex.obj");
  requireCleanFailure(runTool("mass " + writeScratch("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")),
                      "open.obj");
  requireCleanFailure(runTool("mass " + kBox + " --resolution 0"), "resolution");
  requireCleanFailure(runTool("mass " + kBox + " --resolution 100000"), "resolution");
  requireCleanFailure(runTool("hydrostatics " + kBox + " --fluid-density -5"), "fluid-density");
  requireCleanFailure(runTool("hydrostatics " + kBox + " --translate 1,2"), "translate");
  requireCleanFailure(runTool("hydrostatics " + kBox + " --rotate-deg nan,0,0"), "rotate-deg");
  requireCleanFailure(runTool("frobnicate " + kBox), "frobnicate");
  requireCleanFailure(runTool("mass " + kBox + " --backend quantum"), "backend");
}

namespace {
/// OBJ of a 2 m cube at the origin and a 1 m cube at x = 3..4 written inside out (the RexROV's
/// defect: closed, positive total volume 8 - 1 = 7, one part inside out).
std::string twoBoxesOneInsideOut() {
  std::string obj = "# a box and an inside-out box\n";
  for (int part = 0; part < 2; ++part)
    for (int i = 0; i < 8; ++i) {
      const double size = part == 0 ? 2.0 : 1.0, shift = part == 0 ? 0.0 : 3.0;
      obj += "v " + std::to_string(size * (i & 1) + shift) + " " + std::to_string(size * ((i >> 1) & 1)) + " " +
             std::to_string(size * ((i >> 2) & 1)) + "\n";
    }
  obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";  // outward
  obj += "f 10 12 11 9\nf 15 16 14 13\nf 13 14 10 9\nf 12 16 15 11\nf 11 15 13 9\nf 14 16 12 10\n";  // inward
  return obj;
}
}  // namespace

TEST_CASE("an inside-out part: inspect says so, mass repairs it, --no-repair refuses", "[tool][repair]") {
  const std::string path = writeScratch("two_boxes_one_inside_out.obj", twoBoxesOneInsideOut());
  const ToolRun asIs = runTool("inspect " + path + " --no-repair --json");
  REQUIRE(asIs.exitCode == 0);
  const auto before = nlohmann::json::parse(asIs.out);
  CHECK(before["watertight"] == true);
  CHECK(before["outward_oriented"] == false);
  CHECK(before["inside_out_parts"] == 1);

  const ToolRun repaired = runTool("inspect " + path + " --json");
  REQUIRE(repaired.exitCode == 0);
  const auto after = nlohmann::json::parse(repaired.out);
  CHECK(after["outward_oriented"] == true);
  CHECK(after["repairs"]["parts_flipped"] == 1);
  // The OBJ's coordinates are small integers, exact in float: volumes exact up to rounding.
  CHECK(after["repairs"]["flipped_volume"].get<double>() == Approx(1.0).epsilon(1e-12));
  CHECK(after["volume"].get<double>() == Approx(9.0).epsilon(1e-12));
  const ToolRun text = runTool("inspect " + path);
  CHECK(text.out.find("parts turned right side out: 1") != std::string::npos);

  // Closed form: V = 8 + 1, centre x = (8 * 1 + 1 * 3.5) / 9, y = z = (8 * 1 + 1 * 0.5) / 9.
  const ToolRun mass = runTool("mass " + path + " --method exact --json");
  REQUIRE(mass.exitCode == 0);
  const auto props = nlohmann::json::parse(mass.out);
  CHECK(props["volume"].get<double>() == Approx(9.0).epsilon(1e-12));
  CHECK(props["center_of_mass"][0].get<double>() == Approx(11.5 / 9.0).epsilon(1e-12));
  CHECK(props["center_of_mass"][1].get<double>() == Approx(8.5 / 9.0).epsilon(1e-12));
  for (int i = 0; i < 3; ++i) CHECK(props["inertia"][i][i].get<double>() > 0.0);

  requireCleanFailure(runTool("mass " + path + " --method exact --no-repair"), "inside out");
  requireCleanFailure(runTool("mass " + path + " --method texture --resolution 32 --no-repair"), "inside out");
}

TEST_CASE("--up z and --scale: a z-up file in centimetres gives the y-up metre answer", "[tool][axes]") {
  // The unit box written z up in centimetres: y-up (x, y, z) stored as 100 * (x, -z, y).
  std::string obj;
  for (int i = 0; i < 8; ++i) {
    const int x = i & 1, y = (i >> 1) & 1, z = (i >> 2) & 1;
    obj += "v " + std::to_string(100 * x) + " " + std::to_string(-100 * z) + " " + std::to_string(100 * y) + "\n";
  }
  obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  const std::string path = writeScratch("box_z_up_cm.obj", obj);
  const ToolRun run = runTool("inspect " + path + " --up z --scale 0.01 --json");
  REQUIRE(run.exitCode == 0);
  const auto json = nlohmann::json::parse(run.out);
  CHECK(json["up"] == "z");
  CHECK(json["outward_oriented"] == true);
  CHECK(json["volume"].get<double>() == Approx(1.0).epsilon(1e-12));
  for (int i = 0; i < 3; ++i) {
    CHECK(json["bounds_min"][i].get<double>() == Approx(0.0).margin(1e-12));
    CHECK(json["bounds_max"][i].get<double>() == Approx(1.0).epsilon(1e-12));
  }
  requireCleanFailure(runTool("inspect " + path + " --up x"), "--up");
}

TEST_CASE("a hole too large to close is refused with one line naming it", "[tool][repair][bad-input]") {
  // The unit cube without its top face: a 4 m loop against the 1.73 m diagonal.
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n";
  obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 1 5 7 3\nf 2 4 8 6\n";
  const std::string path = writeScratch("open_top_box.obj", obj);
  requireCleanFailure(runTool("mass " + path + " --method exact"), "open hull: a boundary loop of 4 m");
  const ToolRun closed = runTool("mass " + path + " --method exact --max-hole-fraction 3 --json");
  REQUIRE(closed.exitCode == 0);
  CHECK(nlohmann::json::parse(closed.out)["volume"].get<double>() == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("--open-hull caps a deckless box with a lid that inspect lists", "[tool][repair][open_hull]") {
  // The unit cube without its top face (y = 1), as above: an open hull by design.
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n";
  obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 1 5 7 3\nf 2 4 8 6\n";
  const std::string path = writeScratch("open_top_box_lid.obj", obj);
  const ToolRun inspect = runTool("inspect " + path + " --open-hull --json");
  REQUIRE(inspect.exitCode == 0);
  const auto json = nlohmann::json::parse(inspect.out);
  REQUIRE(json["repairs"]["lids"].size() == 1);
  // Sums of four unit edges and of the fan's four triangles: exact in double.
  CHECK(json["repairs"]["lids"][0]["loop_length"].get<double>() == Approx(4.0).epsilon(1e-12));
  CHECK(json["repairs"]["lids"][0]["area"].get<double>() == Approx(1.0).epsilon(1e-12));
  CHECK(json["repairs"]["not_repaired"].empty());
  CHECK(json["volume"].get<double>() == Approx(1.0).epsilon(1e-12));
  // The closed volume floats it: 300 kg in 1000 kg/m^3 on a 1 m^2 water plane draws 0.3 m
  // (exact path: polyhedral clipping, rounding only), upright with its centre of mass low
  // (GM = 0.15 + 1 / (12 x 0.3) - 0.2 = 0.23 m).
  const ToolRun floating = runTool("equilibrium " + path + " --open-hull --mass 300 --center-of-mass 0.5,0.2,0.5 --json");
  REQUIRE(floating.exitCode == 0);
  CHECK(nlohmann::json::parse(floating.out)["draft"].get<double>() == Approx(0.3).epsilon(1e-6));
  // Weighed from its walls: 60 kg/m^2 over 5 m^2 is 300 kg, centred at y = (1 x 0 + 4 x 0.5) / 5
  // = 0.4 m, not at the closed cube's 0.5 m (exact triangle sums: 1e-12).
  const ToolRun shell = runTool("equilibrium " + path + " --open-hull --shell-density 60 --json");
  REQUIRE(shell.exitCode == 0);
  const auto shellJson = nlohmann::json::parse(shell.out);
  CHECK(shellJson["mass"].get<double>() == Approx(300.0).epsilon(1e-12));
  CHECK(shellJson["center_of_mass"][1].get<double>() == Approx(0.4).epsilon(1e-12));
  // Still upright (GM = 0.15 + 1 / (12 x 0.3) - 0.4 = 0.028 m) at 0.3 m.
  CHECK(shellJson["draft"].get<double>() == Approx(0.3).epsilon(1e-6));
  // Without repair there is nothing to cap: refused as an open mesh, with one line.
  requireCleanFailure(runTool("mass " + path + " --method exact --open-hull --no-repair"), "open");
}
