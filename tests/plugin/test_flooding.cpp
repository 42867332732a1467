// SPDX-License-Identifier: Zlib
// The flooding effect in Bullet: a barge with a hole in its bottom takes on water and sinks, an
// intact one floats on; damage on one side makes it list to that side (the held liquid gathers
// on the low side); the held liquid's mass is the body's extra mass; settings are checked.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

#include "PluginTestWorld.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mesh/ImageMap.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::TestWorld;

namespace {

constexpr int kResolution = 64;

/// A permeability map of the bake's size (texel (row, column) takes pixel (row, column)): white
/// where `damaged(position, unit normal)` holds on the physics atlas the controller will bake.
std::shared_ptr<const ImageMap> damageMap(const Mesh& mesh,
                                          const std::function<bool(const Eigen::Vector3f&, const Eigen::Vector3f&)>& damaged) {
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = kResolution;
  auto geometry = prepareBodyGeometry(mesh, settings);
  REQUIRE(geometry.ok());
  auto map = std::make_shared<ImageMap>();
  map->width = map->height = kResolution;
  map->values.assign(std::size_t(kResolution * kResolution), 0.0f);
  const SurfaceTextures& tex = geometry->textures;
  for (std::size_t t = 0; t < tex.size(); ++t) {
    const Eigen::Vector3f normal = tex.areaVector[t] / std::max(tex.area[t], 1e-30f);
    if (damaged(tex.position[t], normal)) map->values[geometry->bake.texelIndex[t]] = 1.0f;
  }
  return map;
}

/// A hollow 2 m x 1 m x 1 m barge: 60 kg/m^2 shell over 10 m^2 floats at a 0.3 m draft (centre
/// 0.2 m above the surface).
FloatingBodySettings barge(std::shared_ptr<const ImageMap> map) {
  FloatingBodySettings settings;
  settings.shellDensity = 60.0;
  settings.method = HydrostaticsMethod::Texture;  // the texture path on every backend (Auto picks the exact one for a box)
  settings.resolution = kResolution;
  settings.effects = EffectSet{Effect::Buoyancy, Effect::Drag, Effect::Flooding};
  settings.flooding.permeabilityMap = std::move(map);
  settings.flooding.graph.permeability = 1.0e-8;
  settings.flooding.graph.wallThickness = 0.01;
  settings.flooding.graph.cellBudget = 4096;
  return settings;
}

bool bottomPatch(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  return n.y() < -0.99f && std::abs(p.x()) < 0.2f && std::abs(p.z()) < 0.2f;
}

}  // namespace

TEST_CASE("flooding: a barge with a hole in its bottom sinks, an intact one floats") {
  const Mesh box = primitives::subdividedBox(Eigen::Vector3d(2, 1, 1), 2);
  TestWorld world;
  btRigidBody* holed = world.add(box, barge(damageMap(box, bottomPatch)), btVector3(0, 0.2f, 0));
  REQUIRE(holed != nullptr);
  btRigidBody* intact = world.add(box, barge(damageMap(box, [](auto&, auto&) { return false; })), btVector3(5, 0.2f, 0));
  REQUIRE(intact != nullptr);
  const double emptyMass = world.controller().report(holed)->massProperties.mass;
  CHECK(emptyMass == Approx(600.0).epsilon(1e-6));
  for (int i = 0; i < 120 * 20; ++i) world.step(1.0 / 120.0);
  const FloatingBodyReport& holedReport = *world.controller().report(holed);
  const FloatingBodyReport& intactReport = *world.controller().report(intact);
  // Flooded: 600 kg of hull and up to 2000 kg of water against 2000 kg of displacement, so it
  // goes under (its top, 0.5 m above its centre, is below the surface) and keeps going.
  CHECK(holed->getCenterOfMassPosition().y() < -1.0f);
  CHECK(holedReport.liquidVolume > 1.5);
  // The held liquid is the body's extra mass (1000 kg/m^3; the mass model combines in double).
  CHECK(holedReport.massProperties.mass == Approx(emptyMass + 1000.0 * holedReport.liquidVolume).epsilon(1e-9));
  // Intact: nothing enters, it stays at its 0.3 m draft (within the 1 mm the rest detection allows).
  CHECK(intactReport.liquidVolume == 0.0);
  CHECK(intact->getCenterOfMassPosition().y() == Approx(0.2).margin(1e-3));
  CHECK(world.controller().statistics().floodingSteps > 0);
}

