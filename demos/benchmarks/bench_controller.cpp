// SPDX-License-Identifier: Zlib
// bench_controller: 100 floating boxes at 256^2 with buoyancy and drag in flat water, in a Bullet
// world stepped at 60 Hz; the split between Bullet's own work and the BuoyancyController, on 1
// thread and on 2 (ControllerSettings::threads), and the whole step's speed-up. Prints a table
// and writes CSV (argv[1], default bench_controller.csv). Medians of several runs.
//
// With --same-state [RUNS]: only the per-body cost of buoyancy and of drag in the same states
// (sameStateCosts), which the full table also prints last.
//
// With --changing [RUNS]: the controller when something changes every step (variable-mass bodies
// whose density maps are replaced every step; soft bodies), on 1 and 2 threads (runChanging).
//
// With --backend cpu|gpu (and --bodies N, --threads T, --runs R, --steps S, --drag 0|1,
// --bandwidth-gbs B, --csv FILE): one table for that backend of the controller (issue 18: 1,000
// bodies on the CPU and on the GL backend), with the bandwidth floor of the texels the backend
// reads per step beside it (GL texel layout, at B GB/s).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <BulletSoftBody/btSoftBody.h>

#include "ControllerBench.hpp"
#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bullet/Scene.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/MeshDragPatches.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"
#ifdef HYDROTEX_WITH_GPU
#include "hydrotex/gpu/MakeBackend.hpp"
#include "hydrotex/gpu/ShaderLayouts.hpp"
using gpuTexelRecord = hydrotex::gpu::layout::HydroTexel;
#else
using gpuTexelRecord = hydrotex::TextureHydrostatics::Texel;  // no GL here: the CPU's texel record
#endif

using namespace hydrotex;
using namespace hydrotex::bullet;
using Clock = std::chrono::steady_clock;

namespace {

using bench::TimedAction;

struct Run {
  double totalMs, controllerMs;
  double registerMs = 0.0;   ///< SceneWorld::create: every body registered
  double residentMb = 0.0;   ///< the process's resident memory after registration
  double steppedMb = 0.0;    ///< ... and after the warm-up steps (a GPU backend's tables exist by then)
  ControllerStatistics counters;  ///< the timed steps' work (the controller's counters, warm-up excluded)
  ControllerTimings phases;       ///< the timed steps' time per phase, ms a step
};

/// (after - before) / steps, in ms, phase by phase.
ControllerTimings phasesPerStep(const ControllerTimings& before, const ControllerTimings& after, int steps) {
  const double k = 1000.0 / steps;
  return {k * (after.read - before.read),       k * (after.wetting - before.wetting), k * (after.plan - before.plan),
          k * (after.backend - before.backend), k * (after.drag - before.drag),       k * (after.update - before.update),
          k * (after.write - before.write),     k * (after.softBodies - before.softBodies)};
}

/// Resident memory of this process (MB), from /proc/self/statm.
double residentMegabytes() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0, resident = 0.0;
  statm >> pages >> resident;
  return resident * 4096.0 / 1e6;
}

