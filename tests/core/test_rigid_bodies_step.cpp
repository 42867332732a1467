// SPDX-License-Identifier: Zlib
// Core's phased step of many rigid bodies (RigidBodiesStep.hpp): each body's answer is the one
// stepRigidBody gives it alone with its own hydrostatics (bit for bit: the same operations; under
// waves an exact body's drag reads its query's jets, within the drag's height error), the
// plan's closed forms (free fall above the liquid, nothing for a sleeping or static body), one
// backend batch a step with the drag run while it is in flight, a failed batch asked again body by
// body, the same bits for any thread count or order, and a box body's rule under waves.

#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <thread>
#include <vector>

#include "hydrostatics/BoxHydrostaticsWaves.hpp"
#include "step/RigidBodyDragWithJets.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/step/RigidBodiesStep.hpp"

using namespace hydrotex;

namespace {

constexpr double kDt = 1.0 / 60.0;

// A CPU backend that counts its batches and how often the caller's work ran meanwhile.
class CountingBackend final : public ComputeBackend {
 public:
  CountingBackend() : inner_(makeCpuBackend()) {}
  std::string name() const override { return inner_->name(); }
  std::string renderer() const override { return inner_->renderer(); }
  Expected<BackendBodyId> addBody(const SurfaceBake& bake, const SurfaceTextures& textures,
                                  const Eigen::Vector3d& reference) override {
    return inner_->addBody(bake, textures, reference);
  }
  Status updateSurface(BackendBodyId body, const SurfaceTextures& textures) override {
    return inner_->updateSurface(body, textures);
  }
  std::size_t bodyCount() const override { return inner_->bodyCount(); }
  using ComputeBackend::hydrostatics;
  Status hydrostatics(const LiquidSurface& surface, std::span<const BackendHydrostaticsQuery> queries,
                      std::span<HydrostaticsResult> results, const std::function<void()>& meanwhile) override {
    ++batches;
    return inner_->hydrostatics(surface, queries, results, [&] {
      ++meanwhileRuns;
      if (meanwhile) meanwhile();
    });
  }
  Status massProperties(std::span<const BackendBodyId> bodies, std::span<const TextureMassModel> models,
                        std::span<MassProperties> results) override {
    return inner_->massProperties(bodies, models, results);
  }
  Expected<std::unique_ptr<BackendWetting>> makeWetting(TexelAdjacency adjacency, const SurfaceTextures& textures,
                                                        const WettingSettings& settings) override {
    return inner_->makeWetting(std::move(adjacency), textures, settings);
  }
  Expected<std::unique_ptr<FloodingTexelPass>> makeFloodingPass(const LiquidGraph& graph) override {
    return inner_->makeFloodingPass(graph);
  }
  int batches = 0;
  int meanwhileRuns = 0;

 private:
  std::unique_ptr<ComputeBackend> inner_;
};

// A 1 x 0.5 x 1 m box of 500 kg/m^3 (mesh frame = centred), its drag patches and a texture body.
struct BoxWorld {
  Mesh box = primitives::box({1.0, 0.5, 1.0});
  MassProperties properties = *polyhedralMassProperties(box, 500.0);
  std::vector<DragPatch> patches;
  DragPatchSet prepared;
  double patchArea = 0.0;
  CountingBackend backend;
  BackendBodyId textureBody = 0;
  FlatSurface water{0.0, 1000.0};

  BoxWorld() {
    BodyGeometrySettings settings;
    settings.bake.width = settings.bake.height = 64;
    Expected<BodyGeometry> geometry = prepareBodyGeometry(box, settings);
    REQUIRE(geometry);
    Expected<BackendBodyId> id = backend.addBody(geometry->bake, geometry->textures, properties.centerOfMass);
    REQUIRE(id);
    textureBody = *id;
    patches = mergeTexelsIntoDragPatches(geometry->bake, geometry->textures, 0.9, 0.1);
    prepared = prepareDragPatches(patches);
    for (const DragPatch& p : patches) patchArea += p.area;
  }

