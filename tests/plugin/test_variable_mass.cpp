// SPDX-License-Identifier: Zlib
// The variable_mass effect against closed forms (docs/references.md "Hydrostatics"): a point mass
// moved sideways heels a floating box to tan(heel) = w d / (Delta GM); a shell box floats at the
// draft its mass gives; nothing is recomputed when nothing changed; scene keys and their errors.

#include <catch2/catch.hpp>
#include <cmath>

#include "PluginTestWorld.hpp"
#include "TestPaths.hpp"
#include "hydrotex/bullet/Scene.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

namespace {

constexpr double kWater = 1000.0;

/// The mesh's up axis in the world.
btVector3 meshUp(TestWorld& world, const btRigidBody* body) {
  return world.controller().meshTransform(body)->getBasis() * btVector3(0, 1, 0);
}

}  // namespace

TEST_CASE("a point mass moved sideways heels a box to tan(heel) = w d / (Delta GM)", "[variable-mass][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 120.0);
  const bool fromCode = GENERATE(false, true);
  CAPTURE(dt, fromCode);
  // Box barge: breadth B along x, height H, length L along z; solid 400 kg/m^3 plus w on deck.
  const double breadth = 2.0, height = 1.0, length = 1.5, density = 400.0, w = 60.0, d = 0.4;
  FloatingBodySettings settings = solid(density, {Effect::Buoyancy, Effect::Drag, Effect::VariableMass});
  PointMass cargo;
  cargo.mass = w;
  cargo.position = Eigen::Vector3d(0.0, height / 2, 0.0);
  if (!fromCode) cargo.path = {{0.0, cargo.position}, {2.0, Eigen::Vector3d(d, height / 2, 0.0)}};
  settings.pointMasses = {cargo};
  TestWorld world;
  btRigidBody* box = world.add(primitives::box({breadth, height, length}), settings, btVector3(0, 0.1f, 0));
  REQUIRE(box != nullptr);
  MassModel* model = world.controller().massModel(box);
  REQUIRE(model != nullptr);
  // The controller lets a body sleep once the net torque is under 1e-3 m g L (ControllerSettings),
  // which here is 0.004 rad of heel: kept awake to measure the equilibrium itself.
  box->setActivationState(DISABLE_DEACTIVATION);
  for (int i = 0; i < int(40.0 / dt); ++i) {
    if (fromCode && i == int(1.0 / dt)) REQUIRE(model->setPointMassPosition(0, Eigen::Vector3d(d, height / 2, 0.0)).ok());
    world.step(dt);
  }
  // Closed form (wall-sided box): Delta = box + w, draft T = Delta / (rho B L), KB = T / 2,
  // BM = I_wp / V = B^2 / (12 T), KG from the keel with the cargo on deck.
  const double boxMass = density * breadth * height * length, delta = boxMass + w;
  const double draft = delta / (kWater * breadth * length);
  const double kg = (boxMass * height / 2 + w * height) / delta;
  const double bm = breadth * breadth / (12.0 * draft);
  const double gm = draft / 2 + bm - kg;
  REQUIRE(gm > 0.0);
  const double smallAngle = w * d / (delta * gm);
  const btVector3 up = meshUp(world, box);
  const double tanHeel = double(up.x() / up.y());  // the loaded side (+x) goes down
  // Tolerances: the small-angle law leaves out the wall-sided term, tan(heel) = w d /
  // (Delta (GM + BM tan^2(heel) / 2)) (Biran, Ship Hydrostatics and Stability, 2003, eq. 6.6),
  // 0.13 % here; the box's texel mass properties are exact to float rounding (1e-6); what is left
  // is the residual roll after 40 s of damping and Bullet's float transforms (1e-4 rad on a
  // 0.04 rad heel: 0.25 %). So 0.5 % against the wall-sided law, 0.5 % + 0.13 % against the
  // small-angle law (1 %).
  double wallSided = smallAngle;
  for (int k = 0; k < 50; ++k) wallSided = w * d / (delta * (gm + bm * wallSided * wallSided / 2));
  CHECK(tanHeel == Approx(wallSided).epsilon(5e-3));
  CHECK(tanHeel == Approx(smallAngle).epsilon(1e-2));
  CHECK(world.controller().report(box)->massProperties.mass == Approx(delta).epsilon(1e-6));
  // Only the point mass moved: no texel pass after registration.
  CHECK(world.controller().statistics().massTexelPasses == 0);
  CHECK(world.controller().statistics().massUpdates >= 1);
}

