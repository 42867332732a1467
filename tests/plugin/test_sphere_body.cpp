// SPDX-License-Identifier: Zlib
// A true sphere (a btSphereShape given no mesh) floats by its closed forms (issue 19 item 4): its
// mass is the sphere's, not its tessellation's, and it settles at the draft where the spherical
// cap displaces its weight; under waves it takes its rule on the true sphere, and its drag the
// rule's nodes.

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

#include "PluginTestWorld.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::TestWorld;

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

TEST_CASE("a sphere shape floats at its closed-form draft with its closed-form mass", "[floating][sphere]") {
  for (HydrostaticsMethod method : {HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Auto}) {
    INFO("method " << int(method));
    TestWorld world;
    const double radius = 0.5, density = 300.0;
    btSphereShape shape{btScalar(radius)};
    btRigidBody::btRigidBodyConstructionInfo info(1, nullptr, &shape, btVector3(1, 1, 1));
    btRigidBody body(info);
    body.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.1f, 0)));
    FloatingBodySettings settings;
    settings.method = method;
    settings.density = density;
    settings.effects = {Effect::Buoyancy, Effect::Drag};
    REQUIRE(world.controller().addBody(&body, settings).ok());
    world.world().addRigidBody(&body);
    const FloatingBodyReport* report = world.controller().report(&body);
    REQUIRE(report != nullptr);
    CHECK(report->method == HydrostaticsMethod::Polyhedral);
    // m = rho 4/3 pi r^3 exactly (double rounding), where the tessellated sphere is up to 1e-3 lighter.
    const double mass = density * 4.0 / 3.0 * kPi * radius * radius * radius;
    CHECK(report->massProperties.mass == Approx(mass).epsilon(1e-12));
    CHECK(report->massProperties.inertia(0, 0) == Approx(0.4 * mass * radius * radius).epsilon(1e-12));
    for (int i = 0; i < 600; ++i) world.step(1.0 / 60.0);  // 10 s: drag settles it
    // At rest the cap displaces the weight: V = m / rho_w, the centre r - h above the water.
    const double h = testing::sphereDraft(radius, mass / 1000.0);
    // Bullet's float positions (1e-7 m) and the rest rule's residual force (1e-3 of the weight,
    // over the water plane's stiffness rho g pi a^2: about 0.1 mm) bound the draft's error.
    CHECK(double(body.getCenterOfMassPosition().y()) == Approx(radius - h).margin(2e-4));
    INFO("submerged volume " << report->hydrostatics.submergedVolume << " m^3, weight / rho_w " << mass / 1000.0);
    // At rest the net force is at most 1e-3 of the weight (the rest rule), so the buoyancy, and the
    // displaced volume, equal the weight's within 1e-3. Measured: 1.4e-4.
    CHECK(report->hydrostatics.submergedVolume == Approx(mass / 1000.0).epsilon(1e-3));
    world.world().removeRigidBody(&body);
    world.controller().removeBody(&body);
  }
}

TEST_CASE("a sphere shape asked for the texture path keeps it", "[floating][sphere]") {
  TestWorld world;
  btSphereShape shape(0.5f);
  btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &shape, btVector3(1, 1, 1)));
  FloatingBodySettings settings;
  settings.method = HydrostaticsMethod::Texture;
  settings.resolution = 64;
  settings.density = 300.0;
  settings.effects = {Effect::Buoyancy};
  REQUIRE(world.controller().addBody(&body, settings).ok());
  CHECK(world.controller().report(&body)->method == HydrostaticsMethod::Texture);
  // The tessellated sphere's mass: below the true sphere's (its vertices lie on it).
  CHECK(world.controller().report(&body)->massProperties.mass < 300.0 * 4.0 / 3.0 * kPi * 0.125);
  world.controller().removeBody(&body);
}

