// SPDX-License-Identifier: Zlib
// Determinism: the same scene run twice gives bit-identical results on the CPU backend, through
// the API (every body's state compared bit for bit after every step) and through
// `hydrotex simulate` (the CSV files compared byte for byte), and so does the same scene run on
// 1, 2 and 8 threads (ControllerSettings::threads), work counters included. A difference would
// come from uninitialised memory, iteration over pointer-keyed containers, a thread race in a
// reduction, or a body's numbers that depend on another body's or on the order they are computed.

#include <btBulletDynamicsCommon.h>

#include <LinearMath/btThreads.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "TestPaths.hpp"
#include "ToolRun.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bullet/Scene.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::test::outputPath;
using hydrotex::test::readFile;
using hydrotex::test::sourcePath;

namespace {

/// Every body's position, orientation and velocities after each step, as raw floats; the
/// controller's work counters at the end in `statistics` when given.
std::vector<btScalar> trajectory(const bullet::Scene& scene, long long steps,
                                 bullet::ControllerStatistics* statistics = nullptr) {
  auto created = bullet::SceneWorld::create(scene);
  INFO((created ? std::string() : created.error().message));
  REQUIRE(created.ok());
  bullet::SceneWorld& world = **created;
  std::vector<btScalar> states;
  for (long long i = 0; i < steps; ++i) {
    world.step();
    for (const btRigidBody* body : world.bodies()) {
      const btTransform& t = body->getCenterOfMassTransform();
      const btQuaternion q = t.getRotation();
      const btVector3 v = body->getLinearVelocity(), w = body->getAngularVelocity();
      for (btScalar value : {t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z(), q.x(), q.y(), q.z(), q.w(), v.x(),
                             v.y(), v.z(), w.x(), w.y(), w.z()})
        states.push_back(value);
    }
  }
  if (statistics != nullptr) *statistics = world.controller().statistics();
  return states;
}

/// The scene with its controller on `threads` threads.
bullet::Scene withThreads(bullet::Scene scene, int threads) {
  scene.threads = threads;
  return scene;
}

/// Twelve bodies in waves, each taking another branch of a step: texture and polyhedral
/// hydrostatics, drag, added mass, a moving point mass (variable mass), scale keyframes
/// (deformation), a liquid texture (wetting), a body that starts in the air (free fall) and
/// one that lists no effect.
bullet::Scene mixedScene() {
  bullet::Scene scene;
  scene.sourceName = "mixed";
  scene.dt = 1.0 / 60.0;
  scene.surface.type = bullet::SceneSurface::Type::Waves;
  scene.surface.waves = {GerstnerWave{0.15, 8.0, Eigen::Vector2d(1.0, 0.3), 0.2, 0.4}};
  auto box = std::make_shared<const Mesh>(primitives::box({1.0, 0.5, 0.7}));
  for (int i = 0; i < 12; ++i) {
    bullet::SceneBody body;
    body.name = "body" + std::to_string(i);
    body.mesh = box;
    body.density = 350.0 + 40.0 * i;
    body.position = Eigen::Vector3d(2.5 * (i % 4), 0.1 * (i % 3), 2.5 * (i / 4));
    body.rotationDegrees = Eigen::Vector3d(5.0 * (i % 3), 20.0 * i, 3.0 * (i % 2));
    body.resolution = 32;
    body.effects = EffectSet{Effect::Buoyancy, Effect::Drag};
    switch (i) {
      case 1: body.method = HydrostaticsMethod::Polyhedral; break;
      case 2: body.effects = EffectSet{Effect::Buoyancy, Effect::Drag, Effect::AddedMass}; break;
      case 3:
        body.effects = EffectSet{Effect::Buoyancy, Effect::Drag, Effect::VariableMass};
        body.pointMasses = {PointMass{40.0, Eigen::Vector3d::Zero(),
                                      {PathKeyframe{0.0, Eigen::Vector3d(-0.3, 0, 0)}, PathKeyframe{2.0, Eigen::Vector3d(0.3, 0, 0)}}}};
        break;
      case 4:
        body.effects = EffectSet{Effect::Buoyancy, Effect::Deformation};
        body.scaleKeyframes = {bullet::ScaleKeyframe{0.0, Eigen::Vector3d::Ones()},
                               bullet::ScaleKeyframe{2.0, Eigen::Vector3d(1.2, 1.0, 1.1)}};
        break;
      case 5: body.effects = EffectSet{Effect::Buoyancy, Effect::Drag, Effect::Wetting}; break;
      case 6: body.position.y() = 3.0; break;  // falls in from the air
      case 7: body.effects = EffectSet{}; break;
      default: break;
    }
    scene.bodies.push_back(body);
  }
  return scene;
}

/// Every counter of `statistics`, in declaration order.
std::vector<std::uint64_t> counters(const bullet::ControllerStatistics& s) {
  return {s.steps, s.hydrostaticsQueries, s.dragPasses, s.dragPatchesVisited, s.addedMassUpdates,
          s.skippedOutOfLiquid, s.skippedAsleep, s.failedQueries, s.massUpdates, s.massTexelPasses,
          s.deformations, s.floodingSteps, s.permeableTexelsVisited, s.wettingSteps, s.massBatches, s.massBatchBodies};
}

/// A Bullet task scheduler with two threads (as a BT_THREADSAFE Bullet's would be): the first
/// half of each range on a std::thread, the rest on the caller. Counts the ranges it was given.
class TwoThreadScheduler final : public btITaskScheduler {
 public:
  TwoThreadScheduler() : btITaskScheduler("two threads (test)") {}
  int getMaxNumThreads() const override { return 2; }
  int getNumThreads() const override { return 2; }
  void setNumThreads(int) override {}
  void parallelFor(int begin, int end, int, const btIParallelForBody& body) override {
    ++calls;
    const int middle = begin + (end - begin) / 2;
    std::thread first([&] { body.forLoop(begin, middle); });
    body.forLoop(middle, end);
    first.join();
  }
  btScalar parallelSum(int begin, int end, int, const btIParallelSumBody& body) override {
    return body.sumLoop(begin, end);
  }
  std::atomic<int> calls{0};
};

}  // namespace

