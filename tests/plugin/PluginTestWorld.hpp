// SPDX-License-Identifier: Zlib
#pragma once
// A small headless Bullet world with one BuoyancyController, for the plugin's tests: boxes are
// added with full FloatingBodySettings so that each test can pick effects and coefficients.

#include <btBulletDynamicsCommon.h>
#include <catch2/catch.hpp>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"
#if defined(HYDROTEX_TEST_HAS_GPU)
#include "hydrotex/gpu/MakeBackend.hpp"
#endif

namespace hydrotex::bullet::testing {

/// The controller settings a test world gets unless a test names its own: the controller's own
/// CPU backend, or the backend HYDROTEX_TEST_BACKEND names ("gpu": the GL compute backend, for a
/// suite built with it), so that CTest runs the same test bodies on every backend (issue 18).
inline ControllerSettings testControllerSettings() {
  ControllerSettings settings;
  const char* named = std::getenv("HYDROTEX_TEST_BACKEND");
  const std::string backend = named != nullptr ? named : "cpu";
  if (backend == "cpu") return settings;
#if defined(HYDROTEX_TEST_HAS_GPU)
  Expected<std::unique_ptr<ComputeBackend>> made = gpu::makeBackend(backend);
  INFO("HYDROTEX_TEST_BACKEND=" << backend << ": " << (made ? std::string() : made.error().message));
  REQUIRE(made);  // a named backend that cannot open fails the suite rather than passing it on the CPU
  settings.backend = std::move(made).value();
#else
  FAIL("HYDROTEX_TEST_BACKEND=" << backend << ", but this suite was built without the GL backend");
#endif
  return settings;
}

/// World + controller; bodies are removed and destroyed in the right order.
class TestWorld {
 public:
  explicit TestWorld(std::shared_ptr<const LiquidSurface> surface = std::make_shared<FlatSurface>(0.0, 1000.0),
                     double viscosity = 1.0e-3, ControllerSettings settings = testControllerSettings())
      : dispatcher_(&configuration_), world_(&dispatcher_, &broadphase_, &solver_, &configuration_) {
    world_.setGravity(btVector3(0, btScalar(-9.81), 0));
    LiquidSettings liquid;
    liquid.surface = std::move(surface);
    liquid.viscosity = viscosity;
    controller_ = std::make_unique<BuoyancyController>(world_, liquid, std::move(settings));
    world_.addAction(controller_.get());
  }
  ~TestWorld() {
    world_.removeAction(controller_.get());
    controller_.reset();
    for (auto& body : bodies_) world_.removeRigidBody(body.get());
  }
  TestWorld(const TestWorld&) = delete;
  TestWorld& operator=(const TestWorld&) = delete;

  /// Adds a body with `mesh` placed (mesh frame) at `position`, rotated by `rotation`, floating per
  /// `settings` (its mesh is set here unless settings.mesh is given, e.g. one mesh shared by many
  /// bodies). Returns null and stores the error when addBody fails.
  btRigidBody* add(const Mesh& mesh, FloatingBodySettings settings, const btVector3& position,
                   const btQuaternion& rotation = btQuaternion::getIdentity()) {
    auto hull = std::make_unique<btConvexHullShape>();
    for (const Eigen::Vector3d& p : mesh.positions) {
      hull->addPoint(btVector3(btScalar(p.x()), btScalar(p.y()), btScalar(p.z())), false);
    }
    hull->recalcLocalAabb();
    btRigidBody::btRigidBodyConstructionInfo info(1, nullptr, hull.get(), btVector3(1, 1, 1));
    auto body = std::make_unique<btRigidBody>(info);
    body->setWorldTransform(btTransform(rotation, position));
    if (!settings.mesh) settings.mesh = std::make_shared<const Mesh>(mesh);  // given: shared with other bodies
    lastStatus = controller_->addBody(body.get(), settings);
    if (!lastStatus) return nullptr;
    world_.addRigidBody(body.get());
    shapes_.push_back(std::move(hull));
    bodies_.push_back(std::move(body));
    return bodies_.back().get();
  }

  /// One fixed step of `dt` seconds (one sub-step).
  void step(double dt) { world_.stepSimulation(btScalar(dt), 1, btScalar(dt)); }

  btDiscreteDynamicsWorld& world() { return world_; }
  BuoyancyController& controller() { return *controller_; }
  Status lastStatus = Ok{};  ///< result of the last add()

 private:
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::unique_ptr<BuoyancyController> controller_;
};

/// Settings for a uniform solid of `density` with the listed effects and the given method.
inline FloatingBodySettings solid(double density, EffectSet effects,
                                  HydrostaticsMethod method = HydrostaticsMethod::Polyhedral, int resolution = 64) {
  FloatingBodySettings settings;
  settings.density = density;
  settings.effects = effects;
  settings.method = method;
  settings.resolution = resolution;
  return settings;
}

/// Draft h (m) of a sphere of `radius` (m) floating with displaced volume `volume` (m^3): the
/// spherical cap V(h) = pi h^2 (3 R - h) / 3, solved by bisection on [0, 2R] to double rounding.
inline double sphereDraft(double radius, double volume) {
  constexpr double pi = 3.14159265358979323846;
  double low = 0.0, high = 2.0 * radius;
  for (int i = 0; i < 100; ++i) {
    const double h = 0.5 * (low + high);
    (pi * h * h * (3.0 * radius - h) / 3.0 < volume ? low : high) = h;
  }
  return 0.5 * (low + high);
}

}  // namespace hydrotex::bullet::testing