Run runOnce(EffectSet effects, int resolution, int bodies, int steps, int threads, const std::string& backend = "cpu",
           std::string* renderer = nullptr) {
  Scene scene;
  scene.sourceName = "bench";
  scene.dt = 1.0 / 60.0;
  scene.threads = threads;
  scene.backend = backend;
  auto box = std::make_shared<const Mesh>(primitives::box({1.0, 0.6, 0.8}));
  for (int i = 0; i < bodies; ++i) {
    SceneBody body;
    body.name = "box" + std::to_string(i);
    body.mesh = box;
    body.density = 400.0 + 4.0 * i;
    const int columns = bodies > 100 ? 32 : 10;
    body.position = Eigen::Vector3d(2.0 * (i % columns), 0.5 + 0.05 * (i % 7), 2.0 * (i / columns));
    body.rotationDegrees = Eigen::Vector3d(3.0 * (i % 5), 10.0 * i, 0.0);
    body.resolution = resolution;
    body.method = HydrostaticsMethod::Texture;  // what this benchmark measures (Auto takes the exact path for a box)
    body.effects = effects;
    scene.bodies.push_back(body);
  }
  const auto registerStart = Clock::now();
#ifdef HYDROTEX_WITH_GPU
  auto created = SceneWorld::create(scene, gpu::makeControllerBackend);
#else
  auto created = SceneWorld::create(scene);
#endif
  const double registerMs = 1000.0 * std::chrono::duration<double>(Clock::now() - registerStart).count();
  const double residentMb = residentMegabytes();
  if (!created) {
    std::fprintf(stderr, "bench_controller: %s\n", created.error().message.c_str());
    std::exit(1);
  }
  SceneWorld& world = **created;
  if (renderer != nullptr) *renderer = world.controller().backend().name() + ": " + world.controller().backend().renderer();
  // Time the controller from inside the world: swap the action for a timed wrapper.
  TimedAction timed(world.controller());
  world.world().removeAction(&world.controller());
  world.world().addAction(&timed);
  for (int i = 0; i < 30; ++i) world.step();  // warm-up: bodies enter the water
  const double steppedMb = residentMegabytes();
  timed.seconds = 0.0;
  const ControllerStatistics before = world.controller().statistics();
  const ControllerTimings phasesBefore = world.controller().timings();
  const auto start = Clock::now();
  for (int i = 0; i < steps; ++i) world.step();
  const double total = std::chrono::duration<double>(Clock::now() - start).count();
  world.world().removeAction(&timed);
  world.world().addAction(&world.controller());
  ControllerStatistics counters = world.controller().statistics();
  counters.hydrostaticsQueries -= before.hydrostaticsQueries;
  counters.dragPasses -= before.dragPasses;
  counters.dragPatchesVisited -= before.dragPatchesVisited;
  counters.skippedOutOfLiquid -= before.skippedOutOfLiquid;
  counters.skippedAsleep -= before.skippedAsleep;
  return {1000.0 * total / steps, 1000.0 * timed.seconds / steps, registerMs, residentMb, steppedMb, counters,
          phasesPerStep(phasesBefore, world.controller().timings(), steps)};
}

using bench::eigen;

/// The cost of buoyancy and of drag for the same bodies in the same states (issue 19 item 3: "with
/// drag, a body costs at most 1.5x its buoyancy-only cost"): a world of `worldEffects` (buoyancy
/// with or without drag) is stepped past its warm-up, then every body's pose and velocities are
/// read and, on one thread, the box's texture hydrostatics (TextureHydrostatics::query, the CPU
/// backend's call) and its drag sum (rigidBodyDrag with the model's DragPatchSet, the controller's
/// call) are timed over all bodies, alternately, `runs` times.
/// The two worlds of the table above settle differently (without drag the boxes keep bouncing,
/// often through cheap states), so their ratio mixes the drag's cost with the states' change.
struct SameStateCost {
  double buoyancyUs = 0.0, dragUs = 0.0;  ///< per body, medians
  double patches = 0.0, wetPatches = 0.0; ///< per body
  double clusterPatches = 0.0;            ///< per body, patches in the clusters not skipped as dry
  double dragForceSum = 0.0, dragTorqueSum = 0.0;  ///< sum over the bodies of |F| (N) and |T| (N m): a check of results
};

double median(std::vector<double> v);

