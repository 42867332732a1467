// SPDX-License-Identifier: Zlib
// The buoyancy controller on every backend from one test body (issue 18): the CPU backend and
// the GL compute backend (llvmpipe on CI) float the same bodies along the same trajectories,
// read their results back once per step, cost nothing for effects a body does not list, and
// serve every effect (wetting and flooding's texel pass on the GPU). Short scenes: llvmpipe is slow.
// Without an EGL context the GL sections fail (REQUIRE), as the tests/gpu suites do.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "../plugin/PluginTestWorld.hpp"
#include "hydrotex/gpu/MakeBackend.hpp"

using namespace hydrotex;
using hydrotex::bullet::ControllerSettings;
using hydrotex::bullet::HydrostaticsMethod;
using hydrotex::bullet::ControllerStatistics;
using hydrotex::bullet::Effect;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

namespace {

/// A controller's settings on the backend named `name` ("cpu": the controller's own).
ControllerSettings onBackend(const std::string& name) {
  ControllerSettings settings;
  settings.threads = 1;
  if (name == "gpu") {
    Expected<std::unique_ptr<ComputeBackend>> gl = gpu::makeBackend("gpu");
    REQUIRE(gl);  // no headless EGL context: this suite cannot check the GL backend
    settings.backend = std::move(gl).value();
  }
  return settings;
}

/// Heights (m) of a 1 x 0.5 x 1 m box of density 500 dropped 0.1 m above its draft, per step.
struct Run {
  std::vector<double> heights;
  ControllerStatistics statistics;
  std::string backend;
};

Run dropBox(const std::string& backend, int steps) {
  TestWorld world(std::make_shared<FlatSurface>(0.0, 1000.0), 1.0e-3, onBackend(backend));
  const Mesh box = primitives::box({1, 0.5, 1});
  // A plain body (no effects) beside it: it must cost nothing on either backend.
  btRigidBody* plain = world.add(box, solid(500, {}, HydrostaticsMethod::Texture, 64), btVector3(3, 0, 0));
  btRigidBody* body = world.add(box, solid(500, {Effect::Buoyancy, Effect::Drag}, HydrostaticsMethod::Texture, 64),
                                btVector3(0, btScalar(0.1), 0));
  REQUIRE(plain != nullptr);
  REQUIRE(body != nullptr);
  Run run;
  run.backend = world.controller().backend().name();
  for (int i = 0; i < steps; ++i) {
    world.step(1.0 / 60.0);
    run.heights.push_back(double(body->getCenterOfMassPosition().y()));
  }
  run.statistics = world.controller().statistics();
  return run;
}

}  // namespace

TEST_CASE("every backend floats a box along the same trajectory, one read-back per step", "[backends][controller]") {
  const int steps = 120;  // 2 s at 60 Hz: the drop, the first bounces and most of the settling
  const Run cpu = dropBox("cpu", steps);
  const Run gl = dropBox("gpu", steps);
  CHECK(cpu.backend == "cpu");
  CHECK(gl.backend == "gpu");
  // The GL backend sums its texels in float (relative rounding ~1e-7 per term) where the CPU
  // sums in double: the buoyancy differs by ~1e-6 of the weight, and Bullet's float positions
  // round at ~1e-8 m near 0. Measured: 1.5e-8 m over the 120 steps (llvmpipe). 1e-6 m leaves
  // room for another GPU's summation order (a few float ulps of the sums) and catches a wrong
  // pose, frame or waterline (mm and up).
  double worst = 0.0;
  for (int i = 0; i < steps; ++i) worst = std::max(worst, std::abs(cpu.heights[std::size_t(i)] - gl.heights[std::size_t(i)]));
  INFO("largest height difference CPU vs GL: " << worst << " m");
  CHECK(worst < 1e-6);
  // Still settling towards the closed-form draft: the centre of mass of a half-density box sits at
  // the waterline (0 m); after 2 s with drag it is within 2 cm of it on both backends.
  CHECK(std::abs(cpu.heights.back()) < 0.02);
  CHECK(std::abs(gl.heights.back()) < 0.02);
  for (const Run* run : {&cpu, &gl}) {
    INFO("backend " << run->backend);
    // Each backend is asked once per step and read back once (one batch); only the buoyant body
    // is in it: the plain body costs no query, no drag pass and no added mass.
    CHECK(run->statistics.backendBatches == std::uint64_t(steps));
    CHECK(run->statistics.hydrostaticsQueries == std::uint64_t(steps));
    CHECK(run->statistics.dragPasses == std::uint64_t(steps));
    CHECK(run->statistics.addedMassUpdates == 0);
    CHECK(run->statistics.failedQueries == 0);
  }
}

