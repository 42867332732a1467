// SPDX-License-Identifier: Zlib
// BuoyancyController bookkeeping: effects on demand cost nothing, settings are validated, mass
// changes keep the shape and the momentum, floating bodies are not frozen mid-oscillation, scene
// files are checked key by key.

#include <atomic>
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <new>

#include "PluginTestWorld.hpp"
#include "TestPaths.hpp"
#include "hydrotex/bullet/Scene.hpp"
#include "hydrotex/hydrostatics/MeshDragPatches.hpp"

// Allocation counter for the "no allocation" check: every operator new in this executable.
// GCC 12 flags free() on memory from the replaced operator new as mismatched; here both are ours.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<long long> gAllocations{0};
}
void* operator new(std::size_t size) {
  ++gAllocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// The nothrow form too (Catch2 uses it): left to the runtime, it would hand out memory that the
// delete above frees with free(), which AddressSanitizer reports as alloc-dealloc-mismatch.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++gAllocations;
  return std::malloc(size == 0 ? 1 : size);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

TEST_CASE("an effect a body does not list costs nothing", "[controller][effects]") {
  TestWorld world;
  const Mesh box = primitives::box({1, 0.5, 1});
  btRigidBody* plain = world.add(box, solid(500, {}, HydrostaticsMethod::Texture, 64), btVector3(0, 0, 0));
  btRigidBody* buoyant = world.add(box, solid(500, {Effect::Buoyancy}, HydrostaticsMethod::Texture, 64), btVector3(3, 0, 0));
  btRigidBody* dragged =
      world.add(box, solid(500, {Effect::Buoyancy, Effect::Drag}, HydrostaticsMethod::Texture, 64), btVector3(6, 0, 0));
  REQUIRE(plain != nullptr);
  REQUIRE(buoyant != nullptr);
  REQUIRE(dragged != nullptr);
  // Memory: nothing for the plain body, texels for buoyancy, texels and patches with drag.
  CHECK(world.controller().report(plain)->effectMemoryBytes == 0);
  CHECK(world.controller().report(buoyant)->effectMemoryBytes > 0);
  CHECK(world.controller().report(dragged)->effectMemoryBytes > world.controller().report(buoyant)->effectMemoryBytes);

  for (int i = 0; i < 10; ++i) world.step(1.0 / 60.0);  // settle containers
  world.controller().resetStatistics();
  const long long before = gAllocations.load();
  const int steps = 20;
  for (int i = 0; i < steps; ++i) world.controller().updateAction(&world.world(), btScalar(1.0 / 60.0));
  // The per-step path allocates nothing at all.
  CHECK(gAllocations.load() - before == 0);
  const ControllerStatistics& stats = world.controller().statistics();
  CHECK(stats.steps == steps);
  CHECK(stats.hydrostaticsQueries == 2 * steps);  // the buoyant and the dragged body only
  CHECK(stats.dragPasses == steps);               // the dragged body only
  CHECK(stats.dragPatchesVisited > 0);
  CHECK(stats.addedMassUpdates == 0);             // nobody listed added_mass
  CHECK(stats.backendBatches == steps);           // both texture bodies in one batch, read back once a step
  CHECK(stats.massBatches == 0);                  // nobody listed variable_mass
  CHECK(stats.massBatchBodies == 0);
}

TEST_CASE("a rigid body's drag runs on its mesh's patches on either path", "[controller][drag]") {
  // A box held deep under the surface (every patch wet) on the texture and on the exact path: one
  // step visits exactly the patches meshDragPatches makes from its triangles with the settings'
  // defaults (cosine 0.9, radius 0.2 of the 1 m largest extent), not the 64^2 bake's texel patches.
  const Mesh box = primitives::box({1, 0.5, 1});
  const std::size_t meshPatches = meshDragPatches(box, 0.9, 0.2 * 1.0).size();
  REQUIRE(meshPatches > 0);
  for (HydrostaticsMethod method : {HydrostaticsMethod::Texture, HydrostaticsMethod::Polyhedral}) {
    CAPTURE(int(method));
    TestWorld world;
    REQUIRE(world.add(box, solid(500, {Effect::Buoyancy, Effect::Drag}, method, 64), btVector3(0, -5, 0)) != nullptr);
    world.step(1.0 / 60.0);
    CHECK(world.controller().statistics().dragPasses == 1);
    CHECK(world.controller().statistics().dragPatchesVisited == meshPatches);
  }
}

TEST_CASE("density maps replaced every step: one mass batch a step, no allocation", "[controller][mass]") {
  TestWorld world;
  const Mesh box = primitives::box({1, 0.5, 1});
  std::vector<btRigidBody*> bodies;
  for (int k = 0; k < 3; ++k)
    bodies.push_back(world.add(box, solid(500, {Effect::Buoyancy, Effect::VariableMass}, HydrostaticsMethod::Texture, 64),
                               btVector3(3.0f * float(k), 0, 0)));
  std::vector<MassModel*> models;
  for (btRigidBody* body : bodies) {
    REQUIRE(body != nullptr);
    models.push_back(world.controller().massModel(body));
    REQUIRE(models.back() != nullptr);
  }
  // Two buffers a body, swapped in turn (MassModel::swapTexelDensity allocates nothing).
  std::vector<std::vector<float>> spare(models.size());
  auto replaceMaps = [&](int step) {
    for (std::size_t k = 0; k < models.size(); ++k) {
      if (spare[k].size() != models[k]->texelCount()) spare[k].assign(models[k]->texelCount(), 0.0f);
      std::fill(spare[k].begin(), spare[k].end(), float(400 + 5 * step + int(k)));
      REQUIRE(models[k]->swapTexelDensity(spare[k]).ok());
    }
  };
  for (int i = 0; i < 10; ++i) {  // settle containers (both buffers of each body grown)
    replaceMaps(i);
    world.step(1.0 / 60.0);
  }
  world.controller().resetStatistics();
  const long long before = gAllocations.load();
  const int steps = 20;
  for (int i = 0; i < steps; ++i) {
    replaceMaps(i);
    world.controller().updateAction(&world.world(), btScalar(1.0 / 60.0));
  }
  CHECK(gAllocations.load() - before == 0);
  const ControllerStatistics& stats = world.controller().statistics();
  CHECK(stats.massBatches == steps);               // every body's pass in one batch, read back once a step
  CHECK(stats.massBatchBodies == 3 * steps);
  CHECK(stats.massTexelPasses == 3 * steps);
  CHECK(stats.backendBatches == steps);            // the hydrostatics: their own batch
}

TEST_CASE("settings say what is wrong", "[controller][settings]") {
  FloatingBodySettings settings;
  settings.mesh = std::make_shared<const Mesh>(primitives::box({1, 1, 1}));
  REQUIRE(settings.validate().ok());
  auto message = [](const FloatingBodySettings& s) { return s.validate().ok() ? std::string() : s.validate().error().message; };
  FloatingBodySettings s = settings;
  s.resolution = 8;
  CHECK_THAT(message(s), Catch::Contains("resolution"));
  s = settings;
  s.density = -1.0;
  CHECK_THAT(message(s), Catch::Contains("density"));
  s = settings;
  s.density = 500.0;
  s.mass = 10.0;
  CHECK_THAT(message(s), Catch::Contains("not both"));
  s = settings;
  s.effects.add(Effect::Flooding);
  s.flooding.graph.wallThickness = 0.0;  // flooding exists now: its own settings are checked
  CHECK_THAT(message(s), Catch::Contains("flooding.wall_thickness"));
  s = settings;
  s.rotationalDamping = std::nan("");
  CHECK_THAT(message(s), Catch::Contains("rotationalDamping"));
  s = settings;
  s.mesh.reset();  // no mesh: the body's collision shape is meshed (ShapeMesh.hpp) as s.shape says
  CHECK(s.validate().ok());
  s.shape.maxRelativeVolumeError = 0.5;
  CHECK_THAT(message(s), Catch::Contains("shape: maxRelativeVolumeError"));

  TestWorld world;
  CHECK_FALSE(world.controller().addBody(nullptr, settings).ok());
  Mesh open = primitives::box({1, 1, 1});
  open.triangles.pop_back();
  CHECK(world.add(open, solid(500, {Effect::Buoyancy}), btVector3(0, 0, 0)) == nullptr);
  FloatingBodySettings missing = solid(500, {Effect::Buoyancy});
  missing.meshPath = "no/such/mesh.obj";
  btBoxShape shape(btVector3(1, 1, 1));
  btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &shape));
  const Status status = world.controller().addBody(&body, missing);
  REQUIRE_FALSE(status.ok());
  CHECK_THAT(status.error().message, Catch::Contains("no/such/mesh.obj"));
}

