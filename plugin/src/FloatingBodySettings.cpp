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

Status FloatingBodySettings::validate() const {
  if (!mesh && meshPath.empty()) return Error{"mesh: neither a mesh nor a mesh file is given"};
  if (mesh && mesh->triangles.empty()) return Error{"mesh: the mesh has no triangles"};
  if (resolution < 16 || resolution > 4096) {
    return Error{"resolution: " + std::to_string(resolution) + " is outside 16..4096"};
  }
  if (density && mass) return Error{"density and mass: give one of them, not both"};
  if (density && !(std::isfinite(*density) && *density > 0.0)) {
    return Error{"density: " + std::to_string(*density) + " kg/m^3 must be positive and finite"};
  }
  if (mass && !(std::isfinite(*mass) && *mass > 0.0)) {
    return Error{"mass: " + std::to_string(*mass) + " kg must be positive and finite"};
  }
  for (Effect reserved : {Effect::VariableMass, Effect::Flooding, Effect::Deformation, Effect::Wetting}) {
    if (effects.has(reserved)) {
      return Error{"effects: '" + std::string(effectName(reserved)) + "' is not available yet"};
    }
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