TEST_CASE("under waves a sphere shape takes its rule on the true sphere; under a height grid Auto takes its tessellation",
          "[floating][sphere][waves]") {
  // Under waves (a surface with smoothness bounds) a true sphere, on Auto as on the exact path,
  // keeps its closed-form mass and takes core's rule on the true sphere (SphereHydrostaticsWaves.cpp,
  // its own suite: test_primitive_hydrostatics), not a tessellation 1e-3 lighter.
  auto waves = std::make_shared<GerstnerWaves>(
      std::vector<GerstnerWave>{GerstnerWave{0.1, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5}});
  const double sphereMass = 300.0 * 4.0 / 3.0 * kPi * 0.125;
  for (HydrostaticsMethod method : {HydrostaticsMethod::Auto, HydrostaticsMethod::Polyhedral}) {
    INFO("method " << int(method));
    TestWorld world(waves);
    btSphereShape shape(0.5f);
    btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &shape, btVector3(1, 1, 1)));
    body.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.3f, -2.0f, 0.1f)));
    FloatingBodySettings settings;
    settings.method = method;
    settings.autoMethodError = 1e-2;
    settings.resolution = 64;
    settings.density = 300.0;
    settings.effects = {Effect::Buoyancy};
    REQUIRE(world.controller().addBody(&body, settings).ok());
    const FloatingBodyReport* report = world.controller().report(&body);
    CHECK(report->method == HydrostaticsMethod::Polyhedral);
    CHECK(report->massProperties.mass == Approx(sphereMass).epsilon(1e-12));  // the closed form
    // 2 m under the waves its buoyancy is the whole true sphere's (the rule's, within 2.2e-6 of the
    // volume: test_primitive_hydrostatics), where its tessellation's is 1e-3 short.
    world.world().addRigidBody(&body);
    world.step(1.0 / 60.0);
    CHECK(report->hydrostatics.submergedVolume == Approx(4.0 / 3.0 * kPi * 0.125).epsilon(1e-5));
    world.world().removeRigidBody(&body);
    world.controller().removeBody(&body);
  }
  // A height grid offers no smoothness bounds: neither the closed form nor the rule holds, and Auto
  // prices the tessellation's paths as for any mesh (its mass the tessellation's: its vertices lie
  // on the sphere).
  auto grid = std::make_shared<HeightGrid>(16, 16, 0.5, -4.0, -4.0, 0.0);
  TestWorld world(grid);
  btSphereShape shape(0.5f);
  btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &shape, btVector3(1, 1, 1)));
  FloatingBodySettings settings;
  settings.method = HydrostaticsMethod::Auto;
  settings.autoMethodError = 1e-2;
  settings.resolution = 64;
  settings.density = 300.0;
  settings.effects = {Effect::Buoyancy};
  REQUIRE(world.controller().addBody(&body, settings).ok());
  CHECK(world.controller().report(&body)->massProperties.mass < sphereMass);
  world.controller().removeBody(&body);
}

TEST_CASE("a sphere shape's drag runs on its rule's nodes, in flat water and under waves; without drag on none",
          "[floating][sphere][waves][drag]") {
  // Half in the water, the drag sums its law on the sphere's 8 x 4 drag nodes (under this wave its
  // rule's every other meridian, 16 x 8 for the buoyancy, answering every step; in flat water the
  // cap's), not on the tessellation's 153 patches: test_rigid_body_step checks the drag they
  // give. A body that asks no drag pays for none: no drag pass, no node visited.
  auto waves = std::make_shared<GerstnerWaves>(
      std::vector<GerstnerWave>{GerstnerWave{0.1, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5}});
  auto flat = std::make_shared<FlatSurface>(0.0);
  for (const std::shared_ptr<LiquidSurface>& surface : {std::shared_ptr<LiquidSurface>(waves), std::shared_ptr<LiquidSurface>(flat)})
    for (bool drag : {true, false}) {
      INFO("drag " << drag << ", waves " << (surface == waves));
      TestWorld world(surface);
      btSphereShape shape(0.5f);
      btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &shape, btVector3(1, 1, 1)));
      body.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.3f, 0.05f, 0.1f)));
      FloatingBodySettings settings;
      settings.method = HydrostaticsMethod::Polyhedral;
      settings.density = 500.0;
      settings.effects = drag ? EffectSet{Effect::Buoyancy, Effect::Drag} : EffectSet{Effect::Buoyancy};
      REQUIRE(world.controller().addBody(&body, settings).ok());
      world.world().addRigidBody(&body);
      const int steps = 30;
      for (int i = 0; i < steps; ++i) world.step(1.0 / 60.0);
      const ControllerStatistics& statistics = world.controller().statistics();
      CHECK(statistics.hydrostaticsQueries == std::uint64_t(steps));
      CHECK(statistics.failedQueries == 0);
      CHECK(statistics.dragPasses == (drag ? std::uint64_t(steps) : 0u));
      CHECK(statistics.dragPatchesVisited == (drag ? std::uint64_t(steps) * 32u : 0u));
      world.world().removeRigidBody(&body);
      world.controller().removeBody(&body);
    }
}
