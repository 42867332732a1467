// SPDX-License-Identifier: Zlib
// The deformation effect: vertices moved every step (scale keyframes or a callback), PT/VAT
// re-evaluated from the kept bake, buoyancy and mass following; hot-air balloons lifting off when
// the displaced air outweighs envelope, basket and inner gas (ideal gas law), against the closed
// form. A callback's moved vertices move the collision shape too (hulls, triangle meshes; a
// convex hull on request for primitives), so an inflated body rests on the floor at its new size.

#include <catch2/catch.hpp>

#include <BulletCollision/Gimpact/btGImpactShape.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "PluginTestWorld.hpp"
#include "hydrotex/mass/IdealGas.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

namespace {

constexpr double kAir = 1.225;     // kg/m^3, sea level
constexpr double kHot = 373.15;    // K, inner gas of the inflating balloon
constexpr double kBasket = 5.0;    // kg
constexpr double kEnvelope = 0.05; // kg/m^2

/// An envelope whose lowest point is the mesh origin, so that scaling about the origin keeps it on
/// the ground.
Mesh envelopeMesh(double radius) {
  Mesh mesh = primitives::icosphere(radius, 3);
  double lowest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : mesh.positions) lowest = std::min(lowest, p.y());
  for (Eigen::Vector3d& p : mesh.positions) p.y() -= lowest;
  return mesh;
}

double surfaceArea(const Mesh& mesh) {
  double area = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    area += 0.5 * (mesh.positions[std::size_t(t[1])] - mesh.positions[std::size_t(t[0])])
                      .cross(mesh.positions[std::size_t(t[2])] - mesh.positions[std::size_t(t[0])])
                      .norm();
  }
  return area;
}

/// A world of air over a ground plane at y = 0.
struct BalloonWorld {
  TestWorld world{std::make_shared<UniformMedium>(kAir, std::numeric_limits<double>::infinity(), 0.0), 1.8e-5};
  btStaticPlaneShape groundShape{btVector3(0, 1, 0), 0};
  btRigidBody ground{btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &groundShape)};
  BalloonWorld() {
    world.world().addRigidBody(&ground);
    // Contacts correct penetration by split impulses only, so that the velocity the tests read
    // is the controller's (lift - weight) and never Bullet's push out of the ground.
    world.world().getSolverInfo().m_splitImpulse = 1;
    world.world().getSolverInfo().m_splitImpulsePenetrationThreshold = 0;
  }
  ~BalloonWorld() { world.world().removeRigidBody(&ground); }
  /// The balloon resting on the ground (mesh origin at its lowest point), touching it exactly.
  btRigidBody* add(const Mesh& mesh, const FloatingBodySettings& settings) {
    btRigidBody* body = world.add(mesh, settings, btVector3(0, 0, 0));
    if (body != nullptr) {
      auto* compound = static_cast<btCompoundShape*>(body->getCollisionShape());
      compound->getChildShape(0)->setMargin(0);
      compound->recalculateLocalAabb();
    }
    return body;
  }
};

FloatingBodySettings balloonSettings(double gasDensity, EffectSet effects) {
  FloatingBodySettings settings;
  settings.density = gasDensity;  // the inner gas fills the envelope
  settings.shellDensity = kEnvelope;
  PointMass basket;
  basket.mass = kBasket;
  settings.pointMasses = {basket};  // hangs at the envelope's lowest point
  settings.effects = effects;
  settings.resolution = 128;
  return settings;
}

}  // namespace

