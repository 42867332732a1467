// SPDX-License-Identifier: Zlib
#pragma once
// What the controller benchmarks share (bench_controller, bench_peers): the controller's action
// timed from inside a world, and the states of its bodies as core's per-step calls take them, to
// time those calls alone on the states the controller reached.

#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <optional>
#include <vector>

#include "hydrotex/bullet/BuoyancyController.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"

namespace hydrotex::bench {

/// Wraps an action (the controller) to time its updateAction apart from the rest of the step.
class TimedAction : public btActionInterface {
 public:
  explicit TimedAction(btActionInterface& inner) : inner_(inner) {}
  void updateAction(btCollisionWorld* world, btScalar dt) override {
    const auto start = std::chrono::steady_clock::now();
    inner_.updateAction(world, dt);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  void debugDraw(btIDebugDraw* drawer) override { inner_.debugDraw(drawer); }
  double seconds = 0.0;  ///< s in updateAction since construction or the last reset of this field

 private:
  btActionInterface& inner_;
};

/// Eigen from Bullet.
inline Eigen::Vector3d eigen(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

/// One body's state now: its hydrostatics query (gravity 9.81 m/s^2) and its motion.
struct BodyState {
  HydrostaticsQuery query;
  RigidBodyMotion motion;
};

/// The states of `bodies` registered with `controller` (those it does not know are skipped).
inline std::vector<BodyState> bodyStates(const bullet::BuoyancyController& controller,
                                         const std::vector<btRigidBody*>& bodies) {
  std::vector<BodyState> states;
  for (const btRigidBody* body : bodies) {
    const bullet::FloatingBodyReport* report = controller.report(body);
    const std::optional<btTransform> meshWorld = controller.meshTransform(body);
    if (report == nullptr || !meshWorld) continue;
    Pose pose;
    const btMatrix3x3& basis = meshWorld->getBasis();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) pose.rotation(r, c) = basis[r][c];
    pose.translation = eigen(meshWorld->getOrigin());
    BodyState state;
    state.query.pose = pose;
    state.query.gravity = 9.81;
    state.query.centerOfMass = report->massProperties.centerOfMass;
    state.query.time = controller.time();
    state.query.mass = report->massProperties.mass;
    state.motion.meshPose = pose;
    state.motion.center = eigen(body->getCenterOfMassPosition());
    state.motion.linearVelocity = eigen(body->getLinearVelocity());
    state.motion.angularVelocity = eigen(body->getAngularVelocity());
    state.motion.mass = report->massProperties.mass;
    state.motion.inertiaWorld = pose.rotation * report->massProperties.inertia * pose.rotation.transpose();
    states.push_back(state);
  }
  return states;
}

}  // namespace hydrotex::bench
