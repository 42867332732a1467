// SPDX-License-Identifier: Zlib
#pragma once
/// @file BuoyancyController.hpp
/// The drop-in object: one btActionInterface that makes registered rigid bodies float, tip and
/// sink in a liquid (or rise in a gas). Added to a world with world->addAction(&controller);
/// updateAction runs once per fixed sub-step, after Bullet integrated the bodies.

#include <btBulletDynamicsCommon.h>

#include <cstdint>
#include <map>
#include <memory>
#include <tuple>
#include <optional>
#include <vector>

#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/flooding/LiquidGraph.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/step/MassModelsStep.hpp"
#include "hydrotex/step/RigidBodiesStep.hpp"
#include "hydrotex/bullet/FloatingBodySettings.hpp"
#include "hydrotex/bullet/SoftBodyBuoyancy.hpp"

namespace hydrotex {
class PreparedPolyhedron;
}

namespace hydrotex::bullet {

/// The liquid (or gas) the bodies are in.
struct LiquidSettings {
  /// Free surface, density and velocity field; shared with whoever moves it (waves, a grid fed
  /// by a liquid simulation). Required.
  std::shared_ptr<const LiquidSurface> surface;
  /// Dynamic viscosity (Pa s): 1.0e-3 for water at 20 C, 1.8e-5 for air.
  double viscosity = 1.0e-3;
  /// Uniform current (m/s, world) added to the surface's own velocity field.
  btVector3 current{0, 0, 0};
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// Controller-wide tuning (rest detection, debug drawing).
struct ControllerSettings {
  /// A body is at rest afloat when |net force| < this * m g (1e-3: within 1 mm of the draft of a 1 m box) ...
  double restForceFraction = 1.0e-3;
  /// ... its speed is below this (m/s) ...
  double restLinearSpeed = 0.02;
  /// ... and its angular speed below this (rad/s). Until then it is kept awake, whatever
  /// Bullet's own sleeping thresholds (0.8 m/s, 1 rad/s for 2 s) say.
  double restAngularSpeed = 0.02;
  /// Length of the debug force arrows per newton of force (m/N); 0 picks one per body so that
  /// the weight arrow is as long as the body.
  double debugMetersPerNewton = 0.0;
  /// Threads that compute the rigid bodies' loads and implicit updates each step (the parallel
  /// phase of updateAction). 0: every core the process may use, or, when the user set a Bullet
  /// btITaskScheduler with more than one thread (btSetTaskScheduler), that scheduler; N >= 1: at
  /// most N (capped at the cores). Each body's numbers depend only on its own state, so results
  /// are bit-identical for every count: the default takes them all. 1 starts no thread.
  int threads = 0;
  /// The backend that computes the texture path's hydrostatics of every body, once per step in
  /// one batch (the only per-step door to texel passes): null (the default) makes the controller
  /// its own CPU backend on its threads. Pass hydrotex::gpu::makeGlBackend() (or
  /// gpu::makeBackend("auto")) for the GL compute backend; `plugin/` itself links no GL. Drag,
  /// added mass, the exact path, a deforming body's mass (per triangle) and deformation's surface
  /// evaluation run on the controller's CPU threads with either backend; the texel mass passes of
  /// variable-mass bodies (one batch a step), wetting and flooding's pass over the permeable
  /// texels run on the backend (massProperties, makeWetting, makeFloodingPass: the GL one runs
  /// them on the GPU).
  std::shared_ptr<ComputeBackend> backend;
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// Counters of work done, to prove that an effect a body does not list costs nothing.
struct ControllerStatistics {
  std::uint64_t steps = 0;                ///< updateAction calls
  std::uint64_t hydrostaticsQueries = 0;  ///< buoyancy queries (texture or polyhedral)
  std::uint64_t dragPasses = 0;           ///< passes over a body's drag patches
  std::uint64_t dragPatchesVisited = 0;   ///< patches whose drag was evaluated
  std::uint64_t addedMassUpdates = 0;     ///< bodies whose added mass was evaluated
  std::uint64_t skippedOutOfLiquid = 0;   ///< bodies wholly out of the liquid (bounding-sphere test)
  std::uint64_t skippedAsleep = 0;        ///< sleeping bodies left asleep
  std::uint64_t failedQueries = 0;        ///< queries that returned an error (force skipped)
  std::uint64_t massUpdates = 0;          ///< mass properties recomputed and handed to Bullet (variable mass, deformation)
  std::uint64_t massTexelPasses = 0;      ///< of those, the ones that needed a texel pass (not only point masses)
  std::uint64_t deformations = 0;         ///< surfaces re-evaluated from moved vertices
  std::uint64_t floodingSteps = 0;        ///< liquid graph steps (bodies listing Effect::Flooding)
  std::uint64_t permeableTexelsVisited = 0; ///< permeable texels those steps evaluated
  std::uint64_t wettingSteps = 0;         ///< liquid texture steps (bodies listing Effect::Wetting)
  std::uint64_t backendBatches = 0;       ///< hydrostatics batches asked of the backend (results read back once each)
  std::uint64_t autoMethodChoices = 0;    ///< HydrostaticsMethod::Auto resolved at addBody (bodies of one mesh share one: one Mesh given, or shapes and files alike)
  std::uint64_t exactPreparations = 0;    ///< meshes prepared for the exact path at addBody (PreparedPolyhedron), Auto's pricing under waves included
  std::uint64_t massBatches = 0;          ///< mass-pass batches asked of the backend (MassModelsStep; results read back once each)
  std::uint64_t massBatchBodies = 0;      ///< bodies whose texel mass pass those batches ran
};

/// Where the controller's time went since construction or resetStatistics(), by phase of its step
/// (wall clock, s): a benchmark's per-phase split. Not deterministic; nothing depends on it.
struct ControllerTimings {
  double read = 0.0;      ///< reading Bullet's bodies, with deformation, flooding and mass changes
  double wetting = 0.0;   ///< the liquid textures
  double plan = 0.0;      ///< core's plan (RigidBodiesStepStatistics)
  double backend = 0.0;   ///< the backend's hydrostatics batch, less the drag run meanwhile
  double drag = 0.0;      ///< the drag sums (overlapping a GPU backend's batch)
  double update = 0.0;    ///< the exact path's queries and the implicit updates
  double write = 0.0;     ///< writing velocities and sleeping state back to Bullet
  double softBodies = 0.0;  ///< the soft bodies
};

/// What the controller knows about one registered body after the last step.
struct FloatingBodyReport {
  MassProperties massProperties;     ///< mass (kg), volume, centre of mass and inertia in the mesh frame
  btTransform meshToBody = btTransform::getIdentity();///< mesh frame expressed in Bullet's body (centre-of-mass, principal) frame
  HydrostaticsResult hydrostatics;   ///< last buoyancy answer (zero when out of the liquid or not listed)
  btVector3 dragForce{0, 0, 0};      ///< last drag force (N, world)
  btVector3 dragTorque{0, 0, 0};     ///< last drag torque about the centre of mass (N m, world)
  double addedMass = 0.0;            ///< last added mass (kg)
  std::size_t effectMemoryBytes = 0; ///< heap held for the listed effects (0 for buoyancy-only bodies' drag; 0 for a body that shares its model)
  bool sharesModel = false;          ///< it reuses the bake, texels and drag patches of an earlier body of its mesh (the same Mesh pointer, or a shape or file alike) and settings
  double liquidVolume = 0.0;         ///< with Effect::Flooding: liquid held in the liquid graph (m^3)
  bool atRest = false;               ///< at rest afloat at the last step
  double liquidHeld = 0.0;           ///< with Effect::Wetting: liquid held in the surface layer (m^3)
  double liquidAbsorbed = 0.0;       ///< with Effect::Wetting: absorbed since registration (m^3)
  double liquidEvaporated = 0.0;     ///< with Effect::Wetting: evaporated since registration (m^3)
  HydrostaticsMethod method = HydrostaticsMethod::Texture;  ///< the path it runs (HydrostaticsMethod::Auto resolved at addBody)
};

class BodyThreads;
class InternedMeshes;
struct FloatingBody;
struct SharedBodyModel;

/// Makes registered btRigidBody objects float. Not copyable; the world and the bodies must
/// outlive it (or be removed first).
class BuoyancyController : public btActionInterface {
 public:
  /// Controller for bodies of `world` in `liquid`. Does not add itself: call
  /// world.addAction(&controller). Invalid settings are reported by addBody().
  BuoyancyController(btDynamicsWorld& world, LiquidSettings liquid, ControllerSettings settings = {});
  ~BuoyancyController() override;
  BuoyancyController(const BuoyancyController&) = delete;
  BuoyancyController& operator=(const BuoyancyController&) = delete;

