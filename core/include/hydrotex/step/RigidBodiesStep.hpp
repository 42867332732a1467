// SPDX-License-Identifier: Zlib
#pragma once
/// @file RigidBodiesStep.hpp
/// The phased step of many rigid bodies in one liquid (docs/design.md "The phased step"): plan
/// each body (asleep, static, out of the liquid, or computed), ask the backend once for every
/// texture body's hydrostatics (read back once) while the drag over every body's patches runs on
/// the CPU threads, then each body's implicit update (stepRigidBody) in parallel. A physics
/// engine's adapter reads its bodies into RigidBodyTask records, calls stepRigidBodies, and writes
/// the velocities back; it holds no law of its own.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"

namespace hydrotex {

/// One rigid body's question for a step (world frame, SI units). The adapter fills it from its
/// engine's body; stepRigidBodies only reads it.
struct RigidBodyTask {
  RigidBodyMotion motion;            ///< pose of the mesh frame, centre of mass, velocities, mass, inertia
  /// Gravity, the effects' settings and the liquid (stepRigidBody's input); its `hydrostatics`
  /// is ignored: the step sets it from the backend's or the exact path's answer.
  RigidBodyStepInput input;
  bool active = true;                ///< awake in the engine: a sleeping body in a still liquid is left as it is
  bool dynamic = true;               ///< positive mass in the engine: a static or kinematic body is left alone
  /// Buoyancy or added mass is listed: the body's hydrostatics are needed (when gravity points down).
  bool wantsHydrostatics = true;
  /// The texture path: the body's id in the backend, asked in the step's one batch.
  std::optional<BackendBodyId> backendBody;
  /// The exact polyhedral path (when backendBody is empty): the closed mesh prepared once
  /// (PreparedPolyhedron), or, for a mesh that moves from step to step (a deforming body), the
  /// mesh itself (exactMesh, when exactPrepared is null); mesh frame (m).
  const PreparedPolyhedron* exactPrepared = nullptr;
  const Mesh* exactMesh = nullptr;  ///< see exactPrepared
  /// The body is a true sphere of this radius (m) about the mesh frame's origin: in flat water its
  /// hydrostatics in closed form (sphereHydrostatics), elsewhere the exact path on its mesh.
  std::optional<double> sphereRadius;
  /// The body is a box of these half extents (m, along the mesh frame's axes) about the mesh
  /// frame's origin, its mesh the box's 12 triangles: under waves its hydrostatics by a rule on
  /// its faces where that applies, elsewhere the exact path on its mesh.
  std::optional<Eigen::Vector3d> boxHalfExtents;
  Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();  ///< m, mesh frame (the query's)
  Eigen::Vector3d boundsCenter = Eigen::Vector3d::Zero();  ///< m, mesh frame: centre of a sphere holding the mesh
  double boundsRadius = 0.0;                               ///< m, its radius
};

/// What the step decided for a body.
enum class RigidBodyPlan {
  Computed,      ///< in the liquid: loads and the implicit update
  Asleep,        ///< asleep in a still liquid: nothing the liquid does changes it; no velocities
  Static,        ///< not dynamic: no velocities
  OutOfLiquid,   ///< wholly above the surface (whollyAboveSurface): free fall, v + g dt
};

/// The work a step did for one body (the adapter adds them to its statistics).
struct RigidBodyStepCounters {
  std::uint64_t hydrostaticsQueries = 0;  ///< hydrostatics asked (backend or exact path)
  std::uint64_t failedQueries = 0;        ///< a query or the update that failed (its forces skipped)
  std::uint64_t dragPasses = 0;           ///< passes over the body's drag patches
  std::uint64_t dragPatchesVisited = 0;   ///< patches at least partly wet
  std::uint64_t addedMassUpdates = 0;     ///< added mass evaluated
};

/// One body's outcome of a step.
struct RigidBodyTaskResult {
  RigidBodyPlan plan = RigidBodyPlan::Computed;
  HydrostaticsResult hydrostatics;       ///< this step's answer (zero when none was asked or it failed)
  /// The velocities and loads after the step: set for Computed bodies whose update succeeded and
  /// for OutOfLiquid ones (free fall; zero drag); empty for the others.
  std::optional<RigidBodyStepResult> step;
  RigidBodyStepCounters counters;
};

/// The work of one whole step (besides each body's counters), and where its time went (wall
/// clock, s: a benchmark's per-phase split; not deterministic).
struct RigidBodiesStepStatistics {
  std::uint64_t backendBatches = 0;  ///< hydrostatics batches asked of the backend, each read back once
  double planSeconds = 0.0;          ///< the serial plan
  double backendSeconds = 0.0;       ///< in the backend's batch calls, less the drag run meanwhile
  double dragSeconds = 0.0;          ///< the drag of the bodies summed beside the batch (overlapping a GPU's)
  double updateSeconds = 0.0;        ///< the exact path's queries (with their drag under waves) and the implicit updates
};

/// The phased step of many rigid bodies, with the room it works in kept between steps (a step
/// allocates nothing once the number of bodies stopped growing). Not thread-safe: one thread
/// drives it (as one drives a backend).
class RigidBodiesStep {
 public:
  /// Steps every body of `tasks` by `dt` seconds (> 0) in `surface` (the liquid the tasks'
  /// `input.liquid` names, at its `time`): plan (serial), the drag of every computed body through
  /// `parallelFor` while `backend` answers one hydrostatics batch for the texture bodies (a GPU
  /// overlaps the two; a failed batch is asked again body by body, so that one bad body does not
  /// cost the others their buoyancy), then the exact path's queries and stepRigidBody through
  /// `parallelFor` (empty: in order). Under waves (a surface that is neither flat nor a medium) a
  /// body on the prepared exact path has its drag summed after its query instead, reading the
  /// surface's heights from the jets the query sampled (within the drag's height error, 1e-4 m)
  /// rather than sampling its own; a sphere or box whose own rule answered (sphereRadius,
  /// boxHalfExtents) sums it on that rule's nodes of its wetted surface instead of its patches.
  /// Each result depends only on its own task, so the results are the same for every thread
  /// count. Writes min(tasks.size(), results.size()) results. Never throws; failures are counted
  /// in each body's counters.
  RigidBodiesStepStatistics run(ComputeBackend& backend, const LiquidSurface& surface,
                                std::span<const RigidBodyTask> tasks, std::span<RigidBodyTaskResult> results,
                                const ParallelFor& parallelFor, double dt);

 private:
  struct Batch;
  void plan(const Batch& batch);
  void sumDrag(const Batch& batch, std::size_t i);
  /// Whether body i's drag is summed in update() after its exact query under waves, on the jets
  /// that query sampled, rather than beside the backend's batch.
  bool dragAfterExactQuery(const Batch& batch, std::size_t i) const;
  void update(const Batch& batch, std::size_t i);

  static constexpr std::size_t kNoQuery = ~std::size_t{0};
  std::vector<BackendHydrostaticsQuery> queries_;  ///< the step's batch
  std::vector<std::size_t> queryOfBody_;           ///< index in queries_, or kNoQuery
  std::vector<HydrostaticsResult> answers_;        ///< the backend's answers, by query
  std::vector<char> answered_;                     ///< by query: the answer is valid
  std::vector<DragLoads> drag_;                    ///< by body: this step's drag
  bool anyDrag_ = false;                           ///< a computed body's drag is summed beside the batch this step
};

}  // namespace hydrotex
