// SPDX-License-Identifier: Zlib
#pragma once
/// @file TexelPosing.hpp
/// Private to core: a packed texel and a box of texels moved by a rigid pose, shared by the
/// texture path's flat and wavy traversals (TextureHydrostatics.cpp, TextureHydrostaticsWaves.cpp).

#include <Eigen/Core>
#include <cmath>

#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex::detail {

/// The world-frame quantities of one texel under a rigid pose: x' = R p + offset, A' = R A.
struct PosedTexel {
  double x, y, z, ax, ay, az;
};

[[gnu::always_inline]] inline PosedTexel pose(const TextureHydrostatics::Texel& t, const Eigen::Matrix3d& r, const Eigen::Vector3d& offset) {
  const double px = t.position[0], py = t.position[1], pz = t.position[2];
  const double ax = t.areaVector[0], ay = t.areaVector[1], az = t.areaVector[2];
  return {r(0, 0) * px + r(0, 1) * py + r(0, 2) * pz + offset.x(),
          r(1, 0) * px + r(1, 1) * py + r(1, 2) * pz + offset.y(),
          r(2, 0) * px + r(2, 1) * py + r(2, 2) * pz + offset.z(),
          r(0, 0) * ax + r(0, 1) * ay + r(0, 2) * az,
          r(1, 0) * ax + r(1, 1) * ay + r(1, 2) * az,
          r(2, 0) * ax + r(2, 1) * ay + r(2, 2) * az};
}

/// Vertical extents of the texel's edges: a = eU'.y, b = eV'.y.
[[gnu::always_inline]] inline void verticalEdges(const TextureHydrostatics::Texel& t, const Eigen::Matrix3d& r, double& a, double& b) {
  a = r(1, 0) * t.edgeU[0] + r(1, 1) * t.edgeU[1] + r(1, 2) * t.edgeU[2];
  b = r(1, 0) * t.edgeV[0] + r(1, 1) * t.edgeV[1] + r(1, 2) * t.edgeV[2];
}

/// Range along the world axis `row` (0 x, 1 y, 2 z) of a body-frame box under the rotation and
/// an offset along that axis.
inline void axisRange(const Eigen::Vector3d& center, const Eigen::Vector3d& halfExtent, const Eigen::Matrix3d& r,
                      int row, double offset, double& low, double& high) {
  const double c = r(row, 0) * center.x() + r(row, 1) * center.y() + r(row, 2) * center.z() + offset;
  const double h = std::abs(r(row, 0)) * halfExtent.x() + std::abs(r(row, 1)) * halfExtent.y() +
                   std::abs(r(row, 2)) * halfExtent.z();
  low = c - h;
  high = c + h;
}

/// Vertical range of a body-frame box under the rotation's y row and a vertical offset.
inline void verticalRange(const Eigen::Vector3d& center, const Eigen::Vector3d& halfExtent, const Eigen::Matrix3d& r,
                          double offsetY, double& low, double& high) {
  axisRange(center, halfExtent, r, 1, offsetY, low, high);
}

}  // namespace hydrotex::detail