TEST_CASE("the same scene twice gives bit-identical trajectories", "[robustness][determinism]") {
  const std::string file = GENERATE(as<std::string>{}, "log_waves.json", "log_cargo.json", "box_floating.json");
  CAPTURE(file);
  const Expected<bullet::Scene> scene = bullet::loadScene(sourcePath("data/scenes/" + file));
  INFO((scene ? std::string() : scene.error().message));
  REQUIRE(scene.ok());
  const long long steps = std::min<long long>(scene->stepCount(), 600);
  const std::vector<btScalar> first = trajectory(*scene, steps);
  const std::vector<btScalar> second = trajectory(*scene, steps);
  REQUIRE(first.size() == second.size());
  REQUIRE(!first.empty());
  // Bitwise, not ==: a NaN must compare equal to itself, and -0 must not pass for +0.
  CHECK(std::memcmp(first.data(), second.data(), first.size() * sizeof(btScalar)) == 0);
}

#ifdef HYDROTEX_TOOL_PATH
TEST_CASE("hydrotex simulate writes byte-identical CSV twice", "[robustness][determinism][tool]") {
  using hydrotex::test::runTool;
  for (const std::string file : {"log_waves.json", "log_cargo.json"}) {
    CAPTURE(file);
    const std::string scene = sourcePath("data/scenes/" + file);
    std::string csv[2];
    for (int run = 0; run < 2; ++run) {
      const std::string path = outputPath("robust_determinism_" + std::to_string(run) + "_" + file + ".csv");
      const test::ToolRun result = runTool("simulate " + scene + " --csv " + path, 300);
      INFO(result.err);
      REQUIRE(result.exitCode == 0);
      csv[run] = readFile(path);
    }
    REQUIRE(csv[0].size() > 1000);  // a real trajectory, not an empty file
    CHECK(csv[0] == csv[1]);
  }
}
#endif

