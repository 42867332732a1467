// SPDX-License-Identifier: Zlib
/// @file RigidBodiesStep.cpp
/// The phased step of many rigid bodies: plan, one backend batch overlapped with the drag, then
/// each body's update.
#include "hydrotex/step/RigidBodiesStep.hpp"

#include <chrono>
#include <functional>
#include <optional>
#include <vector>

#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PrimitiveHydrostatics.hpp"
#include "hydrostatics/BoxHydrostaticsWaves.hpp"
#include "hydrostatics/SphereHydrostaticsWaves.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "step/RigidBodyDragWithJets.hpp"

namespace hydrotex {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Runs work(i) for i in [0, count) through `parallelFor`, or in order when it is empty.
void forEach(const ParallelFor& parallelFor, std::size_t count, const std::function<void(std::size_t)>& work) {
  if (count == 0) return;
  if (parallelFor) {
    parallelFor(count, work);
    return;
  }
  for (std::size_t i = 0; i < count; ++i) work(i);
}

// The hydrostatics query of a body in its pose (the buoyancy's pressure acts along -g_y).
HydrostaticsQuery queryOf(const RigidBodyTask& task) {
  HydrostaticsQuery query;
  query.pose = task.motion.meshPose;
  query.gravity = -task.input.gravity.y();
  query.centerOfMass = task.centerOfMass;
  query.time = task.input.liquid.time;
  query.mass = task.motion.mass;
  return query;
}

// The grid of surface jets a body's exact query keeps for its drag: one per thread, reused. GCC
// zero-fills a default-constructed optional<SurfaceJetGrid> (over 50 KiB): one on the stack of each
// update cost every body that memset, about 0.6 us of a box's 1.65 in flat water (bench_peers).
std::optional<detail::SurfaceJetGrid>& threadJetGrid() {
  static thread_local std::optional<detail::SurfaceJetGrid> grid;
  return grid;
}

// The nodes of a sphere's or box's rule on its wetted surface, for its drag: one list per thread, reused.
std::vector<detail::WettedNode>& threadWettedNodes() {
  static thread_local std::vector<detail::WettedNode> nodes;
  return nodes;
}

// Body `task`'s hydrostatics on the exact path (or a sphere's closed form) into `out`; false when
// the query fails. With `jets`, a prepared body's query keeps the surface jets it sampled there.
// With `nodes`, a sphere or box whose rule answers under waves gives its drag's nodes there and
// sets `*onNodes`.
bool exactHydrostatics(const LiquidSurface& surface, const RigidBodyTask& task,
                       std::optional<detail::SurfaceJetGrid>* jets, HydrostaticsResult& out,
                       std::vector<detail::WettedNode>* nodes = nullptr, bool* onNodes = nullptr) {
  if (onNodes) *onNodes = false;
  const HydrostaticsQuery query = queryOf(task);
  // A sphere in flat water in closed form; under waves by its rule on the true sphere
  // (SphereHydrostaticsWaves.cpp: 16 x 8 nodes and 36 jets for bench_peers' sphere, where its mesh
  // of 17,160 triangles took about three times as long), keeping its jets for the drag as the
  // prepared mesh does, unless the rule does not apply there. The prepared mesh gives the mesh's
  // own answer (PreparedPolyhedron.hpp), faster, and under waves models the surface over its
  // triangles.
  const bool closedForm = task.sphereRadius && surface.flatHeight().has_value();
  if (task.sphereRadius && !closedForm) {
    std::optional<detail::SurfaceJetGrid>& grid = jets ? *jets : threadJetGrid();
    std::optional<Expected<HydrostaticsResult>> waves =
        detail::waveSphereHydrostatics(*task.sphereRadius, Eigen::Vector3d::Zero(), surface, query, &grid, {}, nullptr,
                                       nodes);
    if (!jets) grid.reset();  // it refers to the surface
    if (waves) {
      if (!*waves) return false;
      out = **waves;
      if (onNodes) *onNodes = nodes != nullptr;
      return true;
    }
  }
  // A box under waves by its rule on its faces (BoxHydrostaticsWaves.cpp: 6 x 3 nodes a face and
  // 36-64 jets, 53 on average over headings, for bench_peers' box, where its 12 triangles took
  // about 90 local models and 180 clipped pieces), keeping its jets for the drag, unless the rule
  // does not apply there.
  if (task.boxHalfExtents && !surface.flatHeight()) {
    std::optional<detail::SurfaceJetGrid>& grid = jets ? *jets : threadJetGrid();
    std::optional<Expected<HydrostaticsResult>> waves =
        detail::waveBoxHydrostatics(*task.boxHalfExtents, Eigen::Vector3d::Zero(), surface, query, &grid, {}, nullptr,
                                    nodes);
    if (!jets) grid.reset();  // it refers to the surface
    if (waves) {
      if (!*waves) return false;
      out = **waves;
      if (onNodes) *onNodes = nodes != nullptr;
      return true;
    }
  }
  Expected<HydrostaticsResult> exact =
      closedForm                     ? sphereHydrostatics(*task.sphereRadius, Eigen::Vector3d::Zero(), surface, query)
      : task.exactPrepared != nullptr ? (jets ? detail::polyhedralHydrostaticsKeepingJets(*task.exactPrepared, surface, query, *jets)
                                              : polyhedralHydrostatics(*task.exactPrepared, surface, query))
      : task.exactMesh != nullptr    ? polyhedralHydrostaticsUnchecked(*task.exactMesh, surface, query)
                                     : Expected<HydrostaticsResult>(Error{"no mesh for the exact path"});
  if (!exact) return false;
  out = *exact;
  return true;
}

// Whether the body needs hydrostatics this step: buoyancy or added mass listed, and a weight that
// presses it into the liquid (no hydrostatic head without downward gravity).
bool asksHydrostatics(const RigidBodyTask& task) {
  return task.wantsHydrostatics && -task.input.gravity.y() > 0.0;
}

}  // namespace

