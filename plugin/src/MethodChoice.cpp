// SPDX-License-Identifier: Zlib
/// @file MethodChoice.cpp
/// HydrostaticsMethod::Auto: core's cost model and, where the texture path is cheaper, the advisor's
/// error measurement restricted to the body's own resolution, so that Auto chooses the path and
/// never changes the bake the user asked for;
/// under a surface the prepared exact path cannot model (no smoothness bound), its error from
/// linearizing the surface between vertices (which the advisor, measuring in flat water, cannot
/// see) is core's preparedExactSurfaceError.

#include "MethodChoice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hydrotex/hydrostatics/Advisor.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/mass/MassProperties.hpp"

namespace hydrotex::bullet {

HydrostaticsMethod resolveHydrostaticsMethod(const FloatingBodySettings& settings,
                                             const std::shared_ptr<const Mesh>& meshPointer, const LiquidSurface& surface,
                                             std::shared_ptr<const PreparedPolyhedron>* prepared) {
  if (prepared) prepared->reset();
  if (settings.method != HydrostaticsMethod::Auto) return settings.method;
  const Mesh& mesh = *meshPointer;
  // Only the texture path follows a deforming mesh (its bake is re-evaluated from moved vertices).
  if (settings.effects.has(Effect::Deformation)) return HydrostaticsMethod::Texture;
  const double target = settings.autoMethodError;
  const Expected<MassProperties> solid = polyhedralMassProperties(mesh, 1.0);
  if (!solid) return HydrostaticsMethod::Polyhedral;  // addBody names the mesh's defect itself
  // The exact path's error: none in flat water, nor beyond its local surface models under waves
  // (the texture path's kind, which neither path's figure here counts); under other surfaces,
  // linearizing the surface between vertices.
  const double exactError = preparedExactSurfaceError(mesh, solid->volume, surface);
  // Costs from core's model, not a timing: the same choice on every machine and run, so that a
  // scene's trajectory does not depend on the load of the machine that registered it.
  // A free surface that is not a flat plane is priced as waves (the model's figures were taken
  // under Gerstner waves; a height grid leaves the exact path out by its error below); a medium
  // without a free surface as flat water (no surface to model).
  const bool waves = surface.hasFreeSurface() && !surface.flatHeight().has_value();
  // Both prices grow with the waterline's length (waterlineFactor): the exact path's by the
  // triangles it crosses, the texture path's by its tiles; under waves the exact path's instead by
  // its counted work below.
  const double factor = waterlineFactor(mesh);
  double exactCost = modeledMicrosecondsPerQuery(hydrotex::HydrostaticsMethod::Exact, mesh.triangles.size(), 0, waves, factor);
  // Under waves the exact path's work depends on its triangles' size against the waves (a 3 m
  // log's sides take thousands of local models where a ship's small triangles take one each):
  // priced from the work of queries at a standard pose, counted, not timed.
  if (waves && surface.smoothness(0.0))
    if (Expected<PreparedPolyhedron> made = PreparedPolyhedron::prepare(meshPointer)) {
      if (const Expected<double> priced = modeledExactMicroseconds(*made, surface)) exactCost = *priced;
      if (prepared) *prepared = std::make_shared<const PreparedPolyhedron>(std::move(made).value());
    }
  const double textureCost = modeledMicrosecondsPerQuery(hydrotex::HydrostaticsMethod::TextureHierarchy,
                                                         mesh.triangles.size(), settings.resolution, waves, factor);
  if (exactError <= target && exactCost <= textureCost) return HydrostaticsMethod::Polyhedral;  // nothing to measure
  // The texture path's error at the body's resolution, measured against the exact path in flat
  // water (under waves its texels see the surface's true height at their centres, a far finer
  // sampling than the mesh's vertices).
  AdvisorSettings advisor;
  advisor.resolutions = {settings.resolution};
  advisor.timing.modeled = true;
  const Expected<Advice> advice = adviseHydrostatics(mesh, target, advisor);
  if (!advice) return HydrostaticsMethod::Polyhedral;
  double textureError = std::numeric_limits<double>::infinity();
  for (const MethodMeasurement& m : advice->candidates)
    if (m.method != hydrotex::HydrostaticsMethod::Exact) textureError = std::min(textureError, m.maxErrors.worst());
  if (textureError <= target && (textureCost < exactCost || exactError > target)) return HydrostaticsMethod::Texture;
  if (exactError <= target) return HydrostaticsMethod::Polyhedral;
  return textureError < exactError ? HydrostaticsMethod::Texture : HydrostaticsMethod::Polyhedral;
}

}  // namespace hydrotex::bullet
