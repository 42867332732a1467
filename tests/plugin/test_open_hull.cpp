// SPDX-License-Identifier: Zlib
// Open hulls by design in Bullet (issue 20 item 2): an open-top box whose mass is its shell's
// floats at the closed-form draft with its lid dry and no liquid taken on; loaded past its
// freeboard, its rim goes under, liquid pours in through the lid, and it swamps and sinks with
// the volume below its rim held.
#include <catch2/catch.hpp>

#include <iomanip>

#include "OpenTopBox.hpp"
#include "PluginTestWorld.hpp"
#include "hydrotex/mesh/MeshRepair.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::TestWorld;

namespace {

// 2 m x 0.5 m x 1 m (x, y, z) open at the top: walls 5 m^2, lid 2 m^2 at y = +0.25 (mesh frame),
// volume below the rim L B H = 1 m^3 (its displacement when the rim reaches the surface).
constexpr double kLength = 2.0, kDepth = 0.5, kBeam = 1.0, kWallArea = 5.0;
constexpr double kWater = 1000.0;  // kg/m^3 (TestWorld's surface)

Mesh openBox() {
  Mesh mesh = hydrotex::testing::openTopBox(Eigen::Vector3d(kLength, kDepth, kBeam), 4);
  RepairSettings settings;
  settings.openHull = true;
  auto report = repairMesh(mesh, settings);
  REQUIRE(report);
  REQUIRE(report->unrepaired.empty());
  REQUIRE(report->lids.size() == 1);
  return mesh;
}

FloatingBodySettings shellOnly(double shellDensity) {
  FloatingBodySettings settings;
  settings.shellDensity = shellDensity;
  settings.method = HydrostaticsMethod::Texture;  // the path whose lids and texels this suite checks (Auto picks the exact one)
  settings.resolution = 64;
  settings.effects = EffectSet{Effect::Buoyancy, Effect::Drag, Effect::Flooding};
  settings.flooding.graph.cellBudget = 4096;
  return settings;
}

}  // namespace

TEST_CASE("open hull: an open box of shell density floats at its closed-form draft, dry", "[open_hull]") {
  // Mass m = sigma A_walls = 60 x 5 = 300 kg; a box floats upright at draft d = m / (rho L B)
  // = 300 / (1000 x 2 x 1) = 0.15 m (Archimedes; the walls' centre of mass, 0.1 m below the box's
  // centre, keeps it upright: GM = d / 2 + B^2 / (12 d) - 0.15 = 0.48 m > 0). Its mesh origin,
  // the box's centre, then rests at y = H / 2 - d = 0.10 m, its rim 0.35 m over the surface.
  TestWorld world;
  const Mesh box = openBox();
  btRigidBody* body = world.add(box, shellOnly(60.0), btVector3(0, 0.2f, 0));
  REQUIRE(body != nullptr);
  const FloatingBodyReport& report = *world.controller().report(body);
  // The lid has no mass: the walls' 300 kg (texel areas in float, 1e-5 relative).
  CHECK(report.massProperties.mass == Approx(60.0 * kWallArea).epsilon(1e-5));
  for (int i = 0; i < 120 * 20; ++i) world.step(1.0 / 120.0);
  const double draft = 0.5 * kDepth - double(world.controller().meshTransform(body)->getOrigin().y());
  INFO("draft " << std::setprecision(10) << draft << " m");
  // Within the 1 mm the controller's rest detection allows (as the intact barge of test_flooding).
  CHECK(draft == Approx(60.0 * kWallArea / (kWater * kLength * kBeam)).margin(1e-3));
  // The lid stays above the surface and the walls are tight without a map: nothing enters.
  CHECK(world.controller().report(body)->liquidVolume == 0.0);
}

TEST_CASE("open hull: loaded past its freeboard, an open box swamps and holds the volume below its rim",
          "[open_hull][flooding]") {
  // 300 kg of shell and 800 kg of cargo weigh more than the 1000 kg the box displaces with its
  // rim at the surface: the rim goes under, liquid pours in through the lid, and the box, its
  // walls having no volume, sinks full: the liquid graph holds L B H = 1 m^3.
  TestWorld world;
  FloatingBodySettings settings = shellOnly(60.0);
  PointMass cargo;
  cargo.mass = 800.0;
  cargo.position = Eigen::Vector3d(0, -0.2, 0);
  settings.pointMasses.push_back(cargo);
  btRigidBody* body = world.add(openBox(), settings, btVector3(0, 0.2f, 0));
  REQUIRE(body != nullptr);
  const double dryMass = world.controller().report(body)->massProperties.mass;
  CHECK(dryMass == Approx(60.0 * kWallArea + 800.0).epsilon(1e-5));
  for (int i = 0; i < 120 * 20; ++i) world.step(1.0 / 120.0);
  const FloatingBodyReport& report = *world.controller().report(body);
  INFO("held " << std::setprecision(10) << report.liquidVolume << " m^3, mesh origin at y = "
               << world.controller().meshTransform(body)->getOrigin().y() << " m");
  // Full: the graph's capacity is the volume below the rim from the texels' exact cones, in float
  // (1e-5 relative).
  CHECK(report.liquidVolume == Approx(kLength * kDepth * kBeam).epsilon(1e-5));
  // The held liquid is the body's extra mass (the mass model combines in double).
  CHECK(report.massProperties.mass == Approx(dryMass + kWater * report.liquidVolume).epsilon(1e-9));
  // Sunk: its rim (0.25 m above its origin) well under the surface and still going.
  CHECK(world.controller().meshTransform(body)->getOrigin().y() < -1.0f);
}
