// SPDX-License-Identifier: Zlib
// The paper's Liquid Density Field (section 4.2.3 b): Fick's law J = -D grad rho in 3D on a
// regular grid, rho = liquid volume per voxel volume. Between face neighbours the flux over the
// face (area h^2) is D (rho_u - rho_v) / h, so the volume moved per step is D dt (V_u - V_v) / h^2;
// explicit steps are non-negative for D dt / h^2 <= 1/6 (six faces). Only occupied voxels hold
// liquid; faces to empty voxels carry nothing, so the volume is conserved.
#include "hydrotex/wetting/LiquidDensityField.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

namespace hydrotex {

Expected<LiquidDensityField> LiquidDensityField::build(const TexelAdjacency& graph, double voxelSize) {
  if (!(voxelSize > 0.0 && std::isfinite(voxelSize)))
    return Error{"liquid density field: voxel size " + std::to_string(voxelSize) + " m is not positive"};
  LiquidDensityField field;
  field.voxelSize_ = voxelSize;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (const auto& c : graph.centroid) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  if (graph.centroid.empty()) return field;
  const Eigen::Vector3d extent = (hi - lo) / voxelSize + Eigen::Vector3d::Constant(2.0);
  if (extent.prod() > 2147483647.0) return Error{"liquid density field: voxel size " + std::to_string(voxelSize) + " m gives too many voxels"};
  const std::int64_t nx = static_cast<std::int64_t>(extent.x()) + 1, ny = static_cast<std::int64_t>(extent.y()) + 1;
  // Half a voxel of margin so that a plane of centroids does not sit on a voxel boundary.
  const Eigen::Vector3d origin = lo - Eigen::Vector3d::Constant(0.5 * voxelSize);
  std::unordered_map<std::int64_t, std::uint32_t> occupied;
  field.voxelOfTexel_.resize(graph.centroid.size());
  field.texelArea_ = graph.area;
  std::vector<std::int64_t> keys;
  for (std::size_t i = 0; i < graph.centroid.size(); ++i) {
    const Eigen::Vector3d cell = ((graph.centroid[i] - origin) / voxelSize).array().floor();
    const std::int64_t key = (static_cast<std::int64_t>(cell.z()) * ny + static_cast<std::int64_t>(cell.y())) * nx +
                             static_cast<std::int64_t>(cell.x());
    auto [it, inserted] = occupied.try_emplace(key, static_cast<std::uint32_t>(keys.size()));
    if (inserted) {
      keys.push_back(key);
      field.voxelArea_.push_back(0.0);
    }
    field.voxelOfTexel_[i] = it->second;
    field.voxelArea_[it->second] += graph.area[i];
  }
  for (std::size_t v = 0; v < keys.size(); ++v)
    for (std::int64_t step : {std::int64_t{1}, nx, nx * ny}) {
      auto it = occupied.find(keys[v] + step);
      if (it != occupied.end()) {
        field.faceFirst_.push_back(static_cast<std::uint32_t>(v));
        field.faceSecond_.push_back(it->second);
      }
    }
  return field;
}

int LiquidDensityField::diffuse(std::vector<float>& liquid, double diffusivity, double dt) {
  if (liquid.size() != voxelOfTexel_.size() || !(dt > 0.0) || !(diffusivity > 0.0)) return 0;
  volume_.assign(voxelArea_.size(), 0.0);
  change_.assign(voxelArea_.size(), 0.0);
  for (std::size_t i = 0; i < liquid.size(); ++i) volume_[voxelOfTexel_[i]] += liquid[i] * texelArea_[i];
  const int substeps = std::max(1, static_cast<int>(std::ceil(dt / stableTimeStep(diffusivity))));
  const double factor = diffusivity * (dt / substeps) / (voxelSize_ * voxelSize_);
  for (int s = 0; s < substeps; ++s) {
    for (std::size_t f = 0; f < faceFirst_.size(); ++f) {
      const double moved = factor * (volume_[faceFirst_[f]] - volume_[faceSecond_[f]]);
      change_[faceFirst_[f]] -= moved;
      change_[faceSecond_[f]] += moved;
    }
    for (std::size_t v = 0; v < volume_.size(); ++v) {
      volume_[v] += change_[v];
      change_[v] = 0.0;
    }
  }
  for (std::size_t i = 0; i < liquid.size(); ++i) {
    const double area = voxelArea_[voxelOfTexel_[i]];
    liquid[i] = area > 0.0 ? static_cast<float>(volume_[voxelOfTexel_[i]] / area) : 0.0f;
  }
  return substeps;
}

}  // namespace hydrotex
