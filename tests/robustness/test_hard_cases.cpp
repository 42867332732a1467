// SPDX-License-Identifier: Zlib
// Hard cases for the Bullet plugin, each run for thousands of steps: every step must stay finite
// and bounded, and where a closed form exists the body must end where it says (the draft of a
// floating box, d = rho_b / rho h). Waterline contacts, fast crossings, fast tumbling, thin and
// needle-like bodies, extreme densities and sizes, far from the origin, time steps from 1 ms to
// 100 ms and a spike, mass changing 1000x, a rod, overturning waves, surfaces that answer NaN or
// jump, and energy with and without drag.

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>

#include "../plugin/PluginTestWorld.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

namespace {

constexpr double kWater = 1000.0;
constexpr double kGravity = 9.81;

double centerY(const btRigidBody* body) { return double(body->getCenterOfMassPosition().y()); }

bool finiteState(const btRigidBody* body) {
  const btVector3 p = body->getCenterOfMassPosition(), v = body->getLinearVelocity(), w = body->getAngularVelocity();
  const btQuaternion q = body->getOrientation();
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(double(p[i])) || !std::isfinite(double(v[i])) || !std::isfinite(double(w[i]))) return false;
  return std::isfinite(double(q.w())) && std::isfinite(double(q.x())) && std::isfinite(double(q.y())) &&
         std::isfinite(double(q.z()));
}

/// Limits a run must respect at every step.
struct Bounds {
  double distance;         ///< m, largest distance of the centre of mass from where it started
  double speed;            ///< m/s
  double angularSpeed = 200.0;  ///< rad/s
};

/// Steps `world` `steps` times by `dt`, requiring a finite state within `bounds` at every step.
void runBounded(TestWorld& world, btRigidBody* body, double dt, int steps, const Bounds& bounds) {
  const btVector3 start = body->getCenterOfMassPosition();
  for (int i = 0; i < steps; ++i) {
    world.step(dt);
    INFO("step " << i << " of " << steps << ", dt " << dt);
    REQUIRE(finiteState(body));
    REQUIRE(double((body->getCenterOfMassPosition() - start).length()) < bounds.distance);
    REQUIRE(double(body->getLinearVelocity().length()) < bounds.speed);
    REQUIRE(double(body->getAngularVelocity().length()) < bounds.angularSpeed);
  }
}

/// Settled: slow, and at the centre height `expectedY` within `margin` (m).
void checkSettled(const btRigidBody* body, double expectedY, double margin, double speed = 1e-2) {
  CHECK(centerY(body) == Approx(expectedY).margin(margin));
  CHECK(double(body->getLinearVelocity().length()) < speed);
  CHECK(double(body->getAngularVelocity().length()) < 0.05);
}

const EffectSet kBuoyancyAndDrag{Effect::Buoyancy, Effect::Drag};

/// Quaternion that turns the cube's corner (1, 1, 1) to point straight down.
btQuaternion cornerDown() {
  const btVector3 from = btVector3(1, 1, 1).normalized(), to(0, -1, 0);
  return shortestArcQuat(from, to);
}

}  // namespace

