// SPDX-License-Identifier: Zlib
// `hydrotex simulate` with a soft body (issue 5): the CSV keeps its columns and their order and
// gains one row per soft body after the rigid ones, with the nodes' centre of mass, velocities,
// node mass and submerged volume; the flooding and wetting columns read 0 (not applicable), as
// they do for rigid bodies that do not list those effects. Checked against the scene's inputs and
// Archimedes (at rest the submerged volume is m / rho).

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "TestPaths.hpp"
#include "ToolRun.hpp"

namespace {

using hydrotex::test::runTool;
using hydrotex::test::ToolRun;

const std::string kHeader =
    "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,mass,submerged_volume,liquid_volume,liquid_surface,absorbed,"
    "evaporated";

struct Row {
  std::string body;
  std::vector<double> values;  // every column but `body`, in file order (time first)
};

std::vector<Row> parseRows(const std::string& text, std::string& header) {
  std::istringstream in(text);
  std::getline(in, header);
  std::vector<Row> rows;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    Row row;
    std::string field;
    for (int column = 0; std::getline(fields, field, ','); ++column) {
      if (column == 1)
        row.body = field;
      else
        row.values.push_back(std::stod(field));
    }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST_CASE("simulate writes CSV rows for soft bodies with the rigid bodies' columns", "[tool][soft]") {
  // data/meshes/sphere.obj: radius 0.5 m. 150 kg floats with 0.15 m^3 under water.
  const std::string mesh = hydrotex::test::sourcePath("data/meshes/sphere.obj");
  const std::string box = hydrotex::test::sourcePath("data/meshes/box.obj");
  const std::string scene = hydrotex::test::writeScratch("simulate_soft.json", R"({
    "dt": 0.004166666666666667, "duration": 4.0,
    "fluid": {"density": 1000, "surface": {"type": "plane", "height": 0}},
    "bodies": [
      {"name": "ball", "mesh": ")" + mesh + R"(", "mass": 150, "position": [0, 0.25, 0], "resolution": 128,
       "soft": true, "soft_material": {"linear_stiffness": 1.0, "volume_conservation": 50, "damping": 0.01,
                                       "shape_matching": 0.5, "iterations": 8, "bending_distance": 2}},
      {"name": "box", "mesh": ")" + box + R"(", "density": 500, "position": [2, 0.5, 0], "resolution": 64}]})");
  const std::string csv = hydrotex::test::outputPath("simulate_soft.csv");
  const ToolRun run = runTool("simulate " + scene + " --csv " + csv + " --every 48 --json", 300);
  INFO(run.err);
  REQUIRE(run.exitCode == 0);

  std::string header;
  const std::vector<Row> rows = parseRows(hydrotex::test::readFile(csv), header);
  CHECK(header == kHeader);  // the columns and their order are unchanged
  // 960 steps, a row per body at step 0 and every 48 steps: 21 times, rigid body first.
  REQUIRE(rows.size() == 2 * 21);
  for (std::size_t i = 0; i < rows.size(); i += 2) {
    CHECK(rows[i].body == "box");
    CHECK(rows[i + 1].body == "ball");
    CHECK(rows[i].values[0] == rows[i + 1].values[0]);  // same time
  }
  for (const Row& row : rows) REQUIRE(row.values.size() == 20);
  // Column indices in `values` (body removed): time 0, p 1-3, q 4-7, v 8-10, w 11-13, mass 14,
  // submerged 15, liquid_volume 16, liquid_surface 17, absorbed 18, evaporated 19.
  const Row& first = rows[1];
  const Row& last = rows.back();
  // Centre of mass of the nodes at t = 0: the scene's position (the mesh is centred on its
  // origin; Bullet spreads the mass by face area, symmetric to 1 mm on this mesh).
  CHECK(first.values[1] == Approx(0.0).margin(1e-3));
  CHECK(first.values[2] == Approx(0.25).margin(1e-3));
  CHECK(first.values[3] == Approx(0.0).margin(1e-3));
  for (const Row* row : {&first, &last}) {
    // The orientation is a unit quaternion (the pose-matching frame; identity at rest).
    const double norm = std::sqrt(row->values[4] * row->values[4] + row->values[5] * row->values[5] +
                                  row->values[6] * row->values[6] + row->values[7] * row->values[7]);
    CHECK(norm == Approx(1.0).epsilon(1e-6));
    // Node masses sum to the scene's mass (float sums over 1106 nodes).
    CHECK(row->values[14] == Approx(150.0).epsilon(1e-5));
    // No flooding or wetting for a soft body: 0, the CSV's "not applicable".
    for (int column = 16; column < 20; ++column) CHECK(row->values[std::size_t(column)] == 0.0);
  }
  // Settled after 4 s (kDP and drag): slow, and Archimedes: submerged volume m / rho to 1 % (the
  // texel volume is exact for the mesh; what remains is the last of the heave).
  CHECK(std::abs(last.values[9]) < 0.05);
  CHECK(last.values[15] == Approx(0.15).epsilon(0.01));
  // The rigid box's row is as before: its mass (density 500 x 1 m^3, exact in texel sums to 1e-6).
  CHECK(rows[rows.size() - 2].values[14] == Approx(500.0).epsilon(1e-6));

  const auto json = nlohmann::json::parse(run.out);
  REQUIRE(json["bodies"].size() == 2);
  CHECK(json["bodies"][1]["name"] == "ball");
  CHECK(json["bodies"][1]["soft"] == true);
  CHECK(json["bodies"][1]["submerged_volume"].get<double>() == Approx(last.values[15]).epsilon(1e-6));
}