// One step's inputs, handed to the parallel work through one pointer (a std::function holding two
// pointers does not allocate).
struct RigidBodiesStep::Batch {
  ComputeBackend& backend;
  const LiquidSurface& surface;
  std::span<const RigidBodyTask> tasks;
  std::span<RigidBodyTaskResult> results;
  const ParallelFor& parallelFor;
  double dt;
};

RigidBodiesStepStatistics RigidBodiesStep::run(ComputeBackend& backend, const LiquidSurface& surface,
                                               std::span<const RigidBodyTask> tasks,
                                               std::span<RigidBodyTaskResult> results, const ParallelFor& parallelFor,
                                               double dt) {
  const std::size_t count = std::min(tasks.size(), results.size());
  const Batch batch{backend, surface, tasks.first(count), results.first(count), parallelFor, dt};
  RigidBodiesStepStatistics statistics;
  Clock::time_point start = Clock::now();
  plan(batch);
  statistics.planSeconds = secondsSince(start);

  // The backend: one batch, read back once, while the drag of every body is summed (pure).
  drag_.resize(count);
  const struct {
    RigidBodiesStep* self;
    const Batch* batch;
    double* seconds;
  } drag{this, &batch, &statistics.dragSeconds};
  const std::function<void()> sumAllDrag = [&drag] {
    if (!drag.self->anyDrag_) return;  // no pass over the threads for nothing
    const Clock::time_point dragStart = Clock::now();
    forEach(drag.batch->parallelFor, drag.batch->tasks.size(),
            [&drag](std::size_t i) { drag.self->sumDrag(*drag.batch, i); });
    *drag.seconds += secondsSince(dragStart);
  };
  start = Clock::now();
  answers_.resize(queries_.size());
  answered_.assign(queries_.size(), 0);
  if (queries_.empty()) {
    sumAllDrag();
  } else {
    ++statistics.backendBatches;
    if (backend.hydrostatics(surface, queries_, answers_, sumAllDrag)) {
      answered_.assign(queries_.size(), 1);
    } else {
      // A batch fails whole (nothing written): ask each body alone. Counted: each is a batch.
      for (std::size_t q = 0; q < queries_.size(); ++q) {
        ++statistics.backendBatches;
        answered_[q] = backend.hydrostatics(surface, std::span(&queries_[q], 1), std::span(&answers_[q], 1)).ok();
      }
    }
  }
  statistics.backendSeconds = secondsSince(start) - statistics.dragSeconds;
  // Each body's update (parallel).
  start = Clock::now();
  forEach(parallelFor, count, [this, &batch](std::size_t i) { update(batch, i); });
  statistics.updateSeconds = secondsSince(start);
  return statistics;
}

void RigidBodiesStep::plan(const Batch& batch) {
  queries_.clear();
  queryOfBody_.assign(batch.tasks.size(), kNoQuery);
  anyDrag_ = false;
  const bool flat = batch.surface.flatHeight().has_value();
  for (std::size_t i = 0; i < batch.tasks.size(); ++i) {
    const RigidBodyTask& task = batch.tasks[i];
    RigidBodyTaskResult& result = batch.results[i];
    result = RigidBodyTaskResult{};
    // A body asleep in a still liquid stays as it was: nothing the liquid does can have changed.
    if (!task.active && flat && task.input.liquid.current.isZero()) {
      result.plan = RigidBodyPlan::Asleep;
      continue;
    }
    if (!task.dynamic) {
      result.plan = RigidBodyPlan::Static;
      continue;
    }
    const Eigen::Vector3d sphereCenter = task.motion.meshPose.apply(task.boundsCenter);
    if (whollyAboveSurface(batch.surface, sphereCenter, task.boundsRadius, task.input.liquid.time)) {
      result.plan = RigidBodyPlan::OutOfLiquid;  // free fall
      RigidBodyStepResult fall;
      fall.velocities.linear = task.motion.linearVelocity + batch.dt * task.input.gravity;
      fall.velocities.angular = task.motion.angularVelocity;
      fall.drag.liquidVelocityAtCenter = task.input.liquid.current;
      result.step = fall;
      continue;
    }
    if (task.backendBody && asksHydrostatics(task)) {
      ++result.counters.hydrostaticsQueries;
      queryOfBody_[i] = queries_.size();
      queries_.push_back(BackendHydrostaticsQuery{*task.backendBody, queryOf(task)});
    }
    anyDrag_ = anyDrag_ || (task.input.drag != nullptr && !dragAfterExactQuery(batch, i));
  }
}