TEST_CASE("bodies exactly at the waterline, touching it with one vertex, wholly under and over", "[robustness][hard]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(method == HydrostaticsMethod::Texture);
  const double dt = 1.0 / 60.0, density = 500.0;
  struct Start {
    const char* what;
    btVector3 position;
    btQuaternion rotation;
  };
  const double cornerHeight = std::sqrt(3.0) / 2.0;  // centre to corner of the unit cube
  for (const Start& start : {Start{"bottom face on the surface", btVector3(0, 0.5f, 0), btQuaternion::getIdentity()},
                             Start{"top face on the surface", btVector3(0, -0.5f, 0), btQuaternion::getIdentity()},
                             Start{"one corner touching", btVector3(0, btScalar(cornerHeight), 0), cornerDown()},
                             Start{"wholly over", btVector3(0, 4, 0), btQuaternion::getIdentity()},
                             Start{"wholly under", btVector3(0, -6, 0), btQuaternion::getIdentity()}}) {
    CAPTURE(start.what);
    TestWorld world;
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(density, kBuoyancyAndDrag, method), start.position,
                                 start.rotation);
    REQUIRE(box != nullptr);
    // Falling 4 m gives 9 m/s; rising from 6 m deep at most the same order.
    runBounded(world, box, dt, int(40.0 / dt), {12.0, 15.0});
    // A cube at half density floats on a face or on an edge (both are equilibria; the cube's GM
    // is negative upright only at densities between 0.21 and 0.79: here it settles tilted), so
    // only the submerged volume is a closed form: V = m / rho = 0.5 m^3, to 1 % (the
    // residual motion after 40 s and, for the texture path, the waterline inside texels).
    const FloatingBodyReport* report = world.controller().report(box);
    REQUIRE(report != nullptr);
    CHECK(report->hydrostatics.submergedVolume == Approx(density / kWater).epsilon(1e-2));
    CHECK(double(box->getLinearVelocity().length()) < 2e-2);
  }
}

TEST_CASE("crossing the surface at high speed and tumbling fast", "[robustness][hard]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  CAPTURE(method == HydrostaticsMethod::Texture, dt);
  const double density = 600.0;
  SECTION("down at 50 m/s") {
    TestWorld world;
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(density, kBuoyancyAndDrag, method), btVector3(0, 2, 0));
    REQUIRE(box != nullptr);
    box->setLinearVelocity(btVector3(0, -50, 0));
    runBounded(world, box, dt, int(30.0 / dt), {60.0, 52.0});
    CHECK(finiteState(box));
    // Back at the surface, floating: whatever orientation it settled in (a cube at 0.6 tilts), its
    // centre sits where that orientation displaces m / rho, found on the exact path by bisection.
    const btTransform placed = *world.controller().meshTransform(box);
    Pose pose;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) pose.rotation(r, c) = double(placed.getBasis()[r][c]);
    const Mesh cube = primitives::box({1, 1, 1});
    double low = -1.0, high = 1.0;  // centre heights: wholly under, wholly out
    for (int i = 0; i < 60; ++i) {
      pose.translation.y() = 0.5 * (low + high);
      HydrostaticsQuery query;
      query.pose = pose;
      const double submerged = polyhedralHydrostatics(cube, FlatSurface(0.0), query)->submergedVolume;
      (submerged > density / kWater ? low : high) = pose.translation.y();
    }
    // Measured within 2.3e-4 m on both paths and time steps (the texture path's waterline, what is
    // left of the motion): 1e-3 m. Before, |y| < 1 m.
    CHECK(centerY(box) == Approx(0.5 * (low + high)).margin(1e-3));
  }
  SECTION("up at 50 m/s from 3 m deep") {
    TestWorld world;
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(density, kBuoyancyAndDrag, method), btVector3(0, -3, 0));
    REQUIRE(box != nullptr);
    box->setLinearVelocity(btVector3(0, 50, 0));
    // Out of the water it flies ballistically: at most v^2 / 2g = 127 m up.
    runBounded(world, box, dt, int(30.0 / dt), {140.0, 52.0});
  }
  SECTION("spinning at 60 rad/s about a tilted axis, half under") {
    TestWorld world;
    btRigidBody* box = world.add(primitives::box({2, 0.5, 1}), solid(density, kBuoyancyAndDrag, method), btVector3(0, 0, 0));
    REQUIRE(box != nullptr);
    box->setAngularVelocity(btVector3(60, 20, -40).normalized() * 60);
    // A half-submerged spinning box paddles itself along: its spin energy (0.5 I w^2 = 380 kJ,
    // I <= m (4 + 0.25) / 12) bounds its speed by sqrt(2 E / m) = 36 m/s.
    runBounded(world, box, dt, int(30.0 / dt), {300.0, 36.0, 61.0});
    // Drag takes the spin out: well under a rad/s after 30 s.
    CHECK(double(box->getAngularVelocity().length()) < 0.5);
  }
}

