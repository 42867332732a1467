// SPDX-License-Identifier: Zlib
// bench_peers: what a simple body costs against a peer engine (issue 19: "a simple body costs no
// more than in Jolt"). 100 awake bodies of one kind in a Bullet world at 60 Hz, one thread
// (ControllerSettings::threads = 1), flat water and three Gerstner waves, buoyancy and buoyancy +
// drag, each hydrostatics path (exact, texture 256^2, auto); the figure is the controller's
// updateAction per body per step (us), the median of --runs passes (default 5), each pass a fresh
// world. The bodies and the liquids are data/scenes/peers_flat.json and peers_waves.json (shared
// with the tests): each template body there is registered 100 times on a grid, released off its
// equilibrium (heights and tilts varied per body) and kept awake (DISABLE_DEACTIVATION), so that
// every body is computed every step; the table prints the queries per step and the bodies' mean
// vertical speed to show it.
//
// Beside the controller's figure, for bodies on the exact path, the per-step core calls on the same
// states, timed alone: "exact us" polyhedralHydrostaticsUnchecked on the mesh, "prep us"
// polyhedralHydrostatics on a PreparedPolyhedron (what the controller calls; to rounding the
// same) and "closed" sphereHydrostatics (what the controller calls for a sphere: its closed form
// in flat water, its rule on the true sphere under waves), "update us" implicitVelocityUpdate with those loads and stiffness (every body's step
// solves it), "mdrag us" rigidBodyDrag on meshDragPatches with the law's whole derivative (what
// the controller makes for a rigid body, on either path, no bake) and "drag us" the same law on
// texel patches from a 256^2 bake with the secant damping (what a deforming body takes); the rest
// of "ours" is the controller's own (Bullet reads and writes). "d/b": a row with drag against the
// same body's row without (issue 19: drag at the price of buoyancy, at most 1.5x).
//
// Options: --runs N (5), --steps S (60 timed steps after 10 of warm-up), --csv FILE
// (bench_peers.csv), --bodies LIST (box,hull,sphere,mesh), --methods LIST (exact,texture,auto),
// --surfaces LIST (flat,waves), --mixed N (100; 0: skip): after the table, a world of N bodies of
// the templates in turn on `auto` with buoyancy + drag, the whole world step on 1 and 2 threads
// (issue 19's goal: under 2 ms on three waves with both cores), written to FILE_mixed.csv;
// --resolution N (256): the table's bodies' texture resolution (the mixed world keeps the
// scenes').

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "BenchmarkTiming.hpp"
#include "ControllerBench.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/bullet/Scene.hpp"
#include "hydrotex/bullet/ShapeMesh.hpp"
#include "hydrotex/hydrostatics/MeshDragPatches.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/hydrostatics/PrimitiveHydrostatics.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using Clock = std::chrono::steady_clock;

