// SPDX-License-Identifier: Zlib
#pragma once
/// @file RigidBodyStep.hpp
/// One rigid body's step in the liquid, as pure functions (docs/design.md "The phased step"): the
/// out-of-liquid test, the drag sum over its patches, the added mass, the implicit velocity update
/// with the hydrostatic stiffness and the drag taken implicitly, the rest-afloat rule, and the
/// momentum of liquid that floods in or drains out. A physics engine's adapter (the Bullet plugin)
/// reads a body's kinematics, asks the backend for its hydrostatics, calls stepRigidBody, and
/// writes the velocities back; the laws live here once, for every adapter and every backend.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/Pose.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"

namespace hydrotex {

/// A rigid body's motion at the start of a step (world frame, SI units).
struct RigidBodyMotion {
  Pose meshPose;                                        ///< the mesh frame in the world
  Eigen::Vector3d center = Eigen::Vector3d::Zero();     ///< centre of mass (m)
  Eigen::Vector3d linearVelocity = Eigen::Vector3d::Zero();   ///< of the centre of mass (m/s)
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();  ///< rad/s
  double mass = 0.0;                                    ///< kg (> 0)
  Eigen::Matrix3d inertiaWorld = Eigen::Matrix3d::Zero();     ///< about the centre of mass, world axes (kg m^2)
};

/// The liquid a body's drag sees.
struct DragLiquid {
  const LiquidSurface* surface = nullptr;               ///< free surface, density, velocity field (required)
  Eigen::Vector3d current = Eigen::Vector3d::Zero();    ///< uniform current added to the surface's velocity (m/s)
  double viscosity = 1.0e-3;                            ///< dynamic viscosity (Pa s)
  double time = 0.0;                                    ///< s, passed to the surface
};

/// A body's drag patches laid out for rigidBodyDrag's sum (prepareDragPatches), kept with its model:
/// a structure of arrays (the sum takes two or four patches at a time in SIMD lanes), in clusters
/// of nearby patches of one facing (split across the longest side of their bounds in position and normal)
/// with a bounding sphere that holds every patch's sphere, so that a cluster wholly above a flat
/// surface is skipped in O(1), as the buoyancy's tiles are, and one wholly under it skips the
/// patches' wet ramps. A wet cluster still visits each of its patches: the quadratic law has no
/// closed-form sum over them. The patches are stored in the clusters' order, which the sums follow.
struct DragPatchSet {
  /// Patches [begin, end) (of this set's order) within `radius` (m) of `center` (mesh frame), each
  /// with its own radius: none of them is wet while the centre lies more than `radius` above the
  /// surface, and all are wholly wet while it lies more than `radius` below.
  struct Cluster {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radius = 0.0;
    std::uint32_t begin = 0, end = 0;
  };
  /// The columns hold size() patches and then kPadding zeros, so that the sum's SIMD lanes may
  /// load past the last patch.
  static constexpr std::size_t kPadding = 3;
  std::vector<float> x, y, z;               ///< centroid (m, mesh frame), as DragPatch::position
  std::vector<float> ax, ay, az;            ///< area vector (m^2, mesh frame), as DragPatch::areaVector
  std::vector<float> area, radius;          ///< m^2 and m, as DragPatch
  std::vector<double> inverseRadius;        ///< 1 / max(radius, 1e-9) (1/m): the wet ramp's slope, once
  std::vector<Cluster> clusters;            ///< covering every patch once, in order
  /// Patches.
  std::size_t size() const { return x.size() > kPadding ? x.size() - kPadding : 0; }
  std::size_t memoryBytes() const;          ///< heap held
};

/// The patches laid out for rigidBodyDrag, in clusters of at most `clusterSize` (>= 1) patches.
DragPatchSet prepareDragPatches(std::span<const DragPatch> patches, std::size_t clusterSize = 16);

/// How rigidBodyDrag linearizes the drag for the implicit update (DragLoads::damping).
enum class DragDamping {
  /// The law's whole derivative, C = sum of J^T C_p J over the wet patches (about 60 multiply-adds
  /// a patch): every direction the drag acts on is damped implicitly, including forces across the
  /// motion that a coarse or lopsided layout makes (a spinning 1 mm plate, a rolling needle on
  /// mesh patches pumped energy with the secant below). For coarse layouts: meshDragPatches.
  Linearized,
  /// The secant damping along the relative motion, C = (lambda / dt) diag(m I, I_world) with lambda
  /// removing the energy this step's drag would: O(1) a body. For dense layouts (texel patches of
  /// a bake, as a deforming body re-merges), whose drag across the motion nearly cancels and where
  /// the whole derivative would cost 2.5 us a body on a 256^2 box's 325 patches.
  Secant,
};

/// A body's drag model: its patches (mergeTexelsIntoDragPatches, body = mesh frame) and coefficients.
struct DragBody {
  std::span<const DragPatch> patches;                   ///< mesh frame
  /// prepareDragPatches(patches), made once with the patches (a model's, shared by its bodies); null:
  /// rigidBodyDrag prepares them for the call (an allocation and a pass, the per-patch work it saves).
  const DragPatchSet* prepared = nullptr;
  double totalPatchArea = 0.0;                          ///< m^2, sum of the patches' areas
  double referenceLength = 1.0;                         ///< m, the Reynolds number's length (> 0)
  DragCoefficients coefficients;                        ///< per-element law
  double rotationalDamping = 0.0;                       ///< 1/s-free factor on -I w, scaled by the wetted fraction
  DragDamping damping = DragDamping::Linearized;        ///< how the implicit update sees the drag
  /// The body is a true sphere of this radius (m) about the mesh frame's origin, or a box of these
  /// half extents (m, along the mesh frame's axes) about it: under a flat free surface rigidBodyDrag
  /// sums the law on the nodes of a quadrature rule over its wetted surface (its cap; its faces'
  /// wet parts, cut at their straight water lines) instead of on the patches, which still give
  /// totalPatchArea (the rotational damping's wetted fraction). The patches approximate the
  /// water line by their wet-fraction ramp and merged normals (a sphere's 153 patches: up to 19 %
  /// off the law's integral in force; its 32 nodes within 2.1e-3, test_rigid_body_step).
  std::optional<double> sphereRadius;
  std::optional<Eigen::Vector3d> boxHalfExtents;  ///< see sphereRadius
};

/// The drag of one step.
struct DragLoads {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();      ///< N, world
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();     ///< N m about the centre of mass
  double wettedArea = 0.0;                              ///< m^2, sum of wet fraction x patch area
  /// The drag's damping C (6 x 6, symmetric positive semidefinite, on u = (v, w) at the centre of
  /// mass: N s/m, N s and N m s blocks), so that the drag of velocities u' near u is taken as
  /// F(u) - C (u' - u). DragDamping::Linearized: minus its derivative, the sum over wet patches of
  /// J^T C_p J (J: the patch's velocity from u) with C_p the law's own derivative, plus the
  /// rotational damping on w; DragDamping::Secant: (lambda / dt) diag(m I, I_world).
  Eigen::Matrix<double, 6, 6> damping = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Vector3d liquidVelocityAtCenter = Eigen::Vector3d::Zero();  ///< m/s, current + surface velocity
  std::uint64_t patchesVisited = 0;                     ///< patches at least partly wet
};

/// The fraction of a drag patch of bounding radius `radius` (m) that is wet when its centre lies
/// `depth` (m) below the surface: a linear ramp over the sphere's height, 0 above, 1 below, so
/// that the force stays continuous as the waterline moves. The one rule for a patch cut by the
/// waterline.
double patchWetFraction(double depth, double radius);

/// The skin friction coefficient of a whole body (scaled): one per body and step, from the body's
/// Reynolds number rho |u| L / mu (the ITTC line is a whole-body correlation); 0 without
/// viscosity or with a zero scale. Used by rigid and soft bodies alike.
double bodySkinFriction(double density, double relativeSpeed, double referenceLength, double viscosity,
                        const DragCoefficients& coefficients);

/// The drag on a rigid body over its wet patches (texelDragForceWithFriction per patch, at the
/// patch's velocity v + w x r relative to the liquid there), or, for a sphere or box under a flat
/// free surface, over the nodes of its wetted surface (DragBody::sphereRadius); its rotational
/// damping, and the implicit damping for a step of `dt` seconds. Pure: reads the surface through
/// const calls.
DragLoads rigidBodyDrag(const DragBody& body, const RigidBodyMotion& motion, const DragLiquid& liquid, double dt);

/// What the implicit velocity update needs besides the motion (world frame).
struct ImplicitUpdateInput {
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();         ///< m/s^2
  Eigen::Vector3d force = Eigen::Vector3d::Zero();           ///< N, buoyancy + drag (not the weight)
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();          ///< N m about the centre of mass
  /// Hydrostatic stiffness on (heave, roll, pitch) (Hydrostatics.hpp's convention; zero: none).
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();
  double addedMass = 0.0;                                    ///< kg, on the translation only
  /// DragLoads::damping (6 x 6 on (v, w)); zero: the drag, if any, taken explicitly.
  Eigen::Matrix<double, 6, 6> dragDamping = Eigen::Matrix<double, 6, 6>::Zero();
};

/// The velocities after a step.
struct RigidBodyVelocities {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();    ///< m/s
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();   ///< rad/s
};

/// The velocity update of a step of `dt` seconds with the hydrostatic stiffness and the drag
/// taken implicitly (linearized backward Euler):
///   (M + theta dt^2 K + C dt) u' = M u + dt (m g + F) + C dt u ,
/// M = diag(m + m_a, I), K on (v_y, w_x, w_z) in the modes of the mass metric (stable modes
/// implicit, capsizing ones explicit unless faster than the step resolves), theta = min(1,
/// omega_max^2 dt^2): nearly symplectic for ordinary bodies, fully implicit for light ones, and
/// never gaining energy from the stiffness (derivation in RigidBodyStep.cpp). Error: a system that
/// gives non-finite velocities (a singular mass matrix, non-finite input).
Expected<RigidBodyVelocities> implicitVelocityUpdate(const RigidBodyMotion& motion, const ImplicitUpdateInput& input,
                                                     double dt);

/// Whether a body is wholly out of the liquid, from its bounding sphere (centre in the world and
/// radius, m) at `time` (s): above a flat plane exactly; above waves or a height grid with a margin
/// of one radius, which covers surface slopes up to 1 within the sphere's footprint. A surface
/// without a free surface (a uniform medium) holds every body. A cheap test before any texel.
bool whollyAboveSurface(const LiquidSurface& surface, const Eigen::Vector3d& sphereCenter, double radius, double time);

/// The translational added mass (kg): the liquid accelerated with the body, C_a rho V_submerged
/// (C_a dimensionless, 0.5 for a sphere; rho in kg/m^3; V in m^3).
double translationalAddedMass(double coefficient, double fluidDensity, double submergedVolume);

/// When a floating body is at rest: balanced and slow.
struct RestThresholds {
  double forceFraction = 1.0e-3;  ///< |net force| <= this * m |g|, |net torque| <= this * m |g| * reference length
  double linearSpeed = 0.02;      ///< m/s, speed relative to the liquid at the centre of mass
  double angularSpeed = 0.02;     ///< rad/s
};

/// Everything one rigid body's step needs beside its motion (world frame, SI units).
struct RigidBodyStepInput {
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< m/s^2
  /// The body's hydrostatics this step (a backend's answer or the exact path's); null when it
  /// has none (buoyancy and added mass not listed, no weight, or a failed query).
  const HydrostaticsResult* hydrostatics = nullptr;
  bool buoyancy = true;                               ///< apply the hydrostatics' force, torque and stiffness
  /// C_a of the added mass (translationalAddedMass); nullopt: the effect is not listed.
  std::optional<double> addedMassCoefficient;
  const DragBody* drag = nullptr;                     ///< null: drag not listed (no pass over the patches)
  /// rigidBodyDrag(*drag, motion, liquid, dt) already summed for this step (stepRigidBodies runs
  /// the drag of all bodies while the backend answers their hydrostatics); null: summed here.
  const DragLoads* dragLoads = nullptr;
  DragLiquid liquid;                                  ///< the liquid drag and the rest rule see
  double referenceLength = 1.0;                       ///< m, scales the rest rule's torque
  RestThresholds rest;                                ///< when the body counts as at rest
};

/// One rigid body's step.
struct RigidBodyStepResult {
  RigidBodyVelocities velocities;                     ///< after the step
  DragLoads drag;                                     ///< zero without drag (liquidVelocityAtCenter = the current)
  double addedMass = 0.0;                             ///< kg, 0 without the effect
  bool atRest = false;                                ///< balanced and slow at the start of the step (RestThresholds)
};

/// One rigid body's step of `dt` seconds in the liquid, whole: drag over its patches, added mass,
/// the implicit velocity update, and the rest rule (net force and torque of weight, buoyancy and
/// drag against RestThresholds, with the velocities at the start of the step). Pure; errors as
/// implicitVelocityUpdate's.
Expected<RigidBodyStepResult> stepRigidBody(const RigidBodyMotion& motion, const RigidBodyStepInput& input, double dt);

/// The velocity change (m/s) of a flooding body whose mass went from `massBefore` to `massAfter`
/// (kg) while `inflow` and `outflow` (m^3) of liquid of `density` (kg/m^3) crossed its hull, when
/// the adapter kept the momentum m v at `velocity` (liquid entering at rest): liquid enters with
/// the liquid's velocity `liquidVelocity` and leaves with the body's, so P' = m v + rho (V_in
/// u_liquid - V_out v). Zero when the mass did not change or is not positive.
Eigen::Vector3d floodingVelocityCorrection(const Eigen::Vector3d& velocity, const Eigen::Vector3d& liquidVelocity,
                                           double massBefore, double massAfter, double density, double inflow,
                                           double outflow);

}  // namespace hydrotex