TEST_CASE("changing mass and centre of mass keeps the shape in place and the momentum", "[controller][frame]") {
  TestWorld world(std::make_shared<FlatSurface>(-100.0, 1000.0));  // far below: no liquid effects
  world.world().setGravity(btVector3(0, 0, 0));
  // A box whose mesh origin is not its centre of mass.
  Mesh box = primitives::box({2, 1, 1});
  for (Eigen::Vector3d& p : box.positions) p += Eigen::Vector3d(1.0, 0.0, 0.0);
  btRigidBody* body = world.add(box, solid(500, {Effect::Buoyancy}), btVector3(5, 0, 0),
                                btQuaternion(btVector3(0, 1, 0), 0.5f));
  REQUIRE(body != nullptr);
  const btTransform placed = *world.controller().meshTransform(body);
  // The mesh frame is where it was put (1e-6 m: float transforms), the body origin is the centre.
  CHECK(double((placed.getOrigin() - btVector3(5, 0, 0)).length()) < 1e-5);
  CHECK(double((body->getCenterOfMassPosition() - placed * btVector3(1, 0, 0)).length()) < 1e-5);

  body->setLinearVelocity(btVector3(1, 0, 0));
  body->setAngularVelocity(btVector3(0, 0, 0));
  MassProperties doubled = world.controller().report(body)->massProperties;
  doubled.mass *= 2.0;
  doubled.inertia *= 2.0;
  REQUIRE(world.controller().setMassProperties(body, doubled).ok());
  // Momentum m v kept: the velocity halves; the mesh has not moved.
  CHECK(double(body->getLinearVelocity().x()) == Approx(0.5).epsilon(1e-5));
  CHECK(double((world.controller().meshTransform(body)->getOrigin() - placed.getOrigin()).length()) < 1e-5);

  MassProperties shifted = doubled;
  shifted.centerOfMass += Eigen::Vector3d(0.5, 0.0, 0.0);
  REQUIRE(world.controller().setMassProperties(body, shifted).ok());
  CHECK(double((world.controller().meshTransform(body)->getOrigin() - placed.getOrigin()).length()) < 1e-5);
  CHECK(double((body->getCenterOfMassPosition() - placed * btVector3(1.5f, 0, 0)).length()) < 1e-5);
  CHECK(double(body->getLinearVelocity().x()) == Approx(0.5).epsilon(1e-5));

  MassProperties bad = shifted;
  bad.inertia(0, 0) = -1.0;
  CHECK_FALSE(world.controller().setMassProperties(body, bad).ok());
}