  // A body at height y (m) tilted by `roll` (rad), moving; drag listed when `drag`.
  RigidBodyTask task(double y, double roll, bool texture, const DragBody* drag) const {
    RigidBodyTask t;
    t.motion.meshPose.rotation = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
    t.motion.meshPose.translation = {0.0, y, 0.0};
    t.motion.center = t.motion.meshPose.apply(properties.centerOfMass);
    t.motion.linearVelocity = {0.4, -0.3, 0.1};
    t.motion.angularVelocity = {0.2, 0.0, -0.1};
    t.motion.mass = properties.mass;
    t.motion.inertiaWorld = t.motion.meshPose.rotation * properties.inertia * t.motion.meshPose.rotation.transpose();
    t.input.gravity = {0.0, -9.81, 0.0};
    t.input.drag = drag;
    t.input.liquid = DragLiquid{&water, Eigen::Vector3d::Zero(), 1.0e-3, 2.0};
    if (texture) {
      t.backendBody = textureBody;
    } else {
      t.exactMesh = &box;
    }
    t.centerOfMass = properties.centerOfMass;
    t.boundsRadius = std::sqrt(0.5 * 0.5 + 0.25 * 0.25 + 0.5 * 0.5);
    return t;
  }

  DragBody dragBody() const {
    DragBody d;
    d.patches = patches;
    d.prepared = &prepared;
    d.totalPatchArea = patchArea;
    return d;
  }

  // What stepRigidBody gives the task alone, with its hydrostatics asked alone.
  RigidBodyStepResult alone(const RigidBodyTask& t) {
    HydrostaticsQuery query;
    query.pose = t.motion.meshPose;
    query.gravity = 9.81;
    query.centerOfMass = t.centerOfMass;
    query.time = t.input.liquid.time;
    query.mass = t.motion.mass;
    HydrostaticsResult hydrostatics;
    if (t.backendBody) {
      const BackendHydrostaticsQuery asked{*t.backendBody, query};
      REQUIRE(backend.hydrostatics(water, std::span(&asked, 1), std::span(&hydrostatics, 1)));
    } else {
      hydrostatics = *polyhedralHydrostaticsUnchecked(box, water, query);
    }
    RigidBodyStepInput input = t.input;
    input.hydrostatics = &hydrostatics;
    Expected<RigidBodyStepResult> stepped = stepRigidBody(t.motion, input, kDt);
    REQUIRE(stepped);
    return *stepped;
  }
};

bool sameBits(const RigidBodyStepResult& a, const RigidBodyStepResult& b) {
  return a.velocities.linear == b.velocities.linear && a.velocities.angular == b.velocities.angular &&
         a.drag.force == b.drag.force && a.drag.torque == b.drag.torque && a.addedMass == b.addedMass &&
         a.atRest == b.atRest;
}

}  // namespace

TEST_CASE("each body gets what stepRigidBody gives it alone", "[step][bodies]") {
  BoxWorld world;
  const DragBody drag = world.dragBody();
  // A texture body and an exact one, each with and without drag, at a draft and tilt of their own.
  std::vector<RigidBodyTask> tasks = {world.task(-0.05, 0.1, true, nullptr), world.task(0.02, -0.2, true, &drag),
                                      world.task(-0.1, 0.3, false, nullptr), world.task(0.0, 0.05, false, &drag)};
  tasks[1].backendBody.reset();  // a texture id may be asked once per batch: this one runs exact too
  tasks[1].exactMesh = &world.box;
  tasks[3].input.addedMassCoefficient = 0.5;
  std::vector<RigidBodyTaskResult> results(tasks.size());
  RigidBodiesStep stepper;
  const RigidBodiesStepStatistics statistics = stepper.run(world.backend, world.water, tasks, results, {}, kDt);
  CHECK(statistics.backendBatches == 1);  // the one texture body, one batch
  CHECK(world.backend.batches == 1);
  CHECK(world.backend.meanwhileRuns == 1);  // the drag ran once, while the batch was in flight
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    INFO("body " << i);
    REQUIRE(results[i].plan == RigidBodyPlan::Computed);
    REQUIRE(results[i].step);
    // The same operations in the same order: equal to the last bit.
    CHECK(sameBits(*results[i].step, world.alone(tasks[i])));
    CHECK(results[i].counters.hydrostaticsQueries == 1);
    CHECK(results[i].counters.failedQueries == 0);
    CHECK(results[i].counters.dragPasses == (tasks[i].input.drag != nullptr ? 1u : 0u));
    CHECK(results[i].counters.addedMassUpdates == (i == 3 ? 1u : 0u));
    CHECK(results[i].hydrostatics.submergedVolume > 0.0);
  }
  CHECK(results[1].counters.dragPatchesVisited > 0);
  CHECK(results[3].step->addedMass > 0.0);
}

