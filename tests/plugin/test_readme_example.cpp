// SPDX-License-Identifier: Zlib
// The README's drop-in examples, compiled and run exactly as printed there (between each pair of
// markers; ReadmeExampleInSync.cmake checks every pair).
#include <catch2/catch.hpp>

// README example begins
#include <btBulletDynamicsCommon.h>

#include <memory>

#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"

// Your existing world and a body (a 1 x 0.5 x 1 m crate whose shape is in its mesh's frame).
double floatCrate() {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, -9.81f, 0));

  btBoxShape crateShape(btVector3(0.5f, 0.25f, 0.5f));
  btDefaultMotionState crateMotion(btTransform(btQuaternion::getIdentity(), btVector3(0, 2, 0)));
  btRigidBody crate(btRigidBody::btRigidBodyConstructionInfo(1, &crateMotion, &crateShape));

  // 1. One controller for the liquid: still water at y = 0.
  hydrotex::bullet::LiquidSettings water;
  water.surface = std::make_shared<hydrotex::FlatSurface>(0.0, 1000.0);
  hydrotex::bullet::BuoyancyController controller(world, water);
  world.addAction(&controller);

  // 2. Register each floating body with its closed mesh (or settings.meshPath = "crate.obj").
  hydrotex::bullet::FloatingBodySettings settings;
  settings.mesh = std::make_shared<const hydrotex::Mesh>(hydrotex::primitives::box({1.0, 0.5, 1.0}));
  settings.density = 600.0;  // kg/m^3; or settings.mass
  settings.effects = {hydrotex::bullet::Effect::Buoyancy, hydrotex::bullet::Effect::Drag};
  if (!controller.addBody(&crate, settings)) return 0.0;
  world.addRigidBody(&crate);

  // 3. Step as usual.
  for (int i = 0; i < 600; ++i) world.stepSimulation(1.0f / 60.0f, 1, 1.0f / 60.0f);
  const double height = crate.getCenterOfMassPosition().y();  // -0.05 m: 60 % of it under water

  world.removeRigidBody(&crate);
  controller.removeBody(&crate);
  world.removeAction(&controller);
  return height;
}
// README example ends

// README example begins
#include <btBulletDynamicsCommon.h>

#include <array>
#include <memory>

#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"

// An existing world whose bodies have only their Bullet shapes (a 1 x 0.5 x 1 m crate and a log,
// a capsule 0.5 m across lying along z): no mesh files, each floats as its own collision shape.
std::array<double, 2> floatShapes() {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, -9.81f, 0));

  btBoxShape crateShape(btVector3(0.5f, 0.25f, 0.5f));
  btCapsuleShapeZ logShape(0.25f, 1.0f);  // radius, length of the cylindrical part
  btDefaultMotionState crateMotion(btTransform(btQuaternion::getIdentity(), btVector3(-2, 1, 0)));
  btDefaultMotionState logMotion(btTransform(btQuaternion::getIdentity(), btVector3(2, 1, 0)));
  btRigidBody crate(btRigidBody::btRigidBodyConstructionInfo(1, &crateMotion, &crateShape));
  btRigidBody log(btRigidBody::btRigidBodyConstructionInfo(1, &logMotion, &logShape));
  world.addRigidBody(&crate);
  world.addRigidBody(&log);

  hydrotex::bullet::LiquidSettings water;
  water.surface = std::make_shared<hydrotex::FlatSurface>(0.5, 1000.0);  // still water at y = 0.5 m
  hydrotex::bullet::BuoyancyController controller(world, water);
  world.addAction(&controller);

  // No mesh and no meshPath: every dynamic body of the world is meshed from its own shape.
  hydrotex::bullet::FloatingBodySettings settings;
  settings.density = 500.0;  // kg/m^3: both float half under water
  if (!controller.addAllBodies(settings)) return {};

  for (int i = 0; i < 600; ++i) world.stepSimulation(1.0f / 60.0f, 1, 1.0f / 60.0f);
  const std::array<double, 2> heights{crate.getCenterOfMassPosition().y(), log.getCenterOfMassPosition().y()};

  for (btRigidBody* body : {&crate, &log}) {
    world.removeRigidBody(body);
    controller.removeBody(body);
  }
  world.removeAction(&controller);
  return heights;  // both 0.5 m: centres at the surface
}
// README example ends

TEST_CASE("the README's drop-in example floats a crate at its draft", "[readme]") {
  // 600 kg/m^3 in water: draft 0.6 x 0.5 = 0.3 m, centre at 0.25 - 0.3 = -0.05 m (stable: GM =
  // 0.15 + 1/(12 x 0.3) - 0.25 = 0.18 m > 0). 2 mm: the body may fall asleep
  // once its net force is within 0.1 % of its weight (about 0.6 mm), plus float positions.
  CHECK(floatCrate() == Approx(-0.05).margin(2e-3));
}

TEST_CASE("the README's shape example floats a world's crate and log, meshed from their shapes", "[readme]") {
  // Half the density of water: the crate (draft 0.25 m of 0.5 m) and the log (a capsule, by its
  // symmetry) float with their centres at the surface, y = 0.5 m. 2 mm as above.
  const std::array<double, 2> heights = floatShapes();
  CHECK(heights[0] == Approx(0.5).margin(2e-3));
  CHECK(heights[1] == Approx(0.5).margin(2e-3));
}