  /// Registers `body` (dynamic, in the world or not yet). Its current world transform is taken
  /// as the placement of the mesh's own frame. The controller sets the body's mass and inertia
  /// from the mesh and settings, moves its origin to the centre of mass (principal axes), and
  /// wraps its collision shape in a compound whose child offset keeps the shape in place; a
  /// btDefaultMotionState gets the matching centre-of-mass offset. The body's velocity is kept.
  /// Errors: null or static body, body already registered, invalid settings, an unreadable or
  /// open mesh, a bake that fails, a deformation function with a collision shape that cannot
  /// follow it (FloatingBodySettings::deformedCollision).
  /// With neither settings.mesh nor settings.meshPath, the mesh is the body's own collision shape
  /// (meshFromCollisionShape, ShapeMesh.hpp; an unsupported shape is refused with its type named).
  /// Meshes made from shapes or files are interned by content: bodies of equal ones share a model
  /// (report sharesModel) as bodies given one Mesh pointer do; a primitive shape (box, sphere,
  /// capsule, cylinder, cone) of the same dimensions and tessellation is not meshed again.
  Status addBody(btRigidBody* body, const FloatingBodySettings& settings);

  /// Registers every dynamic rigid body already in the world, in the world's order, with
  /// `defaults` (usually with no mesh, so each floats as its own collision shape); static and
  /// kinematic bodies, soft bodies and bodies already registered are skipped. Returns how many
  /// were added, or the first error (naming the object's index in the world): the bodies added
  /// before it stay registered.
  Expected<std::size_t> addAllBodies(const FloatingBodySettings& defaults);