SameStateCost sameStateCosts(int bodies, int resolution, int steps, int runs, EffectSet worldEffects) {
  Scene scene;
  scene.sourceName = "bench";
  scene.dt = 1.0 / 60.0;
  scene.threads = 1;
  const Mesh mesh = primitives::box({1.0, 0.6, 0.8});
  auto box = std::make_shared<const Mesh>(mesh);
  for (int i = 0; i < bodies; ++i) {
    SceneBody body;
    body.name = "box" + std::to_string(i);
    body.mesh = box;
    body.density = 400.0 + 4.0 * i;
    body.position = Eigen::Vector3d(2.0 * (i % 10), 0.5 + 0.05 * (i % 7), 2.0 * (i / 10));
    body.rotationDegrees = Eigen::Vector3d(3.0 * (i % 5), 10.0 * i, 0.0);
    body.resolution = resolution;
    body.method = HydrostaticsMethod::Texture;
    body.effects = worldEffects;
    scene.bodies.push_back(body);
  }
  auto created = SceneWorld::create(scene);
  if (!created) return {};
  SceneWorld& world = **created;
  for (int i = 0; i < 30 + steps; ++i) world.step();
  BuoyancyController& controller = world.controller();
  // The box's model as the controller builds it: default hydrostatics, drag patches of cosine 0.9
  // and radius 0.2 of the largest extent (FloatingBodySettings' defaults).
  BodyGeometrySettings geometrySettings;
  geometrySettings.bake.width = geometrySettings.bake.height = resolution;
  Expected<BodyGeometry> geometry = prepareBodyGeometry(mesh, geometrySettings);
  if (!geometry) return {};
  Expected<TextureHydrostatics> hydrostatics = TextureHydrostatics::build(geometry->bake, geometry->textures);
  if (!hydrostatics) return {};
  Eigen::Vector3d lower = mesh.positions.front(), upper = lower;
  for (const Eigen::Vector3d& vertex : mesh.positions) {
    lower = lower.cwiseMin(vertex);
    upper = upper.cwiseMax(vertex);
  }
  const double referenceLength = (upper - lower).maxCoeff();
  // A rigid body's drag patches come from its triangles, with the law's whole derivative.
  const std::vector<DragPatch> patches = meshDragPatches(mesh, 0.9, 0.2 * referenceLength);
  const DragPatchSet prepared = prepareDragPatches(patches);
  DragBody dragBody;
  dragBody.patches = patches;
  dragBody.prepared = &prepared;
  for (const DragPatch& patch : patches) dragBody.totalPatchArea += patch.area;
  dragBody.referenceLength = referenceLength;
  dragBody.damping = DragDamping::Linearized;
  const LiquidSurface& surface = *controller.liquid().surface;
  const DragLiquid liquid{&surface, eigen(controller.liquid().current), controller.liquid().viscosity, controller.time()};
  std::vector<HydrostaticsQuery> queries;
  std::vector<RigidBodyMotion> motions;
  for (const bench::BodyState& state : bench::bodyStates(controller, world.bodies())) {
    queries.push_back(state.query);
    motions.push_back(state.motion);
  }
  SameStateCost cost;
  cost.patches = double(patches.size());
  std::vector<double> buoyancy, drag;
  double sink = 0.0;
  std::uint64_t wet = 0;
  const int repeats = 20;
  for (int r = 0; r < runs; ++r) {
    auto start = Clock::now();
    for (int k = 0; k < repeats; ++k)
      for (const HydrostaticsQuery& query : queries)
        if (Expected<HydrostaticsResult> answer = hydrostatics->query(surface, query)) sink += answer->buoyancyForce.y();
    buoyancy.push_back(1e6 * std::chrono::duration<double>(Clock::now() - start).count() / (repeats * double(queries.size())));
    start = Clock::now();
    wet = 0;
    for (int k = 0; k < repeats; ++k)
      for (const RigidBodyMotion& motion : motions) {
        const DragLoads loads = rigidBodyDrag(dragBody, motion, liquid, 1.0 / 60.0);
        sink += loads.force.y();
        wet += loads.patchesVisited;
      }
    drag.push_back(1e6 * std::chrono::duration<double>(Clock::now() - start).count() / (repeats * double(motions.size())));
  }
  cost.buoyancyUs = median(buoyancy);
  cost.dragUs = median(drag) + (sink == 12345.678 ? 1e-9 : 0.0);  // keeps the sums alive
  cost.wetPatches = double(wet) / (repeats * double(motions.size()));
  const double level = surface.flatHeight().value_or(0.0);
  for (const RigidBodyMotion& motion : motions) {
    const Eigen::Vector3d up = motion.meshPose.rotation.row(1).transpose();
    for (const DragPatchSet::Cluster& cluster : prepared.clusters)
      if (level - motion.meshPose.translation.y() - up.dot(cluster.center) >= -cluster.radius)
        cost.clusterPatches += double(cluster.end - cluster.begin) / double(motions.size());
    const DragLoads loads = rigidBodyDrag(dragBody, motion, liquid, 1.0 / 60.0);
    cost.dragForceSum += loads.force.norm();
    cost.dragTorqueSum += loads.torque.norm();
  }
  return cost;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

/// The value after `flag` in argv, or `fallback`.
std::string option(int argc, char** argv, const std::string& flag, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (argv[i] == flag) return argv[i + 1];
  return fallback;
}

/// One backend's table: --backend NAME --bodies N ...
int runBackend(int argc, char** argv) {
  const std::string backend = option(argc, argv, "--backend", "cpu");
  const int bodies = std::stoi(option(argc, argv, "--bodies", "1000"));
  const int threads = std::stoi(option(argc, argv, "--threads", "0"));
  const int runs = std::stoi(option(argc, argv, "--runs", "3"));
  const int steps = std::stoi(option(argc, argv, "--steps", "60"));
  const bool drag = option(argc, argv, "--drag", "1") == "1";
  const double bandwidth = std::stod(option(argc, argv, "--bandwidth-gbs", "4800"));  // H200's HBM3e
  const std::string csvPath = option(argc, argv, "--csv", "bench_controller_backend.csv");
  const int resolution = 256;
  const EffectSet effects = drag ? EffectSet{Effect::Buoyancy, Effect::Drag} : EffectSet{Effect::Buoyancy};
  std::vector<double> totals, controllers, registers;
  // Memory from the first run only: a later one's figure holds what the earlier worlds' allocator
  // and driver kept after they were gone.
  double residentMb = 0.0, steppedMb = 0.0;
  std::string renderer;
  ControllerStatistics counters;
  std::vector<ControllerTimings> phases;
  for (int r = 0; r < runs; ++r) {
    const Run run = runOnce(effects, resolution, bodies, steps, threads, backend, &renderer);
    counters = run.counters;
    phases.push_back(run.phases);
    totals.push_back(run.totalMs);
    controllers.push_back(run.controllerMs);
    registers.push_back(run.registerMs);
    if (r == 0) {
      residentMb = run.residentMb;
      steppedMb = run.steppedMb;
    }
  }
  // The floor: every covered texel of every body read once per step (the GL backend's HydroTexel
  // record), at the stated memory bandwidth.
  BodyGeometrySettings geometrySettings;
  geometrySettings.bake.width = geometrySettings.bake.height = resolution;
  Expected<BodyGeometry> geometry = prepareBodyGeometry(primitives::box({1.0, 0.6, 0.8}), geometrySettings);
  const double texelsPerBody = geometry ? double(geometry->textures.size()) : 0.0;
  const double bytes = double(bodies) * texelsPerBody * double(sizeof(gpuTexelRecord));
  const double floorMs = 1000.0 * bytes / (bandwidth * 1e9);
  std::printf("backend %s (%s), %d bodies at %d^2, %s, %d threads requested, %d runs of %d steps\n", backend.c_str(),
              renderer.c_str(), bodies, resolution, drag ? "buoyancy+drag" : "buoyancy", threads, runs, steps);
  std::printf("%-12s %12s %12s %15s %18s %10s\n", "backend", "total ms", "bullet ms", "controller ms", "bandwidth floor ms",
              "goal ms");
  std::vector<double> bullet;
  for (int r = 0; r < runs; ++r) bullet.push_back(totals[std::size_t(r)] - controllers[std::size_t(r)]);
  std::printf("%-12s %12.3f %12.3f %15.3f %18.4f %10.1f\n", backend.c_str(), median(totals), median(bullet),
              median(controllers), floorMs, 1.0);
  // The controller's phases (medians over the runs, phase by phase): where a GPU's batch waits,
  // and how much of the drag it hides (the drag runs while the batch is in flight).
  auto phaseMedian = [&](double ControllerTimings::*field) {
    std::vector<double> values;
    for (const ControllerTimings& p : phases) values.push_back(p.*field);
    return median(values);
  };
  const double read = phaseMedian(&ControllerTimings::read), plan = phaseMedian(&ControllerTimings::plan),
               batch = phaseMedian(&ControllerTimings::backend), dragMs = phaseMedian(&ControllerTimings::drag),
               update = phaseMedian(&ControllerTimings::update), write = phaseMedian(&ControllerTimings::write);
  std::printf("controller phases, ms a step: read %.3f, plan %.3f, backend batch %.3f beside drag %.3f, update %.3f, "
              "write %.3f\n",
              read, plan, batch, dragMs, update, write);
  std::ofstream csv(csvPath);
  csv << "backend,renderer,bodies,resolution,effects,threads,runs,total_ms_per_step,bullet_ms_per_step,controller_ms_per_step,"
         "bandwidth_floor_ms,goal_ms,register_ms,resident_mb,resident_stepping_mb,read_ms,plan_ms,backend_ms,drag_ms,update_ms,write_ms\n";
  csv << backend << ",\"" << renderer << "\"," << bodies << ',' << resolution << ',' << (drag ? "buoyancy+drag" : "buoyancy")
      << ',' << threads << ',' << runs << ',' << median(totals) << ',' << median(bullet) << ',' << median(controllers)
      << ',' << floorMs << ",1," << median(registers) << ',' << residentMb << ',' << steppedMb << ',' << read << ',' << plan << ','
      << batch << ',' << dragMs << ',' << update << ',' << write << '\n';
  std::printf("a step (last run): %.1f buoyancy queries, %.1f drag passes of %.1f wet patches each, %.1f bodies out of "
              "the liquid, %.1f asleep\n",
              double(counters.hydrostaticsQueries) / steps, double(counters.dragPasses) / steps,
              counters.dragPasses ? double(counters.dragPatchesVisited) / double(counters.dragPasses) : 0.0,
              double(counters.skippedOutOfLiquid) / steps, double(counters.skippedAsleep) / steps);
  std::printf("covered texels per body %.0f, %.0f bytes a step through the backend\n", texelsPerBody, bytes);
  // Identical crates share one model (issue 19): registering them all, and the memory they hold.
  // Each run's registration opens a GPU backend too; the first on a machine also has the driver
  // compile the shaders into its cache (about 1.5 s on an H100), which a median of 3 runs or more
  // leaves out.
  std::printf("registering the %d identical bodies: %.1f ms (%.3f ms a body; goal 1000 under 500 ms), resident %.0f MB "
              "after registration and %.0f MB after the first steps, first run (goal 1000 under 100 MB)\n",
              bodies, median(registers), median(registers) / bodies, residentMb, steppedMb);
  return 0;
}

/// One timed world of the --changing table: `bodies` variable-mass boxes at `resolution` whose
/// density maps are replaced every step (two buffers a body, swapped: what an animation does), or
/// `softBodies` soft balls (buoyancy and drag) in waves; controller ms a step over `steps` steps
/// after a warm-up. The maps are filled outside the timed controller call.
double changingRun(bool softCase, int bodies, int resolution, int steps, int threads, double* checksum = nullptr) {
  Scene scene;
  scene.sourceName = "bench";
  scene.threads = threads;
  if (softCase) {
    scene.dt = 1.0 / 120.0;
    scene.surface.type = SceneSurface::Type::Waves;
    scene.surface.waves = {GerstnerWave{0.1, 6.0, Eigen::Vector2d(1.0, 0.2), 0.1, 0.3}};
    auto ball = std::make_shared<const Mesh>(primitives::uvSphere(0.25, 32, 16));
    for (int i = 0; i < bodies; ++i) {
      SceneBody body;
      body.name = "soft" + std::to_string(i);
      body.mesh = ball;
      body.soft = true;
      body.mass = 20.0 + i;
      body.position = Eigen::Vector3d(1.0 * (i % 8), 0.05, 1.0 * (i / 8));
      body.resolution = resolution;
      body.effects = EffectSet{Effect::Buoyancy, Effect::Drag};
      body.softMaterial.shapeMatching = 0.5;
      scene.softBodies.push_back(body);
    }
  } else {
    scene.dt = 1.0 / 60.0;
    auto box = std::make_shared<const Mesh>(primitives::box({1.0, 0.6, 0.8}));
    for (int i = 0; i < bodies; ++i) {
      SceneBody body;
      body.name = "box" + std::to_string(i);
      body.mesh = box;
      body.density = 400.0 + 4.0 * i;
      body.position = Eigen::Vector3d(2.0 * (i % 10), 0.3, 2.0 * (i / 10));
      body.resolution = resolution;
      body.effects = EffectSet{Effect::Buoyancy, Effect::Drag, Effect::VariableMass};
      body.method = HydrostaticsMethod::Texture;
      scene.bodies.push_back(body);
    }
  }
  auto created = SceneWorld::create(scene);
  if (!created) {
    std::fprintf(stderr, "bench_controller: %s\n", created.error().message.c_str());
    std::exit(1);
  }
  SceneWorld& world = **created;
  std::vector<MassModel*> models;
  for (btRigidBody* body : world.bodies())
    if (MassModel* model = world.controller().massModel(body)) models.push_back(model);
  std::vector<std::vector<float>> spare(models.size());
  auto replaceMaps = [&](int step) {
    for (std::size_t k = 0; k < models.size(); ++k) {
      spare[k].resize(models[k]->texelCount());
      std::fill(spare[k].begin(), spare[k].end(), float(400.0 + 4.0 * double(k) + 0.5 * (step % 20)));
      if (!models[k]->swapTexelDensity(spare[k])) std::exit(1);
    }
  };
  TimedAction timed(world.controller());
  world.world().removeAction(&world.controller());
  world.world().addAction(&timed);
  for (int i = 0; i < 20; ++i) {
    replaceMaps(i);
    world.step();
  }
  timed.seconds = 0.0;
  for (int i = 0; i < steps; ++i) {
    replaceMaps(i);
    world.step();
  }
  world.world().removeAction(&timed);
  world.world().addAction(&world.controller());
  if (checksum != nullptr) {  // the final states, to compare two builds' trajectories
    double sum = 0.0;
    for (const btRigidBody* body : world.bodies())
      for (int k = 0; k < 3; ++k)
        sum += double(body->getCenterOfMassPosition()[k]) + double(body->getLinearVelocity()[k]) +
               double(body->getAngularVelocity()[k]);
    for (const btSoftBody* soft : world.softBodies())
      for (int n = 0; n < soft->m_nodes.size(); ++n)
        for (int k = 0; k < 3; ++k) sum += double(soft->m_nodes[n].m_x[k]) + double(soft->m_nodes[n].m_v[k]);
    *checksum = sum;
  }
  return 1000.0 * timed.seconds / steps;
}

/// --changing [RUNS]: the controller's cost when something changes every step: 100 variable-mass
/// boxes at 128^2 whose density maps are replaced every step (a texel mass pass each), and 16
/// soft balls (1 k nodes, 64^2) with buoyancy and drag in waves; 1 and 2 threads, medians, and a
/// sum of the final states (positions, velocities, nodes) that two builds must share bit for bit.
int runChanging(int runs) {
  std::printf("%-44s %7s %5s %7s %15s\n", "case", "bodies", "res", "threads", "controller ms");
  struct Case {
    const char* name;
    bool soft;
    int bodies, resolution, steps;
  };
  const Case cases[] = {{"variable_mass (maps replaced every step)", false, 100, 128, 60},
                        {"soft bodies (buoyancy+drag, waves)", true, 16, 64, 60}};
  for (const Case& c : cases) {
    double byThreads[2] = {0.0, 0.0};
    for (int t = 0; t < 2; ++t) {
      std::vector<double> times;
      double checksum = 0.0;
      for (int r = 0; r < runs; ++r)
        times.push_back(changingRun(c.soft, c.bodies, c.resolution, c.steps, t + 1, r == 0 ? &checksum : nullptr));
      byThreads[t] = median(times);
      std::printf("%-44s %7d %5d %7d %15.3f   states %.17g\n", c.name, c.bodies, c.resolution, t + 1, byThreads[t], checksum);
    }
    std::printf("%s: 2 threads against 1: %.2fx\n", c.name, byThreads[0] / byThreads[1]);
  }
  return 0;
}

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::printf("usage: bench_controller [CSV] | --same-state [RUNS] | --changing [RUNS] | --backend cpu|gpu [--bodies N] "
                  "[--threads T] [--runs R] [--steps S] [--drag 0|1] [--bandwidth-gbs B] [--csv FILE]\n");
      return 0;
    }
  }
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--backend") return runBackend(argc, argv);
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--changing") return runChanging(i + 1 < argc ? std::stoi(argv[i + 1]) : 3);
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--same-state") {  // only the same-state line: --same-state RUNS
      const SameStateCost same = sameStateCosts(100, 256, 120, i + 1 < argc ? std::stoi(argv[i + 1]) : 9,
                                                EffectSet{Effect::Buoyancy, Effect::Drag});
      std::printf("same states: buoyancy %.2f us a body, drag %.2f us (%.0f patches, %.1f in clusters "
                  "not dry, %.1f wet), (buoyancy+drag) / buoyancy %.2fx (goal 1.5x)\n",
                  same.buoyancyUs, same.dragUs, same.patches, same.clusterPatches, same.wetPatches, (same.buoyancyUs + same.dragUs) / same.buoyancyUs);
      std::printf("drag over the bodies: sum |F| %.17g N, sum |T| %.17g N m\n", same.dragForceSum, same.dragTorqueSum);
      return 0;
    }
  // No mode: the first argument, if any, is the CSV path, and an option there is a mistake, not a
  // file to write where the benchmark runs.
  if (argc > 1 && argv[1][0] == '-') {
    std::fprintf(stderr, "bench_controller: unknown option '%s' (--help lists them)\n", argv[1]);
    return 2;
  }
  const std::string csvPath = argc > 1 ? argv[1] : "bench_controller.csv";
  struct Case {
    const char* name;
    EffectSet effects;
  };
  const Case cases[] = {
      {"none", EffectSet{}},
      {"buoyancy", EffectSet{Effect::Buoyancy}},
      {"buoyancy+drag", EffectSet{Effect::Buoyancy, Effect::Drag}},
      {"buoyancy+drag+added_mass", EffectSet{Effect::Buoyancy, Effect::Drag, Effect::AddedMass}},
  };
  const int bodies = 100, resolution = 256, steps = 120, runs = 5;
  std::ofstream csv(csvPath);
  csv << "effects,bodies,resolution,threads,runs,total_ms_per_step,bullet_ms_per_step,controller_ms_per_step\n";
  std::printf("%-26s %7s %5s %7s %12s %12s %15s\n", "effects", "bodies", "res", "threads", "total ms", "bullet ms",
              "controller ms");
  double speedUp = 0.0, controllerSpeedUp = 0.0;
  double buoyancyController[2] = {0.0, 0.0}, dragRatio[2] = {0.0, 0.0};  // per thread count
  const int threadCounts[2] = {1, 2};
  for (const Case& c : cases) {
    // The runs alternate between the counts, so that a neighbour's load on a shared machine falls
    // on both alike.
    std::vector<double> totals[2], controllers[2], bullets[2];
    for (int r = 0; r < runs; ++r) {
      for (int k = 0; k < 2; ++k) {
        const Run run = runOnce(c.effects, resolution, bodies, steps, threadCounts[k]);
        totals[k].push_back(run.totalMs);
        controllers[k].push_back(run.controllerMs);
        bullets[k].push_back(run.totalMs - run.controllerMs);
      }
    }
    double serialTotal = 0.0, serialController = 0.0;
    for (int k = 0; k < 2; ++k) {
      const int threads = threadCounts[k];
      const std::vector<double>& total = totals[k];
      const std::vector<double>& controller = controllers[k];
      const std::vector<double>& bullet = bullets[k];
      std::printf("%-26s %7d %5d %7d %12.3f %12.3f %15.3f\n", c.name, bodies, resolution, threads, median(total),
                  median(bullet), median(controller));
      csv << c.name << ',' << bodies << ',' << resolution << ',' << threads << ',' << runs << ',' << median(total) << ','
          << median(bullet) << ',' << median(controller) << '\n';
      if (std::string(c.name) == "buoyancy") buoyancyController[k] = median(controller);
      if (std::string(c.name) == "buoyancy+drag" && buoyancyController[k] > 0.0)
        dragRatio[k] = median(controller) / buoyancyController[k];
      if (threads == 1) {
        serialTotal = median(total);
        serialController = median(controller);
      } else if (std::string(c.name) == "buoyancy+drag") {
        speedUp = serialTotal / median(total);
        controllerSpeedUp = serialController / median(controller);
      }
    }
  }
  std::printf("buoyancy+drag, 2 threads against 1: whole step %.2fx, controller %.2fx (goal 1.8x)\n", speedUp,
              controllerSpeedUp);
  std::printf("target: buoyancy+drag under 8 ms per step (60 Hz, 100 bodies, 256^2)\n");
  std::printf("controller, 1 thread: buoyancy+drag / buoyancy %.2fx, 2 threads %.2fx (goal 1.5x; the two worlds settle "
              "differently, see below)\n",
              dragRatio[0], dragRatio[1]);
  for (const Case& c : {cases[2], cases[1]}) {
    const SameStateCost same = sameStateCosts(bodies, resolution, steps, 9, c.effects);
    std::printf("same states (%s world after %d steps, 1 thread): buoyancy %.2f us a body, drag %.2f us (%.0f patches, "
                "%.1f in clusters not dry, %.1f wet), (buoyancy+drag) / buoyancy %.2fx (goal 1.5x)\n",
                c.name, 30 + steps, same.buoyancyUs, same.dragUs, same.patches, same.clusterPatches, same.wetPatches,
                (same.buoyancyUs + same.dragUs) / same.buoyancyUs);
  }
  return 0;
}