TEST_CASE("the plan: free fall above the liquid, nothing for sleeping or static bodies", "[step][bodies]") {
  BoxWorld world;
  std::vector<RigidBodyTask> tasks = {world.task(5.0, 0.4, true, nullptr), world.task(-0.05, 0.0, true, nullptr),
                                      world.task(-0.05, 0.0, false, nullptr)};
  tasks[1].active = false;   // asleep in still water
  tasks[2].dynamic = false;  // static
  std::vector<RigidBodyTaskResult> results(tasks.size());
  RigidBodiesStep stepper;
  const RigidBodiesStepStatistics statistics = stepper.run(world.backend, world.water, tasks, results, {}, kDt);
  CHECK(statistics.backendBatches == 0);  // nobody to ask
  CHECK(world.backend.batches == 0);
  // Above the water: v' = v + g dt exactly (one double operation per component), w unchanged.
  REQUIRE(results[0].plan == RigidBodyPlan::OutOfLiquid);
  REQUIRE(results[0].step);
  CHECK(results[0].step->velocities.linear == tasks[0].motion.linearVelocity + kDt * tasks[0].input.gravity);
  CHECK(results[0].step->velocities.angular == tasks[0].motion.angularVelocity);
  CHECK(results[0].counters.hydrostaticsQueries == 0);
  CHECK(results[1].plan == RigidBodyPlan::Asleep);
  CHECK_FALSE(results[1].step);
  CHECK(results[2].plan == RigidBodyPlan::Static);
  CHECK_FALSE(results[2].step);
  // A current moves the liquid past a sleeping body: it is computed.
  tasks[1].input.liquid.current = {0.5, 0.0, 0.0};
  stepper.run(world.backend, world.water, tasks, results, {}, kDt);
  CHECK(results[1].plan == RigidBodyPlan::Computed);
  CHECK(world.backend.batches == 1);
}

TEST_CASE("a failed batch is asked body by body: one bad body costs the others nothing", "[step][bodies]") {
  BoxWorld world;
  Mesh second = primitives::box({1.0, 0.5, 1.0});
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = 64;
  Expected<BodyGeometry> geometry = prepareBodyGeometry(second, settings);
  REQUIRE(geometry);
  Expected<BackendBodyId> other = world.backend.addBody(geometry->bake, geometry->textures, world.properties.centerOfMass);
  REQUIRE(other);
  std::vector<RigidBodyTask> tasks = {world.task(-0.05, 0.1, true, nullptr), world.task(-0.05, 0.1, true, nullptr)};
  tasks[1].backendBody = *other;
  tasks[1].motion.mass = std::numeric_limits<double>::quiet_NaN();  // an invalid query
  std::vector<RigidBodyTaskResult> results(tasks.size());
  RigidBodiesStep stepper;
  const RigidBodiesStepStatistics statistics = stepper.run(world.backend, world.water, tasks, results, {}, kDt);
  CHECK(statistics.backendBatches == 3);    // the batch, then each body alone
  CHECK(world.backend.meanwhileRuns == 3);  // once per call, whatever its outcome
  REQUIRE(results[0].step);
  CHECK(sameBits(*results[0].step, world.alone(tasks[0])));
  CHECK(results[0].counters.failedQueries == 0);
  CHECK(results[1].counters.failedQueries >= 1);
}

TEST_CASE("the same bits for any thread count and order", "[step][bodies]") {
  BoxWorld world;
  const DragBody drag = world.dragBody();
  std::vector<RigidBodyTask> tasks;
  for (int i = 0; i < 12; ++i) tasks.push_back(world.task(-0.2 + 0.03 * i, 0.1 * i, i % 3 == 0, i % 2 == 0 ? &drag : nullptr));
  // Each texture id once per batch: only body 0 keeps the texture path.
  for (std::size_t i = 1; i < tasks.size(); ++i) {
    tasks[i].backendBody.reset();
    tasks[i].exactMesh = &world.box;
  }
  std::vector<RigidBodyTaskResult> serial(tasks.size()), threaded(tasks.size());
  RigidBodiesStep stepper;
  stepper.run(world.backend, world.water, tasks, serial, {}, kDt);
  // Two threads, each taking every other index from the end: another order, other threads.
  const ParallelFor twoThreads = [](std::size_t count, const std::function<void(std::size_t)>& work) {
    std::thread other([&] {
      for (std::size_t i = count; i-- > 0;)
        if (i % 2 == 1) work(i);
    });
    for (std::size_t i = count; i-- > 0;)
      if (i % 2 == 0) work(i);
    other.join();
  };
  stepper.run(world.backend, world.water, tasks, threaded, twoThreads, kDt);
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    INFO("body " << i);
    REQUIRE(serial[i].step);
    REQUIRE(threaded[i].step);
    CHECK(sameBits(*serial[i].step, *threaded[i].step));
  }
}