namespace {

/// A btIDebugDraw that keeps the lines it is given.
class LineRecorder : public btIDebugDraw {
 public:
  struct Line {
    btVector3 from, to, color;
  };
  std::vector<Line> lines;
  void drawLine(const btVector3& from, const btVector3& to, const btVector3& color) override {
    lines.push_back({from, to, color});
  }
  void drawContactPoint(const btVector3&, const btVector3&, btScalar, int, const btVector3&) override {}
  void reportErrorWarning(const char*) override {}
  void draw3dText(const btVector3&, const char*) override {}
  void setDebugMode(int) override {}
  int getDebugMode() const override { return 0; }
  /// The lines drawn in `color`.
  std::vector<Line> inColor(const btVector3& color) const {
    std::vector<Line> out;
    for (const Line& line : lines)
      if (line.color == color) out.push_back(line);
    return out;
  }
};

}  // namespace

TEST_CASE("setLiquid: a slab floating in water rises to the draft of a denser liquid", "[controller][closed-form]") {
  // A 2 x 0.5 x 2 m slab of 500 kg/m^3 (wide: a cube would tip at these relative densities)
  // floats at draft rho_b / rho h: 0.25 m in water, 0.2 m in a liquid of 1250 kg/m^3 (its centre
  // 0.05 m above the surface). The texels of flat faces are exact; what the drag leaves of the
  // heave after 20 s: measured 1.1e-5 m, bound 5e-5 m.
  TestWorld world;
  btRigidBody* slab = world.add(primitives::box({2.0, 0.5, 2.0}), solid(500.0, {Effect::Buoyancy, Effect::Drag},
                                                                        HydrostaticsMethod::Texture, 32),
                                btVector3(0, 0, 0));
  REQUIRE(slab != nullptr);
  for (int i = 0; i < 20 * 60; ++i) world.step(1.0 / 60.0);
  CHECK(double(slab->getCenterOfMassPosition().y()) == Approx(0.25 - 0.25).margin(5e-5));
  LiquidSettings denser;
  denser.surface = std::make_shared<FlatSurface>(0.0, 1250.0);
  REQUIRE(world.controller().setLiquid(denser).ok());
  for (int i = 0; i < 20 * 60; ++i) world.step(1.0 / 60.0);
  CHECK(double(slab->getCenterOfMassPosition().y()) == Approx(0.25 - 0.2).margin(5e-5));
  CHECK(world.controller().report(slab)->hydrostatics.fluidDensity == 1250.0);
  // A liquid that cannot be used is refused and the last one kept.
  LiquidSettings none;
  CHECK_FALSE(world.controller().setLiquid(none).ok());
  world.step(1.0 / 60.0);
  CHECK(world.controller().report(slab)->hydrostatics.fluidDensity == 1250.0);
}

