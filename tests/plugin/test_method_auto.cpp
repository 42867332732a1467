// SPDX-License-Identifier: Zlib
// bullet::HydrostaticsMethod::Auto: resolved at addBody by core's advisor to the exact path for a
// low-poly body and to the texture path for a high-poly one under a loose target; the report says
// which; the scene key and the settings' target are checked.

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "PluginTestWorld.hpp"
#include "TestPaths.hpp"
#include "hydrotex/bullet/Scene.hpp"
#include "hydrotex/hydrostatics/Advisor.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

TEST_CASE("method auto: the advisor picks the exact path for a low-poly body, the texture path for a high-poly one",
          "[floating][method][auto]") {
  TestWorld world;
  // A 12-triangle box: the exact path answers in well under a microsecond, far under the texture
  // path at 64^2 (README: 3.8 us), whatever the texture's error.
  FloatingBodySettings box = solid(500.0, {Effect::Buoyancy}, bullet::HydrostaticsMethod::Auto);
  btRigidBody* low = world.add(primitives::box({1.0, 0.5, 1.0}), box, btVector3(0, 0, 0));
  REQUIRE(low != nullptr);
  CHECK(world.controller().report(low)->method == bullet::HydrostaticsMethod::Polyhedral);
  // A 32k-triangle sphere under a 1e-2 target: the texture path at 64^2 meets it (its error is
  // about 3e-4, README) in two thirds of the exact path's time (modeled 6.6 against 9.0 us,
  // measured 5.9 against 9.1 at the model's pose, Advisor.hpp).
  FloatingBodySettings sphere = solid(500.0, {Effect::Buoyancy}, bullet::HydrostaticsMethod::Auto);
  sphere.autoMethodError = 1e-2;
  btRigidBody* high = world.add(primitives::uvSphere(0.5, 256, 64), sphere, btVector3(5, 0, 0));
  REQUIRE(high != nullptr);
  CHECK(world.controller().report(high)->method == bullet::HydrostaticsMethod::Texture);
  // A 17,160-triangle sphere: the exact path visits the triangles along its waterline (about
  // sqrt(T)), so it is the cheaper at 256^2 (modeled 6.6 against 23.7 us; measured 5.2 against
  // 25.4, Advisor.hpp), where a cost linear in T had sent it to the texture path; at 64^2 too,
  // barely (6.56 against 6.60 modeled, 5.2 against 5.8 measured), since the flat walk halves its
  // hierarchy across the height (before, 11.4 against 6.9 measured sent it to the texture path).
  auto middle = std::make_shared<const Mesh>(primitives::uvSphere(0.5, 132, 66));
  REQUIRE(middle->triangles.size() == 17160);
  FloatingBodySettings fine = solid(500.0, {Effect::Buoyancy}, bullet::HydrostaticsMethod::Auto, 256);
  fine.autoMethodError = 1e-2;
  btRigidBody* exactSphere = world.add(*middle, fine, btVector3(10, 0, 0));
  REQUIRE(exactSphere != nullptr);
  CHECK(world.controller().report(exactSphere)->method == bullet::HydrostaticsMethod::Polyhedral);
  FloatingBodySettings coarse = fine;
  coarse.resolution = 64;
  btRigidBody* coarseSphere = world.add(*middle, coarse, btVector3(15, 0, 0));
  REQUIRE(coarseSphere != nullptr);
  CHECK(world.controller().report(coarseSphere)->method == bullet::HydrostaticsMethod::Polyhedral);
  // Explicit methods are reported as given.
  btRigidBody* given = world.add(primitives::box({1.0, 0.5, 1.0}), solid(500.0, {Effect::Buoyancy}, bullet::HydrostaticsMethod::Texture),
                                 btVector3(-5, 0, 0));
  REQUIRE(given != nullptr);
  CHECK(world.controller().report(given)->method == bullet::HydrostaticsMethod::Texture);
  for (int i = 0; i < 30; ++i) world.step(1.0 / 60.0);
  CHECK(world.controller().statistics().failedQueries == 0);
}

