// SPDX-License-Identifier: Zlib
// `hydrotex advise` as a user meets it: the advice's JSON keys, that the advised settings, passed
// on to `hydrotex hydrostatics`, keep the error under the target, and clean failures.

#include <sys/wait.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "TestPaths.hpp"

namespace {

struct ToolRun {
  int exitCode = -1;
  std::string out;
  std::string err;
};

std::string readFile(const std::string& path) {
  std::ifstream file(path);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

/// Runs the tool with `arguments` (as test_cli.cpp does).
ToolRun runTool(const std::string& arguments) {
  static int counter = 0;
  const std::string base = hydrotex::test::outputPath("advise_run_" + std::to_string(++counter));
  const std::string command = std::string(HYDROTEX_TOOL_PATH) + " " + arguments + " >" + base + ".out 2>" + base + ".err";
  const int status = std::system(command.c_str());
  ToolRun run;
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.out = readFile(base + ".out");
  run.err = readFile(base + ".err");
  return run;
}

/// Exactly one line on stderr mentioning `needle`, a failing exit code that is not a crash.
void requireCleanFailure(const ToolRun& run, const std::string& needle) {
  INFO("stderr: " << run.err);
  CHECK(run.exitCode != 0);
  CHECK(run.exitCode < 128);
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK(run.err.find(needle) != std::string::npos);
  CHECK(run.out.empty());
}

const std::string kSphere = hydrotex::test::sourcePath("data/meshes/sphere.obj");
const std::string kBox = hydrotex::test::sourcePath("data/meshes/box.obj");

}  // namespace

TEST_CASE("advise answers with the documented keys, and the advice holds when used", "[tool][advise]") {
  const double target = 1e-3;
  const ToolRun run = runTool("advise " + kSphere + " --error 1e-3 --max-resolution 256 --json");
  INFO("stderr: " << run.err);
  REQUIRE(run.exitCode == 0);
  const auto advice = nlohmann::json::parse(run.out);
  for (const char* key : {"method", "resolution", "time_us", "rel_error"}) CHECK(advice.contains(key));
  CHECK(advice["rel_error"].get<double>() <= target);
  CHECK(advice["time_us"].get<double>() > 0.0);
  REQUIRE(advice["candidates"].size() >= 2);  // the exact path and at least one texture resolution
  CHECK(advice["candidates"][0]["method"] == "exact");
  CHECK(advice["candidates"][0]["rel_error"].get<double>() == 0.0);

  // The advice goes straight into `hydrotex hydrostatics`. At a pose the advisor did not sample
  // (tilted, water 0.3 m above the centre of the unit sphere), the volume error relative to the
  // total volume stays under the target with a margin of 2 for an unsampled pose.
  std::string method = "--method " + advice["method"].get<std::string>();
  if (advice["method"] == "texture") method += " --resolution " + std::to_string(advice["resolution"].get<int>());
  const std::string pose = " --rotate-deg 13,-7,29 --translate 0.05,-0.3,0.02 --json";
  const ToolRun used = runTool("hydrostatics " + kSphere + " " + method + pose);
  const ToolRun exact = runTool("hydrostatics " + kSphere + " --method exact" + pose);
  const ToolRun total = runTool("inspect " + kSphere + " --json");
  REQUIRE(used.exitCode == 0);
  REQUIRE(exact.exitCode == 0);
  REQUIRE(total.exitCode == 0);
  const double volume = nlohmann::json::parse(total.out)["volume"].get<double>();
  const double error = std::abs(nlohmann::json::parse(used.out)["submerged_volume"].get<double>() -
                                nlohmann::json::parse(exact.out)["submerged_volume"].get<double>()) /
                       volume;
  INFO("error at the unsampled pose " << error);
  CHECK(error <= 2.0 * target);
}

TEST_CASE("advise picks the exact path when no texture resolution is good enough", "[tool][advise]") {
  const ToolRun run = runTool("advise " + kBox + " --error 1e-12 --max-resolution 64 --json");
  INFO("stderr: " << run.err);
  REQUIRE(run.exitCode == 0);
  const auto advice = nlohmann::json::parse(run.out);
  CHECK(advice["method"] == "exact");
  CHECK(advice["resolution"].is_null());
  CHECK(advice["rel_error"].get<double>() == 0.0);
}

TEST_CASE("advise's texture error estimates are the errors `hydrostatics` gives at the sampled poses", "[tool][advise]") {
  // Whichever method wins (here the exact path: no texture resolution reaches 1e-12), each texture
  // candidate's estimate is the worst error over the sample: with one orientation (the mesh as
  // modelled) and 3 depths, the water at 1/4, 1/2 and 3/4 of the sphere's height. Recomputed here
  // through `hydrostatics` (texture at that resolution against exact): volume error over the total
  // volume, centre-of-buoyancy error over the bounding box's diagonal. Same bake and sums, printed
  // at full precision: 1e-9.
  const ToolRun run = runTool("advise " + kSphere + " --error 1e-12 --max-resolution 64 --orientations 1 --depths 3 --json");
  INFO("stderr: " << run.err);
  REQUIRE(run.exitCode == 0);
  const auto advice = nlohmann::json::parse(run.out);
  CHECK(advice["method"] == "exact");
  const ToolRun inspected = runTool("inspect " + kSphere + " --json");
  REQUIRE(inspected.exitCode == 0);
  const auto mesh = nlohmann::json::parse(inspected.out);
  const double volume = mesh["volume"].get<double>();
  const double low = mesh["bounds_min"][1].get<double>(), high = mesh["bounds_max"][1].get<double>();
  double size2 = 0.0;
  for (int c = 0; c < 3; ++c) size2 += std::pow(mesh["bounds_max"][c].get<double>() - mesh["bounds_min"][c].get<double>(), 2);
  const double size = std::sqrt(size2);
  int checked = 0;
  for (const auto& candidate : advice["candidates"]) {
    if (candidate["method"] != "texture") continue;
    const int resolution = candidate["resolution"].get<int>();
    CAPTURE(resolution);
    double volumeError = 0.0, centerError = 0.0;
    for (int d = 1; d <= 3; ++d) {
      const double level = low + d / 4.0 * (high - low);
      char translate[64];
      std::snprintf(translate, sizeof translate, " --translate 0,%.17g,0 --json", -level);
      const ToolRun texture = runTool("hydrostatics " + kSphere + " --method texture --resolution " + std::to_string(resolution) + translate);
      const ToolRun exact = runTool("hydrostatics " + kSphere + " --method exact" + translate);
      REQUIRE(texture.exitCode == 0);
      REQUIRE(exact.exitCode == 0);
      const auto t = nlohmann::json::parse(texture.out), e = nlohmann::json::parse(exact.out);
      volumeError = std::max(volumeError, std::abs(t["submerged_volume"].get<double>() - e["submerged_volume"].get<double>()) / volume);
      double distance2 = 0.0;
      for (int c = 0; c < 3; ++c)
        distance2 += std::pow(t["center_of_buoyancy"][c].get<double>() - e["center_of_buoyancy"][c].get<double>(), 2);
      centerError = std::max(centerError, std::sqrt(distance2) / size);
    }
    CHECK(volumeError > 0.0);
    CHECK(candidate["volume_error"].get<double>() == Approx(volumeError).margin(1e-9));
    CHECK(candidate["center_of_buoyancy_error"].get<double>() == Approx(centerError).margin(1e-9));
    CHECK(candidate["rel_error"].get<double>() == Approx(std::max(volumeError, centerError)).margin(1e-9));
    ++checked;
  }
  CHECK(checked == 2);  // 32^2 and 64^2
}

TEST_CASE("advise prints a readable summary without --json", "[tool][advise]") {
  const ToolRun run = runTool("advise " + kBox + " --error 0.01 --max-resolution 64");
  REQUIRE(run.exitCode == 0);
  CHECK(run.out.find("use --method") != std::string::npos);
  CHECK(run.out.find("exact") != std::string::npos);
}

TEST_CASE("advise fails cleanly on bad input", "[tool][advise][bad-input]") {
  requireCleanFailure(runTool("advise " + hydrotex::test::outputPath("missing.obj") + " --error 0.01"), "missing.obj");
  const std::string open = hydrotex::test::outputPath("advise_open.obj");
  std::ofstream(open) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  requireCleanFailure(runTool("advise " + open + " --error 0.01"), "advise_open.obj");
  requireCleanFailure(runTool("advise " + kBox), "--error");
  requireCleanFailure(runTool("advise " + kBox + " --error -1"), "--error");
  requireCleanFailure(runTool("advise " + kBox + " --error 0.01 --max-resolution 8"), "--max-resolution");
}
