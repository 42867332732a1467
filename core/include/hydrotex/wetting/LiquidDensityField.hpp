// SPDX-License-Identifier: Zlib
#pragma once
/// @file LiquidDensityField.hpp
/// The paper's Liquid Density Field (section 4.2.3 b): the liquid of the texels is splatted into a
/// 3D grid around the body, diffused there by Fick's law (7-point stencil between occupied voxels),
/// and gathered back. Kept beside the texel graph (TexelAdjacency) to compare the two on accuracy
/// and time (bench_wetting); the texel graph is what Wetting uses. Known limit of the 3D grid: it
/// evens out the volume per voxel, not the liquid per area, so a voxel that holds little surface
/// ends up with more liquid per area, and paths between texels follow voxel faces (staircase).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/bake/TexelAdjacency.hpp"

namespace hydrotex {

/// Occupied voxels of a regular grid and which texels fall in each.
class LiquidDensityField {
 public:
  /// Voxels of side `voxelSize` (m, > 0) over the texel centroids of `graph` (areas and centroids
  /// are used). Errors: a non-positive or non-finite voxel size, more than 2^31 voxels in the box.
  static Expected<LiquidDensityField> build(const TexelAdjacency& graph, double voxelSize);

  /// Diffuses `liquid` (m per texel, same order as the graph) for `dt` s with diffusivity D
  /// (m^2/s): splat volumes into voxels, explicit sub-steps within the 3D bound h^2 / (6 D),
  /// gather back (every texel of a voxel gets the voxel's volume over the voxel's surface area).
  /// Conserves the volume to rounding. Returns the sub-steps used.
  int diffuse(std::vector<float>& liquid, double diffusivity, double dt);

  /// Occupied voxels.
  std::size_t voxelCount() const { return voxelArea_.size(); }
  /// Voxel side (m).
  double voxelSize() const { return voxelSize_; }
  /// Largest stable explicit step (s): h^2 / (6 D).
  double stableTimeStep(double diffusivity) const { return voxelSize_ * voxelSize_ / (6.0 * diffusivity); }

 private:
  double voxelSize_ = 0.0;
  std::vector<std::uint32_t> voxelOfTexel_;   // per texel: occupied voxel index
  std::vector<double> texelArea_;             // per texel (m^2)
  std::vector<double> voxelArea_;             // per voxel: surface area inside (m^2)
  std::vector<std::uint32_t> faceFirst_, faceSecond_;  // face-neighbour pairs of occupied voxels
  std::vector<double> volume_, change_;       // scratch per voxel (m^3)
};

}  // namespace hydrotex