TEST_CASE("method auto under waves: the exact path where it models the surface, the texture path where it cannot",
          "[floating][method][auto][waves]") {
  // The log_waves scene's sea: curvature bound sum A k^2 / (1 - sum Q k A)^2 = 0.240 / 0.859^2 =
  // 0.325 1/m. A 1 x 0.5 x 1 m box of 12 triangles (longest edge sqrt 2 m): the plain exact path,
  // which takes the surface linear between vertices, may err 0.325 x 2 / 8 x 1 m^2 / 0.5 m^3 =
  // 0.16 of the volume. The prepared path the controller runs models the surface over its
  // triangles instead (test_polyhedral_hydrostatics_waves: within 4.4e-5 V of the per-texel
  // answer, this box under this sea 2.2e-5): beyond its flat-water exactness it has no error of
  // its own to count. At 256^2 it is also the cheaper (modeledExactMicroseconds of its counted
  // work 28.7 against the texture path's modeled 86.8 us; measured under bench_peers' sea 28-38
  // against 48): the exact path.
  const auto logWaves = std::make_shared<GerstnerWaves>(
      std::vector<GerstnerWave>{GerstnerWave{0.3, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                                GerstnerWave{0.1, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5}},
      0.0, 1025.0);
  const Mesh box = primitives::box({1.0, 0.5, 1.0});
  REQUIRE(surfaceCurvatureBound(*logWaves).has_value());
  CHECK(*surfaceCurvatureBound(*logWaves) == Approx(0.2400 / (0.8587 * 0.8587)).epsilon(2e-3));
  CHECK(exactLinearizationError(box, 0.5, *logWaves) == Approx(0.325 * 2.0 / 8.0 * 1.0 / 0.5).epsilon(3e-3));
  CHECK(preparedExactSurfaceError(box, 0.5, *logWaves) == 0.0);
  FloatingBodySettings settings = solid(500.0, {Effect::Buoyancy}, bullet::HydrostaticsMethod::Auto, 256);
  settings.autoMethodError = 1e-3;
  {
    TestWorld world(logWaves);
    settings.mesh = std::make_shared<const Mesh>(box);  // one mesh for both boxes below
    btRigidBody* body = world.add(box, settings, btVector3(0, 0, 0));
    REQUIRE(body != nullptr);
    CHECK(world.controller().report(body)->method == bullet::HydrostaticsMethod::Polyhedral);
    // The mesh Auto prepared to price the exact path is the one the body runs: one preparation,
    // where the body had been prepared again after its pricing; a second box of the kind shares it.
    CHECK(world.controller().statistics().exactPreparations == 1);
    REQUIRE(world.add(box, settings, btVector3(3, 0, 0)) != nullptr);
    CHECK(world.controller().statistics().exactPreparations == 1);
    for (int i = 0; i < 30; ++i) world.step(1.0 / 60.0);
    CHECK(world.controller().statistics().failedQueries == 0);
  }
  // A 3 m log of 32 sides: each side two slivers 3 m long, which the prepared path cuts into
  // strips a local model each (thousands a query). Priced by its counted work, 209 us a query
  // under this sea (measured 267 us a query over 100 poses on the 2-core machine, commit 9edba03), it takes the
  // texture path at 256^2 (modeled 144 us with its waterline factor, 1.75) and at 64^2 (43.6) when
  // the target lets that resolution in; a model in sqrt(T) alone (34 us) had kept it on the exact
  // path. In flat water the exact
  // path stays (modeled 1.7 us against 9.7 at 64^2 and 32.7 at 256^2).
  const Mesh log = primitives::cylinder(0.25, 3.0, 32);
  const Expected<PreparedPolyhedron> preparedLog = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(log));
  REQUIRE(preparedLog.ok());
  const Expected<double> logCost = modeledExactMicroseconds(*preparedLog, *logWaves);
  REQUIRE(logCost.ok());
  CHECK(*logCost > 4.0 * modeledMicrosecondsPerQuery(hydrotex::HydrostaticsMethod::Exact, log.triangles.size(), 0, true));
  for (const int resolution : {256, 64}) {
    FloatingBodySettings logSettings = solid(500.0, {Effect::Buoyancy}, bullet::HydrostaticsMethod::Auto, resolution);
    logSettings.autoMethodError = 1e-2;
    TestWorld world(logWaves);
    btRigidBody* body = world.add(log, logSettings, btVector3(0, 0, 0));
    REQUIRE(body != nullptr);
    INFO("log at " << resolution << "^2");
    CHECK(world.controller().report(body)->method == bullet::HydrostaticsMethod::Texture);
    TestWorld flat;
    btRigidBody* calm = flat.add(log, logSettings, btVector3(0, 0, 0));
    REQUIRE(calm != nullptr);
    CHECK(flat.controller().report(calm)->method == bullet::HydrostaticsMethod::Polyhedral);
  }
  // A long low swell (100 m, 5 cm): the plain path's linearization within 1e-4 of the volume,
  // the interpolated heights' bound (kExactWaveHeightError x 1 m^2 / 0.5 m^3 = 6.7e-6) beside
  // it; the prepared path's exact as well.
  const auto swell = std::make_shared<GerstnerWaves>(
      std::vector<GerstnerWave>{GerstnerWave{0.05, 100.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5}}, 0.0, 1025.0);
  const double swellCurvature = 0.05 * std::pow(2.0 * 3.141592653589793 / 100.0, 2) /
                                std::pow(1.0 - 0.5 * 0.05 * 2.0 * 3.141592653589793 / 100.0, 2);
  CHECK(exactLinearizationError(box, 0.5, *swell) ==
        Approx((swellCurvature * 2.0 / 8.0 + kExactWaveHeightError) * 1.0 / 0.5).epsilon(1e-9));
  CHECK(exactLinearizationError(box, 0.5, *swell) < 1.1e-4);
  {
    TestWorld world(swell);
    btRigidBody* body = world.add(box, settings, btVector3(0, 0, 0));
    REQUIRE(body != nullptr);
    CHECK(world.controller().report(body)->method == bullet::HydrostaticsMethod::Polyhedral);
  }
  // A height grid has no smoothness bound for the models, nor a curvature bound for the plain
  // path's linearization: the texture path.
  const auto grid = std::make_shared<HeightGrid>(8, 8, 1.0, -4.0, -4.0, 0.0, 1000.0);
  CHECK_FALSE(surfaceCurvatureBound(*grid).has_value());
  CHECK(preparedExactSurfaceError(box, 0.5, *grid) == std::numeric_limits<double>::infinity());
  {
    TestWorld world(grid);
    btRigidBody* body = world.add(box, settings, btVector3(0, 0, 0));
    REQUIRE(body != nullptr);
    CHECK(world.controller().report(body)->method == bullet::HydrostaticsMethod::Texture);
  }
}

