// SPDX-License-Identifier: Zlib
#pragma once
// Small pieces shared by the verbs: option helpers, JSON and text output, error reporting.

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <memory>
#include <string>

#include "Verbs.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/MeshIO.hpp"

namespace hydrotex::tool {

/// Adds an option that takes three comma-separated numbers ("1,2,3") into `target`.
CLI::Option* addVector3Option(CLI::App& app, const std::string& name, Eigen::Vector3d& target,
                              const std::string& description);

/// Adds `--resolution N` (texels per side, 16..4096).
CLI::Option* addResolutionOption(CLI::App& app, int& resolution);

/// How a verb computes: the exact polyhedral path or the texture path at a resolution.
struct MethodOptions {
  std::string method = "texture";  ///< "exact" or "texture"
  int resolution = 256;            ///< texels per side (texture path)
  std::string backend = "cpu";     ///< "cpu" or "gpu" (texture path)
  /// True for the texture path.
  bool texture() const { return method == "texture"; }
  /// "MESH (texture, 256^2 texels)" or "MESH (exact)", the first line of a readable summary.
  std::string describe(const std::string& meshPath) const;
  /// The `method`, `resolution`, `backend` and `renderer` JSON keys (null where they do not
  /// apply: the exact path has no resolution and runs on no backend).
  void addTo(nlohmann::json& out, const ComputeBackend* backend) const;
};

/// Adds `--up y|z`, `--scale S`, `--no-repair`, `--max-hole-fraction F` and `--open-hull`: how the verb's mesh
/// file becomes a body (MeshLoadSettings).
void addMeshLoadOptions(CLI::App& verb, MeshLoadSettings& settings);

/// Adds `--method exact|texture`, `--resolution N` and `--backend cpu|gpu`.
void addMethodOptions(CLI::App& verb, MethodOptions& options);

/// A body registered with a compute backend, for the texture path of a verb.
struct BackendBody {
  std::unique_ptr<ComputeBackend> backend;  ///< "cpu", or "gpu" when built with hydrotex::gpu
  BackendBodyId id = 0;                     ///< the body in that backend
};

/// A BuoyancyController's backend by name (scene key `backend`, `simulate --backend`), for
/// SceneWorld::create: hydrotex::gpu::makeControllerBackend when this tool has the GPU backend;
/// without it "cpu" and "auto" give the controller's own CPU backend (null) and "gpu" an error.
Expected<std::shared_ptr<ComputeBackend>> controllerBackend(const std::string& name);

/// Opens the backend named `backendName` and registers the baked body with the cone apex
/// `massReferencePoint` (m, body frame). Errors name the backend or the mesh.
Expected<BackendBody> registerWithBackend(const std::string& backendName, const SurfaceBake& bake,
                                          const SurfaceTextures& textures, const Eigen::Vector3d& massReferencePoint);

/// Registers a verb whose options live in `options` (which has a `bool json`): adds `--json` and
/// makes `run(*options)` the action when the verb is chosen.
template <class Options>
CLI::App* addVerb(CLI::App& app, VerbAction& action, const std::string& name, const std::string& description,
                  const std::shared_ptr<Options>& options, int (*run)(const Options&)) {
  CLI::App* verb = app.add_subcommand(name, description);
  verb->add_flag("--json", options->json, "print one JSON object");
  verb->callback([options, run, &action] { action = [options, run] { return run(*options); }; });
  return verb;
}

/// Prints the error on one line to stderr, prefixed "hydrotex: ", and returns exit code 1.
int reportError(const Error& error);

/// A 3-vector as a JSON array.
nlohmann::json toJson(const Eigen::Vector3d& v);
/// A 3x3 matrix as a JSON array of three rows.
nlohmann::json toJson(const Eigen::Matrix3d& m);

/// Prints `object` as one JSON object on stdout (with --json), or the readable text otherwise.
void printResult(bool json, const nlohmann::json& object, const std::string& text);

/// Formats a vector as "(x, y, z)" with 6 significant digits for readable output.
std::string formatVector(const Eigen::Vector3d& v);

/// Formats a 3x3 matrix as three indented rows, one per line.
std::string formatMatrix(const Eigen::Matrix3d& m);

}  // namespace hydrotex::tool