TEST_CASE("thin plates, needles and a rod (nearly singular inertia)", "[robustness][hard]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(method == HydrostaticsMethod::Texture);
  const double dt = 1.0 / 60.0, density = 500.0;
  struct Shape {
    const char* what;
    Mesh mesh;
    double height;  ///< vertical extent when lying flat (m)
  };
  for (const Shape& shape : {Shape{"plate 1 m x 1 mm x 1 m", primitives::box({1, 0.001, 1}), 0.001},
                             Shape{"rod 2 m x 2 cm", primitives::cylinder(0.01, 2.0, 16), 0.02}}) {
    CAPTURE(shape.what);
    TestWorld world;
    btRigidBody* body = world.add(shape.mesh, solid(density, kBuoyancyAndDrag, method, 128), btVector3(0, 0.3f, 0),
                                  btQuaternion(btVector3(0, 0, 1), 0.2f));
    INFO((world.lastStatus.ok() ? std::string() : world.lastStatus.error().message));
    REQUIRE(body != nullptr);
    body->setAngularVelocity(btVector3(3, 1, 2));
    runBounded(world, body, dt, int(30.0 / dt), {5.0, 10.0, 100.0});
    // Afloat at the surface: its centre within its own thickness of the waterline.
    CHECK(std::abs(centerY(body)) < shape.height + 1e-3);
  }
}

TEST_CASE("a needle (1 m x 1 mm x 1 mm) gains no rotational energy", "[robustness][hard]") {
  // About its long axis the needle's inertia is 8e-11 kg m^2 and its roll stiffness about
  // 8e-7 N m/rad: a natural frequency of 100 rad/s, omega dt = 1.6 at 60 Hz, which no step
  // resolves. The energy it can draw on (its roll potential, m g 1e-4 m, plus the start spin)
  // bounds its spin to about 110 rad/s. While the controller measured mode rates by I_xx instead
  // of the needle's own roll inertia (BuoyancyController.cpp, rollPitchInertia) it reached
  // 340 rad/s on the polyhedral path; while it kicked an under-resolved capsizing roll (a square
  // section at half density is unstable upright) explicitly, 800 rad/s on the texture path.
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(method == HydrostaticsMethod::Texture);
  const double dt = 1.0 / 60.0;
  TestWorld world;
  btRigidBody* body = world.add(primitives::box({1, 0.001, 0.001}), solid(500.0, kBuoyancyAndDrag, method, 128),
                                btVector3(0, 0.3f, 0), btQuaternion(btVector3(0, 0, 1), 0.2f));
  REQUIRE(body != nullptr);
  body->setAngularVelocity(btVector3(3, 1, 2));
  double fastest = 0.0;
  for (int i = 0; i < int(30.0 / dt); ++i) {
    world.step(dt);
    REQUIRE(finiteState(body));
    fastest = std::max(fastest, double(body->getAngularVelocity().length()));
  }
  CHECK(fastest < 110.0);
}

TEST_CASE("very light and very heavy bodies", "[robustness][hard]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(method == HydrostaticsMethod::Texture);
  const double dt = 1.0 / 60.0;
  SECTION("1 % of the liquid's density floats at a 1 cm draft") {
    TestWorld world;
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(10.0, kBuoyancyAndDrag, method), btVector3(0, 1, 0));
    REQUIRE(box != nullptr);
    runBounded(world, box, dt, int(30.0 / dt), {3.0, 10.0});
    // Draft 0.01 m: centre at 0.49; 2 mm for the waterline inside a texel (1.6 cm at 64^2).
    checkSettled(box, 0.5 - 0.01, 2e-3);
  }
  SECTION("100 times the liquid's density sinks, never faster than free fall") {
    TestWorld world;
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(100.0 * kWater, kBuoyancyAndDrag, method), btVector3(0, 0, 0));
    REQUIRE(box != nullptr);
    double time = 0.0;
    for (int i = 0; i < int(20.0 / dt); ++i) {
      world.step(dt);
      time += dt;
      REQUIRE(finiteState(box));
      // Buoyancy and drag only slow it: never faster than free fall (1e-3 for float velocities).
      REQUIRE(-double(box->getLinearVelocity().y()) <= kGravity * time * (1.0 + 1e-3) + 1e-6);
    }
    CHECK(box->getLinearVelocity().y() < 0);
  }
}

