// SPDX-License-Identifier: Zlib
#pragma once
/// @file MassModelsStep.hpp
/// The mass phase of a step over many bodies (docs/design.md "The phased step"): every body whose
/// mass model has a texel pass due (MassModel::needsTexelPass: a new density map, a solid or shell
/// density changed) and whose texels a ComputeBackend holds is asked of the backend in one
/// massProperties batch, read back once; each model then finishes with the backend's answer plus
/// its point masses (MassModel::finish). Models with nothing due only combine their point masses
/// (no pass), and models that follow triangles (a deforming body: TriangleMassIntegrator's sums,
/// O(triangles) and exact, no texel pass) or whose texels no backend holds evaluate themselves
/// (MassModel::properties) on the calling thread.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mass/MassProperties.hpp"

namespace hydrotex {

/// One body's mass model in the mass phase.
struct MassModelTask {
  /// The model, already told this step's changes (point masses moved, advanceTo); null: the
  /// body has nothing to recompute this step (its result is emptied). A model is named by one
  /// task at most (its map is lent to the batch, MassModel::lendTexelModel).
  MassModel* model = nullptr;
  /// Where its texel pass runs: the body's id in the backend, registered with the model's
  /// textures and reference point (ComputeBackend::addBody); empty: inside the model, here.
  std::optional<BackendBodyId> backendBody;
};

/// The work of one mass phase.
struct MassModelsStepStatistics {
  std::uint64_t massBatches = 0;      ///< massProperties batches asked of the backend (each read back once)
  std::uint64_t massBatchBodies = 0;  ///< bodies in those batches (a body asked again alone counts again)
};

/// The mass phase, with the room its batch works in kept between steps (allocation-free once the
/// number of bodies stopped growing; the maps are lent by the models, not copied). Not thread-safe.
class MassModelsStep {
 public:
  /// For every task with a model, sets results[i] to its mass properties (MassModel::properties,
  /// or MassModel::finish with the backend's texel pass), the others' to empty: the due texel passes of the tasks that
  /// name a backend body go to `backend` in one batch (none asked when none is due); a failed
  /// batch is asked again body by body, so that one bad map does not cost the others their
  /// update. A task whose pass or combination failed gets its Error. Each result depends only on
  /// its own model and texels, so the results are the same in any batch. The CPU backend holds an
  /// equal TextureMassIntegrator, so its answers have the bits of MassModel::properties; the GL
  /// backend's sums round in float per workgroup (parity with the CPU within 1e-5 of the mass,
  /// tests/gpu/test_backend_parity.cpp). Writes
  /// min(tasks.size(), results.size()) results.
  MassModelsStepStatistics run(ComputeBackend& backend, std::span<const MassModelTask> tasks,
                               std::span<std::optional<Expected<MassProperties>>> results);

 private:
  std::vector<BackendBodyId> ids_;          ///< the batch's bodies
  std::vector<TextureMassModel> models_;    ///< ... their models (maps lent by the models during the batch)
  std::vector<MassProperties> answers_;     ///< ... and the backend's answers
  std::vector<std::size_t> taskOfQuery_;    ///< task index per batch entry
  std::vector<std::optional<Error>> failures_;  ///< per batch entry: the backend's error, if any
};

}  // namespace hydrotex