TEST_CASE("method auto: its target is checked, and scenes take \"auto\"", "[floating][method][auto][scene]") {
  FloatingBodySettings settings = solid(500.0, {Effect::Buoyancy}, bullet::HydrostaticsMethod::Auto);
  settings.mesh = std::make_shared<const Mesh>(primitives::box({1.0, 1.0, 1.0}));
  CHECK(settings.validate().ok());
  settings.autoMethodError = 0.0;
  REQUIRE_FALSE(settings.validate().ok());
  CHECK(settings.validate().error().message.find("autoMethodError") != std::string::npos);

  const std::string base = test::sourcePath("data/meshes");
  auto parse = [&](const std::string& body) {
    return parseScene(R"({"bodies": [{"mesh": "sphere.obj", "mass": 10, )" + body + "}]}", base, "auto.json");
  };
  auto scene = parse(R"("method": "auto", "auto_method_error": 1e-3)");
  REQUIRE(scene.ok());
  CHECK(scene->bodies[0].method == bullet::HydrostaticsMethod::Auto);
  CHECK(scene->bodies[0].autoMethodError == 1e-3);
  CHECK(parse(R"("method": "auto")")->bodies[0].autoMethodError == 1e-4);
  auto bad = parse(R"("method": "fastest")");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("auto") != std::string::npos);
  CHECK_FALSE(parse(R"("method": "auto", "auto_method_error": 0)").ok());
}

TEST_CASE("method auto: bodies given one mesh are measured once", "[floating][method][auto]") {
  TestWorld world;
  // A 32k-triangle sphere at 64^2: the cost model finds the texture path cheaper, so the advisor
  // measures its error (a bake and 20 poses); the second and third body take the first's choice.
  auto sphere = std::make_shared<const Mesh>(primitives::uvSphere(0.5, 256, 64));
  FloatingBodySettings settings = solid(500.0, {Effect::Buoyancy}, bullet::HydrostaticsMethod::Auto);
  settings.autoMethodError = 1e-2;
  settings.mesh = sphere;
  std::vector<btRigidBody*> bodies;
  for (int i = 0; i < 3; ++i) {
    bodies.push_back(world.add(*sphere, settings, btVector3(btScalar(3 * i), 0, 0)));
    REQUIRE(bodies.back() != nullptr);
    CHECK(world.controller().report(bodies.back())->method == bullet::HydrostaticsMethod::Texture);
  }
  CHECK(world.controller().statistics().autoMethodChoices == 1);
  // Another target is another choice.
  settings.autoMethodError = 1e-9;
  btRigidBody* strict = world.add(*sphere, settings, btVector3(12, 0, 0));
  REQUIRE(strict != nullptr);
  CHECK(world.controller().report(strict)->method == bullet::HydrostaticsMethod::Polyhedral);
  CHECK(world.controller().statistics().autoMethodChoices == 2);
}
