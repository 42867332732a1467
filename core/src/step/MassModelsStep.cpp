// SPDX-License-Identifier: Zlib
/// @file MassModelsStep.cpp
/// The mass phase of a step: one backend batch for every due texel pass, then each model finishes.
#include "hydrotex/step/MassModelsStep.hpp"

#include <algorithm>

namespace hydrotex {

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
    // The map is lent, not copied (a map is 4 bytes a texel, the pass reads 20): every lent map
    // goes back below, before any model is touched again, whatever the backend answered.
    task.model->lendTexelModel(models_[used++]);
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
  for (std::size_t k = 0; k < taskOfQuery_.size(); ++k) tasks[taskOfQuery_[k]].model->takeBackTexelModel(models_[k]);
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
