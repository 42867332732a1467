// SPDX-License-Identifier: Zlib
#include "ToolSupport.hpp"

#include <cmath>
#include <iostream>
#include <sstream>
#include <vector>

#ifdef HYDROTEX_WITH_GPU
#include "hydrotex/gpu/MakeBackend.hpp"
#endif

namespace hydrotex::tool {

CLI::Option* addVector3Option(CLI::App& app, const std::string& name, Eigen::Vector3d& target,
                              const std::string& description) {
  return app.add_option_function<std::vector<double>>(
               name,
               [&target, name](const std::vector<double>& values) {
                 if (values.size() != 3) throw CLI::ValidationError(name, "expects three numbers X,Y,Z");
                 for (double value : values)
                   if (!std::isfinite(value)) throw CLI::ValidationError(name, "must be finite numbers");
                 target = Eigen::Vector3d(values[0], values[1], values[2]);
               },
               description)
      ->delimiter(',')
      ->expected(3);
}

CLI::Option* addResolutionOption(CLI::App& app, int& resolution) {
  return app.add_option("--resolution", resolution, "texels per side of the bake (16..4096)")
      ->check(CLI::Range(16, 4096));
}

std::string MethodOptions::describe(const std::string& meshPath) const {
  std::string text = meshPath + " (" + method;
  if (texture()) text += ", " + std::to_string(resolution) + "^2 texels, " + backend + " backend";
  return text + ")";
}

void MethodOptions::addTo(nlohmann::json& out, const ComputeBackend* computeBackend) const {
  out["method"] = method;
  out["resolution"] = texture() ? nlohmann::json(resolution) : nlohmann::json(nullptr);
  out["backend"] = computeBackend ? nlohmann::json(computeBackend->name()) : nlohmann::json(nullptr);
  out["renderer"] = computeBackend ? nlohmann::json(computeBackend->renderer()) : nlohmann::json(nullptr);
}

namespace {
Expected<std::unique_ptr<ComputeBackend>> makeToolBackend(const std::string& name) {
#ifdef HYDROTEX_WITH_GPU
  Expected<std::unique_ptr<ComputeBackend>> backend = gpu::makeBackend(name);
  if (!backend) return Error{"--backend " + name + ": " + backend.error().message};
  return backend;
#else
  if (name == "cpu") return makeCpuBackend();
  return Error{"--backend " + name + ": this hydrotex was built without the GPU backend (hydrotex::gpu)"};
#endif
}
}  // namespace

Expected<std::shared_ptr<ComputeBackend>> controllerBackend(const std::string& name) {
#ifdef HYDROTEX_WITH_GPU
  return gpu::makeControllerBackend(name);
#else
  if (name == "cpu" || name == "auto") return std::shared_ptr<ComputeBackend>();  // the controller's own
  return Error{"\"" + name + "\": this hydrotex was built without the GPU backend (hydrotex::gpu)"};
#endif
}

Expected<BackendBody> registerWithBackend(const std::string& backendName, const SurfaceBake& bake,
                                          const SurfaceTextures& textures, const Eigen::Vector3d& massReferencePoint) {
  Expected<std::unique_ptr<ComputeBackend>> backend = makeToolBackend(backendName);
  if (!backend) return backend.error();
  BackendBody body;
  body.backend = std::move(backend).value();
  Expected<BackendBodyId> id = body.backend->addBody(bake, textures, massReferencePoint);
  if (!id) return id.error();
  body.id = *id;
  return body;
}

void addMeshLoadOptions(CLI::App& verb, MeshLoadSettings& settings) {
  verb.add_option_function<std::string>(
          "--up",
          [&settings](const std::string& name) {
            Expected<UpAxis> up = upAxisFromName(name);
            if (!up) throw CLI::ValidationError("--up", up.error().message);
            settings.up = *up;
          },
          "the file's up axis: y (default) or z (rotated so that +z becomes +y)");
  verb.add_option("--scale", settings.scale, "metres per file unit (default 1), for files without units")
      ->check(CLI::PositiveNumber);
  verb.add_flag_callback(
      "--no-repair", [&settings] { settings.repair.enabled = false; },
      "refuse a defective mesh instead of repairing it (welds, flipped faces or parts, small holes)");
  verb.add_option("--max-hole-fraction", settings.repair.maxHoleFraction,
                  "repair closes boundary loops up to this fraction of the bounding-box diagonal (default 0.1)")
      ->check(CLI::NonNegativeNumber);
  verb.add_flag_callback(
      "--open-hull", [&settings] { settings.repair.openHull = true; },
      "an open hull by design (a dinghy, an open transom): a boundary loop too large to be a hole is capped "
      "by a lid that closes the volume, has no mass and lets liquid in");
}

void addMethodOptions(CLI::App& verb, MethodOptions& options) {
  verb.add_option("--method", options.method, "exact (polyhedral) or texture (default)")
      ->check(CLI::IsMember({"exact", "texture"}));
  addResolutionOption(verb, options.resolution);
  verb.add_option("--backend", options.backend, "cpu (default) or gpu: where the texture path's passes run")
      ->check(CLI::IsMember({"cpu", "gpu"}));
}

int reportError(const Error& error) {
  std::cerr << "hydrotex: " << error.message << "\n";
  return 1;
}

nlohmann::json toJson(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

nlohmann::json toJson(const Eigen::Matrix3d& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) rows.push_back(toJson(Eigen::Vector3d(m.row(r).transpose())));
  return rows;
}

void printResult(bool json, const nlohmann::json& object, const std::string& text) {
  if (json)
    std::cout << object.dump() << "\n";
  else
    std::cout << text;
}

std::string formatVector(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out.precision(6);
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

std::string formatMatrix(const Eigen::Matrix3d& m) {
  std::ostringstream out;
  out.precision(8);
  for (int r = 0; r < 3; ++r) out << "    " << m(r, 0) << "  " << m(r, 1) << "  " << m(r, 2) << "\n";
  return out.str();
}

}  // namespace hydrotex::tool