bool RigidBodiesStep::dragAfterExactQuery(const Batch& batch, std::size_t i) const {
  const RigidBodyTask& task = batch.tasks[i];
  return task.input.drag != nullptr && queryOfBody_[i] == kNoQuery && asksHydrostatics(task) &&
         task.exactPrepared != nullptr && !batch.surface.flatHeight().has_value() && batch.surface.hasFreeSurface();
}

void RigidBodiesStep::sumDrag(const Batch& batch, std::size_t i) {
  const RigidBodyTask& task = batch.tasks[i];
  if (batch.results[i].plan != RigidBodyPlan::Computed || task.input.drag == nullptr) return;
  if (dragAfterExactQuery(batch, i)) return;  // summed in update(), on its query's jets
  // (A sphere or box in flat water sums it on its wetted surface's nodes: DragBody::sphereRadius.)
  drag_[i] = rigidBodyDrag(*task.input.drag, task.motion, task.input.liquid, batch.dt);
}

void RigidBodiesStep::update(const Batch& batch, std::size_t i) {
  const RigidBodyTask& task = batch.tasks[i];
  RigidBodyTaskResult& result = batch.results[i];
  if (result.plan != RigidBodyPlan::Computed) return;
  RigidBodyStepCounters& counters = result.counters;
  // Hydrostatics: the backend's answer for a texture body, the exact path here for the others.
  bool haveHydrostatics = false;
  if (asksHydrostatics(task)) {
    if (queryOfBody_[i] != kNoQuery) {
      const std::size_t q = queryOfBody_[i];
      if (answered_[q]) {
        result.hydrostatics = answers_[q];
        haveHydrostatics = true;
      }
    } else if (task.sphereRadius || task.exactPrepared != nullptr || task.exactMesh != nullptr) {
      ++counters.hydrostaticsQueries;
      if (dragAfterExactQuery(batch, i)) {
        // Under waves a prepared body's query keeps the surface jets it sampled, and its drag is
        // summed here, after it, reading its heights from them (the drag's own grid took 23-36
        // jets on bench_peers' box and hull under its three waves, ~150 ns each).
        // A sphere or box whose rule answered sums its drag on the rule's nodes instead: the pieces
        // its buoyancy used (issue 19 item 3), wet to the water line, where its mesh's patches
        // asked the jets again (the sphere's 17,160 triangles; the box's 64 patches, up to 24 %
        // off the law's integral under bench_peers' waves, test_rigid_body_step).
        std::optional<detail::SurfaceJetGrid>& jets = threadJetGrid();
        std::vector<detail::WettedNode>& nodes = threadWettedNodes();
        bool onNodes = false;
        haveHydrostatics = exactHydrostatics(batch.surface, task, &jets, result.hydrostatics,
                                             task.sphereRadius || task.boxHalfExtents ? &nodes : nullptr, &onNodes);
        drag_[i] = onNodes ? detail::rigidBodyDragOnNodes(*task.input.drag, task.motion, task.input.liquid, batch.dt, nodes)
                           : detail::rigidBodyDrag(*task.input.drag, task.motion, task.input.liquid, batch.dt,
                                                   jets ? &*jets : nullptr);
        jets.reset();  // it refers to the surface
      } else {
        haveHydrostatics = exactHydrostatics(batch.surface, task, nullptr, result.hydrostatics);
      }
    }
    if (!haveHydrostatics) ++counters.failedQueries;
  }
  RigidBodyStepInput input = task.input;
  input.hydrostatics = haveHydrostatics ? &result.hydrostatics : nullptr;
  input.dragLoads = input.drag != nullptr ? &drag_[i] : nullptr;
  if (input.drag != nullptr) {
    ++counters.dragPasses;
    counters.dragPatchesVisited += drag_[i].patchesVisited;
  }
  if (input.addedMassCoefficient) ++counters.addedMassUpdates;
  Expected<RigidBodyStepResult> stepped = stepRigidBody(task.motion, input, batch.dt);
  if (!stepped) {
    ++counters.failedQueries;
    return;
  }
  result.step = *stepped;
}

}  // namespace hydrotex