TEST_CASE("huge (1 km), tiny (1 cm) and far away (10 km) bodies", "[robustness][hard]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(method == HydrostaticsMethod::Texture);
  const double dt = 1.0 / 60.0, density = 500.0;
  SECTION("a 1 km cube starting 100 m high stays finite and oscillates within its start") {
    TestWorld world;
    const double side = 1000.0;
    btRigidBody* box = world.add(primitives::box({side, side, side}), solid(density, kBuoyancyAndDrag, method),
                                 btVector3(0, btScalar(side / 2 + 100.0), 0));
    REQUIRE(box != nullptr);
    // Released 600 m above its equilibrium (100 m of free fall, then 500 m of draft): the fastest
    // it can pass the equilibrium is sqrt(2 g (600 - 250)) = 83 m/s (the buoyancy's stored energy
    // rho g A d^2 / 2 at d = 500 m takes m g 250 m); the heave period is 45 s.
    runBounded(world, box, dt, int(200.0 / dt), {1000.0, 85.0});
    // Energy cannot lift it above where it started.
    CHECK(centerY(box) < side / 2 + 100.0);
  }
  SECTION("a 1 cm cube settles at its draft of 5 mm") {
    TestWorld world;
    const double side = 0.01;
    btRigidBody* box = world.add(primitives::box({side, side, side}), solid(density, kBuoyancyAndDrag, method),
                                 btVector3(0, 0.02f, 0));
    REQUIRE(box != nullptr);
    runBounded(world, box, dt, int(20.0 / dt), {1.0, 5.0, 500.0});
    // Centre at side/2 - draft = 0; 0.2 mm: 2 % of the side (texel 0.16 mm at 64^2, the
    // residual motion, float positions).
    checkSettled(box, 0.0, 2e-4, 1e-3);
  }
  SECTION("a cube 10 km from the origin floats at its draft and drifts as it does at the origin") {
    // Bullet's positions are btScalar: 1e4 m is stored to a spacing of 2^-10 m (0.98 mm) in float,
    // 2^-39 m (1.8e-12 m) in a double-precision Bullet (HYDROTEX_BULLET_DOUBLE).
    const double far = 10000.0;
    const double spacing = std::ldexp(1.0, 13 - (std::numeric_limits<btScalar>::digits - 1));
    CAPTURE(spacing);
    const btQuaternion tilted(btVector3(1, 0, 2).normalized(), 0.1f);  // so that it capsizes
    const auto sideways = [&](double at, const EffectSet& effects) {
      TestWorld world;
      btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(density, effects, method),
                                   btVector3(btScalar(at), 0.3f, btScalar(-at)), tilted);
      REQUIRE(box != nullptr);
      runBounded(world, box, dt, int(30.0 / dt), {3.0, 10.0});
      // Float positions at 1e4 m are 1 mm apart: 3 mm (the tolerance at the origin, 2e-4 m, where
      // positions are finer).
      if (effects.has(Effect::Drag)) checkSettled(box, 0.0, std::max(3.0 * spacing, 2e-4));
      const btVector3 p = box->getCenterOfMassPosition();
      return Eigen::Vector2d(double(p.x()) - at, double(p.z()) + at);
    };
    // Buoyancy alone is vertical (Archimedes: still water, closed body): while the cube
    // capsizes (a cube at half density is unstable upright) its centre may move sideways only by
    // the rounding of one position update, one float spacing.
    CHECK(sideways(far, EffectSet{Effect::Buoyancy}).norm() <= spacing);
    // With drag the capsizing faces push on the water and the cube moves about 0.14 m sideways,
    // physically, the same at the origin. Far away each of the 1800 position updates is rounded
    // to the float grid (at most half a spacing, 0.49 mm), a random walk of about
    // sqrt(1800) 0.49 mm = 2 cm on the trajectory: the two runs agree within twice that.
    const Eigen::Vector2d atOrigin = sideways(0.0, kBuoyancyAndDrag), atFar = sideways(far, kBuoyancyAndDrag);
    CAPTURE(atOrigin.transpose(), atFar.transpose());
    CHECK((atFar - atOrigin).norm() <= 2.0 * std::sqrt(1800.0) * 0.5 * spacing);
  }
}