TEST_CASE("1, 2 and 8 threads give bit-identical trajectories and work counters", "[robustness][determinism][threads]") {
  std::vector<std::pair<std::string, bullet::Scene>> scenes = {{"mixed (12 bodies, every effect branch)", mixedScene()}};
  for (const std::string file : {"box_floating.json", "log_waves.json", "wet_ball.json"}) {
    const Expected<bullet::Scene> scene = bullet::loadScene(sourcePath("data/scenes/" + file));
    INFO((scene ? std::string() : scene.error().message));
    REQUIRE(scene.ok());
    scenes.emplace_back(file, *scene);
  }
  for (const auto& [name, scene] : scenes) {
    CAPTURE(name);
    // 240 steps: several seconds of settling, sleeping (the flat water) and wetting.
    const long long steps = std::min<long long>(scene.stepCount(), 240);
    bullet::ControllerStatistics serialCounters;
    const std::vector<btScalar> serial = trajectory(withThreads(scene, 1), steps, &serialCounters);
    REQUIRE(!serial.empty());
    REQUIRE(serialCounters.steps > 0);
    for (int threads : {2, 8}) {
      CAPTURE(threads);
      bullet::ControllerStatistics parallelCounters;
      const std::vector<btScalar> parallel = trajectory(withThreads(scene, threads), steps, &parallelCounters);
      REQUIRE(parallel.size() == serial.size());
      // Bitwise, not ==: a NaN must compare equal to itself, and -0 must not pass for +0.
      CHECK(std::memcmp(parallel.data(), serial.data(), serial.size() * sizeof(btScalar)) == 0);
      CHECK(counters(parallelCounters) == counters(serialCounters));
    }
  }
}

/// Four soft balls of different masses and one rigid box in waves, with buoyancy and drag: every
/// soft body's nodes (positions and velocities) after each step, as raw floats, then the rigid
/// box's state; the work counters in `statistics`.
std::vector<btScalar> softTrajectory(int threads, long long steps, bullet::ControllerStatistics* statistics) {
  bullet::Scene scene;
  scene.sourceName = "soft";
  scene.dt = 1.0 / 120.0;
  scene.threads = threads;
  scene.surface.type = bullet::SceneSurface::Type::Waves;
  scene.surface.waves = {GerstnerWave{0.1, 6.0, Eigen::Vector2d(1.0, 0.2), 0.1, 0.3}};
  auto ball = std::make_shared<const Mesh>(primitives::uvSphere(0.25, 16, 8));
  for (int i = 0; i < 4; ++i) {
    bullet::SceneBody body;
    body.name = "soft" + std::to_string(i);
    body.mesh = ball;
    body.soft = true;
    body.mass = 10.0 + 12.0 * i;
    body.position = Eigen::Vector3d(1.2 * i, 0.1 - 0.1 * i, 0.3 * (i % 2));
    body.resolution = 32;
    body.effects = EffectSet{Effect::Buoyancy, Effect::Drag};
    body.softMaterial.shapeMatching = 0.5;
    scene.softBodies.push_back(body);
  }
  bullet::SceneBody box;
  box.name = "box";
  box.mesh = std::make_shared<const Mesh>(primitives::box({0.8, 0.5, 0.6}));
  box.density = 450.0;
  box.position = Eigen::Vector3d(-1.5, 0.1, 0.0);
  box.resolution = 32;
  box.effects = EffectSet{Effect::Buoyancy, Effect::Drag};
  scene.bodies.push_back(box);
  auto created = bullet::SceneWorld::create(scene);
  INFO((created ? std::string() : created.error().message));
  REQUIRE(created.ok());
  bullet::SceneWorld& world = **created;
  REQUIRE(world.softBodies().size() == 4);
  std::vector<btScalar> states;
  for (long long i = 0; i < steps; ++i) {
    world.step();
    for (const btSoftBody* soft : world.softBodies())
      for (int n = 0; n < soft->m_nodes.size(); ++n) {
        const btVector3 &x = soft->m_nodes[n].m_x, &v = soft->m_nodes[n].m_v;
        for (btScalar value : {x.x(), x.y(), x.z(), v.x(), v.y(), v.z()}) states.push_back(value);
      }
    for (const btRigidBody* body : world.bodies()) {
      const btVector3& p = body->getCenterOfMassPosition();
      const btVector3& v = body->getLinearVelocity();
      for (btScalar value : {p.x(), p.y(), p.z(), v.x(), v.y(), v.z()}) states.push_back(value);
    }
  }
  *statistics = world.controller().statistics();
  return states;
}

