// SPDX-License-Identifier: Zlib
/// @file RigidBodyStep.cpp
/// A rigid body's step (RigidBodyStep.hpp): the out-of-liquid test, the drag sum, the added mass,
/// the implicit velocity update, the rest rule and flooding's momentum: the laws of the phased
/// step, once.

#include "hydrotex/step/RigidBodyStep.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <optional>

namespace hydrotex {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// The part of a stiffness taken implicitly, in the metric of the generalized mass M (so that
/// heave in N/m and roll in N m/rad compare fairly): with M = L L^T, the modes of L^-1 K L^-T.
/// Stable modes (omega^2 > 0) are kept. Capsizing modes (omega^2 < 0) stay explicit, being
/// physical growth, unless they grow faster than the step resolves (|omega^2| dt^2 > 1): such a
/// mode is taken with |omega^2|, so one step turns the body at most about as far as the
/// linearized torque stays meaningful (backward Euler's quasi-static answer) instead of an
/// explicit kick of dt tau / I, which for a tiny inertia (a needle's roll) throws it far past
/// where that torque holds and pumps energy in. `largestRate`: omega^2 (1/s^2) of the stiffest
/// implicit mode.
Eigen::Matrix3d implicitStiffness(const Eigen::Matrix3d& stiffness, const Eigen::Matrix3d& generalizedMass, double dt,
                                  double& largestRate) {
  const Eigen::LLT<Eigen::Matrix3d> cholesky(generalizedMass);
  const Eigen::Matrix3d lower = cholesky.matrixL();
  const Eigen::Matrix3d symmetric = 0.5 * (stiffness + stiffness.transpose());
  const Eigen::Matrix3d left = lower.triangularView<Eigen::Lower>().solve(symmetric);
  const Eigen::Matrix3d normalized = lower.triangularView<Eigen::Lower>().solve(left.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(0.5 * (normalized + normalized.transpose()));
  Eigen::Vector3d rates = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const double rate = solver.eigenvalues()[i];
    if (rate > 0.0 || rate * dt * dt < -1.0) rates[i] = std::abs(rate);
  }
  largestRate = rates.maxCoeff();
  const Eigen::Matrix3d modal = solver.eigenvectors() * rates.asDiagonal() * solver.eigenvectors().transpose();
  return lower * modal * lower.transpose();
}

/// The inertia that torques about the world x and z axes meet while the spin about y stays free:
/// the inverse of the (x, z) block of the inverse inertia (a Schur complement). For a needle
/// lying in the water this is its tiny inertia about its own axis, where the diagonal entries
/// I_xx, I_zz see the large transverse one whenever the needle is not exactly along x or z.
Eigen::Matrix2d rollPitchInertia(const Eigen::Matrix3d& inertiaWorld) {
  const Eigen::Matrix3d inverse = inertiaWorld.inverse();
  Eigen::Matrix2d block;
  block << inverse(0, 0), inverse(0, 2), inverse(2, 0), inverse(2, 2);
  return block.inverse();
}

}  // namespace

double patchWetFraction(double depth, double radius) {
  return std::clamp(0.5 + 0.5 * depth / std::max(radius, 1e-9), 0.0, 1.0);
}

double bodySkinFriction(double density, double relativeSpeed, double referenceLength, double viscosity,
                        const DragCoefficients& coefficients) {
  if (!(coefficients.skinFrictionScale > 0.0 && viscosity > 0.0)) return 0.0;
  const double reynolds = density * relativeSpeed * referenceLength / viscosity;
  return coefficients.skinFrictionScale * skinFrictionCoefficient(reynolds);
}