TEST_CASE("time steps from 1 ms to 100 ms, and a spike", "[robustness][hard]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  const double dt = GENERATE(1.0 / 1000.0, 1.0 / 100.0, 1.0 / 30.0, 1.0 / 10.0);
  CAPTURE(method == HydrostaticsMethod::Texture, dt);
  const double density = 500.0;
  TestWorld world;
  // A 2 x 1 x 2 box: stable upright (GM > 0), so its centre height is a closed form.
  btRigidBody* box = world.add(primitives::box({2, 1, 2}), solid(density, kBuoyancyAndDrag, method), btVector3(0, 0.4f, 0));
  REQUIRE(box != nullptr);
  const int steps = std::min(int(30.0 / dt), 5000);
  runBounded(world, box, dt, steps / 2, {3.0, 10.0});
  world.step(0.5);  // a spike: one step of half a second
  REQUIRE(finiteState(box));
  runBounded(world, box, dt, std::max(steps / 2, int(20.0 / dt)), {3.0, 10.0});
  // Centre at h/2 - draft = 0: 3 mm (the waterline inside a texel; at 100 ms the implicit
  // stiffness settles it without oscillating).
  checkSettled(box, 0.0, 3e-3);
}

TEST_CASE("mass changing 1000x within a second", "[robustness][hard]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(method == HydrostaticsMethod::Texture);
  const double dt = 1.0 / 60.0;
  TestWorld world;
  btRigidBody* box = world.add(primitives::box({2, 1, 2}), solid(0.45, kBuoyancyAndDrag, method), btVector3(0, 0.5f, 0));
  REQUIRE(box != nullptr);
  const double volume = 4.0, startMass = 0.45 * volume, endMass = 450.0 * volume;
  for (int i = 1; i <= int(20.0 / dt); ++i) {
    // Exponential ramp from 1.8 kg to 1800 kg over the first second.
    const double t = std::min(1.0, i * dt);
    const double mass = startMass * std::pow(endMass / startMass, t);
    MassProperties properties;
    properties.mass = mass;
    properties.volume = volume;
    properties.inertia = Eigen::Vector3d(mass * (1 + 4) / 12.0, mass * (4 + 4) / 12.0, mass * (1 + 4) / 12.0).asDiagonal();
    REQUIRE(world.controller().setMassProperties(box, properties).ok());
    world.step(dt);
    REQUIRE(finiteState(box));
    REQUIRE(std::abs(centerY(box)) < 3.0);
  }
  // Final draft 0.45 m: centre at 0.5 - 0.45 = 0.05 m; 3 mm.
  checkSettled(box, 0.05, 3e-3);
}