  /// Unregisters `body` and gives it back its own collision shape (in the mesh frame, origin at
  /// the mesh origin); mass and inertia stay as the controller set them. False when unknown.
  bool removeBody(btRigidBody* body);

  /// Registers a soft body (in a btSoftRigidDynamicsWorld): every step its nodes get the texel
  /// pressure forces of the liquid (SoftBodyBuoyancy); its shape and mass stay Bullet's (kPR,
  /// kVC, kMT, setTotalMass), and the drag law on its texels when settings.effects lists
  /// Effect::Drag (counted in statistics() as a drag pass, texels as patches). No other effect.
  /// Errors: those of SoftBodyBuoyancy::create, or `body` already registered.
  Status addSoftBody(btSoftBody* body, const SoftBodySettings& settings = {});
  /// Unregisters a soft body. False when unknown.
  bool removeSoftBody(btSoftBody* body);
  /// Last step's forces on a registered soft body, or null. Valid until the next addSoftBody or
  /// removeSoftBody.
  const SoftBodyReport* softBodyReport(const btSoftBody* body) const;

  /// Changes mass, centre of mass and inertia (mesh frame) of a registered body, keeping the shape
  /// where it is in the world and keeping linear and angular momentum (docs/design.md "Bullet's
  /// frame"). Errors: unknown body, non-positive or non-finite mass, non-finite centre, an
  /// inertia that is not symmetric positive definite.
  Status setMassProperties(btRigidBody* body, const MassProperties& massProperties);

  /// The mass model of a body that lists Effect::VariableMass or Effect::Deformation, or null.
  /// Change it at any time (move point masses, replace the density map, heat a balloon's gas by
  /// its solid density): the next step recomputes the mass properties and hands them to Bullet,
  /// keeping the shape in place and momentum; steps where nothing changed recompute nothing.
  MassModel* massModel(const btRigidBody* body);

  /// The liquid texture of a body that lists Effect::Wetting (per covered texel of its wetting
  /// bake; saturation() feeds gpu/shaders/wet_shading.glsl), or null. With the GL backend the
  /// liquid is copied back from the GPU here (not every step); null when that fails.
  const LiquidTexture* liquidTexture(const btRigidBody* body) const;

  /// The liquid graph of a body that lists Effect::Flooding (nodes, held liquid, levels), or null.
  const LiquidGraph* liquidGraph(const btRigidBody* body) const;

  /// Where the mesh's own frame is in the world (for rendering), or empty for an unknown body.
  std::optional<btTransform> meshTransform(const btRigidBody* body) const;
  /// Report of a registered body, or null.
  const FloatingBodyReport* report(const btRigidBody* body) const;
  /// Number of registered bodies.
  std::size_t bodyCount() const { return bodies_.size(); }

  /// The liquid.
  const LiquidSettings& liquid() const { return liquid_; }
  /// Replaces the liquid (e.g. a new surface); bodies keep their bakes and are woken (a body at
  /// rest in the old liquid need not be in the new one). Error, nothing changed, for a bad liquid.
  Status setLiquid(LiquidSettings liquid);
  /// Simulated time (s) passed to the liquid surface; advanced by each updateAction.
  double time() const { return time_; }
  /// Work counters since construction or resetStatistics().
  const ControllerStatistics& statistics() const { return statistics_; }
  /// Zeroes the work counters.
  void resetStatistics() {
    statistics_ = {};
    timings_ = {};
  }
  /// Time per phase of the step since construction or resetStatistics().
  const ControllerTimings& timings() const { return timings_; }
  /// Threads the next step's parallel phase runs on (ControllerSettings::threads resolved: >= 1).
  int threads() const;
  /// The backend the texture path's hydrostatics run on (ControllerSettings::backend, or the
  /// controller's own CPU one): name() "cpu" or "gpu", renderer() what ran it.
  const ComputeBackend& backend() const { return *backend_; }