DragLoads rigidBodyDrag(const DragBody& body, const RigidBodyMotion& motion, const DragLiquid& liquid, double dt) {
  DragLoads out;
  const LiquidSurface& surface = *liquid.surface;
  const Eigen::Matrix3d& rotation = motion.meshPose.rotation;
  const Eigen::Vector3d& center = motion.center;
  const Eigen::Vector3d& v = motion.linearVelocity;
  const Eigen::Vector3d& w = motion.angularVelocity;
  out.liquidVelocityAtCenter = liquid.current + surface.velocity(center, liquid.time);
  // A still, flat, uniform liquid needs no per-patch surface, velocity or density calls.
  const double density = surface.density();
  const bool still = surface.flatHeight().has_value() && liquid.current.isZero();
  const std::optional<double> flatLevel = surface.flatHeight();
  const bool freeSurface = surface.hasFreeSurface();
  const double friction = bodySkinFriction(density, (v - out.liquidVelocityAtCenter).norm(), body.referenceLength,
                                           liquid.viscosity, body.coefficients);
  for (const DragPatch& patch : body.patches) {
    const Eigen::Vector3d p = rotation * patch.position.cast<double>() + motion.meshPose.translation;
    double wetFraction = 1.0;
    if (freeSurface) {
      const double level = flatLevel ? *flatLevel : surface.surfaceHeight(p.x(), p.z(), liquid.time);
      wetFraction = patchWetFraction(level - p.y(), double(patch.radius));
      if (wetFraction <= 0.0) continue;
    }
    ++out.patchesVisited;
    const Eigen::Vector3d r = p - center;
    const Eigen::Vector3d liquidVelocity = still ? liquid.current : Eigen::Vector3d(surface.velocity(p, liquid.time) + liquid.current);
    const Eigen::Vector3d relative = v + w.cross(r) - liquidVelocity;
    const Eigen::Vector3d force =
        wetFraction * texelDragForceWithFriction(rotation * patch.areaVector.cast<double>(), double(patch.area), relative,
                                                 freeSurface ? density : surface.densityAt(p), friction, body.coefficients);
    out.force += force;
    out.torque += r.cross(force);
    out.wettedArea += wetFraction * double(patch.area);
  }
  if (body.totalPatchArea > 0.0 && body.rotationalDamping > 0.0) {
    const double wetted = out.wettedArea / body.totalPatchArea;
    out.torque -= body.rotationalDamping * wetted * (motion.inertiaWorld * w);
  }
  // Drag is taken implicitly too (linearized backward Euler, F_d(u') = F_d(u) - D (u' - u)), with
  // D = lambda M / dt the secant damping along the relative motion: lambda = -(u.J)/(u.M.u),
  // J = dt (F_d, T_d). It can then slow a body but never reverse it, at any time step, and at a
  // steady state (terminal velocity) it changes nothing.
  const Eigen::Vector3d relativeLinear = v - out.liquidVelocityAtCenter;
  const double removed = -dt * (relativeLinear.dot(out.force) + w.dot(out.torque));
  const double kinetic = motion.mass * relativeLinear.squaredNorm() + w.dot(motion.inertiaWorld * w);
  if (removed > 0.0 && kinetic > 0.0) out.damping = removed / kinetic;
  return out;
}

Expected<RigidBodyVelocities> implicitVelocityUpdate(const RigidBodyMotion& motion, const ImplicitUpdateInput& input,
                                                     double dt) {
  // Generalized velocity u = (v, w) at the centre of mass; the engine integrates positions with the
  // u' returned. Linearizing F(x + dt u') = F(x) - K dt u' gives
  //   (M + theta dt^2 K) u' = M u + dt (m g + F) ,
  // K acting on (heave v_y, roll w_x, pitch w_z) (Hydrostatics.hpp; the reference point lies
  // vertically above the centre of mass, so these rates are the body's own). theta = min(1, a),
  // a = (omega dt)^2 of the stiffest mode: almost symplectic (energy kept) for ordinary bodies,
  // fully implicit (dissipative, unconditionally stable) for light ones; every theta > 0 has
  // determinant 1/(1 + theta a) < 1 per step, so the hydrostatic oscillation never gains energy.
  // The rates are those of the modes, not of the diagonal entries: a needle lying in the water
  // has I_xx ~ its transverse inertia unless it points exactly along x, yet rolls about its own
  // axis with an inertia 5e5 times smaller (rollPitchInertia); measured by I_xx its 100 rad/s
  // roll looked slow, stayed explicit at omega dt = 1.6 and gained energy (issue 11).
  const double mass = motion.mass;
  const Eigen::Matrix3d& inertiaWorld = motion.inertiaWorld;
  const Eigen::Vector3d& v = motion.linearVelocity;
  const Eigen::Vector3d& w = motion.angularVelocity;
  const double effectiveMass = mass + input.addedMass;
  Matrix6d system = Matrix6d::Zero();
  system.topLeftCorner<3, 3>() = effectiveMass * Eigen::Matrix3d::Identity();
  system.bottomRightCorner<3, 3>() = inertiaWorld;
  Vector6d rhs;
  rhs.head<3>() = effectiveMass * v + dt * (mass * input.gravity + input.force);
  rhs.tail<3>() = inertiaWorld * w + dt * input.torque;
  if (input.dragDamping > 0.0) {
    rhs.head<3>() += input.dragDamping * mass * v;
    rhs.tail<3>() += input.dragDamping * (inertiaWorld * w);
    system.topLeftCorner<3, 3>() += input.dragDamping * mass * Eigen::Matrix3d::Identity();
    system.bottomRightCorner<3, 3>() += input.dragDamping * inertiaWorld;
  }
  const bool stiff = !input.stiffness.isZero(0.0) && input.stiffness.allFinite();
  if (stiff) {
    double rate = 0.0;
    Eigen::Matrix3d generalizedMass = Eigen::Matrix3d::Zero();
    generalizedMass(0, 0) = effectiveMass;
    generalizedMass.bottomRightCorner<2, 2>() = rollPitchInertia(inertiaWorld);
    const Eigen::Matrix3d implicitPart = implicitStiffness(input.stiffness, generalizedMass, dt, rate);
    const double theta = std::min(1.0, rate * dt * dt);
    static constexpr int kIndex[3] = {1, 3, 5};  // heave -> v_y, roll -> w_x, pitch -> w_z
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) system(kIndex[i], kIndex[j]) += theta * dt * dt * implicitPart(i, j);
  }
  const Vector6d next = system.ldlt().solve(rhs);
  if (!next.allFinite()) return Error{"implicit velocity update: the step's system gave non-finite velocities"};
  return RigidBodyVelocities{next.head<3>(), next.tail<3>()};
}

