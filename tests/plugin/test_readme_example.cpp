// SPDX-License-Identifier: Zlib
// The README's drop-in example, compiled and run exactly as printed there (between the markers).
#include <catch2/catch.hpp>

// README example begins
#include <btBulletDynamicsCommon.h>

#include <memory>

#include "hydrotex/LiquidSurface.hpp"
#include "hydrotex/Primitives.hpp"
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

TEST_CASE("the README's drop-in example floats a crate at its draft", "[readme]") {
  // 600 kg/m^3 in water: draft 0.6 x 0.5 = 0.3 m, centre at 0.25 - 0.3 = -0.05 m (stable: GM =
  // 0.15 + 1/(12 x 0.3) - 0.25 = 0.18 m > 0). 2 mm: the body may fall asleep
  // once its net force is within 0.1 % of its weight (about 0.6 mm), plus float positions.
  CHECK(floatCrate() == Approx(-0.05).margin(2e-3));
}