TEST_CASE("the GL backend serves every effect", "[backends][controller]") {
  TestWorld world(std::make_shared<FlatSurface>(0.0, 1000.0), 1.0e-3, onBackend("gpu"));
  const Mesh box = primitives::box({1, 0.5, 1});
  CHECK(world.add(box, solid(500, {Effect::Buoyancy, Effect::Drag, Effect::AddedMass, Effect::VariableMass, Effect::Wetting},
                             HydrostaticsMethod::Texture, 32),
                  btVector3(0, 0, 0)) != nullptr);
  CHECK(world.add(box, solid(500, {Effect::Buoyancy, Effect::Flooding}, HydrostaticsMethod::Texture, 32),
                  btVector3(3, 0, 0)) != nullptr);
  for (int i = 0; i < 5; ++i) world.step(1.0 / 60.0);
  CHECK(world.controller().statistics().failedQueries == 0);
}

TEST_CASE("a body's liquid texture soaks the same on every backend", "[backends][controller][wetting]") {
  // A box floating at its draft for 1 s with wetting: the GL backend steps its liquid texture with
  // GlWetting, the CPU one with core's Wetting. GlWetting equals Wetting to 1e-6 of the capacity
  // per texel (tests/gpu/test_wetting_gl); the bodies' motions agree to ~1e-8 m (above), so the
  // absorbed volumes and the texels' liquid agree to that order. Measured 3.9e-8 of the capacity
  // per texel; bounds 1e-6 of the capacity per texel (as the GL wetting suite) and 1e-5 relative
  // on the volumes.
  std::vector<double> absorbed, held;
  std::vector<std::size_t> wettingSteps;
  std::vector<std::vector<float>> liquid;
  double capacity = 0.0;
  for (const std::string backend : {"cpu", "gpu"}) {
    TestWorld world(std::make_shared<FlatSurface>(0.0, 1000.0), 1.0e-3, onBackend(backend));
    bullet::FloatingBodySettings wet = solid(500, {Effect::Buoyancy, Effect::Wetting}, HydrostaticsMethod::Texture, 32);
    wet.wetting.physics.diffusivity = 1e-7;
    btRigidBody* body = world.add(primitives::box({1, 0.5, 1}), wet, btVector3(0, 0, 0));
    REQUIRE(body != nullptr);
    for (int i = 0; i < 60; ++i) world.step(1.0 / 60.0);
    CHECK(world.controller().statistics().failedQueries == 0);
    const bullet::FloatingBodyReport& report = *world.controller().report(body);
    absorbed.push_back(report.liquidAbsorbed);
    held.push_back(report.liquidHeld);
    wettingSteps.push_back(world.controller().statistics().wettingSteps);
    // The texture the controller hands out is the backend's liquid (copied back each step).
    const LiquidTexture& texture = *world.controller().liquidTexture(body);
    liquid.push_back(texture.liquid);
    capacity = texture.capacity.empty() ? 0.0 : double(*std::max_element(texture.capacity.begin(), texture.capacity.end()));
  }
  REQUIRE(liquid[0].size() == liquid[1].size());
  double worst = 0.0;
  for (std::size_t i = 0; i < liquid[0].size(); ++i) worst = std::max(worst, double(std::abs(liquid[0][i] - liquid[1][i])));
  CAPTURE(worst / capacity);
  CHECK(worst <= 1e-6 * capacity);
  CAPTURE(absorbed[0], absorbed[1]);
  CHECK(absorbed[0] > 0.0);
  CHECK(absorbed[1] == Approx(absorbed[0]).epsilon(1e-5));
  CHECK(held[1] == Approx(held[0]).epsilon(1e-5));
  CHECK(wettingSteps[0] == 60);
  CHECK(wettingSteps[1] == 60);
}

TEST_CASE("a flooding body takes on the same liquid on every backend", "[backends][controller][flooding]") {
  // A 1 x 0.5 x 1 m box of density 500 with permeable walls floats at its draft and takes on
  // water for 1 s. The GL backend sums Darcy's law over the permeable texels on the GPU
  // (flooding_texels.comp), the CPU backend in the graph's own loop, both in float; the level
  // solve is the same double code. Float sums of ~1e3 texels in a different order differ by
  // ~1e-6 relative, which the implicit solve carries into the held liquid (3.7e-3 m^3 of 0.5):
  // measured 7.6e-9 relative, bound 1e-5.
  std::vector<double> held;
  for (const std::string backend : {"cpu", "gpu"}) {
    TestWorld world(std::make_shared<FlatSurface>(0.0, 1000.0), 1.0e-3, onBackend(backend));
    bullet::FloatingBodySettings leaky = solid(500, {Effect::Buoyancy, Effect::Flooding}, HydrostaticsMethod::Texture, 32);
    leaky.flooding.graph.permeability = 1.0e-11;
    leaky.flooding.graph.wallThickness = 0.01;
    btRigidBody* body = world.add(primitives::box({1, 0.5, 1}), leaky, btVector3(0, 0, 0));
    REQUIRE(body != nullptr);
    for (int i = 0; i < 60; ++i) world.step(1.0 / 60.0);
    CHECK(world.controller().statistics().failedQueries == 0);
    CHECK(world.controller().statistics().floodingSteps == 60);
    held.push_back(world.controller().report(body)->liquidVolume);
  }
  CAPTURE(held[0], held[1], held[1] / held[0] - 1.0);
  CHECK(held[0] > 0.0);
  CHECK(held[1] == Approx(held[0]).epsilon(1e-5));
}