bool whollyAboveSurface(const LiquidSurface& surface, const Eigen::Vector3d& sphereCenter, double radius, double time) {
  if (!surface.hasFreeSurface()) return false;
  const std::optional<double> flat = surface.flatHeight();
  // Away from a flat plane the surface may rise within the sphere's footprint; slopes up to 1 are
  // covered by a margin of one radius.
  const double level = flat ? *flat : surface.surfaceHeight(sphereCenter.x(), sphereCenter.z(), time);
  const double margin = flat ? 0.0 : radius;
  return sphereCenter.y() - radius > level + margin;
}

double translationalAddedMass(double coefficient, double fluidDensity, double submergedVolume) {
  return coefficient * fluidDensity * submergedVolume;
}

Expected<RigidBodyStepResult> stepRigidBody(const RigidBodyMotion& motion, const RigidBodyStepInput& input, double dt) {
  RigidBodyStepResult result;
  Eigen::Vector3d buoyancyForce = Eigen::Vector3d::Zero(), buoyancyTorque = Eigen::Vector3d::Zero();
  ImplicitUpdateInput update;
  if (input.hydrostatics != nullptr && input.buoyancy) {
    buoyancyForce = input.hydrostatics->buoyancyForce;
    buoyancyTorque = input.hydrostatics->torqueAboutCenterOfMass;
    update.stiffness = input.hydrostatics->stiffness;
  }
  result.drag.liquidVelocityAtCenter = input.liquid.current;
  if (input.drag != nullptr) result.drag = rigidBodyDrag(*input.drag, motion, input.liquid, dt);
  if (input.addedMassCoefficient && input.hydrostatics != nullptr) {
    result.addedMass = translationalAddedMass(*input.addedMassCoefficient, input.hydrostatics->fluidDensity,
                                              input.hydrostatics->submergedVolume);
  }
  update.gravity = input.gravity;
  update.force = buoyancyForce + result.drag.force;
  update.torque = buoyancyTorque + result.drag.torque;
  update.addedMass = result.addedMass;
  update.dragDamping = result.drag.damping;
  Expected<RigidBodyVelocities> next = implicitVelocityUpdate(motion, update, dt);
  if (!next) return next.error();
  result.velocities = *next;

  // Rest afloat: balanced and slow, judged on the start of the step (the adapter keeps a body
  // awake until then, whatever its engine's own sleeping thresholds say).
  const double weight = motion.mass * input.gravity.norm();
  const Eigen::Vector3d netForce = motion.mass * input.gravity + buoyancyForce + result.drag.force;
  const Eigen::Vector3d netTorque = buoyancyTorque + result.drag.torque;
  const RestThresholds& rest = input.rest;
  result.atRest = netForce.norm() <= rest.forceFraction * weight &&
                  netTorque.norm() <= rest.forceFraction * weight * input.referenceLength &&
                  (motion.linearVelocity - result.drag.liquidVelocityAtCenter).norm() <= rest.linearSpeed &&
                  motion.angularVelocity.norm() <= rest.angularSpeed;
  return result;
}

Eigen::Vector3d floodingVelocityCorrection(const Eigen::Vector3d& velocity, const Eigen::Vector3d& liquidVelocity,
                                           double massBefore, double massAfter, double density, double inflow,
                                           double outflow) {
  if (massAfter == massBefore || !(massAfter > 0.0) || !(massBefore > 0.0)) return Eigen::Vector3d::Zero();
  // The body's velocity before the change, from the kept momentum m_after v = m_before v_before.
  const Eigen::Vector3d bodyVelocityBefore = velocity * (massAfter / massBefore);
  return density * (inflow * liquidVelocity - outflow * bodyVelocityBefore) / massAfter;
}

}  // namespace hydrotex
