// SPDX-License-Identifier: Zlib
// `hydrotex equilibrium` and `hydrotex stability` as a user meets them: a box barge's draft, GM
// and wall-sided righting levers in the JSON (closed forms, docs/stability.md), the up axis,
// point masses, the CSV and the plot; one line and a non-zero exit, nothing written, on bad input.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "TestPaths.hpp"
#include "ToolRun.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/Primitives.hpp"

namespace {

using hydrotex::test::requireCleanFailure;
using hydrotex::test::runTool;
using hydrotex::test::ToolRun;

constexpr double kPi = 3.14159265358979323846;

/// Writes `mesh` to the test output directory as `name` (OBJ); its path.
std::string saved(const hydrotex::Mesh& mesh, const std::string& name) {
  const std::string path = hydrotex::test::outputPath(name);
  REQUIRE(hydrotex::saveMesh(mesh, path));
  return path;
}

/// The barge 2 (length, x) x 0.5 (depth, y) x 1 (beam, z) m, centred at the origin: volume 1 m^3.
const std::string& bargePath() {
  static const std::string path = saved(hydrotex::primitives::box(Eigen::Vector3d(2.0, 0.5, 1.0)), "eq_barge.obj");
  return path;
}

/// GM = KB + BM - KG of a box of beam B at draft T.
double boxGm(double beam, double draft, double kg) { return 0.5 * draft + beam * beam / (12.0 * draft) - kg; }

nlohmann::json runJson(const std::string& arguments) {
  const ToolRun run = runTool(arguments + " --json");
  INFO("stderr: " << run.err);
  REQUIRE(run.exitCode == 0);
  return nlohmann::json::parse(run.out);
}

// The exact path solves to 1e-10 of the moments and 1e-12 of the volume; values pass through JSON
// at full precision: 1e-9 is what the closed forms are held to.
constexpr double kExact = 1e-9;

}  // namespace

TEST_CASE("equilibrium: the barge at s = 0.4 floats at T = 0.2 m with GM = KB + BM - KG", "[tool][floating]") {
  // T = 0.4 x 0.5 = 0.2 m, KB = 0.1, BM_T = 1/2.4, BM_L = 4/2.4, KG = 0.25 (centre).
  for (const char* mass : {"--density 400", "--mass 400", "--displacement 0.4", "--mass 400 --method auto"}) {
    INFO(mass);
    const auto j = runJson("equilibrium " + bargePath() + " " + std::string(mass));
    CHECK(j["draft"].get<double>() == Approx(0.2).epsilon(kExact));
    CHECK(std::abs(j["heel_deg"].get<double>()) < kExact);
    CHECK(std::abs(j["trim_deg"].get<double>()) < kExact);
    CHECK(j["displaced_volume"].get<double>() == Approx(0.4).epsilon(kExact));
    CHECK(j["waterplane_area"].get<double>() == Approx(2.0).epsilon(kExact));
    CHECK(j["gm_transverse"].get<double>() == Approx(boxGm(1.0, 0.2, 0.25)).epsilon(kExact));
    CHECK(j["gm_longitudinal"].get<double>() == Approx(boxGm(2.0, 0.2, 0.25)).epsilon(kExact));
    CHECK(j["center_of_buoyancy"][1].get<double>() == Approx(-0.1).epsilon(kExact));
    CHECK(j["pose"]["translation"][1].get<double>() == Approx(0.05).epsilon(kExact));
    CHECK(j["stable"] == true);
    CHECK(j["start_unstable"] == false);
    CHECK(j["method"] == "exact");
  }
}

TEST_CASE("equilibrium: a point mass lowers G; --up z reads a z-up file", "[tool][floating]") {
  // 300 kg hull at its centre + 100 kg at 0.25 m below: G at -0.0625, KG = 0.1875.
  const auto ballasted = runJson("equilibrium " + bargePath() + " --mass 300 --point-mass 100@0,-0.25,0");
  CHECK(ballasted["mass"].get<double>() == Approx(400.0).epsilon(1e-12));
  CHECK(ballasted["center_of_mass"][1].get<double>() == Approx(-0.0625).epsilon(1e-12));
  CHECK(ballasted["gm_transverse"].get<double>() == Approx(boxGm(1.0, 0.2, 0.1875)).epsilon(kExact));

  // The same barge modelled z up: its depth along z, its beam along y.
  const std::string zUp = saved(hydrotex::primitives::box(Eigen::Vector3d(2.0, 1.0, 0.5)), "eq_barge_z_up.obj");
  const auto j = runJson("equilibrium " + zUp + " --density 400 --up z --center-of-mass 0,0,0");
  CHECK(j["draft"].get<double>() == Approx(0.2).epsilon(kExact));
  CHECK(j["gm_transverse"].get<double>() == Approx(boxGm(1.0, 0.2, 0.25)).epsilon(kExact));
  // The file's pose: z turned to y is a rotation of -90 deg about x.
  CHECK(j["pose"]["rotation_deg"][0].get<double>() == Approx(-90.0).epsilon(kExact));
}

