// SPDX-License-Identifier: Zlib
#include "hydrotex/bullet/FloatingBodySettings.hpp"

#include <array>
#include <cmath>
#include <utility>

namespace hydrotex::bullet {
namespace {

constexpr std::array<std::pair<Effect, std::string_view>, 7> kEffectNames{{
    {Effect::Buoyancy, "buoyancy"},
    {Effect::Drag, "drag"},
    {Effect::AddedMass, "added_mass"},
    {Effect::VariableMass, "variable_mass"},
    {Effect::Flooding, "flooding"},
    {Effect::Deformation, "deformation"},
    {Effect::Wetting, "wetting"},
}};

bool finiteNonNegative(double value) { return std::isfinite(value) && value >= 0.0; }

}  // namespace

std::optional<Effect> effectFromName(std::string_view name) {
  for (const auto& [effect, effectText] : kEffectNames) {
    if (effectText == name) return effect;
  }
  return std::nullopt;
}

std::string_view effectName(Effect effect) {
  for (const auto& [e, effectText] : kEffectNames) {
    if (e == effect) return effectText;
  }
  return "unknown";
}

Eigen::Vector3d scaleAt(const std::vector<ScaleKeyframe>& keyframes, double time) {
  if (keyframes.empty()) return Eigen::Vector3d::Ones();
  if (!(time > keyframes.front().time)) return keyframes.front().scale;
  if (time >= keyframes.back().time) return keyframes.back().scale;
  std::size_t next = 1;
  while (keyframes[next].time <= time) ++next;
  const ScaleKeyframe& a = keyframes[next - 1];
  const ScaleKeyframe& b = keyframes[next];
  const double s = (time - a.time) / (b.time - a.time);
  return a.scale + s * (b.scale - a.scale);
}

Status WettingBodySettings::validate() const {
  if (resolution != 0 && (resolution < 16 || resolution > 4096)) {
    return Error{"resolution: " + std::to_string(resolution) + " is outside 16..4096 (or 0 for the body's)"};
  }
  if (Status s = material.validate(); !s) return Error{"material: " + s.error().message};
  if (Status s = physics.validate(); !s) return Error{"physics: " + s.error().message};
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const LiquidSource& source = sources[i];
    if (!(std::isfinite(source.rate) && source.rate >= 0.0) || !source.centre.allFinite() ||
        !source.direction.allFinite() || !(std::isfinite(source.radius) && source.radius >= 0.0) ||
        !(source.pigment >= 0.0 && source.pigment <= 1.0)) {
      return Error{"sources[" + std::to_string(i) + "]: rate and radius must be >= 0 and finite, pigment in 0..1"};
    }
  }
  return Ok{};
}

Status FloodingBodySettings::validate() const {
  if (Status s = graph.validate(); !s) return s;
  if (nodeCount < 0 || nodeCount > 1024) return Error{"liquid_graph_nodes: " + std::to_string(nodeCount) + " is outside 0..1024"};
  if (permeabilityMap && permeabilityMap->values.empty()) return Error{"permeability_map: empty image"};
  if (manualGraph && manualGraph->nodes.empty()) return Error{"liquid_graph: no nodes"};
  return Ok{};
}

