// SPDX-License-Identifier: Zlib
#pragma once
/// @file WetTriangleClipping.hpp
/// Private to core: the exact path's law for a triangle under a free surface that is not flat,
/// whose depth below the surface is taken linear over it between its corners (the corners' own
/// depths: the surface's heights there, or a local model's): clipped where the depth changes
/// sign, and the linear pressure integrated exactly over the wetted part. Shared by the plain
/// exact path (PolyhedralHydrostatics.cpp) and its hierarchy under waves
/// (PolyhedralHydrostaticsWaves.cpp).

#include <cmath>

#include "hydrostatics/HydrostaticSums.hpp"

namespace hydrotex::detail {

/// A vertex in the world frame translated to the frame origin o (m), and its depth below the
/// free surface d = h(x, z, t) - y (m; NaN until a triangle that may be wet asks for it).
struct SurfaceVertex {
  double x, y, z, depth;
};

/// Adds the part of a triangle under a free surface that is not flat, whose depth d is linear over
/// the triangle (the piece's corners: a, b, c in frame o, counter-clockwise seen from outside,
/// depths da, db, dc >= 0). With the barycentric coordinates lambda_i and
///   Int_T lambda_i lambda_j dA = |T| (1 + delta_ij) / 12,
/// a product of two linear functions f, g integrates exactly as
///   Int_T f g dA = |T| (Sum f_i Sum g_j + Sum f_i g_i) / 12,                        (1)
/// and a linear one as Int_T f dA = |T| Sum f_i / 3. Hence, with A = |T| n the area vector:
///   force:   -Int p n dA = -rho g Int d dA n = -rho g (Sum d_i / 3) A   (the mean vertex depth),
///   torque:  -Int x' x p n dA = -rho g (Int d x' dA) x n = -rho g m x A,
///            m = (Sum d_i Sum x'_j + Sum d_i x'_i) / 12 by (1): the linear pressure acts at its
///            centre x_P = m / (Sum d_i / 3) = (Sum d_i Sum x'_j + Sum d_i x'_i) / (4 Sum d_i),
///            which is the centroid when the depth is uniform and moves toward the deeper corners;
///   volume and centre of buoyancy: HydrostaticSums.hpp's fields with D x' from m, and
///            Int (d^2/2 - h' d) n_y dA with h' = d + y' (the surface is linear over the piece
///            too: its height at a corner is the surface's, at a cut point the cut point's own):
///            = -(Int d^2 dA / 2 + Int y' d dA) n_y = -((Sum d)^2 + Sum d^2) / 24 A_y - m_y A_y;
///   water plane (the cap's integrals are minus the wetted surface's): Int f n_y dA for
///            f = 1, x', z', x'^2, x' z', z'^2, by (1) again.
inline void addWetTriangle(WettedSums& sums, const SurfaceVertex& a, const SurfaceVertex& b,
                           const SurfaceVertex& c, double da, double db, double dc) {
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const double ax = 0.5 * (uy * vz - uz * vy), ay = 0.5 * (uz * vx - ux * vz), az = 0.5 * (ux * vy - uy * vx);
  const double depthSum = da + db + dc;
  const double sumX = a.x + b.x + c.x, sumY = a.y + b.y + c.y, sumZ = a.z + b.z + c.z;
  const double twelfth = 1.0 / 12.0;
  // m = Int d x' dA / |T| (eq. 1).
  const double mx = (depthSum * sumX + da * a.x + db * b.x + dc * c.x) * twelfth;
  const double my = (depthSum * sumY + da * a.y + db * b.y + dc * c.y) * twelfth;
  const double mz = (depthSum * sumZ + da * a.z + db * b.z + dc * c.z) * twelfth;
  const double meanDepth = depthSum / 3.0;
  sums.sumDA[0] += meanDepth * ax;
  sums.sumDA[1] += meanDepth * ay;
  sums.sumDA[2] += meanDepth * az;
  sums.sumDxA[0] += my * az - mz * ay;
  sums.sumDxA[1] += mz * ax - mx * az;
  sums.sumDxA[2] += mx * ay - my * ax;
  sums.sumDXAy += mx * ay;
  sums.sumDZAy += mz * ay;
  const double meanDepthSq = (depthSum * depthSum + da * da + db * db + dc * dc) * twelfth;
  sums.sumYB -= (0.5 * meanDepthSq + my) * ay;
  sums.sumAy += ay;
  sums.sumXAy += sumX / 3.0 * ay;
  sums.sumZAy += sumZ / 3.0 * ay;
  sums.sumXXAy += (sumX * sumX + a.x * a.x + b.x * b.x + c.x * c.x) * twelfth * ay;
  sums.sumXZAy += (sumX * sumZ + a.x * a.z + b.x * b.z + c.x * c.z) * twelfth * ay;
  sums.sumZZAy += (sumZ * sumZ + a.z * a.z + b.z * b.z + c.z * c.z) * twelfth * ay;
  sums.wettedArea += std::sqrt(ax * ax + ay * ay + az * az);
}

inline SurfaceVertex lerp(const SurfaceVertex& a, const SurfaceVertex& b, double t) {
  return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t, 0.0};
}

/// Adds the part of a triangle where its linearly interpolated depth is positive: the triangle
/// clipped where d changes sign (the cut points, d = 0, by linear interpolation along the edges).
inline void addClippedWetTriangle(WettedSums& sums, const SurfaceVertex* p[3]) {
  const double depth[3] = {p[0]->depth, p[1]->depth, p[2]->depth};
  const bool under[3] = {depth[0] > 0.0, depth[1] > 0.0, depth[2] > 0.0};
  const int count = int(under[0]) + int(under[1]) + int(under[2]);
  if (count == 0) return;
  if (count == 3) {
    addWetTriangle(sums, *p[0], *p[1], *p[2], depth[0], depth[1], depth[2]);
    return;
  }
  // Rotate the corners (keeping orientation) so that corner i is the odd one out.
  int i = 0;
  for (int k = 0; k < 3; ++k)
    if (under[k] == (count == 1)) i = k;
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  const SurfaceVertex qij = lerp(*p[i], *p[j], depth[i] / (depth[i] - depth[j]));
  const SurfaceVertex qik = lerp(*p[i], *p[k], depth[i] / (depth[i] - depth[k]));
  if (count == 1) {
    addWetTriangle(sums, *p[i], qij, qik, depth[i], 0.0, 0.0);
  } else {
    // Corner i is dry: the wetted part is the quad qij, p[j], p[k], qik.
    addWetTriangle(sums, qij, *p[j], *p[k], 0.0, depth[j], depth[k]);
    addWetTriangle(sums, qij, *p[k], qik, 0.0, depth[k], 0.0);
  }
}

}  // namespace hydrotex::detail
