// SPDX-License-Identifier: Zlib
// The wetting effect in the controller: only bodies that list it step a liquid texture (effects on
// demand), a box floating at its draft soaks by Darcy's law below the waterline as the closed form
// says, and the scene key `wetting` is read key by key.
#include <catch2/catch.hpp>

#include <cmath>

#include "PluginTestWorld.hpp"
#include "TestPaths.hpp"
#include "hydrotex/bullet/Scene.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

TEST_CASE("wetting costs nothing for bodies that do not list it; a floating box soaks below its waterline",
          "[wetting][effects][closed-form]") {
  TestWorld world;
  const Mesh box = primitives::box({1, 0.5, 1});
  FloatingBodySettings wet = solid(500, {Effect::Buoyancy, Effect::Wetting}, HydrostaticsMethod::Texture, 64);
  wet.wetting.physics.relativeHumidity = 1.0;  // no evaporation: held = absorbed exactly
  wet.wetting.physics.diffusivity = 1e-7;
  // Density 500 in water: draft 0.25 m, so the box placed with its centre on the surface is at rest.
  btRigidBody* soaking = world.add(box, wet, btVector3(0, 0, 0));
  btRigidBody* dry = world.add(box, solid(500, {Effect::Buoyancy}, HydrostaticsMethod::Texture, 64), btVector3(3, 0, 0));
  REQUIRE(soaking != nullptr);
  REQUIRE(dry != nullptr);
  CHECK(world.controller().liquidTexture(dry) == nullptr);
  REQUIRE(world.controller().liquidTexture(soaking) != nullptr);

  const double dt = 1.0 / 60.0;
  const int steps = 180;
  for (int i = 0; i < steps; ++i) world.step(dt);
  const ControllerStatistics& stats = world.controller().statistics();
  CHECK(stats.wettingSteps == static_cast<std::uint64_t>(steps));  // the wetting body only
  CHECK(stats.failedQueries == 0);
  const FloatingBodyReport& report = *world.controller().report(soaking);
  CHECK(world.controller().report(dry)->liquidAbsorbed == 0.0);
  CHECK(report.liquidEvaporated == 0.0);
  CHECK(report.liquidHeld == Approx(report.liquidAbsorbed).epsilon(1e-12));

  // Closed form (Darcy against the pores' back-pressure at the constant head rho g z): a texel at
  // depth z fills as C (1 - exp(-t k rho g z / (mu L C))). The bottom (1 m^2) is at z = 0.25; the
  // four sides (perimeter 4 m) integrate over z in 0..0.25: int (1 - e^(-a z)) dz = h - (1 - e^(-a h)) / a.
  const WettingMaterial& m = wet.wetting.material;
  const double capacity = m.porosity * m.layerThickness, t = steps * dt, h = 0.25;
  const double a = t * m.permeability * 1000.0 * 9.81 / (wet.wetting.physics.viscosity * m.layerThickness * capacity);
  const double expected = capacity * ((1.0 - std::exp(-a * h)) + 4.0 * (h - (1.0 - std::exp(-a * h)) / a));
  // Error budget: texels straddling the waterline count as wholly in or out (half a texel row of
  // a 25 cm side where the head is smallest), the box's small heave about its draft, diffusion
  // (sqrt(2 D t) = 0.8 mm). Measured -0.14 %; tolerance 1 %.
  CAPTURE(report.liquidAbsorbed / expected - 1.0);
  CHECK(report.liquidAbsorbed == Approx(expected).epsilon(0.01));
  // The liquid texture holds it: wet below, dry above. Diffusion carries traces a texel per
  // explicit step, but over sqrt(2 D t) = 0.8 mm nothing worth counting: the top (1 of the 4 m^2)
  // and the sides' upper halves (1 m^2) stay below 1e-3 saturation.
  const LiquidTexture& texture = *world.controller().liquidTexture(soaking);
  float wettest = 0.0f;
  std::size_t dryTexels = 0;
  for (std::size_t i = 0; i < texture.size(); ++i) {
    wettest = std::max(wettest, texture.saturation(i));
    if (texture.saturation(i) < 1e-3f) ++dryTexels;
  }
  CHECK(wettest > 0.5f);
  CHECK(dryTexels > 2 * texture.size() / 5);
}

TEST_CASE("scene key wetting: values read, errors name the key", "[wetting][scene]") {
  const std::string base = hydrotex::test::sourcePath("data/scenes");
  auto parse = [&](const std::string& wetting, const std::string& effects = R"(["buoyancy", "wetting"])") {
    return parseScene(R"({"bodies": [{"name": "b", "mesh": "../meshes/box.obj", "density": 500, "effects": )" + effects +
                          R"(, "wetting": )" + wetting + "}]}",
                      base, "test.json");
  };
  Expected<Scene> scene = parse(R"({"resolution": 32, "diffusivity": 2e-6, "porosity": 0.2, "permeability": 1e-13,
      "humidity": 0.7, "temperature": 300, "sources": [{"type": "sphere", "rate": 1e-4, "centre": [1, 2, 3], "radius": 0.5}]})");
  REQUIRE(scene.ok());
  const WettingBodySettings& w = scene->bodies[0].wetting;
  CHECK(w.resolution == 32);
  CHECK(w.physics.diffusivity == 2e-6);
  CHECK(w.material.porosity == 0.2);
  CHECK(w.material.permeability == 1e-13);
  CHECK(w.physics.relativeHumidity == 0.7);
  CHECK(w.physics.temperature == 300.0);
  REQUIRE(w.sources.size() == 1);
  CHECK(w.sources[0].kind == LiquidSourceKind::Sphere);
  CHECK(w.sources[0].centre == Eigen::Vector3d(1, 2, 3));
  auto error = [&](const std::string& wetting, const std::string& effects = R"(["buoyancy", "wetting"])") {
    Expected<Scene> parsed = parse(wetting, effects);
    return parsed.ok() ? std::string() : parsed.error().message;
  };
  CHECK_THAT(error(R"({"porosity": 1.5})"), Catch::Contains("wetting.porosity"));
  CHECK_THAT(error(R"({"humidity": -1})"), Catch::Contains("wetting.humidity"));
  CHECK_THAT(error(R"({"temperature": 20})"), Catch::Contains("wetting.temperature"));
  CHECK_THAT(error(R"({"resolution": 8})"), Catch::Contains("wetting.resolution"));
  CHECK_THAT(error(R"({"porosty": 0.3})"), Catch::Contains("wetting.porosty"));
  CHECK_THAT(error(R"({"sources": [{"type": "snow"}]})"), Catch::Contains("wetting.sources[0].type"));
  CHECK_THAT(error(R"({"sources": [{"rate": -1}]})"), Catch::Contains("wetting.sources[0].rate"));
  CHECK_THAT(error("{}", R"(["buoyancy"])"), Catch::Contains("needs \"wetting\" in effects"));
  Expected<Scene> ball = loadScene(base + "/wet_ball.json");
  REQUIRE(ball.ok());
  CHECK(ball->bodies[0].effects.has(Effect::Wetting));
  CHECK(ball->bodies[0].wetting.sources.size() == 2);
}