namespace {

// peers_waves' three Gerstner waves (data/scenes/peers_waves.json), counting the jets asked of them.
class CountingWaves final : public LiquidSurface {
 public:
  GerstnerWaves waves{{GerstnerWave{0.10, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                       GerstnerWave{0.05, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5},
                       GerstnerWave{0.02, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3}},
                      0.0, 1000.0};
  mutable std::size_t jets = 0;

  double surfaceHeight(double x, double z, double time) const override { return waves.surfaceHeight(x, z, time); }
  void surfaceHeights(std::span<const double> x, std::span<const double> z, double time,
                      std::span<double> out) const override {
    waves.surfaceHeights(x, z, time, out);
  }
  Eigen::Vector3d velocity(const Eigen::Vector3d& p, double time) const override { return waves.velocity(p, time); }
  Eigen::Vector3d velocityBelow(const Eigen::Vector3d& p, double surface, double time) const override {
    return waves.velocityBelow(p, surface, time);
  }
  void velocitiesBelow(std::span<const Eigen::Vector3d> points, std::span<const double> surfaces, double time,
                       std::span<Eigen::Vector3d> out) const override {
    waves.velocitiesBelow(points, surfaces, time, out);
  }
  double density() const override { return waves.density(); }
  std::pair<double, double> heightRange(double time) const override { return waves.heightRange(time); }
  std::optional<SurfaceJet> heightJet(double x, double z, double time) const override {
    ++jets;
    return waves.heightJet(x, z, time);
  }
  void heightJets(std::span<const double> x, std::span<const double> z, double time,
                  std::span<std::optional<SurfaceJet>> out) const override {
    jets += x.size();
    waves.heightJets(x, z, time, out);
  }
  std::optional<SurfaceSmoothness> smoothness(double time) const override { return waves.smoothness(time); }
  Status validate() const override { return waves.validate(); }
};

}  // namespace

TEST_CASE("under waves an exact body's drag reads the jets its query sampled", "[step][bodies][waves]") {
  // A prepared box on the exact path under three waves: its query samples a grid of surface jets
  // (~150 ns each) for its local models; its drag, summed after it, interpolates the heights
  // above its patches from that grid instead of sampling a grid of its own.
  BoxWorld world;
  const DragBody drag = world.dragBody();
  CountingWaves sea;
  const Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(world.box));
  REQUIRE(prepared);
  RigidBodiesStep stepper;
  for (int pose = 0; pose < 4; ++pose) {
    INFO("pose " << pose);
    RigidBodyTask task = world.task(-0.05 + 0.04 * pose, 0.15 * pose - 0.2, false, nullptr);
    task.exactMesh = nullptr;
    task.exactPrepared = &*prepared;
    task.input.liquid = DragLiquid{&sea, Eigen::Vector3d::Zero(), 1.0e-3, 1.3 + 0.7 * pose};
    std::vector<RigidBodyTaskResult> results(1);

    sea.jets = 0;
    stepper.run(world.backend, sea, std::span(&task, 1), results, {}, kDt);
    const std::size_t buoyancyJets = sea.jets;
    REQUIRE(results[0].step);

    task.input.drag = &drag;
    sea.jets = 0;
    stepper.run(world.backend, sea, std::span(&task, 1), results, {}, kDt);
    const std::size_t bothJets = sea.jets;
    REQUIRE(results[0].step);
    CHECK(results[0].counters.dragPasses == 1);
    CHECK(results[0].counters.dragPatchesVisited > 0);

    sea.jets = 0;
    const DragLoads own = rigidBodyDrag(drag, task.motion, task.input.liquid, kDt);
    const std::size_t dragAloneJets = sea.jets;
    // The drag alone samples a grid of its own (tens of jets); after the query it asks none.
    CHECK(dragAloneJets >= 10);
    CHECK(bothJets == buoyancyJets);
    // Both grids interpolate the surface within the drag's height error (1e-4 m; the query's
    // within a thirtieth of its model tolerance, 3.3e-5 m): a patch's wet fraction, a ramp as
    // wide as its radius (0.1 m here), moves by at most 1.3e-4 / 0.2, and the orbital velocity
    // below the surface, exp(k (y - eta)), by k 1.3e-4 (k <= 2.7 1/m): under 1e-3 of the force,
    // and of the torque with that force's share at a lever of 1 m (the box reaches 0.75 m).
    const DragLoads& shared = results[0].step->drag;
    CHECK((shared.force - own.force).norm() <= 1e-3 * own.force.norm());
    CHECK((shared.torque - own.torque).norm() <= 1e-3 * own.torque.norm() + 1e-3 * own.force.norm());
    CHECK(shared.force != own.force);  // the heights came from another grid
  }
}