TEST_CASE("an inflating hot-air balloon lifts off when the displaced air outweighs it", "[deformation][gas][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  CAPTURE(dt);
  const Mesh mesh = envelopeMesh(1.0);
  const double gas = idealGasDensity(kStandardPressure, kMolarMassAir, kHot);
  FloatingBodySettings settings = balloonSettings(gas, {Effect::Buoyancy, Effect::Deformation});
  const double s0 = 1.0, s1 = 3.0, inflation = 10.0;  // scale 1 -> 3 over 10 s
  settings.scaleKeyframes = {{0.0, Eigen::Vector3d::Constant(s0)}, {inflation, Eigen::Vector3d::Constant(s1)}};
  BalloonWorld air;
  btRigidBody* balloon = air.add(mesh, settings);
  REQUIRE(balloon != nullptr);

  // Closed form: at scale s the lift rho_air V0 s^3 g balances (sigma A0 + m_b + rho_gas V0 s^3) g,
  // V0 and A0 of the polyhedral envelope (the texel sums give both exactly: PT . VAT, sum |VAT|):
  // the envelope keeps its mass sigma A0 as it stretches, the hot gas its density.
  const auto unit = polyhedralMassProperties(mesh, 1.0);
  REQUIRE(unit.ok());
  const double v0 = unit->volume, a0 = surfaceArea(mesh);
  auto excess = [&](double s) { return (kAir - gas) * v0 * s * s * s - kEnvelope * a0 - kBasket; };
  REQUIRE(excess(s0) < 0.0);
  REQUIRE(excess(s1) > 0.0);
  double low = s0, high = s1;
  for (int i = 0; i < 60; ++i) (excess(0.5 * (low + high)) < 0.0 ? low : high) = 0.5 * (low + high);
  const double liftOff = (0.5 * (low + high) - s0) / (s1 - s0) * inflation;

  double measured = -1.0;
  int steps = 0;
  for (int i = 0; i < int(inflation / dt) && measured < 0.0; ++i, ++steps) {
    air.world.step(dt);
    // The controller sets the velocity after Bullet's contacts: it points up from the first step
    // whose net force (lift - weight) is positive.
    if (balloon->getLinearVelocity().y() > 0) measured = (i + 1) * dt;
  }
  // One step to see the sign change, one for the mass and shape taken at the step's end time:
  // 2 dt. The texel sums hold volume and area to float rounding (1e-6, far below).
  CHECK(measured == Approx(liftOff).margin(2.0 * dt));
  // And it leaves the ground: a second later its lowest point (the mesh origin) is in the air.
  for (int i = 0; i < int(1.0 / dt); ++i, ++steps) air.world.step(dt);
  CHECK(double(air.world.controller().meshTransform(balloon)->getOrigin().y()) > 1e-2);
  // One deformation per step, and one at registration.
  CHECK(air.world.controller().statistics().deformations == std::uint64_t(steps) + 1);
}

TEST_CASE("a heated balloon lifts off at the temperature the ideal gas law gives", "[variable-mass][gas][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  CAPTURE(dt);
  const Mesh mesh = envelopeMesh(4.0);
  const double startTemperature = 288.15, heating = 20.0;  // K, K/s
  FloatingBodySettings settings = balloonSettings(idealGasDensity(kStandardPressure, kMolarMassAir, startTemperature),
                                                  {Effect::Buoyancy, Effect::VariableMass});
  BalloonWorld air;
  btRigidBody* balloon = air.add(mesh, settings);
  REQUIRE(balloon != nullptr);
  MassModel* model = air.world.controller().massModel(balloon);
  REQUIRE(model != nullptr);

  // Closed form: lift-off when rho_gas(T) = rho_air - (sigma A + m_b) / V, T = p M / (R rho_gas).
  const auto unit = polyhedralMassProperties(mesh, 1.0);
  REQUIRE(unit.ok());
  const double gasAtLiftOff = kAir - (kEnvelope * surfaceArea(mesh) + kBasket) / unit->volume;
  REQUIRE(gasAtLiftOff > 0.0);
  const double liftOffTemperature = kStandardPressure * kMolarMassAir / (kGasConstant * gasAtLiftOff);
  const double liftOff = (liftOffTemperature - startTemperature) / heating;

  double measured = -1.0;
  for (int i = 0; i < int(2.0 * liftOff / dt) && measured < 0.0; ++i) {
    const double temperature = startTemperature + heating * (i + 1) * dt;  // at the step's end
    REQUIRE(model->setSolidDensity(idealGasDensity(kStandardPressure, kMolarMassAir, temperature)).ok());
    air.world.step(dt);
    if (balloon->getLinearVelocity().y() > 0) measured = (i + 1) * dt;
  }
  // One step to see the sign change (dt); the texel sums are exact for volume and area.
  CHECK(measured == Approx(liftOff).margin(1.01 * dt));
}

