// The deformation effect: a body's vertices move (a callback or scale keyframes) and its texel
// fields, hydrostatics, mass model, drag patches and collision bounds follow (issue 5).
#include <algorithm>

#include "BulletEigen.hpp"
#include "FloatingBody.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"

namespace hydrotex::bullet {

void BuoyancyController::deform(FloatingBody& floating) {
  DeformationState& state = *floating.deformation;
  const FloatingBodySettings& settings = floating.settings;
  std::vector<Eigen::Vector3d>& positions = state.current->positions;
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  if (settings.deformation) {
    state.positions = state.rest.positions;
    settings.deformation(time_, state.rest, state.positions);
    if (state.positions.size() != positions.size() || !std::all_of(state.positions.begin(), state.positions.end(),
                                                                    [](const Eigen::Vector3d& p) { return p.allFinite(); })) {
      ++statistics_.failedQueries;  // a callback that broke the topology: keep the last shape
      return;
    }
    positions.swap(state.positions);
  } else {
    scale = scaleAt(settings.scaleKeyframes, time_);
    for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = state.rest.positions[i].cwiseProduct(scale);
  }
  ++statistics_.deformations;
  // PT/VAT from the moved vertices through the kept texel pieces (DESIGN.md "Exact texels").
  // In place, allocation-free: the evaluator, the hydrostatics and the mass model reuse their buffers.
  state.evaluator.evaluate(*state.current, state.textures);
  if (floating.texture && !floating.texture->update(state.textures)) ++statistics_.failedQueries;
  if (floating.massModel && !floating.massModel->setGeometry(state.textures)) ++statistics_.failedQueries;
  if (settings.effects.has(Effect::Drag)) {
    floating.dragPatches = mergeTexelsIntoDragPatches(state.bake, state.textures, settings.dragPatchNormalCosine,
                                                      settings.dragPatchRadiusFraction * floating.referenceLength);
    floating.totalDragPatchArea = 0.0;
    for (const DragPatch& patch : floating.dragPatches) floating.totalDragPatchArea += patch.area;
  }
  Eigen::Vector3d lower = positions.front(), upper = lower;
  for (const Eigen::Vector3d& p : positions) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  floating.boundsCenter = 0.5 * (lower + upper);
  floating.boundsRadius = 0.5 * (upper - lower).norm();
  if (!settings.scaleKeyframes.empty() && floating.compound) {
    floating.originalShape->setLocalScaling(toBullet(scale));
    floating.compound->recalculateLocalAabb();
    if (floating.body->getBroadphaseHandle() != nullptr) world_.updateSingleAabb(floating.body);
  }
}

}  // namespace hydrotex::bullet
