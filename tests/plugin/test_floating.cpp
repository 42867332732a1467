// SPDX-License-Identifier: Zlib
// Floating in Bullet against closed forms (docs/references.md "Hydrostatics"), each at several time
// steps: draft, heave period, metacentric stability, sinking and terminal velocity, light and
// dropped bodies, balloons in air.

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "PluginTestWorld.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

namespace {

constexpr double kWater = 1000.0;
constexpr double kGravity = 9.81;
constexpr double kPi = 3.14159265358979323846;

double centerY(const btRigidBody* body) { return double(body->getCenterOfMassPosition().y()); }

/// Angle (rad) of the mesh's y axis away from the world vertical (Bullet's own frame is the
/// principal frame, whose axes may be any of the mesh's).
double tiltAngle(TestWorld& world, const btRigidBody* body) {
  const btVector3 up = world.controller().meshTransform(body)->getBasis() * btVector3(0, 1, 0);
  return std::acos(std::clamp(double(up.dot(btVector3(0, 1, 0))), -1.0, 1.0));
}

}  // namespace

TEST_CASE("a box floats at draft (rho_b / rho) x height", "[floating][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 120.0, 1.0 / 240.0);
  const double density = GENERATE(250.0, 600.0);
  // Auto, the default, is run as a user gets it: on a 12-triangle box it resolves to the exact path
  // (core's cost model: 1.2 us against 9.7 us for 64^2 texels), which the report says.
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture, HydrostaticsMethod::Auto);
  CAPTURE(dt, density, int(method));
  const double height = 1.0;
  TestWorld world;
  btRigidBody* box = world.add(primitives::box({2.0, height, 1.5}), solid(density, {Effect::Buoyancy, Effect::Drag}, method),
                               btVector3(0, 0.3f, 0));
  REQUIRE(box != nullptr);
  const HydrostaticsMethod resolved = method == HydrostaticsMethod::Auto ? HydrostaticsMethod::Polyhedral : method;
  CHECK(world.controller().report(box)->method == resolved);
  for (int i = 0; i < int(25.0 / dt); ++i) world.step(dt);
  const double draft = density / kWater * height;
  // Centre of the box sits at h - draft + height / 2. Tolerance 2 mm: float positions in Bullet
  // (1e-7 relative), the residual oscillation after 25 s of damping (< 0.1 mm), and for the texture
  // path the waterline inside a texel at 64^2 (texel about 1 cm, second order: well under 1 mm).
  CHECK(centerY(box) == Approx(height / 2 - draft).margin(2e-3));
  CHECK(double(box->getLinearVelocity().length()) < 1e-2);
  CHECK(tiltAngle(world, box) < 1e-2);
}

TEST_CASE("heave period with buoyancy only is 2 pi sqrt(m / (rho g A_wp))", "[floating][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 120.0, 1.0 / 240.0);
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(dt, method == HydrostaticsMethod::Texture);
  // A 2 x 1 x 2 box: a cube at half density is unstable in roll (GM = -1/12 m) and would mix
  // capsizing into the heave; this one has GM = 0.42 m.
  const double density = 500.0, side = 2.0, height = 1.0;
  const double mass = density * side * side * height, area = side * side;
  const double expected = 2.0 * kPi * std::sqrt(mass / (kWater * kGravity * area));
  const double equilibrium = height / 2 - density / kWater * height;
  TestWorld world;
  btRigidBody* box = world.add(primitives::box({side, height, side}), solid(density, {Effect::Buoyancy}, method),
                               btVector3(0, btScalar(equilibrium - 0.05), 0));
  REQUIRE(box != nullptr);
  // Upward crossings of the equilibrium, linearly interpolated between steps.
  std::vector<double> crossings;
  double previous = centerY(box) - equilibrium;
  for (int i = 1; i <= int(8.0 * expected / dt); ++i) {
    world.step(dt);
    const double now = centerY(box) - equilibrium;
    if (previous < 0.0 && now >= 0.0) crossings.push_back((i - 1 + previous / (previous - now)) * dt);
    previous = now;
  }
  REQUIRE(crossings.size() >= 6);
  const double period = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  // Tolerance 0.5 %: symplectic Euler's period error is (omega dt)^2 / 24 = 2.3e-4 at 60 Hz
  // (omega dt = 0.074), the crossing interpolation error is second order in dt, and the partly
  // implicit stiffness (theta = (omega dt)^2) shifts the frequency by a similar amount.
  CHECK(period == Approx(expected).epsilon(5e-3));
  // Nothing but buoyancy: the amplitude must neither grow nor vanish (theta keeps the scheme almost
  // energy-conserving: loss (omega dt)^4 / 2 per step, under 1 % over 8 periods at 60 Hz).
  CHECK(std::abs(previous) < 0.0501);
}