namespace {

/// Gerstner waves steeper than physical (steepness 1 and k A > 1: the trochoid loops).
std::shared_ptr<const LiquidSurface> overturningWaves() {
  GerstnerWave a;
  a.amplitude = 2.0;
  a.wavelength = 6.0;  // k A = 2.1
  a.steepness = 1.0;
  GerstnerWave b = a;
  b.direction = Eigen::Vector2d(0.3, 1.0);
  b.amplitude = 1.5;
  b.wavelength = 4.0;
  return std::make_shared<GerstnerWaves>(std::vector<GerstnerWave>{a, b}, 0.0, kWater, kGravity);
}

/// A surface that answers NaN over half the plane (a broken height field).
class NanPatchSurface final : public LiquidSurface {
 public:
  double surfaceHeight(double x, double, double) const override {
    return x > 0.0 ? std::numeric_limits<double>::quiet_NaN() : 0.0;
  }
  double density() const override { return kWater; }
  Status validate() const override { return Ok{}; }
};

/// A surface that jumps between -1 m and +1 m every 0.25 s (a teleporting water level).
class JumpingSurface final : public LiquidSurface {
 public:
  double surfaceHeight(double, double, double time) const override {
    return static_cast<long long>(std::floor(time / 0.25)) % 2 == 0 ? -1.0 : 1.0;
  }
  double density() const override { return kWater; }
  Status validate() const override { return Ok{}; }
};

/// A surface whose every answer is NaN, velocity included.
class AllNanSurface final : public LiquidSurface {
 public:
  double surfaceHeight(double, double, double) const override { return std::numeric_limits<double>::quiet_NaN(); }
  Eigen::Vector3d velocity(const Eigen::Vector3d&, double) const override {
    return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  double density() const override { return kWater; }
  Status validate() const override { return Ok{}; }
};

}  // namespace

TEST_CASE("waves steeper than physical keep every query finite and bodies bounded", "[robustness][hard][waves]") {
  const auto surface = overturningWaves();
  for (double x = -10.0; x <= 10.0; x += 0.37)
    for (double t = 0.0; t < 5.0; t += 0.71) {
      const double h = surface->surfaceHeight(x, 0.3 * x, t);
      REQUIRE(std::isfinite(h));
      // Heights lie within the mean level +- the sum of amplitudes.
      REQUIRE(std::abs(h) <= 3.5 + 1e-9);
    }
  TestWorld world(surface);
  btRigidBody* box = world.add(primitives::box({2, 1, 1}), solid(500.0, kBuoyancyAndDrag, HydrostaticsMethod::Texture),
                               btVector3(0, 0, 0));
  REQUIRE(box != nullptr);
  // Heaving with 3.5 m waves that loop over: carried along (the orbital speed k A c is 6 m/s, the
  // drift of looping crests more), within 300 m and 30 m/s over 50 s.
  runBounded(world, box, 1.0 / 60.0, 3000, {300.0, 30.0, 100.0});
}

TEST_CASE("a surface that answers NaN or jumps never makes a body non-finite", "[robustness][hard][surface]") {
  const double dt = 1.0 / 60.0;
  SECTION("NaN over half the plane") {
    TestWorld world(std::make_shared<NanPatchSurface>());
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(500.0, kBuoyancyAndDrag, HydrostaticsMethod::Texture),
                                 btVector3(0.2f, 0, 0));
    REQUIRE(box != nullptr);
    // With forces skipped where the surface fails, it may fall freely: 30 s of free fall is
    // 4.4 km and 300 m/s; it must stay finite.
    runBounded(world, box, dt, int(30.0 / dt), {5000.0, 300.0});
  }
  SECTION("NaN everywhere, velocity included") {
    TestWorld world(std::make_shared<AllNanSurface>());
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(500.0, kBuoyancyAndDrag, HydrostaticsMethod::Texture),
                                 btVector3(0, 0, 0));
    REQUIRE(box != nullptr);
    runBounded(world, box, dt, int(30.0 / dt), {5000.0, 300.0});
  }
  SECTION("a level jumping by 2 m every quarter second") {
    TestWorld world(std::make_shared<JumpingSurface>());
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(500.0, kBuoyancyAndDrag, HydrostaticsMethod::Texture),
                                 btVector3(0, 0, 0));
    REQUIRE(box != nullptr);
    // The level only ever lies in [-1, 1]: a half-density box stays within a few metres of it.
    runBounded(world, box, dt, int(30.0 / dt), {6.0, 15.0});
  }
}