TEST_CASE("debugDraw: the weight and buoyancy arrows and the waterline of a floating slab", "[controller][debug-draw]") {
  // A 2 x 0.5 x 2 m slab at rest at its draft: one red weight arrow from the centre of mass along
  // gravity, one green buoyancy arrow up from the centre of buoyancy, equal at rest; both drawn
  // referenceLength / weight metres per newton (the largest extent, 2 m, for the weight). The
  // waterline crosses the 8 side triangles: 8 blue segments on the surface, 8 m around in all.
  TestWorld world;
  btRigidBody* slab = world.add(primitives::box({2.0, 0.5, 2.0}), solid(500.0, {Effect::Buoyancy, Effect::Drag},
                                                                        HydrostaticsMethod::Texture, 32),
                                btVector3(0, 0, 0));
  REQUIRE(slab != nullptr);
  for (int i = 0; i < 20 * 60; ++i) world.step(1.0 / 60.0);
  LineRecorder recorder;
  world.controller().debugDraw(&recorder);
  const auto weight = recorder.inColor(btVector3(1, 0, 0));
  const auto buoyancy = recorder.inColor(btVector3(0, 1, 0));
  const auto waterline = recorder.inColor(btVector3(0, 0, 1));
  CHECK(recorder.lines.size() == weight.size() + buoyancy.size() + waterline.size());
  REQUIRE(weight.size() == 1);
  REQUIRE(buoyancy.size() == 1);
  // Float vectors: 1e-5 m.
  CHECK(double((weight[0].from - slab->getCenterOfMassPosition()).length()) < 1e-5);
  const btVector3 down = weight[0].to - weight[0].from;
  CHECK(double(down.y()) == Approx(-2.0).epsilon(1e-5));
  CHECK(double(btVector3(down.x(), 0, down.z()).length()) < 1e-5);
  // At rest the buoyancy carries the weight (what the drag leaves of the heave: 1e-4).
  const btVector3 up = buoyancy[0].to - buoyancy[0].from;
  CHECK(double(up.y()) == Approx(2.0).epsilon(1e-4));
  CHECK(double(btVector3(up.x(), 0, up.z()).length()) < 1e-4);
  CHECK(double(buoyancy[0].from.y()) == Approx(-0.125).margin(1e-4));  // half the draft down
  CHECK(waterline.size() == 8);
  double length = 0.0;
  for (const auto& line : waterline) {
    length += double((line.to - line.from).length());
    CHECK(std::abs(double(line.from.y())) < 1e-4);
    CHECK(std::abs(double(line.to.y())) < 1e-4);
  }
  CHECK(length == Approx(8.0).epsilon(1e-4));
  // No drawer: nothing happens.
  world.controller().debugDraw(nullptr);
}