TEST_CASE("soft bodies: 1, 2 and 8 threads give bit-identical nodes and work counters", "[robustness][determinism][threads][soft]") {
  const long long steps = 120;  // 1 s: the balls settle into the waves
  bullet::ControllerStatistics serialCounters;
  const std::vector<btScalar> serial = softTrajectory(1, steps, &serialCounters);
  REQUIRE(!serial.empty());
  // Every soft body got its pressure and drag each step.
  CHECK(serialCounters.failedQueries == 0);
  CHECK(serialCounters.dragPasses >= std::uint64_t(4 * steps));
  for (int threads : {2, 8}) {
    CAPTURE(threads);
    bullet::ControllerStatistics parallelCounters;
    const std::vector<btScalar> parallel = softTrajectory(threads, steps, &parallelCounters);
    REQUIRE(parallel.size() == serial.size());
    // Bitwise, not ==: a NaN must compare equal to itself, and -0 must not pass for +0.
    CHECK(std::memcmp(parallel.data(), serial.data(), serial.size() * sizeof(btScalar)) == 0);
    CHECK(counters(parallelCounters) == counters(serialCounters));
  }
}

TEST_CASE("the controller's thread count: 1 starts none, N at most N, 0 all cores", "[robustness][threads]") {
  bullet::Scene scene = mixedScene();
  scene.bodies.resize(2);
  auto resolved = [&](int threads) {
    auto created = bullet::SceneWorld::create(withThreads(scene, threads));
    REQUIRE(created.ok());
    return (*created)->controller().threads();
  };
  const int all = resolved(0);
  CHECK(all >= 1);
  CHECK(resolved(1) == 1);
  CHECK(resolved(2) == std::min(2, all));
  CHECK(resolved(8) == std::min(8, all));
  CHECK(resolved(1000) == all);  // never more threads than cores: they would only take turns
  // A negative count is refused by the controller's settings and by the scene, naming the value.
  bullet::ControllerSettings settings;
  settings.threads = -1;
  const Status refused = settings.validate();
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().message.find("threads: -1") != std::string::npos);
  const Status badScene = withThreads(scene, -3).validate();
  REQUIRE_FALSE(badScene.ok());
  CHECK(badScene.error().message.find("threads: -3") != std::string::npos);
}

TEST_CASE("with threads 0 the controller follows a Bullet task scheduler of several threads", "[robustness][determinism][threads]") {
  const bullet::Scene scene = mixedScene();
  const long long steps = 60;
  bullet::ControllerStatistics serialCounters, bulletCounters;
  const std::vector<btScalar> serial = trajectory(withThreads(scene, 1), steps, &serialCounters);
  btITaskScheduler* previous = btGetTaskScheduler();
  TwoThreadScheduler scheduler;
  btSetTaskScheduler(&scheduler);
  std::vector<btScalar> followed;
  int reported = 0, explicitCalls = 0;
  {
    auto created = bullet::SceneWorld::create(withThreads(scene, 0));
    REQUIRE(created.ok());
    reported = (*created)->controller().threads();
  }
  followed = trajectory(withThreads(scene, 0), steps, &bulletCounters);
  const int followedCalls = scheduler.calls;
  trajectory(withThreads(scene, 2), 5);  // an explicit count keeps oneTBB
  explicitCalls = scheduler.calls - followedCalls;
  btSetTaskScheduler(previous);
  CHECK(reported == 2);
  // One parallel phase per step went through the scheduler (Bullet's own work, in a build without
  // BT_THREADSAFE, does not call it).
  CHECK(followedCalls >= steps);
  CHECK(explicitCalls == 0);
  REQUIRE(followed.size() == serial.size());
  CHECK(std::memcmp(followed.data(), serial.data(), serial.size() * sizeof(btScalar)) == 0);
  CHECK(counters(bulletCounters) == counters(serialCounters));
}