TEST_CASE("energy: without drag a floating body neither gains energy nor drifts; with drag it only loses",
          "[robustness][hard][energy]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  CAPTURE(method == HydrostaticsMethod::Texture, dt);
  // A 2 x 1 x 2 box (stable upright) of 500 kg/m^3 released 0.2 m above its equilibrium: pure
  // heave. Energy = kinetic + m g y + rho g A d^2 / 2 (d the immersion depth of the bottom face,
  // the work buoyancy stores), exact for a box in heave while 0 < d < h.
  const double density = 500.0, area = 4.0, height = 1.0, mass = density * area * height;
  auto energyOf = [&](const btRigidBody* box) {
    const double v = double(box->getLinearVelocity().length());
    const double omega = double(box->getAngularVelocity().length());
    const double y = centerY(box);
    const double d = std::clamp(height / 2 - y, 0.0, height);
    // Rotational energy with the largest principal inertia (an upper bound; it stays ~0 here).
    const double rotational = 0.5 * mass * (4.0 + 4.0) / 12.0 * omega * omega;
    return 0.5 * mass * v * v + rotational + mass * kGravity * y + 0.5 * kWater * kGravity * area * d * d;
  };
  const double period = 2.0 * std::numbers::pi * std::sqrt(mass / (kWater * kGravity * area));  // 1.0 s
  const int window = int(std::ceil(period / dt));
  const int steps = int(20.0 / dt);
  for (const bool drag : {false, true}) {
    CAPTURE(drag);
    TestWorld world;
    const EffectSet effects = drag ? kBuoyancyAndDrag : EffectSet{Effect::Buoyancy};
    btRigidBody* box = world.add(primitives::box({2, height, 2}), solid(density, effects, method), btVector3(3, 0.2f, -2));
    REQUIRE(box != nullptr);
    const double start = energyOf(box);
    // The first period's peak is the reference, not the start: released at rest, the box starts
    // at a turning point, and within a period the energy of any integrator wobbles above that by
    // about omega dt of the oscillation energy (symplectic Euler conserves a shadow energy).
    double peak = -std::numeric_limits<double>::infinity(), previousPeak = std::numeric_limits<double>::infinity();
    double firstPeak = std::numeric_limits<double>::quiet_NaN(), lastPeak = firstPeak;
    double largestGrowth = -std::numeric_limits<double>::infinity();
    double lowestY = 1e9, highestY = -1e9;
    for (int i = 1; i <= steps; ++i) {
      world.step(dt);
      REQUIRE(finiteState(box));
      const double e = energyOf(box);
      peak = std::max(peak, e);
      if (i > steps - window) {
        lowestY = std::min(lowestY, centerY(box));
        highestY = std::max(highestY, centerY(box));
      }
      if (i % window == 0) {
        largestGrowth = std::max(largestGrowth, peak - previousPeak);
        if (std::isnan(firstPeak)) firstPeak = peak;
        lastPeak = peak;
        previousPeak = peak;
        peak = -std::numeric_limits<double>::infinity();
      }
    }
    // Energy within a period wobbles by (omega dt)^2 of the oscillation energy for any
    // integrator; from one period's peak to the next it must not grow. Noise: float positions
    // (1e-7 m relative) times m g = 2e-3 J, and 1e-6 of the 800 J oscillation energy.
    const double noise = 5e-3;
    CHECK(largestGrowth < noise);
    const double end = energyOf(box);
    // No drift: the box stays where it was put horizontally (float noise 1e-6 m; drag has no
    // horizontal cause here either).
    CHECK(double(box->getCenterOfMassPosition().x()) == Approx(3.0).margin(1e-4));
    CHECK(double(box->getCenterOfMassPosition().z()) == Approx(-2.0).margin(1e-4));
    if (drag) {
      // Drag takes energy out: the last period holds a small fraction of the 800 J at the start.
      const double equilibriumEnergy = mass * kGravity * 0.0 + 0.5 * kWater * kGravity * area * 0.25;
      CHECK(end - equilibriumEnergy < 0.1 * (start - equilibriumEnergy));
    } else {
      CHECK(lastPeak <= firstPeak + noise);
      // The heave amplitude (0.2 m) may only shrink (an implicit integrator damps), never grow.
      CHECK(highestY - lowestY <= 0.4 + 1e-3);
    }
  }
}