TEST_CASE("a slowly heaving body is not put to sleep; a body at rest afloat may sleep", "[controller][sleep]") {
  TestWorld world;
  // Heave amplitude 5 cm, period 1.4 s: peak speed 0.22 m/s, far under Bullet's 0.8 m/s.
  btRigidBody* heaving = world.add(primitives::box({2, 1, 2}), solid(500, {Effect::Buoyancy}), btVector3(0, -0.05f, 0));
  btRigidBody* damped =
      world.add(primitives::box({2, 1, 2}), solid(500, {Effect::Buoyancy, Effect::Drag}), btVector3(5, -0.05f, 0));
  REQUIRE(heaving != nullptr);
  REQUIRE(damped != nullptr);
  for (int i = 0; i < 60 * 30; ++i) world.step(1.0 / 60.0);
  CHECK(heaving->isActive());
  CHECK(world.controller().report(heaving)->atRest == false);
  CHECK_FALSE(damped->isActive());  // Bullet's timer ran once the controller saw it at rest
}

TEST_CASE("scene files: errors name the key or file", "[scene]") {
  const std::string base = hydrotex::test::sourcePath("data/scenes");
  auto error = [&](const std::string& text) {
    Expected<Scene> scene = parseScene(text, base, "test.json");
    return scene.ok() ? std::string() : scene.error().message;
  };
  const std::string body = R"({"name": "b", "mesh": "../meshes/box.obj", "density": 500})";
  CHECK(error(R"({"bodies": [)" + body + "]}").empty());
  CHECK_THAT(error(R"({"bodies": [)" + body + R"(], "gravty": [0,-9.81,0]})"), Catch::Contains("gravty"));
  CHECK_THAT(error(R"({"bodies": [)" + body + R"(], "dt": "fast"})"), Catch::Contains("dt"));
  CHECK_THAT(error(R"({"bodies": [)" + body + R"(], "dt": -1})"), Catch::Contains("dt"));
  CHECK_THAT(error(R"({"bodies": [)" + body + R"(], "substeps": 0})"), Catch::Contains("substeps"));
  CHECK_THAT(error(R"({"bodies": [{"mesh": "missing.obj", "density": 1}]})"), Catch::Contains("missing.obj"));
  CHECK_THAT(error(R"({"bodies": [{"mesh": "../meshes/box.obj"}]})"), Catch::Contains("density or mass"));
  CHECK_THAT(error(R"({"bodies": [{"mesh": "../meshes/box.obj", "density": 1, "effects": ["magic"]}]})"),
             Catch::Contains("magic"));
  CHECK_THAT(error(R"({"bodies": [)" + body + R"(], "fluid": {"surface": {"type": "lava"}}})"),
             Catch::Contains("fluid.surface.type"));
  CHECK_THAT(error(R"({"fluid": {}})"), Catch::Contains("bodies"));
  CHECK_THAT(error("{not json"), Catch::Contains("not valid JSON"));
  for (const char* name : {"box_floating.json", "log_waves.json", "balloon_air.json", "peers_flat.json", "peers_waves.json"}) {
    CAPTURE(name);
    CHECK(loadScene(base + "/" + name).ok());
  }
}

