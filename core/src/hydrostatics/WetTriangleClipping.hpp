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
#include <type_traits>

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
///
/// Written once for a number type T and a sums type (WettedSums for double, one triangle;
/// WettedLaneSums of DoubleLanes or QuadLanes for two or four, each lane with the same operations
/// in the same order, so that a lane rounds as the scalar law does).
template <class T, class Sums>
inline void addWetTriangleTo(Sums& sums, const T (&a)[3], const T (&b)[3], const T (&c)[3], T da, T db, T dc) {
  const T half = T(0.5);
  const T ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const T vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const T ax = half * (uy * vz - uz * vy), ay = half * (uz * vx - ux * vz), az = half * (ux * vy - uy * vx);
  const T depthSum = da + db + dc;
  const T sumX = a[0] + b[0] + c[0], sumY = a[1] + b[1] + c[1], sumZ = a[2] + b[2] + c[2];
  const T twelfth = T(1.0 / 12.0), three = T(3.0);
  const T mx = (depthSum * sumX + da * a[0] + db * b[0] + dc * c[0]) * twelfth;
  const T my = (depthSum * sumY + da * a[1] + db * b[1] + dc * c[1]) * twelfth;
  const T mz = (depthSum * sumZ + da * a[2] + db * b[2] + dc * c[2]) * twelfth;
  const T meanDepth = depthSum / three;
  sums.sumDA[0] += meanDepth * ax;
  sums.sumDA[1] += meanDepth * ay;
  sums.sumDA[2] += meanDepth * az;
  sums.sumDxA[0] += my * az - mz * ay;
  sums.sumDxA[1] += mz * ax - mx * az;
  sums.sumDxA[2] += mx * ay - my * ax;
  sums.sumDXAy += mx * ay;
  sums.sumDZAy += mz * ay;
  const T meanDepthSq = (depthSum * depthSum + da * da + db * db + dc * dc) * twelfth;
  sums.sumYB -= (half * meanDepthSq + my) * ay;
  sums.sumAy += ay;
  sums.sumXAy += sumX / three * ay;
  sums.sumZAy += sumZ / three * ay;
  sums.sumXXAy += (sumX * sumX + a[0] * a[0] + b[0] * b[0] + c[0] * c[0]) * twelfth * ay;
  sums.sumXZAy += (sumX * sumZ + a[0] * a[2] + b[0] * b[2] + c[0] * c[2]) * twelfth * ay;
  sums.sumZZAy += (sumZ * sumZ + a[2] * a[2] + b[2] * b[2] + c[2] * c[2]) * twelfth * ay;
  if constexpr (std::is_same_v<T, double>) {
    sums.wettedArea += std::sqrt(ax * ax + ay * ay + az * az);
  } else {
    sums.wettedArea += squareRoot(ax * ax + ay * ay + az * az);
  }
}

/// addWetTriangleTo for one triangle given by its vertices.
inline void addWetTriangle(WettedSums& sums, const SurfaceVertex& a, const SurfaceVertex& b,
                           const SurfaceVertex& c, double da, double db, double dc) {
  const double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z}, pc[3] = {c.x, c.y, c.z};
  addWetTriangleTo<double>(sums, pa, pb, pc, da, db, dc);
}

inline SurfaceVertex lerp(const SurfaceVertex& a, const SurfaceVertex& b, double t) {
  return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t, 0.0};
}

/// Calls wet(a, b, c, da, db, dc) for each triangle of the part of a triangle where its linearly
/// interpolated depth is positive (none, the whole, the corner under, or the two halves of the quad
/// left by a dry corner): the triangle clipped where d changes sign (the cut points, d = 0, by
/// linear interpolation along the edges).
template <class Wet>
inline void forEachWetPart(const SurfaceVertex* p[3], Wet&& wet) {
  const double depth[3] = {p[0]->depth, p[1]->depth, p[2]->depth};
  const bool under[3] = {depth[0] > 0.0, depth[1] > 0.0, depth[2] > 0.0};
  const int count = int(under[0]) + int(under[1]) + int(under[2]);
  if (count == 0) return;
  if (count == 3) {
    wet(*p[0], *p[1], *p[2], depth[0], depth[1], depth[2]);
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
    wet(*p[i], qij, qik, depth[i], 0.0, 0.0);
  } else {
    // Corner i is dry: the wetted part is the quad qij, p[j], p[k], qik.
    wet(qij, *p[j], *p[k], 0.0, depth[j], depth[k]);
    wet(qij, *p[k], qik, 0.0, depth[k], 0.0);
  }
}