TEST_CASE("a growing box floats at the draft of its current size", "[deformation][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  CAPTURE(dt);
  FloatingBodySettings settings = solid(500.0, {Effect::Buoyancy, Effect::Drag, Effect::Deformation},
                                        HydrostaticsMethod::Texture, 64);
  settings.scaleKeyframes = {{0.0, Eigen::Vector3d::Ones()}, {2.0, Eigen::Vector3d(1.0, 1.6, 1.0)}};
  TestWorld world;
  btRigidBody* box = world.add(primitives::box({2.0, 1.0, 1.5}), settings, btVector3(0, 0, 0));
  REQUIRE(box != nullptr);
  for (int i = 0; i < int(25.0 / dt); ++i) world.step(dt);
  const FloatingBodyReport& report = *world.controller().report(box);
  // Height 1.6 m: volume 4.8 m^3 (PT/VAT exact on flat texels: 1e-6), mass 2400 kg, draft 0.8 m.
  CHECK(report.massProperties.volume == Approx(4.8).epsilon(1e-6));
  CHECK(report.massProperties.mass == Approx(2400.0).epsilon(1e-6));
  CHECK(report.hydrostatics.submergedVolume == Approx(2.4).epsilon(2e-3));  // at rest: weight / (rho g)
  // Mesh origin at the box's middle: it scales about it, so the centre sits at 0.8 - 0.8 = 0.
  // 2 mm as the rigid box's draft test.
  CHECK(double(world.controller().meshTransform(box)->getOrigin().y()) == Approx(0.0).margin(2e-3));
}

TEST_CASE("a growing body keeps the mass or density it was given: closed-form drafts", "[deformation][closed-form]") {
  // A square slab a x h x a (a = 2 m, h = 0.5 m; a cube would tip at these relative densities)
  // grown uniformly to s = 1.2 over 2 s, by scale keyframes or by a callback. At rest its draft is
  // M / (rho (s a)^2) for a kept mass M (given by `mass`, or a shell's sigma A0), and
  // rho_b / rho s h for a kept density rho_b. A shell that kept sigma instead would weigh s^2 more.
  const double a = 2.0, h = 0.5, s = 1.2, rho = 1000.0;
  const bool keyframes = GENERATE(true, false);
  const int given = GENERATE(0, 1, 2);  // mass, density, shell
  CAPTURE(keyframes, given);
  FloatingBodySettings settings;
  settings.effects = EffectSet{Effect::Buoyancy, Effect::Drag, Effect::Deformation};
  settings.resolution = 64;
  double draft = 0.0, mass = 0.0;
  if (given == 0) {
    settings.mass = 1000.0;  // density 500 at rest
    mass = 1000.0;
    draft = mass / (rho * s * a * s * a);
  } else if (given == 1) {
    settings.density = 500.0;
    mass = 500.0 * a * h * a * s * s * s;
    draft = 500.0 / rho * s * h;
  } else {
    settings.shellDensity = 50.0;  // hollow: 50 kg/m^2 over 2 (a^2 + 2 a h) = 12 m^2
    mass = 50.0 * 2.0 * (a * a + 2.0 * a * h);
    draft = mass / (rho * s * a * s * a);
  }
  if (keyframes) {
    settings.scaleKeyframes = {{0.0, Eigen::Vector3d::Ones()}, {2.0, Eigen::Vector3d::Constant(s)}};
  } else {
    settings.deformation = [s](double time, const Mesh& rest, std::vector<Eigen::Vector3d>& positions) {
      const double scale = 1.0 + (s - 1.0) * std::min(time / 2.0, 1.0);
      for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = scale * rest.positions[i];
    };
  }
  TestWorld world;
  btRigidBody* slab = world.add(primitives::box({a, h, a}), settings, btVector3(0, 0, 0));
  REQUIRE(slab != nullptr);
  for (int i = 0; i < int(20.0 / (1.0 / 60.0)); ++i) world.step(1.0 / 60.0);
  const FloatingBodyReport& report = *world.controller().report(slab);
  // Mass: the triangle sums in double are exact on a box (measured 2e-16): 1e-9. Volume: PT/VAT
  // exact on flat texels (1e-6).
  CHECK(report.massProperties.mass == Approx(mass).epsilon(1e-9));
  CHECK(report.massProperties.volume == Approx(a * h * a * s * s * s).epsilon(1e-6));
  // The mesh origin is the slab's middle, so its bottom is s h / 2 below it: draft = s h / 2 - y.
  // Measured within 3e-8 m (flat texels are exact; Bullet's float position and what the drag
  // leaves of the heave after 20 s): 1e-6 m. A shell that kept sigma is 4 cm off, a solid that
  // kept its density under `mass` 4 cm too.
  const double y = double(world.controller().meshTransform(slab)->getOrigin().y());
  CHECK(s * h / 2.0 - y == Approx(draft).margin(1e-6));
}