TEST_CASE("bodies of one mesh and the same settings share one model", "[controller][model]") {
  TestWorld world;
  auto box = std::make_shared<const Mesh>(primitives::box({1, 0.5, 1}));
  FloatingBodySettings settings = solid(500, {Effect::Buoyancy, Effect::Drag}, HydrostaticsMethod::Texture, 64);
  settings.mesh = box;
  btRigidBody* first = world.add(*box, settings, btVector3(0, btScalar(0.1), 0));
  btRigidBody* second = world.add(*box, settings, btVector3(0, btScalar(0.1), 3));
  btRigidBody* third = world.add(*box, settings, btVector3(0, btScalar(0.1), 6));
  // The same box from its own copy of the mesh: a model of its own, the reference.
  FloatingBodySettings own = settings;
  own.mesh = std::make_shared<const Mesh>(*box);
  btRigidBody* alone = world.add(*box, own, btVector3(0, btScalar(0.1), 9));
  REQUIRE(first != nullptr);
  REQUIRE(second != nullptr);
  REQUIRE(third != nullptr);
  REQUIRE(alone != nullptr);
  BuoyancyController& controller = world.controller();
  // Both backends share the first body's texels (addInstance): the CPU one its tiles, the GL one
  // its texel buffers (the instances get chunk records of their own).
  CHECK_FALSE(controller.report(first)->sharesModel);
  CHECK(controller.report(first)->effectMemoryBytes > 0);
  for (const btRigidBody* body : {second, third}) {
    CHECK(controller.report(body)->sharesModel);
    CHECK(controller.report(body)->effectMemoryBytes == 0);  // no texel, no patch of its own
  }
  CHECK_FALSE(controller.report(alone)->sharesModel);
  // A different resolution is a different model.
  FloatingBodySettings finer = settings;
  finer.resolution = 128;
  btRigidBody* other = world.add(*box, finer, btVector3(0, btScalar(0.1), 12));
  REQUIRE(other != nullptr);
  CHECK_FALSE(controller.report(other)->sharesModel);

  // Sharing changes no number: the shared bodies move exactly as the one with its own model
  // (the texture query works relative to each body's own translation).
  for (int i = 0; i < 60; ++i) world.step(1.0 / 60.0);
  // The sharing bodies agree to the bit. The reference lies 9 m away in z: in double-precision
  // Bullet its state rounds at ulp(9 m) = 1.8e-15 m (the drag's lever arms r = p - c are taken
  // from world positions), which after 60 steps leaves its height 1.7e-17 m (one ulp) apart
  // (measured); float Bullet rounds every position to float, and there the heights are equal.
  const btScalar reference = alone->getCenterOfMassPosition().y();
  const double rounding = sizeof(btScalar) == sizeof(double) ? 1e-15 : 0.0;
  CHECK(second->getCenterOfMassPosition().y() == first->getCenterOfMassPosition().y());
  CHECK(third->getCenterOfMassPosition().y() == first->getCenterOfMassPosition().y());
  CHECK(std::abs(double(first->getCenterOfMassPosition().y() - reference)) <= rounding);

  // The body that made the model leaves: the others keep its texels (the backend shares them).
  world.world().removeRigidBody(first);
  CHECK(controller.removeBody(first));
  controller.resetStatistics();
  for (int i = 0; i < 5; ++i) world.step(1.0 / 60.0);
  CHECK(controller.statistics().failedQueries == 0);
  CHECK(controller.report(second)->hydrostatics.submergedVolume > 0.0);
  // ... and a new body of the kind still registers (sharing with the remaining ones).
  btRigidBody* late = world.add(*box, settings, btVector3(0, btScalar(0.1), 15));
  REQUIRE(late != nullptr);
  CHECK(controller.report(late)->sharesModel);
}
