// SPDX-License-Identifier: Zlib
/// @file MassModelsStep.cpp
/// The mass phase of a step: one backend batch for every due texel pass, then each model finishes.
#include "hydrotex/step/MassModelsStep.hpp"

namespace hydrotex {
namespace {

// `into` becomes a copy of `from` without allocating once its map's capacity has grown: the
// backend takes its models as one contiguous span, and a model's map stays the model's. The copy
// is 4 bytes a texel against the pass's 20 (four cone terms and the density) read by the backend.
void copyModel(const TextureMassModel& from, TextureMassModel& into) {
  into.solidDensity = from.solidDensity;
  into.shellDensity = from.shellDensity;
  into.referencePoint = from.referencePoint;
  into.texelDensity.assign(from.texelDensity.begin(), from.texelDensity.end());
}

}  // namespace

MassModelsStepStatistics MassModelsStep::run(ComputeBackend& backend, std::span<const MassModelTask> tasks,
                                             std::span<std::optional<Expected<MassProperties>>> results) {
  const std::size_t count = std::min(tasks.size(), results.size());
  MassModelsStepStatistics statistics;
  // Gather: the due texel passes whose texels the backend holds.
  ids_.clear();
  taskOfQuery_.clear();
  std::size_t used = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const MassModelTask& task = tasks[i];
    if (task.model == nullptr || !task.backendBody || !task.model->needsTexelPass()) continue;
    ids_.push_back(*task.backendBody);
    taskOfQuery_.push_back(i);
    if (models_.size() <= used) models_.emplace_back();
    copyModel(task.model->texelModel(), models_[used++]);
  }
  // One batch, read back once; a failed batch (nothing written) is asked again body by body.
  answers_.resize(ids_.size());
  failures_.assign(ids_.size(), std::nullopt);
  if (!ids_.empty()) {
    ++statistics.massBatches;
    statistics.massBatchBodies += ids_.size();
    const std::span<const TextureMassModel> models(models_.data(), ids_.size());
    if (!backend.massProperties(ids_, models, answers_)) {
      for (std::size_t q = 0; q < ids_.size(); ++q) {
        ++statistics.massBatches;
        ++statistics.massBatchBodies;
        if (Status alone = backend.massProperties(std::span(&ids_[q], 1), models.subspan(q, 1), std::span(&answers_[q], 1));
            !alone)
          failures_[q] = alone.error();
      }
    }
  }
  // Finish: the backend's texel part and the point masses; the others evaluate themselves.
  std::size_t q = 0;
  for (std::size_t i = 0; i < count; ++i) {
    MassModel* model = tasks[i].model;
    if (model == nullptr) {
      results[i].reset();
      continue;
    }
    if (q < taskOfQuery_.size() && taskOfQuery_[q] == i) {
      results[i] = failures_[q] ? Expected<MassProperties>(*failures_[q]) : model->finish(answers_[q]);
      ++q;
    } else {
      results[i] = model->properties();
    }
  }
  return statistics;
}

}  // namespace hydrotex
