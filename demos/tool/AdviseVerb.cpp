// SPDX-License-Identifier: Zlib
// `hydrotex advise MESH --error E [--max-resolution N] [--depths N] [--orientations N] [--json]`:
// the cheapest method and resolution whose submerged-volume and centre-of-buoyancy errors stay
// under E at every sampled depth and orientation, measured on MESH against the exact path.

#include <cstdio>
#include <sstream>

#include "ToolSupport.hpp"
#include "Verbs.hpp"
#include "hydrotex/hydrostatics/Advisor.hpp"
#include "hydrotex/mesh/MeshIO.hpp"

namespace hydrotex::tool {

namespace {
struct AdviseOptions {
  std::string meshPath;
  double error = 0.0;
  int maxResolution = 2048;
  int depths = 5;
  int orientations = 4;
  bool json = false;
};

nlohmann::json toJson(const MethodMeasurement& measurement) {
  nlohmann::json out;
  // As the other verbs take them (`--method exact|texture --resolution N`), so that the advice can
  // be passed on as it is; the resolution is null for the exact path.
  const bool exact = measurement.method == HydrostaticsMethod::Exact;
  out["method"] = exact ? "exact" : "texture";
  out["resolution"] = exact ? nlohmann::json(nullptr) : nlohmann::json(measurement.resolution);
  out["traversal"] = measurement.method == HydrostaticsMethod::TextureBruteForce ? "brute-force"
                     : measurement.method == HydrostaticsMethod::TextureHierarchy ? "hierarchy"
                                                                                    : "mesh";
  out["time_us"] = measurement.microsecondsPerQuery;
  out["rel_error"] = measurement.maxErrors.worst();
  out["volume_error"] = measurement.maxErrors.volume;
  out["center_of_buoyancy_error"] = measurement.maxErrors.centerOfBuoyancy;
  out["bytes"] = measurement.bytes;
  return out;
}

/// "--method texture --resolution 128" or "--method exact", as `hydrotex hydrostatics` takes it.
std::string commandLine(const MethodMeasurement& m) {
  return m.method == HydrostaticsMethod::Exact ? "--method exact"
                                               : "--method texture --resolution " + std::to_string(m.resolution);
}

std::string describe(const MethodMeasurement& m) {
  char line[160];
  const std::string method = m.method == HydrostaticsMethod::Exact ? "exact" : "texture " + std::to_string(m.resolution) + "^2";
  std::snprintf(line, sizeof line, "  %-16s %12.2f us/query   volume %.2e   centre of buoyancy %.2e   %10zu bytes\n",
                method.c_str(), m.microsecondsPerQuery, m.maxErrors.volume, m.maxErrors.centerOfBuoyancy, m.bytes);
  return line;
}

int runAdvise(const AdviseOptions& options) {
  Expected<Mesh> mesh = loadMesh(options.meshPath);
  if (!mesh) return reportError(mesh.error());
  AdvisorSettings settings;
  settings.resolutions.clear();
  for (int resolution = 32; resolution <= options.maxResolution; resolution *= 2) settings.resolutions.push_back(resolution);
  settings.sampling.depthCount = options.depths;
  settings.sampling.orientationCount = options.orientations;
  Expected<Advice> advice = adviseHydrostatics(*mesh, options.error, settings);
  if (!advice) {
    const std::string& message = advice.error().message;
    // The advisor names the mesh by its source name; make sure the file is named once.
    return reportError(Error{message.rfind(options.meshPath, 0) == 0 ? message : options.meshPath + ": " + message});
  }

  nlohmann::json out = toJson(advice->best);
  out["target_error"] = options.error;
  out["samples"] = options.depths * options.orientations;
  out["candidates"] = nlohmann::json::array();
  for (const MethodMeasurement& candidate : advice->candidates) out["candidates"].push_back(toJson(candidate));

  std::ostringstream text;
  text.precision(3);
  text << options.meshPath << ": for volume and centre-of-buoyancy errors under " << options.error << " ("
       << options.depths << " depths x " << options.orientations << " orientations, against the exact path)\n"
       << "  use " << commandLine(advice->best) << ": " << advice->best.microsecondsPerQuery
       << " us per query, worst error " << advice->best.maxErrors.worst() << "\n"
       << "measured:\n";
  for (const MethodMeasurement& candidate : advice->candidates) text << describe(candidate);
  printResult(options.json, out, text.str());
  return 0;
}
}  // namespace

void addAdviseVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<AdviseOptions>();
  CLI::App* verb = addVerb(app, action, "advise",
                           "cheapest method and resolution keeping volume and centre-of-buoyancy errors under E",
                           options, &runAdvise);
  verb->add_option("MESH", options->meshPath, "closed mesh file")->required();
  verb->add_option("--error", options->error,
                   "E: largest relative error allowed (volume relative to the total volume, centre of buoyancy "
                   "relative to the bounding-box diagonal)")
      ->required()
      ->check(CLI::Range(1e-12, 1.0));
  verb->add_option("--max-resolution", options->maxResolution, "largest texture resolution tried (32..4096, default 2048)")
      ->check(CLI::Range(32, 4096));
  verb->add_option("--depths", options->depths, "water levels sampled per orientation (1..20, default 5)")
      ->check(CLI::Range(1, 20));
  verb->add_option("--orientations", options->orientations, "orientations sampled (1..8, default 4)")
      ->check(CLI::Range(1, 8));
}

}  // namespace hydrotex::tool