TEST_CASE("flooding: the barge lists towards its damaged side") {
  // Two compartments side by side (a longitudinal bulkhead at z = 0, nearly tight), damage low on
  // one side: that compartment fills first, and its water, gathered at the low side, heels the
  // barge further that way.
  const Mesh box = primitives::subdividedBox(Eigen::Vector3d(2, 1, 1), 2);
  auto graph = std::make_shared<ManualLiquidGraph>();
  graph->nodes.push_back({Eigen::Vector3d(0, 0, -0.25), std::nullopt});
  graph->nodes.push_back({Eigen::Vector3d(0, 0, 0.25), std::nullopt});
  graph->edges.push_back({0, 1, 1e-9, std::nullopt, std::nullopt});
  for (double side : {1.0, -1.0}) {
    TestWorld world;
    FloatingBodySettings settings = barge(damageMap(box, [side](const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
      return n.y() < -0.99f && double(p.z()) * side > 0.2 && std::abs(p.x()) < 0.3f;
    }));
    settings.flooding.manualGraph = graph;
    btRigidBody* body = world.add(box, settings, btVector3(0, 0.2f, 0));
    REQUIRE(body != nullptr);
    double listed = 0.0;
    for (int i = 0; i < 120 * 6; ++i) {
      world.step(1.0 / 120.0);
      // The side's edge (z = side * 0.5 in the mesh frame) relative to the other's: negative when low.
      const btTransform mesh = *world.controller().meshTransform(body);
      const double damaged = double((mesh * btVector3(0, 0, btScalar(0.5 * side))).y());
      const double other = double((mesh * btVector3(0, 0, btScalar(-0.5 * side))).y());
      listed = damaged - other;
    }
    INFO("damaged side z " << side);
    const LiquidGraph& liquid = *world.controller().liquidGraph(body);
    const std::size_t damagedNode = side > 0 ? 1 : 0;
    CHECK(liquid.nodes()[damagedNode].liquid > 2.0 * liquid.nodes()[1 - damagedNode].liquid);
    CHECK(listed < -0.05);  // at least 3 degrees of list towards the damage
  }
}

TEST_CASE("flooding: settings are checked with a reason") {
  const Mesh box = primitives::box(Eigen::Vector3d(1, 1, 1));
  TestWorld world;
  FloatingBodySettings settings = barge(nullptr);
  settings.flooding.graph.wallThickness = 0.0;
  CHECK(world.add(box, settings, btVector3(0, 0, 0)) == nullptr);
  CHECK(world.lastStatus.error().message.find("wall_thickness") != std::string::npos);
  settings = barge(nullptr);
  settings.flooding.graph.porosity = 1.5;
  CHECK(world.add(box, settings, btVector3(0, 0, 0)) == nullptr);
  settings = barge(nullptr);
  settings.effects.add(Effect::Deformation);
  settings.scaleKeyframes = {{0.0, Eigen::Vector3d::Ones()}};
  CHECK(world.add(box, settings, btVector3(0, 0, 0)) == nullptr);
  // No map: the whole surface lets liquid through (a sponge).
  settings = barge(nullptr);
  btRigidBody* sponge = world.add(box, settings, btVector3(0, -0.2f, 0));
  REQUIRE(sponge != nullptr);
  CHECK(world.controller().liquidGraph(sponge)->permeableTexels().size() > 1000);
}