TEST_CASE("a shell box floats higher than a solid one, exactly as its mass says", "[variable-mass][closed-form]") {
  const double dt = GENERATE(1.0 / 60.0, 1.0 / 240.0);
  CAPTURE(dt);
  const Eigen::Vector3d extents(2.0, 1.0, 1.5);
  const double shellDensity = 20.0;  // kg/m^2, a thin steel-like hull
  const double area = 2.0 * (extents.x() * extents.y() + extents.x() * extents.z() + extents.y() * extents.z());
  const double shellMass = shellDensity * area;
  FloatingBodySettings hollow;
  hollow.shellDensity = shellDensity;
  hollow.method = HydrostaticsMethod::Polyhedral;
  hollow.resolution = 64;
  hollow.effects = {Effect::Buoyancy, Effect::Drag};
  TestWorld world;
  btRigidBody* shell = world.add(primitives::box(extents), hollow, btVector3(0, 0.3f, 0));
  REQUIRE(shell != nullptr);
  btRigidBody* full = world.add(primitives::box(extents), solid(400.0, {Effect::Buoyancy, Effect::Drag}),
                                btVector3(5, 0.3f, 0));
  REQUIRE(full != nullptr);
  for (int i = 0; i < int(25.0 / dt); ++i) world.step(dt);
  // Flat texels tile the box exactly: the shell's mass is sigma A to float rounding (1e-6).
  CHECK(world.controller().report(shell)->massProperties.mass == Approx(shellMass).epsilon(1e-6));
  const double shellDraft = shellMass / (kWater * extents.x() * extents.z());
  const double solidDraft = 400.0 / kWater * extents.y();
  auto draftOf = [&](btRigidBody* body) {
    return extents.y() / 2 - double(world.controller().meshTransform(body)->getOrigin().y());
  };
  // 2 mm: as the solid box's draft test (float positions, residual oscillation after 25 s).
  CHECK(draftOf(shell) == Approx(shellDraft).margin(2e-3));
  CHECK(draftOf(full) == Approx(solidDraft).margin(2e-3));
  CHECK(draftOf(shell) < draftOf(full) - 0.2);
}

TEST_CASE("variable mass recomputes nothing when nothing changed", "[variable-mass][cost]") {
  TestWorld world;
  FloatingBodySettings settings = solid(500.0, {Effect::Buoyancy, Effect::VariableMass});
  PointMass still;
  still.mass = 20.0;
  still.position = Eigen::Vector3d(0.1, 0.2, 0.0);
  settings.pointMasses = {still};
  btRigidBody* box = world.add(primitives::box({1.0, 1.0, 1.0}), settings, btVector3(0, 0, 0));
  REQUIRE(box != nullptr);
  btRigidBody* plain = world.add(primitives::box({1.0, 1.0, 1.0}), solid(500.0, {Effect::Buoyancy}), btVector3(3, 0, 0));
  REQUIRE(plain != nullptr);
  CHECK(world.controller().massModel(plain) == nullptr);  // a body that does not list it has none
  MassModel* model = world.controller().massModel(box);
  REQUIRE(model != nullptr);
  for (int i = 0; i < 100; ++i) world.step(1.0 / 60.0);
  CHECK(world.controller().statistics().massUpdates == 0);
  CHECK(model->texelPasses() == 1);  // the one at registration

  // A point mass moved: recombined, no texel pass.
  REQUIRE(model->setPointMassPosition(0, Eigen::Vector3d(-0.2, 0.2, 0.0)).ok());
  for (int i = 0; i < 10; ++i) world.step(1.0 / 60.0);
  CHECK(world.controller().statistics().massUpdates == 1);
  CHECK(world.controller().statistics().massTexelPasses == 0);
  const Eigen::Vector3d expected = (500.0 * Eigen::Vector3d::Zero() + 20.0 * Eigen::Vector3d(-0.2, 0.2, 0.0)) / 520.0;
  // Box centre at the origin to float rounding of the texel sums (1e-6 m).
  CHECK((world.controller().report(box)->massProperties.centerOfMass - expected).norm() < 1e-6);

  // A new density map: one texel pass, then nothing again.
  REQUIRE(model->setTexelDensity(std::vector<float>(model->texelCount(), 300.0f)).ok());
  for (int i = 0; i < 10; ++i) world.step(1.0 / 60.0);
  CHECK(world.controller().statistics().massUpdates == 2);
  CHECK(world.controller().statistics().massTexelPasses == 1);
  CHECK(world.controller().report(box)->massProperties.mass == Approx(300.0 + 20.0).epsilon(1e-6));
}