TEST_CASE("under waves a box body takes its rule on its faces, and its drag the rule's jets and nodes",
          "[step][bodies][waves][box]") {
  // A body marked as a box (RigidBodyTask::boxHalfExtents, a btBoxShape's in the controller) under
  // three waves: its hydrostatics are the rule's (BoxHydrostaticsWaves.cpp), bit for bit, not its
  // prepared mesh's, and its drag asks the surface for no jets beyond the rule's grid and sums its
  // law on the rule's drag nodes. Where the
  // rule declines (the top face level with the surface) the prepared mesh answers.
  BoxWorld world;
  const DragBody drag = world.dragBody();
  CountingWaves sea;
  const Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(world.box));
  REQUIRE(prepared);
  RigidBodiesStep stepper;
  const Eigen::Vector3d half(0.5, 0.25, 0.5);
  // The query the step makes of a task (RigidBodiesStep.cpp's queryOf).
  const auto queryOfTask = [](const RigidBodyTask& task) {
    HydrostaticsQuery query;
    query.pose = task.motion.meshPose;
    query.centerOfMass = task.centerOfMass;
    query.gravity = -task.input.gravity.y();
    query.time = task.input.liquid.time;
    query.mass = task.motion.mass;
    return query;
  };
  for (int pose = 0; pose < 4; ++pose) {
    INFO("pose " << pose);
    RigidBodyTask task = world.task(-0.05 + 0.03 * pose, 0.05 * pose - 0.1, false, &drag);
    task.exactMesh = nullptr;
    task.exactPrepared = &*prepared;
    task.boxHalfExtents = half;
    task.input.liquid = DragLiquid{&sea, Eigen::Vector3d::Zero(), 1.0e-3, 1.3 + 0.7 * pose};
    std::vector<RigidBodyTaskResult> results(1);
    sea.jets = 0;
    stepper.run(world.backend, sea, std::span(&task, 1), results, {}, kDt);
    REQUIRE(results[0].step);
    const std::size_t stepJets = sea.jets;
    const HydrostaticsQuery query = queryOfTask(task);
    sea.jets = 0;
    const auto rule = detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), sea, query);
    REQUIRE(rule);
    REQUIRE(*rule);
    CHECK(sea.jets == stepJets);  // the drag read the rule's grid
    // ... and summed its law on the rule's drag nodes, not on the box mesh's patches.
    std::vector<detail::WettedNode> nodes;
    REQUIRE(detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), sea, query, nullptr, {}, nullptr, &nodes));
    const DragLoads onNodes = detail::rigidBodyDragOnNodes(drag, task.motion, task.input.liquid, kDt, nodes);
    CHECK(results[0].step->drag.force == onNodes.force);
    CHECK(results[0].counters.dragPatchesVisited == nodes.size());
    CHECK(results[0].hydrostatics.buoyancyForce == (*rule)->buoyancyForce);
    CHECK(results[0].hydrostatics.torqueAboutCenterOfMass == (*rule)->torqueAboutCenterOfMass);
    const Expected<HydrostaticsResult> mesh = polyhedralHydrostatics(*prepared, sea, query);
    REQUIRE(mesh);
    CHECK(results[0].hydrostatics.buoyancyForce != mesh->buoyancyForce);
    CHECK(results[0].counters.dragPasses == 1);
  }
  // Declined: the prepared mesh's answer.
  RigidBodyTask task = world.task(0.0, 0.0, false, nullptr);
  task.exactMesh = nullptr;
  task.exactPrepared = &*prepared;
  task.boxHalfExtents = half;
  task.input.liquid = DragLiquid{&sea, Eigen::Vector3d::Zero(), 1.0e-3, 0.0};
  task.motion.meshPose.translation = {1.0, sea.surfaceHeight(1.0, 2.0, 0.0) - 0.25, 2.0};
  task.motion.center = task.motion.meshPose.apply(task.centerOfMass);
  std::vector<RigidBodyTaskResult> results(1);
  stepper.run(world.backend, sea, std::span(&task, 1), results, {}, kDt);
  REQUIRE(results[0].step);
  const HydrostaticsQuery query = queryOfTask(task);
  CHECK_FALSE(detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), sea, query).has_value());
  const Expected<HydrostaticsResult> mesh = polyhedralHydrostatics(*prepared, sea, query);
  REQUIRE(mesh);
  CHECK(results[0].hydrostatics.buoyancyForce == mesh->buoyancyForce);
}