TEST_CASE("a deformation callback moves the vertices; volume and mass follow", "[deformation]") {
  FloatingBodySettings settings = solid(300.0, {Effect::Buoyancy, Effect::Deformation}, HydrostaticsMethod::Texture, 32);
  settings.deformation = [](double time, const Mesh& rest, std::vector<Eigen::Vector3d>& positions) {
    const double stretch = 1.0 + 0.5 * std::min(time, 1.0);  // x grows to 1.5 in one second
    for (std::size_t i = 0; i < positions.size(); ++i) positions[i].x() = rest.positions[i].x() * stretch;
  };
  TestWorld world(std::make_shared<UniformMedium>(kAir, std::numeric_limits<double>::infinity(), 0.0), 1.8e-5);
  btRigidBody* box = world.add(primitives::box({1.0, 1.0, 1.0}), settings, btVector3(0, 0, 0));
  REQUIRE(box != nullptr);
  for (int i = 0; i < 90; ++i) world.step(1.0 / 60.0);
  const FloatingBodyReport& report = *world.controller().report(box);
  // 1.5 x 1 x 1 box: PT/VAT exact on flat texels (1e-6).
  CHECK(report.massProperties.volume == Approx(1.5).epsilon(1e-6));
  CHECK(report.massProperties.mass == Approx(450.0).epsilon(1e-6));
  CHECK(report.hydrostatics.submergedVolume == Approx(1.5).epsilon(1e-6));
  // Settings that cannot deform are refused with the reason.
  FloatingBodySettings neither = solid(300.0, {Effect::Deformation}, HydrostaticsMethod::Texture);
  neither.mesh = std::make_shared<const Mesh>(primitives::box({1.0, 1.0, 1.0}));
  CHECK(neither.validate().error().message.find("deformation") != std::string::npos);
}

// ---- The collision shape of a body moved by a deformation callback ----