/// Adds the part of a triangle where its linearly interpolated depth is positive (forEachWetPart).
inline void addClippedWetTriangle(WettedSums& sums, const SurfaceVertex* p[3]) {
  forEachWetPart(p, [&](const SurfaceVertex& a, const SurfaceVertex& b, const SurfaceVertex& c, double da, double db,
                        double dc) { addWetTriangle(sums, a, b, c, da, db, dc); });
}

/// Wet triangles (the parts forEachWetPart finds) gathered for the lanes, in columns: the
/// prepared path under waves clips a few hundred a query along the water line (the 17,160-face
/// sphere: their law was 17 % of its step's instructions one by one). A padded entry (all zero)
/// adds zeros.
struct WetTriangleBatch {
  static constexpr unsigned kCapacity = 32;
  double corner[9][kCapacity];  ///< a (x, y, z), then b, then c (m, frame o)
  double depth[3][kCapacity];   ///< at a, b, c (m, >= 0)
  unsigned count = 0;

  /// Appends one wet triangle (count < kCapacity).
  void add(const SurfaceVertex& a, const SurfaceVertex& b, const SurfaceVertex& c, double da, double db, double dc) {
    const SurfaceVertex* p[3] = {&a, &b, &c};
    for (int k = 0; k < 3; ++k) {
      corner[3 * k][count] = p[k]->x;
      corner[3 * k + 1][count] = p[k]->y;
      corner[3 * k + 2][count] = p[k]->z;
    }
    depth[0][count] = da;
    depth[1][count] = db;
    depth[2][count] = dc;
    ++count;
  }
  /// Fills the last lanes of a group of four with entries that add zeros.
  void pad() {
    for (; count % 4 != 0; ++count) {
      for (auto& column : corner) column[count] = 0.0;
      for (auto& column : depth) column[count] = 0.0;
    }
  }
};

/// Adds the batch's triangles (count a multiple of L::kWidth) to `out`, L::kWidth at a time.
template <class L>
inline void sumWetTriangleLanes(const WetTriangleBatch& in, WettedSums& out) {
  WettedLaneSums<L> lanes{};  // value-initialized: zeros
  for (unsigned e = 0; e < in.count; e += L::kWidth) {
    L p[3][3];
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i) p[c][i] = L::loadDoubles(in.corner[3 * c + i] + e);
    addWetTriangleTo<L>(lanes, p[0], p[1], p[2], L::loadDoubles(in.depth[0] + e), L::loadDoubles(in.depth[1] + e),
                        L::loadDoubles(in.depth[2] + e));
  }
  addLaneTotals(out, lanes);
}

/// Adds the batch's triangles to `out` one by one (the scalar law; where there are no lanes).
inline void sumWetTrianglesOneByOne(const WetTriangleBatch& in, WettedSums& out) {
  for (unsigned e = 0; e < in.count; ++e) {
    double p[3][3];
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i) p[c][i] = in.corner[3 * c + i][e];
    addWetTriangleTo<double>(out, p[0], p[1], p[2], in.depth[0][e], in.depth[1][e], in.depth[2][e]);
  }
}

/// sumWetTriangleLanes in AVX2 lanes (WetTriangleLanesAvx2.cpp); false, having added nothing,
/// where the processor or the build has no AVX2 or HYDROTEX_DISABLE_AVX2 is set.
bool sumWetTrianglesAvx2(const WetTriangleBatch& in, WettedSums& out);

/// Adds the batch to `sums` (AVX2 lanes where allowed, else one by one) and empties it.
inline void flushWetTriangles(WetTriangleBatch& batch, WettedSums& sums) {
  batch.pad();
  if (!sumWetTrianglesAvx2(batch, sums)) sumWetTrianglesOneByOne(batch, sums);
  batch.count = 0;
}

/// addClippedWetTriangle through `batch`: the wet parts appended, the batch flushed into `sums`
/// first when it may not hold them.
inline void batchClippedWetTriangle(WetTriangleBatch& batch, WettedSums& sums, const SurfaceVertex* p[3]) {
  if (batch.count + 2 > WetTriangleBatch::kCapacity) flushWetTriangles(batch, sums);
  forEachWetPart(p, [&](const SurfaceVertex& a, const SurfaceVertex& b, const SurfaceVertex& c, double da, double db,
                        double dc) { batch.add(a, b, c, da, db, dc); });
}

}  // namespace hydrotex::detail