TEST_CASE("texel mass passes: one backend batch per step when a map changed, none when none did", "[variable-mass][cost][backend]") {
  TestWorld world;
  // Two variable-mass boxes, one on the texture path (its hydrostatics' registration serves the
  // mass pass) and one on the exact path (registered with the backend for its mass pass alone),
  // and a plain box that lists no variable mass.
  FloatingBodySettings texture = solid(500.0, {Effect::Buoyancy, Effect::VariableMass}, HydrostaticsMethod::Texture);
  FloatingBodySettings exact = solid(500.0, {Effect::Buoyancy, Effect::VariableMass}, HydrostaticsMethod::Polyhedral);
  texture.pointMasses = exact.pointMasses = {PointMass{20.0, Eigen::Vector3d(0.1, 0.2, 0.0), {}}};
  btRigidBody* a = world.add(primitives::box({1.0, 1.0, 1.0}), texture, btVector3(0, 0, 0));
  btRigidBody* b = world.add(primitives::box({1.0, 1.0, 1.0}), exact, btVector3(3, 0, 0));
  btRigidBody* plain = world.add(primitives::box({1.0, 1.0, 1.0}), solid(500.0, {Effect::Buoyancy}), btVector3(6, 0, 0));
  REQUIRE(a != nullptr);
  REQUIRE(b != nullptr);
  REQUIRE(plain != nullptr);
  MassModel* modelA = world.controller().massModel(a);
  MassModel* modelB = world.controller().massModel(b);
  REQUIRE(modelA != nullptr);
  REQUIRE(modelB != nullptr);
  const ControllerStatistics& statistics = world.controller().statistics();
  // Nothing changed: no batch, no pass.
  for (int i = 0; i < 10; ++i) world.step(1.0 / 60.0);
  CHECK(statistics.massBatches == 0);
  CHECK(statistics.massBatchBodies == 0);
  CHECK(statistics.massTexelPasses == 0);
  // Both maps replaced every step (two buffers swapped, as an animation would): one batch a step
  // with both bodies in it, read back once.
  std::vector<float> spareA, spareB;  // swapTexelDensity hands back the previous map (none at first)
  double density = 0.0;
  for (int i = 0; i < 10; ++i) {
    density = 300.0 + 10.0 * i;
    spareA.assign(modelA->texelCount(), float(density));
    spareB.assign(modelB->texelCount(), float(density));
    REQUIRE(modelA->swapTexelDensity(spareA).ok());
    REQUIRE(modelB->swapTexelDensity(spareB).ok());
    world.step(1.0 / 60.0);
  }
  CHECK(statistics.massBatches == 10);
  CHECK(statistics.massBatchBodies == 20);
  CHECK(statistics.massTexelPasses == 20);
  CHECK(statistics.massUpdates == 20);
  // A unit box of the map's uniform density plus the point mass. The cone volumes sum to the box's
  // volume to float rounding: 1e-6 on the CPU backend (TextureMassIntegrator, double across blocks
  // of float sums); the GL backend's partial sums round in float per workgroup, and its parity
  // with the CPU is 1e-5 (tests/gpu/test_backend_parity.cpp): 2e-5 bounds both.
  for (const btRigidBody* body : {a, b})
    CHECK(world.controller().report(body)->massProperties.mass == Approx(density + 20.0).epsilon(2e-5));
  // Only one map changes: a batch of one body.
  for (int i = 0; i < 5; ++i) {
    spareA.assign(modelA->texelCount(), float(250.0 + i));
    REQUIRE(modelA->swapTexelDensity(spareA).ok());
    world.step(1.0 / 60.0);
  }
  CHECK(statistics.massBatches == 15);
  CHECK(statistics.massBatchBodies == 25);
}

