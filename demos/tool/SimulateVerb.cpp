// SPDX-License-Identifier: Zlib
// `hydrotex simulate SCENE.json [--csv OUT.csv] [--every N] [--threads N] [--backend cpu|gpu|auto]
// [--method texture|polyhedral|auto] [--json]`:
// runs a scene headless in Bullet with the BuoyancyController and writes one CSV row per body
// every N steps.

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <unistd.h>

#include "ToolSupport.hpp"
#include "Verbs.hpp"
#include "hydrotex/bullet/Scene.hpp"
#include "hydrotex/bullet/SoftBodyMotion.hpp"

namespace hydrotex::tool {
namespace {

struct SimulateOptions {
  std::string scenePath;
  std::string csvPath;
  long long every = 1;
  std::string threads;  ///< overrides the scene's `threads` when given (parsed here, to name a bad value)
  std::string backend;  ///< overrides the scene's `backend` when given
  std::string method;   ///< overrides every rigid body's `method` when given
  bool json = false;
};

/// The --threads value: a whole number >= 0, or one line naming it.
Expected<int> parseThreads(const std::string& text) {
  int value = -1;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < 0) {
    return Error{"--threads " + text + ": expected a whole number >= 0 (0: all cores)"};
  }
  return value;
}

/// One CSV row per body: the columns of the issue, in that order. Soft bodies follow the rigid
/// ones (Scene::softBodies order) with the same columns: position and velocities of their nodes
/// as a whole (SoftBodyMotion), orientation of Bullet's pose-matching frame (identity when the
/// body tracks none), mass and submerged volume; the flooding and wetting columns, which no soft
/// body has, read 0 as they do for rigid bodies that do not list those effects.
void writeRows(std::ostream& out, bullet::SceneWorld& sceneWorld) {
  const auto& bodies = sceneWorld.bodies();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const btRigidBody* body = bodies[i];
    const btVector3 p = body->getCenterOfMassPosition();
    const btQuaternion q = sceneWorld.controller().meshTransform(body)->getRotation();
    const btVector3 v = body->getLinearVelocity();
    const btVector3 w = body->getAngularVelocity();
    const bullet::FloatingBodyReport* report = sceneWorld.controller().report(body);
    out << sceneWorld.time() << ',' << sceneWorld.scene().bodies[i].name << ',' << p.x() << ',' << p.y() << ','
        << p.z() << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z() << ',' << v.x() << ',' << v.y()
        << ',' << v.z() << ',' << w.x() << ',' << w.y() << ',' << w.z() << ','
        << (report ? report->massProperties.mass : 0.0) << ','
        << (report ? report->hydrostatics.submergedVolume : 0.0) << ',' << (report ? report->liquidVolume : 0.0) << ','
        << (report ? report->liquidHeld : 0.0) << ',' << (report ? report->liquidAbsorbed : 0.0) << ','
        << (report ? report->liquidEvaporated : 0.0) << '\n';
  }
  const auto& softBodies = sceneWorld.softBodies();
  for (std::size_t i = 0; i < softBodies.size(); ++i) {
    const bullet::SoftBodyMotion motion = bullet::softBodyMotion(*softBodies[i]);
    const btVector3& p = motion.centerOfMass;
    const btQuaternion& q = motion.orientation;
    const btVector3& v = motion.linearVelocity;
    const btVector3& w = motion.angularVelocity;
    const bullet::SoftBodyReport* report = sceneWorld.controller().softBodyReport(softBodies[i]);
    out << sceneWorld.time() << ',' << sceneWorld.scene().softBodies[i].name << ',' << p.x() << ',' << p.y() << ','
        << p.z() << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z() << ',' << v.x() << ',' << v.y()
        << ',' << v.z() << ',' << w.x() << ',' << w.y() << ',' << w.z() << ',' << motion.mass << ','
        << (report ? report->submergedVolume : 0.0) << ",0,0,0,0\n";
  }
}

/// True when every coordinate of `p` is finite.
bool finite(const btVector3& p) {
  return std::isfinite(double(p.x())) && std::isfinite(double(p.y())) && std::isfinite(double(p.z()));
}

