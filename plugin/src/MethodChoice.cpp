// SPDX-License-Identifier: Zlib
/// @file MethodChoice.cpp
/// HydrostaticsMethod::Auto: the advisor (core/hydrostatics/Advisor.hpp) restricted to the body's
/// own resolution, so that Auto chooses the path and never changes the bake the user asked for;
/// under waves the exact path's error from linearizing the surface between vertices (which the
/// advisor, measuring in flat water, cannot see) is bounded by core's exactLinearizationError.

#include "MethodChoice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hydrotex/hydrostatics/Advisor.hpp"
#include "hydrotex/mass/MassProperties.hpp"

namespace hydrotex::bullet {

HydrostaticsMethod resolveHydrostaticsMethod(const FloatingBodySettings& settings, const Mesh& mesh,
                                             const LiquidSurface& surface) {
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
  if (!advice || advice->candidates.empty()) return HydrostaticsMethod::Polyhedral;
  const double target = settings.autoMethodError;
  const Expected<MassProperties> solid = polyhedralMassProperties(mesh, 1.0);
  const double exactError = exactLinearizationError(mesh, solid ? solid->volume : 0.0, surface);
  if (exactError <= target)
    return advice->best.method == hydrotex::HydrostaticsMethod::Exact ? HydrostaticsMethod::Polyhedral
                                                                      : HydrostaticsMethod::Texture;
  // The texture path's error at the body's resolution (its flat-water error: under waves its
  // texels see the surface's true height at their centres, a far finer sampling than the mesh's).
  double textureError = std::numeric_limits<double>::infinity();
  for (const MethodMeasurement& m : advice->candidates)
    if (m.method != hydrotex::HydrostaticsMethod::Exact) textureError = std::min(textureError, m.maxErrors.worst());
  return textureError <= target || textureError < exactError ? HydrostaticsMethod::Texture
                                                             : HydrostaticsMethod::Polyhedral;
}

}  // namespace hydrotex::bullet