namespace {

/// Doubles the body about its mesh origin over its first second.
void inflateTwice(double time, const Mesh& rest, std::vector<Eigen::Vector3d>& positions) {
  const double scale = 1.0 + std::min(time, 1.0);
  for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = scale * rest.positions[i];
}

/// Air over a ground plane at y = 0: nothing floats, the ground carries the body.
struct GroundWorld {
  TestWorld world{std::make_shared<UniformMedium>(kAir, std::numeric_limits<double>::infinity(), 0.0), 1.8e-5};
  btStaticPlaneShape groundShape{btVector3(0, 1, 0), 0};
  btRigidBody ground{btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &groundShape)};
  GroundWorld() { world.world().addRigidBody(&ground); }
  ~GroundWorld() { world.world().removeRigidBody(&ground); }
  /// Height of the mesh origin (m) after `seconds` of 1/120 s steps.
  double heightAfter(btRigidBody* body, double seconds) {
    for (int i = 0; i < int(seconds * 120.0); ++i) world.step(1.0 / 120.0);
    return double(world.controller().meshTransform(body)->getOrigin().y());
  }
};

FloatingBodySettings inflatingBox() {
  FloatingBodySettings settings = solid(500.0, {Effect::Buoyancy, Effect::Deformation}, HydrostaticsMethod::Texture, 32);
  settings.deformation = inflateTwice;
  return settings;
}

/// Convex margin of the body's collision shape (the compound's child), m.
double childMargin(btRigidBody* body) {
  return double(static_cast<btCompoundShape*>(body->getCollisionShape())->getChildShape(0)->getMargin());
}

}  // namespace

TEST_CASE("a body inflated 2x by a deformation callback rests on the floor at its new size", "[deformation][collision]") {
  // A 1 m box resting on the ground (centre 0.5 m up) grows to 2 m: its hull follows the vertices,
  // so it ends resting with its centre 1 m up, plus the hull's convex margin (Bullet puts it
  // around the points). 1 mm: Bullet's resting penetration (measured below 1e-6 m).
  GroundWorld ground;
  btRigidBody* box = ground.world.add(primitives::box({1.0, 1.0, 1.0}), inflatingBox(), btVector3(0, 0.5f, 0));
  REQUIRE(box != nullptr);
  const btCollisionShape* hull = static_cast<btCompoundShape*>(box->getCollisionShape())->getChildShape(0);
  btVector3 lower, upper;
  hull->getAabb(btTransform::getIdentity(), lower, upper);
  const btVector3 restSize = upper - lower;  // 1 m plus the margins Bullet adds
  const double height = ground.heightAfter(box, 3.0);
  CHECK(height == Approx(1.0 + childMargin(box)).margin(1e-3));
  // The hull's bounds (mesh frame) grew by the box's growth, 1 m per axis (float bounds: 1e-3).
  hull->getAabb(btTransform::getIdentity(), lower, upper);
  for (int c = 0; c < 3; ++c) CHECK(double((upper - lower)[c] - restSize[c]) == Approx(1.0).margin(1e-3));
  CHECK(ground.world.controller().statistics().failedQueries == 0);
}

TEST_CASE("a deformation callback with a primitive shape: an error, a convex hull on request, or kept as asked", "[deformation][collision]") {
  GroundWorld ground;
  btBoxShape boxShape(btVector3(0.5f, 0.5f, 0.5f));
  auto make = [&] {
    btRigidBody::btRigidBodyConstructionInfo info(1, nullptr, &boxShape, btVector3(1, 1, 1));
    auto body = std::make_unique<btRigidBody>(info);
    body->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0.5f, 0)));
    return body;
  };
  FloatingBodySettings settings = inflatingBox();
  settings.mesh = std::make_shared<const Mesh>(primitives::box({1.0, 1.0, 1.0}));
  BuoyancyController& controller = ground.world.controller();

  // Follow (the default): a box shape cannot follow moved vertices; said at registration.
  auto refused = make();
  const Status status = controller.addBody(refused.get(), settings);
  REQUIRE_FALSE(status.ok());
  CHECK(status.error().message.find("cannot follow") != std::string::npos);
  CHECK(status.error().message.find("Box") != std::string::npos);  // btBoxShape::getName()
  CHECK(refused->getCollisionShape() == &boxShape);                  // given back untouched
  CHECK(controller.bodyCount() == 0);

  SECTION("ConvexHull: the body collides as the hull of its moved vertices") {
    settings.deformedCollision = DeformedCollisionShape::ConvexHull;
    auto body = make();
    REQUIRE(controller.addBody(body.get(), settings).ok());
    ground.world.world().addRigidBody(body.get());
    const double height = ground.heightAfter(body.get(), 3.0);
    CHECK(height == Approx(1.0 + childMargin(body.get())).margin(1e-3));  // as above
    ground.world.world().removeRigidBody(body.get());
    REQUIRE(controller.removeBody(body.get()));
    CHECK(body->getCollisionShape() == &boxShape);  // the user's shape back
  }
  SECTION("Keep: the shape stays the 1 m box, so the grown body sinks into the floor") {
    settings.deformedCollision = DeformedCollisionShape::Keep;
    auto body = make();
    REQUIRE(controller.addBody(body.get(), settings).ok());
    ground.world.world().addRigidBody(body.get());
    CHECK(ground.heightAfter(body.get(), 3.0) == Approx(0.5).margin(1e-2));  // the box shape's own rest height
    ground.world.world().removeRigidBody(body.get());
    REQUIRE(controller.removeBody(body.get()));
  }
}

