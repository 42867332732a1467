// SPDX-License-Identifier: Zlib
#pragma once
/// @file TexelPressure.hpp
/// The hydrostatic pressure on each texel of a surface posed in the world, and the nodal forces
/// it gives (docs/design.md "Pressure integration"): for bodies whose texels move on their own (a
/// soft body's deformed surface), where the rigid texture path's tile sums cannot serve. A texel
/// cut by the waterline is wet in the part under it, by the same rule as the rigid texture path
/// (the parallelogram patch of HydrostaticSums.hpp's waterlineFractions), so one law serves both.

#include <Eigen/Core>
#include <span>

#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// Whole-surface sums of one texelPressures pass (world frame).
struct TexelPressureSums {
  double enclosedVolume = 0.0;   ///< m^3, (1/3) sum p . A: the surface's own volume
  /// m^3, volume below the local surface: -sum(mean wet depth x A_y) (exact for a closed surface
  /// cut by a plane, whose waterplane adds nothing); enclosedVolume in a medium without free surface.
  double submergedVolume = 0.0;
  double wettedArea = 0.0;       ///< m^2, texel area under the surface (cut texels in part)
};

/// Pressure (Pa) and wet fraction (0..1) of every texel of `worldTextures` (positions, area
/// vectors and edges in the world frame, m) in `surface` at `time` (s) under gravity `gravity`
/// (m/s^2, along -y): with a free surface p = rho g (mean depth of the texel's wet part), the depth
/// measured from the surface height above the texel's centre (under Gerstner waves interpolated
/// from surface jets within kExactWaveHeightError where that takes fewer samples than there are
/// texels); in a medium, the medium's pressure
/// at the texel, wholly wet. `pressure` and `wetFraction` hold one entry per texel. A surface that
/// answers NaN gives that texel NaN pressure (the caller skips it).
TexelPressureSums texelPressures(const SurfaceTextures& worldTextures, const LiquidSurface& surface, double time,
                                 double gravity, std::span<float> pressure, std::span<float> wetFraction);

/// The pressure force on each vertex of `mesh` (N, world): each texel's pressure times the area
/// vector of each of its pieces (the piece's share of its triangle's current area vector
/// `triangleAreaVectors`, m^2), given to the triangle's vertices at the piece centroid's
/// barycentric weights, so that the vertex forces sum to -sum p A and their moments to the
/// pieces'. `vertexForce` (one per vertex) is overwritten; texels with zero or non-finite pressure
/// are skipped.
void texelPressureVertexForces(const SurfaceBake& bake, const Mesh& mesh,
                               std::span<const Eigen::Vector3d> triangleAreaVectors, std::span<const float> pressure,
                               std::span<Eigen::Vector3d> vertexForce);

}  // namespace hydrotex
