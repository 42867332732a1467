// SPDX-License-Identifier: Zlib
// The liquid texture (paper section 4.1, figure 6) and its material maps.
#include "hydrotex/wetting/LiquidTexture.hpp"

#include <cmath>
#include <string>

namespace hydrotex {

Status WettingMaterial::validate() const {
  if (!(porosity >= 0.0 && porosity <= 1.0)) return Error{"wetting porosity " + std::to_string(porosity) + " is outside 0..1"};
  if (!(layerThickness > 0.0 && std::isfinite(layerThickness)))
    return Error{"wetting layer thickness " + std::to_string(layerThickness) + " m is not positive"};
  if (!(permeability >= 0.0 && std::isfinite(permeability)))
    return Error{"wetting permeability " + std::to_string(permeability) + " m^2 is negative or not finite"};
  return Ok{};
}

double LiquidTexture::heldVolume(const std::vector<double>& area) const {
  double total = 0.0;
  for (std::size_t i = 0; i < liquid.size() && i < area.size(); ++i) total += static_cast<double>(liquid[i]) * area[i];
  return total;
}

double LiquidTexture::heldPigment(const std::vector<double>& area) const {
  double total = 0.0;
  for (std::size_t i = 0; i < pigment.size() && i < area.size(); ++i) total += static_cast<double>(pigment[i]) * area[i];
  return total;
}

namespace {

Status checkMap(const std::vector<float>& map, std::size_t texelCount, const char* name) {
  if (map.empty()) return Ok{};
  if (map.size() != texelCount)
    return Error{std::string(name) + " map has " + std::to_string(map.size()) + " values for " +
                 std::to_string(texelCount) + " texels"};
  for (std::size_t i = 0; i < map.size(); ++i)
    if (!(map[i] >= 0.0f && map[i] <= 1.0f))
      return Error{std::string(name) + " map value " + std::to_string(map[i]) + " at texel " + std::to_string(i) +
                   " is outside 0..1"};
  return Ok{};
}

}  // namespace

Expected<LiquidTexture> makeLiquidTexture(std::size_t texelCount, const WettingMaterial& material,
                                          const std::vector<float>& porosityMap,
                                          const std::vector<float>& permeabilityMap, bool withPigment) {
  if (Status s = material.validate(); !s) return s.error();
  if (Status s = checkMap(porosityMap, texelCount, "porosity"); !s) return s.error();
  if (Status s = checkMap(permeabilityMap, texelCount, "permeability"); !s) return s.error();
  LiquidTexture texture;
  texture.layerThickness = material.layerThickness;
  texture.liquid.assign(texelCount, 0.0f);
  texture.capacity.assign(texelCount, static_cast<float>(material.porosity * material.layerThickness));
  texture.permeability.assign(texelCount, static_cast<float>(material.permeability));
  for (std::size_t i = 0; i < porosityMap.size(); ++i) texture.capacity[i] *= porosityMap[i];
  for (std::size_t i = 0; i < permeabilityMap.size(); ++i) texture.permeability[i] *= permeabilityMap[i];
  if (withPigment) texture.pigment.assign(texelCount, 0.0f);
  return texture;
}

}  // namespace hydrotex