namespace {

// Jolt Physics 5.5.1, Body::ApplyBuoyancyImpulse, 100 awake bodies at 60 Hz, one thread, per body
// per step, measured on this kind of machine (docs/references.md "Peers"): buoyancy alone / with
// its drag (us). Jolt gives the sphere (closed form) only without drag; its figure stands for both.
// Jolt refuses meshes; the goal of a 256^2-class mesh under auto is issue 19's 10 us.
struct PeerFigure {
  const char* body;
  double buoyancyUs, dragUs;
  const char* source;
};
constexpr PeerFigure kPeers[] = {
    {"box", 0.15, 0.17, "Jolt"},
    {"hull", 3.5, 3.6, "Jolt"},
    {"sphere", 0.07, 0.07, "Jolt"},
    {"mesh", 10.0, 10.0, "goal"},
};

using bench::TimedAction;

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream stream(list);
  for (std::string item; std::getline(stream, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string option(int argc, char** argv, const std::string& flag, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (argv[i] == flag) return argv[i + 1];
  return fallback;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

using bench::eigen;

/// The mesh a template body floats as: its Bullet primitive meshed as the controller meshes a
/// collision shape (meshFromCollisionShape, default tessellation), or its mesh file. Made once and
/// shared by the 100 copies, as a game shares one mesh among crates of a kind.
Expected<std::shared_ptr<const Mesh>> templateMesh(const SceneBody& body) {
  if (body.shape) {
    std::unique_ptr<btCollisionShape> shape;
    if (body.shape->type == SceneShape::Type::Box)
      shape = std::make_unique<btBoxShape>(btVector3(btScalar(body.shape->halfExtents.x()), btScalar(body.shape->halfExtents.y()),
                                                     btScalar(body.shape->halfExtents.z())));
    else if (body.shape->type == SceneShape::Type::Sphere)
      shape = std::make_unique<btSphereShape>(btScalar(body.shape->radius));
    else
      return Error{body.name + ": bench_peers takes box and sphere shapes only"};
    Expected<Mesh> mesh = meshFromCollisionShape(*shape);
    if (!mesh) return mesh.error();
    return std::make_shared<const Mesh>(std::move(mesh).value());
  }
  Expected<Mesh> mesh = loadMesh(body.meshPath, body.load);
  if (!mesh) return mesh.error();
  return std::make_shared<const Mesh>(std::move(mesh).value());
}

struct Case {
  std::string body, method, surface;
  bool drag = false;
  int resolution = 256;  ///< the template bodies' texture resolution (texels per side)
};

struct Pass {
  double controllerUs = 0.0;     ///< per body per step
  double queriesPerStep = 0.0;   ///< hydrostatics queries per step (100: every body computed)
  double meanVerticalSpeed = 0.0;///< m/s, mean |v_y| over the bodies after the timed steps
  double hydrostaticsUs = 0.0;   ///< exact path alone, same states (0: not measured)
  double preparedUs = 0.0;       ///< exact path on a PreparedPolyhedron, same states (0: not measured)
  double closedFormUs = 0.0;     ///< a sphere's closed form or rule (sphereHydrostatics), same states (0: not a sphere)
  double updateUs = 0.0;         ///< implicitVelocityUpdate with the exact hydrostatics' loads, same states
  double dragUs = 0.0;           ///< drag alone, same states (0: not measured)
  double meshDragUs = 0.0;       ///< drag alone on meshDragPatches (same settings), same states
  std::size_t texelPatches = 0, meshPatches = 0;  ///< drag patches: the controller's (from the bake), meshDragPatches'
  std::string resolved;          ///< the path the bodies run (auto resolved)
  std::size_t triangles = 0;
};

constexpr int kBodies = 100;

/// A scene's world with every body kept awake (DISABLE_DEACTIVATION, so that each is computed
/// every step), stepped 10 times to warm up and then `steps` times timed: the whole step and the
/// controller's updateAction apart (s), and the controller's hydrostatics queries in those steps.
struct TimedRun {
  std::unique_ptr<SceneWorld> world;
  double worldSeconds = 0.0, controllerSeconds = 0.0;
  std::uint64_t queries = 0;
};

TimedRun runTimed(const Scene& scene, int steps) {
  auto created = SceneWorld::create(scene);
  if (!created) {
    std::fprintf(stderr, "bench_peers: %s\n", created.error().message.c_str());
    std::exit(1);
  }
  TimedRun run{std::move(created).value()};
  SceneWorld& world = *run.world;
  for (btRigidBody* body : world.bodies()) body->setActivationState(DISABLE_DEACTIVATION);
  BuoyancyController& controller = world.controller();
  TimedAction timed(controller);
  world.world().removeAction(&controller);
  world.world().addAction(&timed);
  for (int i = 0; i < 10; ++i) world.step();
  timed.seconds = 0.0;
  const std::uint64_t queriesBefore = controller.statistics().hydrostaticsQueries;
  const auto start = Clock::now();
  for (int i = 0; i < steps; ++i) world.step();
  run.worldSeconds = std::chrono::duration<double>(Clock::now() - start).count();
  world.world().removeAction(&timed);
  world.world().addAction(&controller);
  run.controllerSeconds = timed.seconds;
  run.queries = controller.statistics().hydrostaticsQueries - queriesBefore;
  return run;
}

Pass runPass(const Scene& base, const SceneBody& prototype, const std::shared_ptr<const Mesh>& mesh, const Case& c,
             int steps) {
  Scene scene = base;
  scene.sourceName = "bench_peers";
  scene.threads = 1;
  scene.backend = "cpu";
  scene.bodies.clear();
  Eigen::Vector3d lower = mesh->positions.front(), upper = lower;
  for (const Eigen::Vector3d& p : mesh->positions) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  const double spacing = (upper - lower).maxCoeff() + 1.0;
  for (int i = 0; i < kBodies; ++i) {
    SceneBody body = prototype;
    body.name = prototype.name + std::to_string(i);
    // A sphere stays a btSphereShape and a box a btBoxShape, as the mixed world's (the controller
    // then takes their own paths: a sphere's closed forms and rule, a box's rule under waves,
    // unless on the texture path); meshes share one mesh, as crates of a kind (the shapes share
    // theirs too).
    const bool primitive = prototype.shape && (prototype.shape->type == SceneShape::Type::Sphere ||
                                                prototype.shape->type == SceneShape::Type::Box);
    if (!primitive) {
      body.mesh = mesh;
      body.shape.reset();
    }
    body.method = c.method == "exact"     ? HydrostaticsMethod::Polyhedral
                  : c.method == "texture" ? HydrostaticsMethod::Texture
                                          : HydrostaticsMethod::Auto;
    body.resolution = c.resolution;
    body.effects = c.drag ? EffectSet{Effect::Buoyancy, Effect::Drag} : EffectSet{Effect::Buoyancy};
    // Off equilibrium, each body its own way: heights 0..0.08 m apart, tilts and headings varied.
    body.position += Eigen::Vector3d(spacing * (i % 10), 0.02 * (i % 5) - 0.04, spacing * (i / 10));
    body.rotationDegrees += Eigen::Vector3d(2.0 * (i % 3), 37.0 * i, 1.5 * (i % 4));
    scene.bodies.push_back(body);
  }
  const TimedRun run = runTimed(scene, steps);
  SceneWorld& world = *run.world;
  BuoyancyController& controller = world.controller();
  Pass pass;
  pass.controllerUs = 1e6 * run.controllerSeconds / (double(steps) * kBodies);
  pass.queriesPerStep = double(run.queries) / steps;
  pass.triangles = mesh->triangles.size();
  const FloatingBodyReport* first = controller.report(world.bodies().front());
  pass.resolved = first && first->method == HydrostaticsMethod::Polyhedral ? "exact" : "texture";

  // The same states, the core calls alone (exact path): poses and velocities now.
  std::vector<HydrostaticsQuery> queries;
  std::vector<RigidBodyMotion> motions;
  for (const btRigidBody* body : world.bodies()) pass.meanVerticalSpeed += std::abs(body->getLinearVelocity().y()) / kBodies;
  for (const bench::BodyState& state : bench::bodyStates(controller, world.bodies())) {
    queries.push_back(state.query);
    motions.push_back(state.motion);
  }
  if (pass.resolved != "exact" || queries.empty()) return pass;
  const LiquidSurface& surface = *controller.liquid().surface;
  double sink = 0.0;
  // Each call timed in batches over all the bodies, batches of about 2 ms, median of 5.
  const int repeats = std::max(1, int(200000 / (mesh->triangles.size() * queries.size())));
  pass.hydrostaticsUs = 1e3 * bench::medianMs(5, [&] {
                          for (int k = 0; k < repeats; ++k)
                            for (const HydrostaticsQuery& query : queries)
                              if (Expected<HydrostaticsResult> answer = polyhedralHydrostaticsUnchecked(*mesh, surface, query))
                                sink += answer->buoyancyForce.y();
                        }) / (repeats * double(queries.size()));
  // What the controller would call instead: the exact path on the mesh prepared once, and for a
  // sphere its closed form (flat water) or its rule (waves).
  const Expected<PreparedPolyhedron> polyhedron = PreparedPolyhedron::prepare(mesh);
  if (polyhedron)
    pass.preparedUs = 1e3 * bench::medianMs(5, [&] {
                        for (int k = 0; k < repeats; ++k)
                          for (const HydrostaticsQuery& query : queries)
                            if (Expected<HydrostaticsResult> answer = polyhedralHydrostatics(*polyhedron, surface, query))
                              sink += answer->buoyancyForce.y();
                      }) / (repeats * double(queries.size()));
  // The implicit velocity update on the same states with their exact loads and stiffness (every
  // body's step solves it once, drag or not).
  if (polyhedron) {
    std::vector<ImplicitUpdateInput> updates;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      Expected<HydrostaticsResult> answer = polyhedralHydrostatics(*polyhedron, surface, queries[i]);
      if (!answer) continue;
      ImplicitUpdateInput update;
      update.gravity = Eigen::Vector3d(0.0, -queries[i].gravity, 0.0);
      update.force = answer->buoyancyForce;
      update.torque = answer->torqueAboutCenterOfMass;
      update.stiffness = answer->stiffness;
      updates.push_back(update);
    }
    const int updateRepeats = 200;
    pass.updateUs = 1e3 * bench::medianMs(5, [&] {
                      for (int k = 0; k < updateRepeats; ++k)
                        for (std::size_t i = 0; i < updates.size(); ++i)
                          if (Expected<RigidBodyVelocities> next = implicitVelocityUpdate(motions[i], updates[i], scene.dt))
                            sink += next->linear.y();
                    }) / (updateRepeats * double(std::max<std::size_t>(updates.size(), 1)));
  }
  if (prototype.shape && prototype.shape->type == SceneShape::Type::Sphere) {
    const int sphereRepeats = surface.flatHeight() ? 200 : 20;
    pass.closedFormUs = 1e3 * bench::medianMs(5, [&] {
                          for (int k = 0; k < sphereRepeats; ++k)
                            for (const HydrostaticsQuery& query : queries)
                              if (Expected<HydrostaticsResult> answer =
                                      sphereHydrostatics(prototype.shape->radius, Eigen::Vector3d::Zero(), surface, query))
                                sink += answer->buoyancyForce.y();
                        }) / (sphereRepeats * double(queries.size()));
  }
  if (c.drag) {
    // Texel drag patches as the controller makes them for a deforming body (FloatingBodySettings'
    // defaults: cosine 0.9, radius 0.2 of the largest extent, from the 256^2 bake).
    BodyGeometrySettings geometrySettings;
    geometrySettings.bake.width = geometrySettings.bake.height = 256;
    Expected<BodyGeometry> geometry = prepareBodyGeometry(*mesh, geometrySettings);
    if (geometry) {
      const double referenceLength = std::max((upper - lower).maxCoeff(), 1e-6);
      const std::vector<DragPatch> patches =
          mergeTexelsIntoDragPatches(geometry->bake, geometry->textures, 0.9, 0.2 * referenceLength);
      const DragPatchSet prepared = prepareDragPatches(patches);
      DragBody dragBody;
      dragBody.patches = patches;
      dragBody.prepared = &prepared;
      for (const DragPatch& patch : patches) dragBody.totalPatchArea += patch.area;
      dragBody.referenceLength = referenceLength;
      dragBody.rotationalDamping = 0.3;
      dragBody.damping = DragDamping::Secant;  // as the controller takes a deforming body's texel patches
      const DragLiquid liquid{&surface, eigen(controller.liquid().current), controller.liquid().viscosity, controller.time()};
      const int dragRepeats = std::max(1, int(20000 / (patches.size() * motions.size())));
      pass.dragUs = 1e3 * bench::medianMs(5, [&] {
                      for (int k = 0; k < dragRepeats; ++k)
                        for (const RigidBodyMotion& motion : motions)
                          sink += rigidBodyDrag(dragBody, motion, liquid, scene.dt).force.y();
                    }) / (dragRepeats * double(motions.size()));
      // The same law on patches made from the mesh's triangles (meshDragPatches, same settings):
      // the controller's for every rigid body.
      const std::vector<DragPatch> meshPatches = meshDragPatches(*mesh, 0.9, 0.2 * referenceLength);
      const DragPatchSet meshPrepared = prepareDragPatches(meshPatches);
      DragBody meshBody = dragBody;
      meshBody.patches = meshPatches;
      meshBody.prepared = &meshPrepared;
      meshBody.damping = DragDamping::Linearized;  // as the controller takes mesh patches
      meshBody.totalPatchArea = 0.0;
      for (const DragPatch& patch : meshPatches) meshBody.totalPatchArea += patch.area;
      pass.meshDragUs = 1e3 * bench::medianMs(5, [&] {
                          for (int k = 0; k < dragRepeats; ++k)
                            for (const RigidBodyMotion& motion : motions)
                              sink += rigidBodyDrag(meshBody, motion, liquid, scene.dt).force.y();
                        }) / (dragRepeats * double(motions.size()));
      pass.texelPatches = patches.size();
      pass.meshPatches = meshPatches.size();
    }
  }
  if (sink == 12345.678) std::printf(" ");  // keeps the sums alive
  return pass;
}

/// A mixed world's step: `bodies` of the scene's template bodies in turn (boxes, hulls, spheres,
/// ships), each `auto` as a user gets it, buoyancy + drag, kept awake; the whole world step
/// (Bullet and the controller) per step in ms over `steps` steps after 10 of warm-up, on `threads`.
struct MixedPass {
  double worldMs = 0.0, controllerMs = 0.0;
  std::map<std::string, int> resolved;  ///< template body -> bodies on the exact path
};

MixedPass runMixed(const Scene& base, int bodies, int threads, int steps) {
  Scene scene = base;
  scene.sourceName = "bench_peers mixed";
  scene.threads = threads;
  scene.backend = "cpu";
  scene.bodies.clear();
  const int columns = 10;
  for (int i = 0; i < bodies; ++i) {
    SceneBody body = base.bodies[std::size_t(i) % base.bodies.size()];
    body.name += std::to_string(i);
    body.method = HydrostaticsMethod::Auto;
    body.effects = EffectSet{Effect::Buoyancy, Effect::Drag};
    // 4 m apart (the ship is 2 m long), heights and headings varied per body.
    body.position += Eigen::Vector3d(4.0 * (i % columns), 0.02 * (i % 5) - 0.04, 4.0 * (i / columns));
    body.rotationDegrees += Eigen::Vector3d(2.0 * (i % 3), 37.0 * i, 1.5 * (i % 4));
    scene.bodies.push_back(body);
  }
  const TimedRun run = runTimed(scene, steps);
  SceneWorld& world = *run.world;
  const BuoyancyController& controller = world.controller();
  MixedPass pass;
  pass.worldMs = 1e3 * run.worldSeconds / steps;
  pass.controllerMs = 1e3 * run.controllerSeconds / steps;
  for (std::size_t i = 0; i < world.bodies().size(); ++i) {
    const FloatingBodyReport* report = controller.report(world.bodies()[i]);
    const std::string& name = base.bodies[i % base.bodies.size()].name;
    pass.resolved[name] += report != nullptr && report->method == HydrostaticsMethod::Polyhedral ? 1 : 0;
  }
  return pass;
}

}  // namespace

int main(int argc, char** argv) {
  // Every argument is a known option followed by its value; --help prints the options.
  static const char* const kOptions[] = {"--runs",    "--steps",    "--csv",   "--bodies",
                                         "--methods", "--surfaces", "--mixed", "--resolution"};
  for (int i = 1; i < argc; i += 2) {
    const std::string argument = argv[i];
    const bool known = std::find(std::begin(kOptions), std::end(kOptions), argument) != std::end(kOptions);
    if (argument == "--help" || argument == "-h" || !known || i + 1 >= argc) {
      std::printf("usage: bench_peers [--runs N] [--steps S] [--csv FILE] [--bodies box,hull,sphere,mesh]\n"
                  "                   [--methods exact,texture,auto] [--surfaces flat,waves] [--mixed N]\n"
                  "                   [--resolution N]\n");
      if (argument == "--help" || argument == "-h") return 0;
      std::fprintf(stderr, "bench_peers: %s '%s'\n", known ? "no value after" : "unknown option", argument.c_str());
      return 2;
    }
  }
  const int runs = std::stoi(option(argc, argv, "--runs", "5"));
  const int steps = std::stoi(option(argc, argv, "--steps", "60"));
  const std::string csvPath = option(argc, argv, "--csv", "bench_peers.csv");
  const std::vector<std::string> bodies = split(option(argc, argv, "--bodies", "box,hull,sphere,mesh"));
  const std::vector<std::string> methods = split(option(argc, argv, "--methods", "exact,texture,auto"));
  const std::vector<std::string> surfaces = split(option(argc, argv, "--surfaces", "flat,waves"));
  const int mixedBodies = std::stoi(option(argc, argv, "--mixed", "100"));
  const int resolution = std::stoi(option(argc, argv, "--resolution", "256"));
  if (resolution < 16 || resolution > 4096) {
    std::fprintf(stderr, "bench_peers: --resolution %d is outside 16..4096\n", resolution);
    return 2;
  }

  std::map<std::string, Scene> scenes;
  for (const std::string& surface : surfaces) {
    Expected<Scene> scene = loadScene(std::string(HYDROTEX_SCENES_DIR) + "/peers_" + surface + ".json");
    if (!scene) {
      std::fprintf(stderr, "bench_peers: %s\n", scene.error().message.c_str());
      return 1;
    }
    scenes.emplace(surface, std::move(scene).value());
  }
  std::ofstream csv(csvPath);
  csv << "body,triangles,method,resolved,surface,effects,runs,bodies,controller_us_per_body_step,peer,peer_us,goal_us,"
         "ratio_to_goal,exact_hydrostatics_us,prepared_exact_us,sphere_closed_form_us,drag_us,texel_patches,mesh_patch_drag_us,"
         "mesh_patches,implicit_update_us,queries_per_step,mean_abs_vy,drag_to_buoyancy,drag_to_buoyancy_goal\n";
  std::printf("%d awake bodies, 60 Hz, 1 thread, controller's updateAction per body per step (us), median of %d passes "
              "of %d steps, textures %d^2\n",
              kBodies, runs, steps, resolution);
  std::printf("%-7s %6s %-8s %-8s %-6s %-14s %9s %11s %9s %7s %9s %8s %8s %8s %9s %9s %8s %7s %5s\n", "body", "tris",
              "method", "runs as", "water", "effects", "ours us", "peer", "goal us", "ratio", "exact us", "prep us", "closed",
              "drag us", "mdrag us", "update us", "query/st", "|vy|m/s", "d/b");
  std::map<std::string, double> flatFigure;
  constexpr double kDragToBuoyancyGoal = 1.5;  // issue 19 item 3
  for (const std::string& surface : surfaces) {
    const Scene& scene = scenes.at(surface);
    for (const std::string& bodyName : bodies) {
      const auto prototype = std::find_if(scene.bodies.begin(), scene.bodies.end(),
                                          [&](const SceneBody& b) { return b.name == bodyName; });
      if (prototype == scene.bodies.end()) {
        std::fprintf(stderr, "bench_peers: no body '%s' in peers_%s.json\n", bodyName.c_str(), surface.c_str());
        return 1;
      }
      Expected<std::shared_ptr<const Mesh>> mesh = templateMesh(*prototype);
      if (!mesh) {
        std::fprintf(stderr, "bench_peers: %s\n", mesh.error().message.c_str());
        return 1;
      }
      const PeerFigure* peer = nullptr;
      for (const PeerFigure& figure : kPeers)
        if (bodyName == figure.body) peer = &figure;
      for (const std::string& method : methods) {
        double buoyancyFigure = 0.0;  // this body's and method's row without drag
        for (const bool drag : {false, true}) {
          const Case c{bodyName, method, surface, drag, resolution};
          std::vector<double> ours, hydro, preparedUs, closedUs, dragUs, meshDragUs, updateUs, queries, speeds;
          Pass last;
          for (int r = 0; r < runs; ++r) {
            last = runPass(scene, *prototype, *mesh, c, steps);
            ours.push_back(last.controllerUs);
            hydro.push_back(last.hydrostaticsUs);
            preparedUs.push_back(last.preparedUs);
            closedUs.push_back(last.closedFormUs);
            dragUs.push_back(last.dragUs);
            meshDragUs.push_back(last.meshDragUs);
            updateUs.push_back(last.updateUs);
            queries.push_back(last.queriesPerStep);
            speeds.push_back(last.meanVerticalSpeed);
          }
          const double figure = median(ours);
          const std::string key = bodyName + "|" + method + "|" + (drag ? "d" : "b");
          if (surface == "flat") flatFigure[key] = figure;
          // Flat water: the peer's figure is the goal. Waves: at most 2x the same row's flat figure.
          const double peerUs = peer ? (drag ? peer->dragUs : peer->buoyancyUs) : 0.0;
          double goal = peerUs;
          std::string peerText = peer ? std::string(peer->source) + " " + std::to_string(peerUs).substr(0, 5) : "-";
          if (surface != "flat") {
            const auto flat = flatFigure.find(key);
            goal = flat != flatFigure.end() ? 2.0 * flat->second : 0.0;
            peerText = "2x flat";
          }
          const double ratio = goal > 0.0 ? figure / goal : 0.0;
          // The row with drag against the same body's row without, run just before it.
          if (!drag) buoyancyFigure = figure;
          const double dragToBuoyancy = drag && buoyancyFigure > 0.0 ? figure / buoyancyFigure : 0.0;
          const char* effects = drag ? "buoyancy+drag" : "buoyancy";
          std::printf("%-7s %6zu %-8s %-8s %-6s %-14s %9.3f %11s %9.3f %7.2f %9.3f %8.3f %8.3f %8.3f %9.3f %9.3f %8.1f %7.3f %5s\n",
                      bodyName.c_str(), last.triangles, method.c_str(), last.resolved.c_str(), surface.c_str(), effects,
                      figure, peerText.c_str(), goal, ratio, median(hydro), median(preparedUs), median(closedUs),
                      median(dragUs), median(meshDragUs), median(updateUs), median(queries), median(speeds),
                      drag ? std::to_string(dragToBuoyancy).substr(0, 4).c_str() : "-");
          std::fflush(stdout);
          csv << bodyName << ',' << last.triangles << ',' << method << ',' << last.resolved << ',' << surface << ','
              << effects << ',' << runs << ',' << kBodies << ',' << figure << ',' << peerText << ',' << peerUs << ','
              << goal << ',' << ratio << ',' << median(hydro) << ',' << median(preparedUs) << ',' << median(closedUs) << ','
              << median(dragUs) << ',' << last.texelPatches << ',' << median(meshDragUs) << ',' << last.meshPatches << ','
              << median(updateUs) << ',' << median(queries) << ',' << median(speeds) << ',' << dragToBuoyancy << ','
              << (drag ? kDragToBuoyancyGoal : 0.0) << '\n';
        }
      }
    }
  }
  // Issue 19: 100 mixed bodies on three waves, buoyancy + drag, whole world step on both cores
  // under 2 ms (the flat row for scale). The table and its CSV (FILE with "_mixed" before ".csv").
  if (mixedBodies > 0) {
    std::string mixedPath = csvPath;
    const std::size_t dot = mixedPath.rfind(".csv");
    mixedPath.insert(dot == std::string::npos ? mixedPath.size() : dot, "_mixed");
    std::ofstream mixedCsv(mixedPath);
    mixedCsv << "surface,bodies,threads,runs,world_ms_per_step,controller_ms_per_step,goal_ms,ratio_to_goal,exact_bodies\n";
    std::printf("\n%d mixed bodies (the templates in turn, auto, buoyancy + drag), whole world step (ms), median of %d "
                "passes of %d steps\n",
                mixedBodies, runs, steps);
    std::printf("%-6s %7s %9s %13s %8s %7s  %s\n", "water", "threads", "world ms", "controller ms", "goal ms", "ratio",
                "exact-path bodies");
    for (const std::string& surface : surfaces) {
      for (const int threads : {1, 2}) {
        std::vector<double> world, controllerMs;
        MixedPass last;
        for (int r = 0; r < runs; ++r) {
          last = runMixed(scenes.at(surface), mixedBodies, threads, steps);
          world.push_back(last.worldMs);
          controllerMs.push_back(last.controllerMs);
        }
        const double goal = surface == "waves" && threads == 2 ? 2.0 : 0.0;
        std::string exact;
        int exactCount = 0;
        for (const auto& [name, count] : last.resolved) {
          exact += (exact.empty() ? "" : " ") + name + " " + std::to_string(count);
          exactCount += count;
        }
        std::printf("%-6s %7d %9.3f %13.3f %8s %7s  %s\n", surface.c_str(), threads, median(world), median(controllerMs),
                    goal > 0.0 ? "2.000" : "-", goal > 0.0 ? std::to_string(median(world) / goal).substr(0, 5).c_str() : "-",
                    exact.c_str());
        std::fflush(stdout);
        mixedCsv << surface << ',' << mixedBodies << ',' << threads << ',' << runs << ',' << median(world) << ','
                 << median(controllerMs) << ',' << goal << ',' << (goal > 0.0 ? median(world) / goal : 0.0) << ','
                 << exactCount << '\n';
      }
    }
  }
  return 0;
}