TEST_CASE("a box barge is stable when GM > 0 and capsizes when GM < 0", "[floating][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  const double density = 500.0;
  // Both paths Auto can choose (docs/design.md "Choosing the method").
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(dt, method == HydrostaticsMethod::Texture);
  const double startRoll = 10.0 * kPi / 180.0;
  const btQuaternion roll(btVector3(1, 0, 0), btScalar(startRoll));
  SECTION("wide barge: B = 2, H = 1, T = 0.5: GM = T/2 + B^2/(12 T) - H/2 = 0.417 m") {
    const double breadth = 2.0, height = 1.0, draft = 0.5;
    REQUIRE(draft / 2 + breadth * breadth / (12 * draft) - height / 2 > 0.0);
    TestWorld world;
    btRigidBody* barge = world.add(primitives::box({4.0, height, breadth}),
                                   solid(density, {Effect::Buoyancy, Effect::Drag}, method), btVector3(0, 0, 0), roll);
    REQUIRE(barge != nullptr);
    double largest = 0.0;
    for (int i = 0; i < int(20.0 / dt); ++i) {
      world.step(dt);
      largest = std::max(largest, tiltAngle(world, barge));
    }
    // Stable: the roll never exceeds the initial heel (energy is only removed) and decays; 0.01 rad
    // is the residual after 20 s with drag (the roll period is about 2.3 s).
    CHECK(largest <= startRoll + 1e-3);
    CHECK(tiltAngle(world, barge) < 0.01);
  }
  SECTION("tall box: B = 1, H = 2, T = 1: GM = T/2 + B^2/(12 T) - H/2 = -0.417 m") {
    const double breadth = 1.0, height = 2.0, draft = 1.0;
    REQUIRE(draft / 2 + breadth * breadth / (12 * draft) - height / 2 < 0.0);
    TestWorld world;
    btRigidBody* tall = world.add(primitives::box({4.0, height, breadth}),
                                  solid(density, {Effect::Buoyancy, Effect::Drag}, method), btVector3(0, 0, 0),
                                  btQuaternion(btVector3(1, 0, 0), btScalar(2.0 * kPi / 180.0)));
    REQUIRE(tall != nullptr);
    for (int i = 0; i < int(20.0 / dt); ++i) world.step(dt);
    // Capsized: it ends on its side (90 degrees), far from the 2 degrees it started at.
    CHECK(tiltAngle(world, tall) > 60.0 * kPi / 180.0);
    CHECK(tiltAngle(world, tall) < 120.0 * kPi / 180.0);
  }
}

TEST_CASE("a dense body sinks at g (1 - rho / rho_b) and with drag reaches its terminal velocity",
          "[floating][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  const double density = 2000.0;
  CAPTURE(dt);
  SECTION("buoyancy only: constant acceleration once submerged") {
    TestWorld world;
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(density, {Effect::Buoyancy}), btVector3(0, -2, 0));
    REQUIRE(box != nullptr);
    const int steps = int(1.0 / dt);
    for (int i = 0; i < steps; ++i) world.step(dt);
    // Exact for symplectic Euler under a constant force; 1e-4 relative covers float velocities.
    const double expected = -kGravity * (1.0 - kWater / density) * steps * dt;
    CHECK(double(box->getLinearVelocity().y()) == Approx(expected).epsilon(1e-4));
  }
  SECTION("with drag: (rho_b - rho) V g = rho A (Cd v^2 / 2 + 2 c_lin v)") {
    FloatingBodySettings settings = solid(density, {Effect::Buoyancy, Effect::Drag});
    settings.drag.skinFrictionScale = 0.0;  // the closed form has only the pressure law
    settings.rotationalDamping = 0.0;
    TestWorld world;
    btRigidBody* box = world.add(primitives::box({1, 1, 1}), settings, btVector3(0, -2, 0));
    REQUIRE(box != nullptr);
    for (int i = 0; i < int(6.0 / dt); ++i) world.step(dt);
    // Bottom face advancing (Cd, linear term), top face retreating (linear term only, no
    // suction), sides tangential. A = 1 m^2, V = 1 m^3.
    const double cd = settings.drag.advancingPressure, c = settings.drag.linearPressureVelocity;
    const double excess = (density / kWater - 1.0) * kGravity;
    const double terminal = (-2.0 * c + std::sqrt(4.0 * c * c + 2.0 * cd * excess)) / cd;
    // 0.5 %: the approach is exponential with a time constant of about 0.3 s (converged after 6 s);
    // the drag patches of flat faces sum exactly; float velocities.
    CHECK(double(box->getLinearVelocity().y()) == Approx(-terminal).epsilon(5e-3));
    CHECK(double(box->getAngularVelocity().length()) < 1e-3);
  }
}

