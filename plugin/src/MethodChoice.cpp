// SPDX-License-Identifier: Zlib
/// @file MethodChoice.cpp
/// HydrostaticsMethod::Auto: the advisor (core/hydrostatics/Advisor.hpp) restricted to the body's
/// own resolution, so that Auto chooses the path and never changes the bake the user asked for.

#include "MethodChoice.hpp"

#include "hydrotex/hydrostatics/Advisor.hpp"

namespace hydrotex::bullet {

HydrostaticsMethod resolveHydrostaticsMethod(const FloatingBodySettings& settings, const Mesh& mesh) {
  if (settings.method != HydrostaticsMethod::Auto) return settings.method;
  // Only the texture path follows a deforming mesh (its bake is re-evaluated from moved vertices).
  if (settings.effects.has(Effect::Deformation)) return HydrostaticsMethod::Texture;
  AdvisorSettings advisor;
  advisor.resolutions = {settings.resolution};
  // Short timing: registration should cost milliseconds; the two paths' times differ by several
  // times wherever the choice matters (README "Choosing a method and a resolution").
  advisor.timing.runs = 3;
  advisor.timing.batchSeconds = 0.002;
  const Expected<Advice> advice = adviseHydrostatics(mesh, settings.autoMethodError, advisor);
  if (!advice) return HydrostaticsMethod::Polyhedral;
  return advice->best.method == hydrotex::HydrostaticsMethod::Exact ? HydrostaticsMethod::Polyhedral
                                                                    : HydrostaticsMethod::Texture;
}

}  // namespace hydrotex::bullet