TEST_CASE("a removed body's backend slot is not asked again", "[backends][controller]") {
  for (const std::string name : {"cpu", "gpu"}) {
    INFO(name);
    TestWorld world(std::make_shared<FlatSurface>(0.0, 1000.0), 1.0e-3, onBackend(name));
    const Mesh box = primitives::box({1, 0.5, 1});
    btRigidBody* first = world.add(box, solid(500, {Effect::Buoyancy}, HydrostaticsMethod::Texture, 32), btVector3(0, 0, 0));
    btRigidBody* second = world.add(box, solid(500, {Effect::Buoyancy}, HydrostaticsMethod::Texture, 32), btVector3(3, 0, 0));
    REQUIRE(first != nullptr);
    REQUIRE(second != nullptr);
    world.world().removeRigidBody(first);
    CHECK(world.controller().removeBody(first));
    for (int i = 0; i < 5; ++i) world.step(1.0 / 60.0);
    CHECK(world.controller().statistics().failedQueries == 0);
    CHECK(world.controller().statistics().hydrostaticsQueries == 5);
    CHECK(world.controller().report(second)->hydrostatics.submergedVolume > 0.0);
  }
}

TEST_CASE("a density map replaced every step weighs the same on every backend, one mass read-back per step",
          "[backends][controller][variable-mass]") {
  // A 1 x 0.5 x 1 m box floating with its density map replaced every step: the first half of its
  // texels (some of the atlas's charts) heavier than the rest, more so every step, so that its
  // centre of mass moves and it heels and sinks. The texel mass pass runs on the backend (one
  // batch a step): in double per block on the CPU, in float per workgroup on the GL backend.
  const int steps = 60;
  std::vector<double> masses[2], heights[2];
  for (int b = 0; b < 2; ++b) {
    const std::string backend = b == 0 ? "cpu" : "gpu";
    CAPTURE(backend);
    TestWorld world(std::make_shared<FlatSurface>(0.0, 1000.0), 1.0e-3, onBackend(backend));
    btRigidBody* body = world.add(primitives::box({1, 0.5, 1}),
                                  solid(500, {Effect::Buoyancy, Effect::Drag, Effect::VariableMass}, HydrostaticsMethod::Texture, 32),
                                  btVector3(0, 0, 0));
    REQUIRE(body != nullptr);
    MassModel* model = world.controller().massModel(body);
    REQUIRE(model != nullptr);
    std::vector<float> map;
    for (int i = 0; i < steps; ++i) {
      map.assign(model->texelCount(), 400.0f);
      std::fill(map.begin(), map.begin() + std::ptrdiff_t(map.size() / 2), float(500 + 5 * i));
      REQUIRE(model->swapTexelDensity(map).ok());
      world.step(1.0 / 60.0);
      masses[b].push_back(world.controller().report(body)->massProperties.mass);
      heights[b].push_back(double(body->getCenterOfMassPosition().y()));
    }
    const ControllerStatistics& statistics = world.controller().statistics();
    CHECK(statistics.massBatches == std::uint64_t(steps));      // one batch a step, read back once
    CHECK(statistics.massBatchBodies == std::uint64_t(steps));
    CHECK(statistics.massTexelPasses == std::uint64_t(steps));
    CHECK(statistics.failedQueries == 0);
  }
  // The masses: the GL sums' float rounding, within the backends' mass parity (1e-5 relative,
  // tests/gpu/test_backend_parity.cpp). The heights: the mass and the buoyancy each differ by
  // that rounding (~1e-6 of the weight), which moves the box by ~1e-6 of its draft per step;
  // 1e-5 m over 60 steps leaves room for the accumulation and catches a wrong map, a stale mass
  // or a pass run on another body's texels (the map's change moves the box by cm). Measured
  // (llvmpipe): 2.6e-7 of the mass, 7.5e-8 m.
  double worstMass = 0.0, worstHeight = 0.0;
  for (int i = 0; i < steps; ++i) {
    worstMass = std::max(worstMass, std::abs(masses[1][std::size_t(i)] / masses[0][std::size_t(i)] - 1.0));
    worstHeight = std::max(worstHeight, std::abs(heights[1][std::size_t(i)] - heights[0][std::size_t(i)]));
  }
  INFO("largest relative mass difference " << worstMass << ", height difference " << worstHeight << " m");
  CHECK(worstMass < 1e-5);
  CHECK(worstHeight < 1e-5);
  // The map did change the body: heavier every step (the map's mean density rose by 2.5 x 59 kg/m^3).
  CHECK(masses[0].back() > masses[0].front() + 0.2 * 2.5 * 59.0 * 0.5);
}