TEST_CASE("a body of 1 % of the liquid's density at 60 Hz settles and never gains energy",
          "[floating][stability]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 30.0);
  CAPTURE(dt);
  const double density = 10.0, side = 1.0;
  const double mass = density, draft = density / kWater * side;
  const double equilibrium = side / 2 - draft;
  TestWorld world;
  btRigidBody* box = world.add(primitives::box({side, side, side}), solid(density, {Effect::Buoyancy}),
                               btVector3(0, btScalar(equilibrium + 0.5 * draft), 0));
  REQUIRE(box != nullptr);
  // Mechanical energy of the box in heave while it is partly immersed: kinetic + gravity +
  // hydrostatic (rho g A d^2 / 2, d the immersion depth).
  auto energy = [&] {
    const double v = double(box->getLinearVelocity().length());
    const double y = centerY(box);
    const double immersion = std::max(0.0, -(y - side / 2));
    return 0.5 * mass * v * v + mass * kGravity * y + 0.5 * kWater * kGravity * side * side * immersion * immersion;
  };
  // Any time-stepping scheme's energy wobbles within a period by (omega dt)^2 of the oscillation
  // energy; what must never happen is growth from one period to the next. Compare the largest
  // energy of each period (2 pi / omega = 0.2 s) with that of the period before; float positions
  // (1e-7 m) times m g give 1e-5 J of noise.
  const double period = 2.0 * kPi * std::sqrt(mass / (kWater * kGravity * side * side));
  const int window = std::max(1, int(std::ceil(period / dt)));
  double windowPeak = energy(), previousPeak = std::numeric_limits<double>::infinity();
  double growth = -std::numeric_limits<double>::infinity();
  for (int i = 1; i <= int(5.0 / dt); ++i) {
    world.step(dt);
    const double now = energy();
    REQUIRE(std::isfinite(now));
    windowPeak = std::max(windowPeak, now);
    if (i % window == 0) {
      growth = std::max(growth, windowPeak - previousPeak);
      previousPeak = windowPeak;
      windowPeak = -std::numeric_limits<double>::infinity();
    }
  }
  CHECK(growth < 1e-5);
  CHECK(centerY(box) == Approx(equilibrium).margin(1e-4));
  CHECK(double(box->getLinearVelocity().length()) < 1e-3);  // no jitter left
}

TEST_CASE("light and fast bodies dropped into the water stay finite and settle", "[floating][stability]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  const double density = GENERATE(10.0, 500.0);
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(dt, density);
  TestWorld world;
  btRigidBody* box = world.add(primitives::box({1, 1, 1}), solid(density, {Effect::Buoyancy, Effect::Drag}, method),
                               btVector3(0, 3, 0), btQuaternion(btVector3(1, 0, 1).normalized(), 0.3f));
  REQUIRE(box != nullptr);
  box->setLinearVelocity(btVector3(0, -10, 0));
  double highest = -1e9;
  for (int i = 0; i < int(30.0 / dt); ++i) {
    world.step(dt);
    REQUIRE(std::isfinite(centerY(box)));
    if (i * dt > 1.0) highest = std::max(highest, centerY(box));
  }
  // After the first second the box never rises above where it was dropped from (no energy made up).
  CHECK(highest < 3.0);
  // Settled upright or on a face at its draft: 5 mm (one texel at 64^2 is 1.6 cm on a face; the
  // waterline inside a texel is second order).
  const double draft = density / kWater;
  CHECK(centerY(box) == Approx(0.5 - draft).margin(5e-3));
  CHECK(double(box->getLinearVelocity().length()) < 1e-2);
  CHECK(double(box->getAngularVelocity().length()) < 1e-2);
}