TEST_CASE("variable mass keeps the shape in place and the momentum when the centre of mass moves", "[variable-mass]") {
  TestWorld world(std::make_shared<UniformMedium>(1.225, std::numeric_limits<double>::infinity(), 0.0), 1.8e-5);
  world.world().setGravity(btVector3(0, 0, 0));
  FloatingBodySettings settings = solid(500.0, {Effect::VariableMass});
  PointMass runner;
  runner.mass = 100.0;
  runner.path = {{0.0, Eigen::Vector3d(-0.4, 0.0, 0.0)}, {1.0, Eigen::Vector3d(0.4, 0.0, 0.0)}};
  settings.pointMasses = {runner};
  btRigidBody* box = world.add(primitives::box({1.0, 1.0, 1.0}), settings, btVector3(0, 0, 0));
  REQUIRE(box != nullptr);
  for (int i = 0; i < 90; ++i) world.step(1.0 / 60.0);
  // docs/design.md "Bullet's frame": a mass moved from outside the dynamics (a path) never makes the
  // body jump: the shape stays where it is and its momentum (zero) is kept, so the hull does not
  // move while the centre of mass follows the runner to (m_r x_r) / M. Float transforms: 1e-5 m.
  const btTransform mesh = *world.controller().meshTransform(box);
  CHECK(mesh.getOrigin().length() < 1e-5);
  CHECK(double(box->getLinearVelocity().length()) < 1e-6);
  CHECK(double(box->getCenterOfMassPosition().x()) == Approx(100.0 * 0.4 / 600.0).margin(1e-5));
  CHECK(world.controller().statistics().massUpdates >= 50);  // every step while the runner moved
}

TEST_CASE("scene keys for mass models and their errors", "[variable-mass][scene]") {
  const std::string base = hydrotex::test::sourcePath("data/scenes");
  const std::string start = R"({"bodies": [{"mesh": "../meshes/box.obj", )";
  auto parse = [&](const std::string& body) { return parseScene(start + body + "}]}", base, "test.json"); };
  {
    auto scene = parse(R"("shell_density": 12.5, "effects": ["buoyancy", "variable_mass"],
                           "point_masses": [{"mass": 80, "position": [0, 0.5, 0], "path": [[0, 0, 0.5, 0], [2, 0.3, 0.5, 0]]}])");
    INFO((scene ? std::string() : scene.error().message));
    REQUIRE(scene.ok());
    REQUIRE(scene->bodies[0].pointMasses.size() == 1);
    CHECK(scene->bodies[0].pointMasses[0].path.size() == 2);
    CHECK(scene->bodies[0].shellDensity == 12.5);
    CHECK_FALSE(scene->bodies[0].density.has_value());
    auto running = SceneWorld::create(*scene);
    INFO((running ? std::string() : running.error().message));
    REQUIRE(running.ok());
  }
  auto errorOf = [&](const std::string& body) {
    auto scene = parse(body);
    return scene ? std::string() : scene.error().message;
  };
  CHECK(errorOf(R"("shell_density": -1)").find("shell_density") != std::string::npos);
  CHECK(errorOf(R"("density_map": "missing.png", "density_range": [0, 1])").find("density_map") != std::string::npos);
  CHECK(errorOf(R"("density": 5, "density_range": [0, 1])").find("density_range") != std::string::npos);
  CHECK(errorOf(R"("density": 5, "point_masses": [{"position": [0, 0, 0]}])").find("point_masses[0].mass") != std::string::npos);
  CHECK(errorOf(R"("density": 5, "point_masses": [{"mass": 1, "path": [[1, 0, 0, 0], [0, 0, 0, 0]]}])")
            .find("point_masses[0].path[1]") != std::string::npos);
  CHECK(errorOf(R"("density": 5, "point_masses": [{"mass": 1, "speed": 3}])").find("point_masses[0].speed") != std::string::npos);
  CHECK(errorOf(R"("density": 5, "deform": {"type": "scale", "keyframes": [[0, 1, 1, 1]]})")
            .find("deform: needs") != std::string::npos);
  CHECK(errorOf(R"("density": 5, "effects": ["deformation"], "deform": {"type": "twist", "keyframes": [[0, 1, 1, 1]]})")
            .find("deform.type") != std::string::npos);
  CHECK(errorOf(R"("density": 5, "effects": ["deformation"], "deform": {"type": "scale", "keyframes": [[0, 1, 0, 1]]})")
            .find("deform.keyframes[0]") != std::string::npos);
  CHECK(errorOf(R"("name": "x")").find("needs density") != std::string::npos);
}