Status FloatingBodySettings::validate() const {
  if (!mesh && meshPath.empty()) {
    if (Status s = shape.validate(); !s) return Error{"shape: " + s.error().message};
  }
  if (mesh && mesh->triangles.empty()) return Error{"mesh: the mesh has no triangles"};
  if (mesh) {
    // Lids over openings (Mesh.hpp) are read in one ascending walk next to the triangles.
    const std::vector<std::uint32_t>& lids = mesh->openingTriangles;
    for (std::size_t i = 0; i < lids.size(); ++i)
      if (lids[i] >= mesh->triangles.size() || (i > 0 && lids[i] <= lids[i - 1]))
        return Error{"mesh: openingTriangles must be ascending indices of its triangles"};
  }
  if (resolution < 16 || resolution > 4096) {
    return Error{"resolution: " + std::to_string(resolution) + " is outside 16..4096"};
  }
  if (!(autoMethodError > 0.0) || !std::isfinite(autoMethodError)) {
    return Error{"autoMethodError: " + std::to_string(autoMethodError) + " is not positive and finite"};
  }
  if (density && mass) return Error{"density and mass: give one of them, not both"};
  if (density && !(std::isfinite(*density) && *density > 0.0)) {
    return Error{"density: " + std::to_string(*density) + " kg/m^3 must be positive and finite"};
  }
  if (mass && !(std::isfinite(*mass) && *mass > 0.0)) {
    return Error{"mass: " + std::to_string(*mass) + " kg must be positive and finite"};
  }
  if (!finiteNonNegative(shellDensity)) return Error{"shellDensity: must be >= 0 and finite"};
  if (densityMap) {
    if (densityMap->values.empty()) return Error{"densityMap: empty image"};
    if (!finiteNonNegative(densityRange[0]) || !finiteNonNegative(densityRange[1])) {
      return Error{"densityRange: both densities must be >= 0 and finite"};
    }
  }
  for (std::size_t i = 0; i < pointMasses.size(); ++i) {
    if (Status s = pointMasses[i].validate(); !s) {
      return Error{"pointMasses[" + std::to_string(i) + "]: " + s.error().message};
    }
  }
  if (effects.has(Effect::Deformation)) {
    if (!deformation && scaleKeyframes.empty()) {
      return Error{"deformation: the effect needs a deformation function or scale keyframes"};
    }
    if (deformation && !scaleKeyframes.empty()) return Error{"deformation: give a function or scale keyframes, not both"};
    if (method == HydrostaticsMethod::Polyhedral) return Error{"deformation: needs the texture method"};
  }
  for (std::size_t i = 0; i < scaleKeyframes.size(); ++i) {
    const ScaleKeyframe& key = scaleKeyframes[i];
    if (!std::isfinite(key.time) || !key.scale.allFinite() || !(key.scale.minCoeff() > 0.0)) {
      return Error{"scaleKeyframes[" + std::to_string(i) + "]: time must be finite and scales positive"};
    }
    if (i > 0 && !(key.time > scaleKeyframes[i - 1].time)) {
      return Error{"scaleKeyframes[" + std::to_string(i) + "]: time must be after the previous key's"};
    }
  }
  if (effects.has(Effect::Wetting)) {
    if (Status s = wetting.validate(); !s) return Error{"wetting." + s.error().message};
  }
  if (effects.has(Effect::Flooding)) {
    if (Status s = flooding.validate(); !s) return Error{"flooding." + s.error().message};
    // The graph's spaces are cut from the registered shape once; a deforming body would outgrow them.
    if (effects.has(Effect::Deformation)) return Error{"flooding: not available together with deformation"};
  }
  if (!finiteNonNegative(drag.advancingPressure)) return Error{"drag.advancingPressure: must be >= 0 and finite"};
  if (!finiteNonNegative(drag.retreatingPressure)) return Error{"drag.retreatingPressure: must be >= 0 and finite"};
  if (!finiteNonNegative(drag.linearPressureVelocity)) {
    return Error{"drag.linearPressureVelocity: must be >= 0 and finite"};
  }
  if (!finiteNonNegative(drag.skinFrictionScale)) return Error{"drag.skinFrictionScale: must be >= 0 and finite"};
  if (!finiteNonNegative(rotationalDamping)) return Error{"rotationalDamping: must be >= 0 and finite"};
  if (!finiteNonNegative(addedMassCoefficient)) return Error{"addedMassCoefficient: must be >= 0 and finite"};
  if (!(dragPatchNormalCosine >= 0.0 && dragPatchNormalCosine <= 1.0)) {
    return Error{"dragPatchNormalCosine: must lie in [0, 1]"};
  }
  if (!(dragPatchRadiusFraction > 0.0 && dragPatchRadiusFraction <= 10.0)) {
    return Error{"dragPatchRadiusFraction: must lie in (0, 10]"};
  }
  return Ok{};
}

}  // namespace hydrotex::bullet
