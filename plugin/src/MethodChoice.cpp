// SPDX-License-Identifier: Zlib
/// @file MethodChoice.cpp
/// HydrostaticsMethod::Auto: the advisor (core/hydrostatics/Advisor.hpp) restricted to the body's
/// own resolution, so that Auto chooses the path and never changes the bake the user asked for;
/// under waves the exact path's error from linearizing the surface between vertices (which the
/// advisor, measuring in flat water, cannot see) is bounded from the surface's curvature.

#include "MethodChoice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hydrotex/hydrostatics/Advisor.hpp"
#include "hydrotex/mass/MassProperties.hpp"

namespace hydrotex::bullet {

std::optional<double> surfaceCurvatureBound(const LiquidSurface& surface) {
  if (surface.flatHeight() || !surface.hasFreeSurface()) return 0.0;
  if (const auto* waves = dynamic_cast<const GerstnerWaves*>(&surface)) {
    // Per wave, at a crest: d2y/dx2 = -A k^2 / (1 - Q A k)^2 (x = x0 - Q A sin k x0, y = A cos k x0);
    // summed with the smallest squeeze of all waves together.
    double curvature = 0.0, squeeze = 0.0;
    for (const GerstnerWaves::Component& c : waves->components()) {
      curvature += c.amplitude * c.waveNumber * c.waveNumber;
      squeeze += c.steepness * c.amplitude * c.waveNumber;
    }
    if (!(squeeze < 1.0)) return std::nullopt;  // crests may loop: no bound
    return curvature / ((1.0 - squeeze) * (1.0 - squeeze));
  }
  return std::nullopt;
}

double exactLinearizationError(const Mesh& mesh, double volume, const LiquidSurface& surface) {
  const std::optional<double> curvature = surfaceCurvatureBound(surface);
  if (!curvature) return std::numeric_limits<double>::infinity();
  if (*curvature == 0.0) return 0.0;
  if (mesh.positions.empty() || !(volume > 0.0)) return std::numeric_limits<double>::infinity();
  double longest = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (mesh.positions[t[(k + 1) % 3]] - mesh.positions[t[k]]).squaredNorm());
  Eigen::Vector3d lower = mesh.positions.front(), upper = lower;
  for (const Eigen::Vector3d& p : mesh.positions) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  const Eigen::Vector3d e = upper - lower;
  const double largestFace = std::max({e.x() * e.y(), e.y() * e.z(), e.x() * e.z()});
  return *curvature * longest / 8.0 * largestFace / volume;
}

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