TEST_CASE("equilibrium: the texture path agrees with the closed form to its resolution", "[tool][floating]") {
  const auto j = runJson("equilibrium " + bargePath() + " --density 400 --method texture --resolution 64");
  CHECK(j["method"] == "texture");
  // Texels are exact planar pieces; the float storage and the waterline texels leave ~1e-7 m on
  // the draft and a few 1e-4 m on GM at 64^2 (core suite: 4.5e-4 m at 128^2).
  CHECK(j["draft"].get<double>() == Approx(0.2).margin(1e-4));
  CHECK(j["gm_transverse"].get<double>() == Approx(boxGm(1.0, 0.2, 0.25)).margin(2e-3));
}

TEST_CASE("stability: the barge's GZ follows the wall-sided formula; CSV and plot", "[tool][floating]") {
  const std::string csv = hydrotex::test::outputPath("eq_barge_gz.csv");
  const std::string png = hydrotex::test::outputPath("eq_barge_gz.png");
  std::filesystem::remove(csv);
  std::filesystem::remove(png);
  const bool gnuplot = std::system("command -v gnuplot >/dev/null 2>&1") == 0;
  const auto j = runJson("stability " + bargePath() + " --density 400 --max-deg 20 --step-deg 1 --csv " + csv +
                         (gnuplot ? " --plot " + png : std::string()));
  const double gm = boxGm(1.0, 0.2, 0.25), bm = 1.0 / 2.4;
  REQUIRE(j["curve"].size() == 21);
  for (const auto& point : j["curve"]) {
    // GZ = sin(phi) (GM + BM/2 tan^2 phi) until the bilge emerges at 21.8 deg.
    const double phi = point[0].get<double>() * kPi / 180.0;
    CHECK(point[1].get<double>() == Approx(std::sin(phi) * (gm + 0.5 * bm * std::tan(phi) * std::tan(phi))).margin(1e-9));
  }
  CHECK(j["gm"].get<double>() == Approx(gm).epsilon(kExact));
  CHECK(j["angle_of_max_gz_deg"].get<double>() == Approx(20.0).epsilon(1e-12));
  CHECK(j["angle_of_vanishing_stability_deg"].is_null());
  CHECK(j["area_30_m_rad"].is_null());
  CHECK(j["area_40_m_rad"].is_null());
  const std::string rows = hydrotex::test::readFile(csv);
  CHECK(std::count(rows.begin(), rows.end(), '\n') == 22);  // header + 21 angles
  CHECK(rows.rfind("angle_deg,gz_m,trim_deg\n", 0) == 0);
  if (gnuplot)
    CHECK(std::filesystem::file_size(png) > 1000);
  else
    WARN("gnuplot not on the PATH: --plot not exercised");

  // Full sweep: the barge's GZ vanishes at 90 deg (symmetric on its side, unstable there).
  const auto full = runJson("stability " + bargePath() + " --density 400");
  CHECK(full["curve"].size() == 91);
  CHECK(full["angle_of_vanishing_stability_deg"].get<double>() == Approx(90.0).margin(1e-6));
  CHECK(full["area_30_m_rad"].get<double>() > 0.0);
  CHECK(full["area_40_m_rad"].get<double>() > full["area_30_m_rad"].get<double>());
}

TEST_CASE("equilibrium and stability: bad input is one line, a non-zero exit and nothing written", "[tool][floating]") {
  const std::string csv = hydrotex::test::outputPath("eq_bad.csv");
  std::filesystem::remove(csv);
  const std::string verb = "stability " + bargePath() + " --csv " + csv + " ";
  requireCleanFailure(runTool(verb + "--displacement 2"), "no floating equilibrium");
  requireCleanFailure(runTool(verb + "--density 1200"), "no floating equilibrium");
  requireCleanFailure(runTool(verb + "--mass 400 --center-of-mass 0,1,0"), "outside the bounds");
  requireCleanFailure(runTool(verb + "--mass -5"), "-5");
  requireCleanFailure(runTool(verb + "--density 400 --step-deg 0"), "--step-deg");
  requireCleanFailure(runTool(verb + "--density 400 --point-mass 5@1,2"), "--point-mass");
  requireCleanFailure(runTool("equilibrium " + bargePath()), "--mass");
  hydrotex::Mesh open = hydrotex::primitives::box(Eigen::Vector3d(2.0, 0.5, 1.0));
  open.triangles.pop_back();
  requireCleanFailure(runTool("equilibrium " + saved(open, "eq_open.obj") + " --density 400"), "eq_open.obj");
  requireCleanFailure(runTool("equilibrium " + bargePath() + " --displacement 2"), "no floating equilibrium");
  CHECK_FALSE(std::filesystem::exists(csv));
}