TEST_CASE("triangle-mesh shapes over the mesh's vertices are rewritten and refitted", "[deformation][collision]") {
  const Mesh mesh = primitives::box({1.0, 1.0, 1.0});
  // The user's vertex array: the mesh's vertices in order (btScalar: this constructor takes
  // Bullet's own precision), its triangles.
  std::vector<btScalar> vertices;
  for (const Eigen::Vector3d& p : mesh.positions)
    for (int c = 0; c < 3; ++c) vertices.push_back(btScalar(p[c]));
  std::vector<int> indices;
  for (const Eigen::Vector3i& t : mesh.triangles)
    for (int c = 0; c < 3; ++c) indices.push_back(t[c]);
  btTriangleIndexVertexArray array(int(mesh.triangles.size()), indices.data(), 3 * int(sizeof(int)),
                                   int(mesh.positions.size()), vertices.data(), 3 * int(sizeof(btScalar)));
  const bool gimpact = GENERATE(true, false);
  CAPTURE(gimpact);
  std::unique_ptr<btCollisionShape> shape;
  if (gimpact) {
    auto made = std::make_unique<btGImpactMeshShape>(&array);
    made->updateBound();
    shape = std::move(made);
  } else {
    shape = std::make_unique<btBvhTriangleMeshShape>(&array, true);
  }
  TestWorld world(std::make_shared<UniformMedium>(kAir, std::numeric_limits<double>::infinity(), 0.0), 1.8e-5);
  btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, shape.get(), btVector3(1, 1, 1)));
  FloatingBodySettings settings = inflatingBox();
  settings.mesh = std::make_shared<const Mesh>(mesh);
  REQUIRE(world.controller().addBody(&body, settings).ok());
  btVector3 lower, upper;
  shape->getAabb(btTransform::getIdentity(), lower, upper);
  const btVector3 restSize = upper - lower;  // 1 m plus whatever margins the shape adds
  for (int i = 0; i < 150; ++i) world.step(1.0 / 120.0);  // 1.25 s: fully grown
  // The vertex array holds the grown vertices (float rounding), and the shape's bounds are 2 m.
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    for (int c = 0; c < 3; ++c) CHECK(double(vertices[3 * i + std::size_t(c)]) == Approx(2.0 * mesh.positions[i][c]).margin(1e-6));
  // The refitted bounds grew by the box's growth, 1 m per axis (float bounds: 1e-3).
  shape->getAabb(btTransform::getIdentity(), lower, upper);
  for (int c = 0; c < 3; ++c) CHECK(double((upper - lower)[c] - restSize[c]) == Approx(1.0).margin(1e-3));
  REQUIRE(world.controller().removeBody(&body));
}