#ifdef HYDROTEX_TOOL_PATH
TEST_CASE("hydrotex simulate writes byte-identical CSV with 1, 2 and 8 threads", "[robustness][determinism][tool][threads]") {
  using hydrotex::test::runTool;
  const std::string scene = sourcePath("data/scenes/box_floating.json");
  std::string csv[3];
  const int counts[3] = {1, 2, 8};
  for (int run = 0; run < 3; ++run) {
    CAPTURE(counts[run]);
    const std::string path = outputPath("robust_threads_" + std::to_string(counts[run]) + ".csv");
    const test::ToolRun result =
        runTool("simulate " + scene + " --csv " + path + " --threads " + std::to_string(counts[run]) + " --json", 300);
    INFO(result.err);
    REQUIRE(result.exitCode == 0);
    const nlohmann::json summary = nlohmann::json::parse(result.out);
    CHECK(summary["threads"].get<int>() >= 1);
    CHECK(summary["threads"].get<int>() <= counts[run]);
    CHECK(summary["backend"] == "cpu");
    csv[run] = readFile(path);
  }
  REQUIRE(csv[0].size() > 1000);  // a real trajectory, not an empty file
  CHECK(csv[1] == csv[0]);
  CHECK(csv[2] == csv[0]);
}

#ifdef HYDROTEX_TOOL_HAS_GPU
TEST_CASE("hydrotex simulate --backend runs the controller on the named backend", "[robustness][tool][backends]") {
  using hydrotex::test::runTool;
  const std::string scene = sourcePath("data/scenes/box_floating.json");
  nlohmann::json summary[3];
  const char* names[3] = {"cpu", "gpu", "auto"};
  for (int run = 0; run < 3; ++run) {
    CAPTURE(names[run]);
    const test::ToolRun result = runTool("simulate " + scene + " --backend " + names[run] + " --json", 300);
    INFO(result.err);
    REQUIRE(result.exitCode == 0);  // gpu: llvmpipe on CI; a machine with no EGL at all fails here
    summary[run] = nlohmann::json::parse(result.out);
  }
  CHECK(summary[0]["backend"] == "cpu");
  CHECK(summary[0]["renderer"] == "CPU");
  CHECK(summary[1]["backend"] == "gpu");
  CHECK(!summary[1]["renderer"].get<std::string>().empty());
  // auto takes a GPU only: on a software rasterizer (llvmpipe) it runs the CPU backend.
  const bool software = summary[1]["renderer"].get<std::string>().find("llvmpipe") != std::string::npos;
  if (software) CHECK(summary[2]["backend"] == "cpu");
  // The GL sums round in float (~1e-6 of the volume a step); over the scene's 10 s of a box
  // rocking on its drag the two trajectories drift apart by that rounding: measured 3.2e-5 m^3 of
  // the 0.5 m^3 submerged at the end (llvmpipe). 1e-4 m^3 (2e-4 of the volume) bounds it; a wrong
  // pose or waterline is off by 1e-2 m^3 and more.
  const double cpuVolume = summary[0]["bodies"][0]["submerged_volume"].get<double>();
  const double glVolume = summary[1]["bodies"][0]["submerged_volume"].get<double>();
  CHECK(std::abs(cpuVolume - glVolume) < 1e-4);
}
#endif  // HYDROTEX_TOOL_HAS_GPU
#endif