  /// Applies the liquid's effects for one fixed sub-step of `deltaTimeStep` seconds, in phases
  /// over the rigid bodies (as btRaycastVehicle::updateVehicle goes over its wheels): apply each
  /// body's deformation and flooding (serial), core's MassModelsStep asks the backend once for
  /// every due texel mass pass and each changed mass goes to Bullet (serial), read its kinematics
  /// into a RigidBodyTask and step its liquid texture (parallel, ControllerSettings::threads); core's
  /// RigidBodiesStep plans, asks the backend once for every texture body's hydrostatics (one
  /// batch, read back once) while the drag is summed, and runs each body's implicit update; write
  /// each body's velocities and sleeping state back (parallel, each its own) and add the counters
  /// in registration order. The soft bodies follow, on the threads (each its own btSoftBody),
  /// their counters added in registration order.
  void updateAction(btCollisionWorld* collisionWorld, btScalar deltaTimeStep) override;
  /// Draws, per body, the weight (red) at the centre of mass, the buoyancy (green) at the centre
  /// of buoyancy (the paper's figure 9) and the waterline (blue) where the mesh crosses the surface.
  void debugDraw(btIDebugDraw* debugDrawer) override;

 private:
  FloatingBody* find(const btRigidBody* body) const;
  HydrostaticsMethod resolveMethod(const FloatingBodySettings& settings, const std::shared_ptr<const Mesh>& mesh,
                                   std::shared_ptr<const PreparedPolyhedron>& prepared);
  void changeBody(FloatingBody& floating, MassModelTask& massTask, double dt);
  void prepareMass(FloatingBody& floating, MassModelTask& massTask) const;
  void applyMass(FloatingBody& floating, const Expected<MassProperties>& properties);
  void readBody(FloatingBody& floating, RigidBodyTask& task) const;
  void wetBodies(double dt);
  static void writeBody(FloatingBody& floating, const RigidBodyTaskResult& result);
  Status applyMassProperties(FloatingBody& floating, const MassProperties& massProperties);
  void deform(FloatingBody& floating);
  Status attachDeformedCollision(FloatingBody& floating);
  void flood(FloatingBody& floating, double dt);
  void wet(FloatingBody& floating, const Pose& meshPose, const Eigen::Vector3d& gravity, double dt) const;

  btDynamicsWorld& world_;
  LiquidSettings liquid_;
  ControllerSettings settings_;
  std::vector<std::unique_ptr<FloatingBody>> bodies_;
  std::vector<SoftBodyBuoyancy> softBodies_;
  std::vector<char> softApplied_;              ///< this step: soft body i's apply() succeeded (registration order)
  ControllerStatistics statistics_;
  ControllerTimings timings_;
  std::unique_ptr<BodyThreads> threads_;
  std::shared_ptr<ComputeBackend> backend_;
  ParallelFor parallelFor_;                    ///< threads_ as core's step takes them
  RigidBodiesStep stepper_;                    ///< core's phased step of the rigid bodies
  MassModelsStep massStepper_;                 ///< core's mass phase (one backend batch of texel mass passes)
  std::vector<MassModelTask> massTasks_;       ///< this step's mass models per body (changeBody), registration order
  std::vector<std::optional<Expected<MassProperties>>> massResults_;  ///< ... and their new mass properties
  std::vector<RigidBodyTask> tasks_;           ///< this step's question per body (readBody), registration order
  std::vector<RigidBodyTaskResult> results_;   ///< ... and the answers (writeBody)
  /// What identifies a shareable model: the mesh (by identity; the meshes the controller makes
  /// from shapes and files are interned, meshes_), resolution, the hydrostatics path it holds (0
  /// none, 1 texture, 2 exact), a true sphere's closed forms, drag and its patch settings.
  using ModelKey = std::tuple<const Mesh*, int, int, bool, bool, double, double>;
  std::map<ModelKey, std::weak_ptr<SharedBodyModel>> models_;  ///< models in use (addBody)
  std::unique_ptr<InternedMeshes> meshes_;                     ///< the meshes made from shapes and files, by content
  /// HydrostaticsMethod::Auto's choice for a mesh (by identity, kept alive-checked), resolution,
  /// target, deformation and liquid surface: bodies of one mesh are measured once.
  using AutoKey = std::tuple<const Mesh*, int, double, bool, const LiquidSurface*>;
  struct AutoChoice {
    std::weak_ptr<const Mesh> mesh;  ///< expired: the address may now be another mesh's
    HydrostaticsMethod method = HydrostaticsMethod::Texture;
  };
  std::map<AutoKey, AutoChoice> autoChoices_;
  double time_ = 0.0;
};

}  // namespace hydrotex::bullet