TEST_CASE("added mass: a submerged sphere released from rest accelerates at g (rho_b - rho) / (rho_b + C_a rho)",
          "[floating][added-mass][closed-form]") {
  // The controller's added mass is isotropic, m_a = C_a rho V_submerged (FloatingBodySettings::
  // addedMassCoefficient; 1/2 for a sphere, Newman, Marine Hydrodynamics, sec. 4.13), so the heave
  // is (m + m_a) a = (rho_b - rho) V g. The volume cancels (body and displaced liquid are the same
  // mesh on both paths): exact up to Bullet's float velocities (measured 1.4e-6): 1e-5.
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  const double density = GENERATE(2000.0, 500.0);  // sinks, rises
  const double coefficient = GENERATE(0.5, 1.0);
  CAPTURE(dt, density, coefficient);
  FloatingBodySettings settings = solid(density, {Effect::Buoyancy, Effect::AddedMass});
  settings.addedMassCoefficient = coefficient;
  TestWorld world;
  btRigidBody* ball = world.add(primitives::icosphere(0.5, 3), settings, btVector3(0, -3, 0));
  REQUIRE(ball != nullptr);
  const int steps = int(0.5 / dt);  // moves 0.6 m at most: stays under water
  for (int i = 0; i < steps; ++i) world.step(dt);
  const double expected = kGravity * (kWater - density) / (density + coefficient * kWater) * steps * dt;
  CHECK(double(ball->getLinearVelocity().y()) == Approx(expected).epsilon(1e-5));
  const double volume = world.controller().report(ball)->massProperties.volume;
  CHECK(world.controller().report(ball)->addedMass == Approx(coefficient * kWater * volume).epsilon(1e-6));
}

TEST_CASE("skin friction on a plate moving along itself is ITTC-57's rho/2 C_f U^2 S", "[floating][drag][closed-form]") {
  // A submerged plate L x t x W moving along its length at U with the pressure law off: only the
  // friction acts, on the faces along the motion (wetted S = 2 L (W + t)), with C_f = 0.075 /
  // (log10 Re - 2)^2 at Re = rho U L / mu (ITTC 1957; above Blasius' laminar 1.328 / sqrt(Re) here).
  // The force of the first step is read before the velocity changes; the patch areas are float
  // sums over flat faces (measured 3e-8): 1e-5.
  const double length = 2.0, thickness = 0.02, width = 1.0, mu = 1.0e-3;
  const double speed = GENERATE(0.2, 1.0, 3.0);
  CAPTURE(speed);
  FloatingBodySettings settings = solid(kWater, {Effect::Buoyancy, Effect::Drag});
  settings.drag.advancingPressure = 0.0;
  settings.drag.retreatingPressure = 0.0;
  settings.drag.linearPressureVelocity = 0.0;
  settings.rotationalDamping = 0.0;
  TestWorld world(std::make_shared<FlatSurface>(0.0, kWater), mu);
  btRigidBody* plate = world.add(primitives::box({length, thickness, width}), settings, btVector3(0, -2, 0));
  REQUIRE(plate != nullptr);
  plate->setLinearVelocity(btVector3(btScalar(speed), 0, 0));
  world.step(1.0 / 60.0);
  const double reynolds = kWater * speed * length / mu;
  const double cf = 0.075 / std::pow(std::log10(reynolds) - 2.0, 2.0);
  REQUIRE(cf > 1.328 / std::sqrt(reynolds));
  const double wetted = 2.0 * length * (width + thickness);
  const btVector3 force = world.controller().report(plate)->dragForce;
  CHECK(double(force.x()) == Approx(-0.5 * kWater * cf * speed * speed * wetted).epsilon(1e-5));
  CHECK(std::abs(double(force.y())) < 1e-6 * std::abs(double(force.x())));
  CHECK(std::abs(double(force.z())) < 1e-6 * std::abs(double(force.x())));
}

TEST_CASE("a balloon lighter than air rises at g (rho_air / rho_b - 1)", "[floating][gas]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  const double air = 1.225, gas = 0.5;
  TestWorld world(std::make_shared<UniformMedium>(air, std::numeric_limits<double>::infinity(), 0.0), 1.8e-5);
  btRigidBody* balloon = world.add(primitives::icosphere(1.0, 3), solid(gas, {Effect::Buoyancy}, method), btVector3(0, 0, 0));
  REQUIRE(balloon != nullptr);
  const int steps = int(1.0 / dt);
  for (int i = 0; i < steps; ++i) world.step(dt);
  // Constant density: the lift is rho_air g V exactly (closed mesh, volume exact on both paths).
  const double expected = kGravity * (air / gas - 1.0) * steps * dt;
  CHECK(double(balloon->getLinearVelocity().y()) == Approx(expected).epsilon(2e-3));
}