int runSimulate(const SimulateOptions& options) {
  if (options.every < 1) return reportError(Error{"--every: must be at least 1"});
  if (!options.backend.empty()) {
    if (Status s = bullet::checkControllerBackend(options.backend); !s) {
      return reportError(Error{"--backend " + s.error().message});
    }
  }
  std::optional<int> threads;
  if (!options.threads.empty()) {
    Expected<int> parsed = parseThreads(options.threads);
    if (!parsed) return reportError(parsed.error());
    threads = *parsed;
  }
  Expected<bullet::Scene> scene = bullet::loadScene(options.scenePath);
  if (!scene) return reportError(scene.error());
  if (threads) scene->threads = *threads;
  if (!options.backend.empty()) scene->backend = options.backend;
  if (!options.method.empty()) {
    const bullet::HydrostaticsMethod method = options.method == "texture"      ? bullet::HydrostaticsMethod::Texture
                                              : options.method == "polyhedral" ? bullet::HydrostaticsMethod::Polyhedral
                                                                               : bullet::HydrostaticsMethod::Auto;
    for (bullet::SceneBody& body : scene->bodies)
      if (!body.soft) body.method = method;
  }
  Expected<std::unique_ptr<bullet::SceneWorld>> created = bullet::SceneWorld::create(*scene, controllerBackend);
  if (!created) return reportError(created.error());
  bullet::SceneWorld& sceneWorld = **created;

  // The CSV goes to a temporary beside the target and is renamed only when the run is complete,
  // so that a failed or interrupted run never leaves a file that looks finished.
  std::string temporaryPath;
  std::ofstream csv;
  if (!options.csvPath.empty()) {
    temporaryPath = options.csvPath + ".partial-" + std::to_string(::getpid());
    csv.open(temporaryPath, std::ios::binary | std::ios::trunc);
    if (!csv) return reportError(Error{options.csvPath + ": cannot be written"});
    csv << std::setprecision(9);
    csv << "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,mass,submerged_volume,liquid_volume,liquid_surface,absorbed,evaporated\n";
    writeRows(csv, sceneWorld);
  }
  const long long steps = scene->stepCount();
  const auto start = std::chrono::steady_clock::now();
  for (long long step = 1; step <= steps; ++step) {
    sceneWorld.step();
    if (csv.is_open() && step % options.every == 0) writeRows(csv, sceneWorld);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  bool diverged = false;
  for (const btRigidBody* body : sceneWorld.bodies()) diverged = diverged || !finite(body->getCenterOfMassPosition());
  for (const btSoftBody* body : sceneWorld.softBodies()) diverged = diverged || !finite(bullet::softBodyMotion(*body).centerOfMass);
  if (diverged) {
    if (csv.is_open()) {
      csv.close();
      std::filesystem::remove(temporaryPath);
    }
    return reportError(Error{options.scenePath + ": the simulation diverged (non-finite position)"});
  }
  if (csv.is_open()) {
    csv.close();
    std::error_code ec;
    if (!csv || (std::filesystem::rename(temporaryPath, options.csvPath, ec), ec)) {
      std::filesystem::remove(temporaryPath, ec);
      return reportError(Error{options.csvPath + ": cannot be written"});
    }
  }

  nlohmann::json result;
  result["scene"] = options.scenePath;
  result["steps"] = steps;
  result["time"] = sceneWorld.time();
  result["wall_seconds"] = seconds;
  result["ms_per_step"] = steps > 0 ? 1000.0 * seconds / double(steps) : 0.0;
  result["threads"] = sceneWorld.controller().threads();
  const ComputeBackend& backend = sceneWorld.controller().backend();
  result["backend"] = backend.name();
  result["renderer"] = backend.renderer();
  nlohmann::json bodies = nlohmann::json::array();
  std::ostringstream text;
  text << "simulated " << sceneWorld.time() << " s in " << steps << " steps (" << std::setprecision(3)
       << (steps > 0 ? 1000.0 * seconds / double(steps) : 0.0) << " ms/step, "
       << sceneWorld.controller().threads() << " thread" << (sceneWorld.controller().threads() == 1 ? "" : "s")
       << ", " << backend.name() << " backend: " << backend.renderer() << ")\n";
  for (std::size_t i = 0; i < sceneWorld.bodies().size(); ++i) {
    const btRigidBody* body = sceneWorld.bodies()[i];
    const Eigen::Vector3d p(body->getCenterOfMassPosition().x(), body->getCenterOfMassPosition().y(),
                            body->getCenterOfMassPosition().z());
    const Eigen::Vector3d v(body->getLinearVelocity().x(), body->getLinearVelocity().y(), body->getLinearVelocity().z());
    const bullet::FloatingBodyReport* report = sceneWorld.controller().report(body);
    nlohmann::json entry;
    entry["name"] = scene->bodies[i].name;
    entry["center_of_mass"] = toJson(p);
    entry["linear_velocity"] = toJson(v);
    entry["mass"] = report->massProperties.mass;
    entry["submerged_volume"] = report->hydrostatics.submergedVolume;
    entry["method"] = report->method == bullet::HydrostaticsMethod::Polyhedral ? "polyhedral" : "texture";
    bodies.push_back(entry);
    text << "  " << scene->bodies[i].name << ": centre of mass " << formatVector(p) << " m, velocity "
         << formatVector(v) << " m/s, submerged " << report->hydrostatics.submergedVolume << " m^3 ("
         << (report->method == bullet::HydrostaticsMethod::Polyhedral ? "polyhedral" : "texture") << ")\n";
  }
  for (std::size_t i = 0; i < sceneWorld.softBodies().size(); ++i) {
    const bullet::SoftBodyMotion motion = bullet::softBodyMotion(*sceneWorld.softBodies()[i]);
    const bullet::SoftBodyReport* report = sceneWorld.controller().softBodyReport(sceneWorld.softBodies()[i]);
    const double submerged = report ? report->submergedVolume : 0.0;
    const Eigen::Vector3d p(motion.centerOfMass.x(), motion.centerOfMass.y(), motion.centerOfMass.z());
    const Eigen::Vector3d v(motion.linearVelocity.x(), motion.linearVelocity.y(), motion.linearVelocity.z());
    nlohmann::json entry;
    entry["name"] = scene->softBodies[i].name;
    entry["soft"] = true;
    entry["center_of_mass"] = toJson(p);
    entry["linear_velocity"] = toJson(v);
    entry["mass"] = motion.mass;
    entry["submerged_volume"] = submerged;
    bodies.push_back(entry);
    text << "  " << scene->softBodies[i].name << " (soft): centre of mass " << formatVector(p) << " m, velocity "
         << formatVector(v) << " m/s, submerged " << submerged << " m^3\n";
  }
  result["bodies"] = bodies;
  if (!options.csvPath.empty()) result["csv"] = options.csvPath;
  printResult(options.json, result, text.str());
  return 0;
}

}  // namespace

void addSimulateVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* verb = app.add_subcommand("simulate", "Run a scene file (JSON) headless in Bullet with the buoyancy controller");
  verb->add_option("scene", options->scenePath, "Scene file (JSON; mesh paths relative to it)")->required();
  verb->add_option("--csv", options->csvPath, "Write one row per body every N steps to this CSV file");
  verb->add_option("--every", options->every, "Write a CSV row every N steps (default 1)");
  verb->add_option("--threads", options->threads,
                   "Threads for the bodies' loads (0: all cores; default: the scene's `threads`, else 0); "
                   "results are bit-identical for every count");
  verb->add_option("--backend", options->backend,
                   "Backend of the controller's texture hydrostatics: cpu, gpu (GL compute) or auto (GL when a GPU opens through EGL, else cpu); default: the scene's `backend`, else auto");
  verb->add_option("--method", options->method,
                   "Hydrostatics path of every rigid body: texture, polyhedral (exact) or auto (chosen per body at "
                   "registration by the advisor, error 1e-4 of the volume unless the scene's auto_method_error says); "
                   "default: each body's `method`, which is auto unless the scene names another")
      ->check(CLI::IsMember({"texture", "polyhedral", "auto"}));
  verb->add_flag("--json", options->json, "Print the summary as one JSON object");
  verb->callback([options, &action] { action = [options] { return runSimulate(*options); }; });
}

}  // namespace hydrotex::tool
