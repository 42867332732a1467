// SPDX-License-Identifier: Zlib
#pragma once
/// @file HydrostaticSums.hpp
/// Private to core: the sums over the wetted surface that both hydrostatics paths accumulate, and
/// their conversion into a HydrostaticsResult. Derivation (divergence theorem, fields that vanish
/// on the water plane so that the cap under the water plane never has to be built):
///   V               = Int_V 1    = -Sum D A_y                  field (0, y - h, 0)
///   V (x_B - o)     = Int_V x'   = -Sum D x' A_y               field (0, x'(y - h), 0)
///   V (y_B - o_y)   = Int_V y'   =  Sum (Q/2 - h' D) A_y       field (0, (y'^2 - h'^2)/2, 0)
///   cap integrals of f(x, z)     = -Sum f A_y                  (closed surface: Int f n_y = Int df/dy = 0)
///   pressure force  = -Sum p A,  p = rho g D; torque = -Sum x' x p A
/// with x' the position relative to the frame origin o, h' the local surface height relative to
/// o_y, D = mean of (h - y)+ over the element, Q = mean of (h - y)+^2, and the area weights of the
/// part of each element under the surface.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex {
struct FlatWettedSums;  // ComputeBackend.hpp
}

namespace hydrotex::detail {

/// The terms one element adds to the wetted sums (WettedSums::addElement), for any number type:
/// double, or several elements at once in SIMD lanes (WaveTexelLanes.hpp). `sums` has
/// WettedSums' sums (sumDA .. wettedArea) as members of type T.
template <class Sums, class T>
[[gnu::always_inline]] inline void addElementTerms(Sums& sums, T x, T y, T z, T ax, T ay, T az, T area, T frac, T depth,
                                                   T depthSq, T localHeight) {
  sums.sumDA[0] += depth * ax;
  sums.sumDA[1] += depth * ay;
  sums.sumDA[2] += depth * az;
  sums.sumDxA[0] += depth * (y * az - z * ay);
  sums.sumDxA[1] += depth * (z * ax - x * az);
  sums.sumDxA[2] += depth * (x * ay - y * ax);
  sums.sumDXAy += depth * x * ay;
  sums.sumDZAy += depth * z * ay;
  sums.sumYB += (T(0.5) * depthSq - localHeight * depth) * ay;
  const T fay = frac * ay;
  sums.sumAy += fay;
  sums.sumXAy += fay * x;
  sums.sumZAy += fay * z;
  sums.sumXXAy += fay * x * x;
  sums.sumXZAy += fay * x * z;
  sums.sumZZAy += fay * z * z;
  sums.wettedArea += frac * area;
}

/// Sums over the wetted surface in a world frame translated to `origin`.
struct WettedSums {
  double sumDA[3] = {0, 0, 0};     ///< Sum D A (m^3)
  double sumDxA[3] = {0, 0, 0};    ///< Sum D x' x A (m^4)
  double sumDXAy = 0, sumDZAy = 0; ///< Sum D x' A_y, Sum D z' A_y (m^4)
  double sumYB = 0;                ///< Sum (Q/2 - h' D) A_y (m^4)
  double sumAy = 0;                ///< Sum frac A_y (m^2)
  double sumXAy = 0, sumZAy = 0;   ///< Sum frac x' A_y, z' A_y (m^3)
  double sumXXAy = 0, sumXZAy = 0, sumZZAy = 0;  ///< (m^4)
  double wettedArea = 0;           ///< Sum frac |A| (m^2)
  double pressureForce[3] = {0, 0, 0};   ///< -Sum p A (N), only for non-flat surfaces
  double pressureTorque[3] = {0, 0, 0};  ///< -Sum x' x p A (N m), only for non-flat surfaces

  /// Adds one element (a texel patch or a triangle) at x' with area vector a (m^2), area |A|,
  /// submerged area fraction `frac`, D, Q (see the file comment) and local surface height h'.
  [[gnu::always_inline]] inline void addElement(double x, double y, double z, double ax, double ay, double az, double area, double frac,
                         double depth, double depthSq, double localHeight) {
    addElementTerms(*this, x, y, z, ax, ay, az, area, frac, depth, depthSq, localHeight);
  }

  /// MomentCorrectionSums' law (below) for one texel under a plane at o_y (h' = 0, no slope), for
  /// the sums a flat surface's result reads (finishHydrostatics with ForceModel::Archimedes), which
  /// need only the column dm(:, 1) = `column` (m^3): sumDA[0], sumDA[2] and sumDxA are left as
  /// they are (a flat surface's force and torque come from the volume and the centre of buoyancy).
  inline void addFlatMomentCorrection(double x, double y, double z, const Eigen::Vector3d& column, double weight,
                                      double depth) {
    const double w = weight;
    sumDA[1] -= w * column.y();
    sumDXAy += w * (depth * column.x() - x * column.y());
    sumDZAy += w * (depth * column.z() - z * column.y());
    sumYB += w * y * column.y();
    sumXAy += w * column.x();
    sumZAy += w * column.z();
    sumXXAy += w * 2.0 * x * column.x();
    sumXZAy += w * (x * column.z() + z * column.x());
    sumZZAy += w * 2.0 * z * column.z();
  }

  /// The pressure sums of the hydrostatic pressure p = rho g D on every element (`rhoG`, N/m^3):
  /// the depth sums times -rho g (the surfaces whose pressure is the depth's: waves, grids).
  inline void setHydrostaticPressure(double rhoG) {
    for (int k = 0; k < 3; ++k) {
      pressureForce[k] = -rhoG * sumDA[k];
      pressureTorque[k] = -rhoG * sumDxA[k];
    }
  }

  /// Adds another set of sums (the same frame).
  inline void add(const WettedSums& o) {
    for (int k = 0; k < 3; ++k) {
      sumDA[k] += o.sumDA[k];
      sumDxA[k] += o.sumDxA[k];
      pressureForce[k] += o.pressureForce[k];
      pressureTorque[k] += o.pressureTorque[k];
    }
    sumDXAy += o.sumDXAy;
    sumDZAy += o.sumDZAy;
    sumYB += o.sumYB;
    sumAy += o.sumAy;
    sumXAy += o.sumXAy;
    sumZAy += o.sumZAy;
    sumXXAy += o.sumXXAy;
    sumXZAy += o.sumXZAy;
    sumZZAy += o.sumZZAy;
    wettedArea += o.wettedArea;
  }

  /// Adds a set of wholly submerged elements under a flat surface at o_y, given their body-frame
  /// moments, the rotation and the body origin's position relative to o (x' = R p + offset).
  void addSubmergedMoments(const TextureHydrostatics::Moments& moments, const Eigen::Matrix3d& rotation,
                           const Eigen::Vector3d& offset);
};

/// WettedSums' element sums, one per lane (addElementTerms and addWetTriangleTo add to them; the
/// texels under waves, WaveTexelLanes.hpp, and the exact path's wet triangles,
/// WetTriangleClipping.hpp). Value-initialize it ({}) for zeros.
template <class L>
struct WettedLaneSums {
  L sumDA[3], sumDxA[3], sumDXAy, sumDZAy, sumYB, sumAy, sumXAy, sumZAy, sumXXAy, sumXZAy, sumZZAy, wettedArea;
};

/// Adds the lanes' totals of `lanes` to `out`.
template <class L>
inline void addLaneTotals(WettedSums& out, const WettedLaneSums<L>& lanes) {
  for (int k = 0; k < 3; ++k) {
    out.sumDA[k] += lanes.sumDA[k].sum();
    out.sumDxA[k] += lanes.sumDxA[k].sum();
  }
  out.sumDXAy += lanes.sumDXAy.sum();
  out.sumDZAy += lanes.sumDZAy.sum();
  out.sumYB += lanes.sumYB.sum();
  out.sumAy += lanes.sumAy.sum();
  out.sumXAy += lanes.sumXAy.sum();
  out.sumZAy += lanes.sumZAy.sum();
  out.sumXXAy += lanes.sumXXAy.sum();
  out.sumXZAy += lanes.sumXZAy.sum();
  out.sumZZAy += lanes.sumZZAy.sum();
  out.wettedArea += lanes.wettedArea.sum();
}

/// The moment corrections of many texels (SurfaceTextures::momentCorrection) summed in the body
/// frame of their moments dM, so that no texel pays for dm = R dM R^T: every term below is linear
/// in dM, so the rotation R (any matrix: the engine's is orthogonal only to ~1e-7) is applied
/// once to the sums (addTo). The law: each of WettedSums' sums is Sum g(x) A_k over the pieces
/// for some g; with c_k = x' + d_k, Sum_k g(c_k) A_k = g(x') A + grad g(x') . Sum_k d_k A_k +
/// O(d^2) = g(x') A + grad g . dm(:, k): exact for the linear g (the volume and force under a
/// plane), first order in the texel size for the others. With D = h' - y' the depth at the
/// texel's centre, h' the local surface height and (slopeX, slopeZ) its slope there (0 under a
/// plane), grad D = g = (slopeX, -1, slopeZ) and grad (Q/2 - h' D) = y' e_y - h' grad h', so with
/// u = (R^T g)^T dM (body) and c = dM r1 (r1 = R^T e_y, the rotation's y row):
///   Sum D A         += R u                      (grad D . dm(:, k) = (R u)_k)
///   Sum D x'_i A_k  += (R (D dM) R^T + x' u^T R^T)_ik
///   Sum (Q/2 - h' D) A_y += (y' - h') r1 . c - h' u . r1
///   Sum f A_y, f = 1, x', z', x'^2, x' z', z'^2 += grad f . R c (dm(:, 1) = R c).
struct alignas(32) MomentCorrectionSums {
  // Rows of four (the fourth unused) on 32 bytes, so that the compiler's paired loads and stores
  // of the sums line up from one texel to the next (mixed widths stall store forwarding).
  double u[4] = {0, 0, 0, 0};     ///< Sum w u (m^3)
  double depthMoment[3][4] = {};  ///< Sum w D dM (m^4)
  double positionU[3][4] = {};    ///< Sum w x' u^T (m^4; rows world, columns body)
  double c[4] = {0, 0, 0, 0};     ///< Sum w c (m^3)
  double xc[4] = {0, 0, 0, 0};    ///< Sum w x' c (m^4)
  double zc[4] = {0, 0, 0, 0};    ///< Sum w z' c (m^4)
  double yb = 0.0;                ///< Sum w ((y' - h') r1 . c - h' u . r1) (m^4)

  /// Adds one texel at x' = (x, y, z) (m, world frame at o) whose body-frame moment is `m`
  /// (m^3, TextureHydrostatics::MomentCorrection::moment), with `weight`, `depth` D (m),
  /// `localHeight` h' (m) and the surface's slope, under the body's rotation R.
  [[gnu::always_inline]] inline void add(double x, double y, double z, const float (&m)[3][3], double weight,
                                         double depth, double localHeight, double slopeX, double slopeZ,
                                         const Eigen::Matrix3d& rotation) {
    const Eigen::Matrix3d& r = rotation;
    double g[3], uu[3], cc[3];
    for (int i = 0; i < 3; ++i) g[i] = slopeX * r(0, i) - r(1, i) + slopeZ * r(2, i);  // R^T (slopeX, -1, slopeZ)
    for (int j = 0; j < 3; ++j) uu[j] = g[0] * double(m[0][j]) + g[1] * double(m[1][j]) + g[2] * double(m[2][j]);
    for (int i = 0; i < 3; ++i) cc[i] = double(m[i][0]) * r(1, 0) + double(m[i][1]) * r(1, 1) + double(m[i][2]) * r(1, 2);
    const double w = weight, wd = weight * depth;
    const double position[3] = {w * x, w * y, w * z};
    for (int i = 0; i < 3; ++i) {
      u[i] += w * uu[i];
      c[i] += w * cc[i];
      xc[i] += position[0] * cc[i];
      zc[i] += position[2] * cc[i];
      for (int j = 0; j < 3; ++j) {
        depthMoment[i][j] += wd * double(m[i][j]);
        positionU[i][j] += position[i] * uu[j];
      }
    }
    const double rc = r(1, 0) * cc[0] + r(1, 1) * cc[1] + r(1, 2) * cc[2];
    const double ru = r(1, 0) * uu[0] + r(1, 1) * uu[1] + r(1, 2) * uu[2];
    yb += w * ((y - localHeight) * rc - localHeight * ru);
  }

  /// Adds another set of corrections (the same rotation).
  inline void add(const MomentCorrectionSums& o) {
    for (int i = 0; i < 3; ++i) {
      u[i] += o.u[i];
      c[i] += o.c[i];
      xc[i] += o.xc[i];
      zc[i] += o.zc[i];
      for (int j = 0; j < 3; ++j) {
        depthMoment[i][j] += o.depthMoment[i][j];
        positionU[i][j] += o.positionU[i][j];
      }
    }
    yb += o.yb;
  }

  /// Adds the corrections to `sums`, with R = `rotation` the rows' matrix.
  inline void addTo(WettedSums& sums, const Eigen::Matrix3d& rotation) const {
    const Eigen::Matrix3d& r = rotation;
    const Eigen::Vector3d along = r * Eigen::Vector3d(u[0], u[1], u[2]);
    Eigen::Matrix3d d, p;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        d(i, j) = depthMoment[i][j];
        p(i, j) = positionU[i][j];
      }
    const Eigen::Matrix3d moment = r * d * r.transpose() + p * r.transpose();  // Sum D x'_i A_k
    for (int k = 0; k < 3; ++k) sums.sumDA[k] += along[k];
    sums.sumDxA[0] += moment(1, 2) - moment(2, 1);
    sums.sumDxA[1] += moment(2, 0) - moment(0, 2);
    sums.sumDxA[2] += moment(0, 1) - moment(1, 0);
    sums.sumDXAy += moment(0, 1);
    sums.sumDZAy += moment(2, 1);
    sums.sumYB += yb;
    const Eigen::Vector3d column = r * Eigen::Vector3d(c[0], c[1], c[2]);  // Sum w dm(:, 1)
    const Eigen::Vector3d xColumn = r * Eigen::Vector3d(xc[0], xc[1], xc[2]);
    const Eigen::Vector3d zColumn = r * Eigen::Vector3d(zc[0], zc[1], zc[2]);
    sums.sumXAy += column.x();
    sums.sumZAy += column.z();
    sums.sumXXAy += 2.0 * xColumn.x();
    sums.sumXZAy += xColumn.z() + zColumn.x();
    sums.sumZZAy += 2.0 * zColumn.z();
  }
};

/// Submerged fractions of a planar patch p + s eU + t eV (s, t uniform on [-1/2, 1/2]) whose
/// height above its centre is X = s eU.y + t eV.y, under a surface `depth` d above the centre.
struct WaterlineFractions {
  double area;      ///< E[1(d > X)]: submerged area fraction
  double depth;     ///< E[(d - X)+] (m): mean depth over the patch
  double depthSq;   ///< E[(d - X)+^2] - frac (a^2 + b^2)/12 (m^2): as the midpoint rule counts d^2
};

/// E[g(d - a U1 - b U2)] for U uniform on [-1/2, 1/2] equals the second difference of G (G'' = g)
/// divided by a b (integrate the box twice); a or b near zero falls back to the 1-D and 0-D limits
/// to avoid cancellation.
[[gnu::always_inline]] inline WaterlineFractions waterlineFractions(double d, double a, double b) {
  a = std::abs(a);
  b = std::abs(b);
  if (a < b) std::swap(a, b);
  const double halfSpan = 0.5 * (a + b);
  const double variance = (a * a + b * b) / 12.0;
  if (d >= halfSpan) return {1.0, d, d * d};
  if (d <= -halfSpan) return {0.0, 0.0, 0.0};
  auto pos = [](double z) { return z > 0.0 ? z : 0.0; };
  double frac, mean, meanSq;
  if (b > 1e-6 * a) {
    // G for g = 1(z>0), z+, z+^2: z+^2/2, z+^3/6, z+^4/12.
    const double z[4] = {pos(d + halfSpan), pos(d + 0.5 * (a - b)), pos(d - 0.5 * (a - b)), pos(d - halfSpan)};
    double s2 = 0, s3 = 0, s4 = 0;
    const double sign[4] = {1.0, -1.0, -1.0, 1.0};
    for (int i = 0; i < 4; ++i) {
      const double z2 = z[i] * z[i];
      s2 += sign[i] * z2;
      s3 += sign[i] * z2 * z[i];
      s4 += sign[i] * z2 * z2;
    }
    const double inv = 1.0 / (a * b);
    frac = s2 * 0.5 * inv;
    mean = s3 / 6.0 * inv;
    meanSq = s4 / 12.0 * inv;
  } else if (a > 0.0) {
    // 1-D: G1 = z+, z+^2/2, z+^3/3.
    const double hi = pos(d + 0.5 * a), lo = pos(d - 0.5 * a);
    const double inv = 1.0 / a;
    frac = (hi - lo) * inv;
    mean = 0.5 * (hi * hi - lo * lo) * inv;
    meanSq = (hi * hi * hi - lo * lo * lo) / 3.0 * inv;
  } else {
    frac = d > 0.0 ? 1.0 : 0.0;
    mean = pos(d);
    meanSq = mean * mean;
  }
  return {frac, mean, meanSq - frac * variance};
}

/// The weight of a texel's moment correction (MomentCorrectionSums): the submerged
/// share of the vertical segment y' +- s about its centre, `depth` d above it, s the larger of the
/// patch's half span and the reach of its pieces' centroids: 1 when every piece is under, 0 when
/// every one is over, linear between (exact for a lid and a bottom stacked in one texel of a
/// packed atlas, where the patch's own fraction would count both or neither).
inline double correctionWeight(double d, double halfSpan, double reach) {
  const double s = std::max(halfSpan, reach);
  if (d >= s) return 1.0;
  if (d <= -s) return 0.0;
  return 0.5 * (d + s) / s;
}

/// How the force and torque are formed.
enum class ForceModel {
  Archimedes,   ///< flat surface: F = rho g V up, acting at the centre of buoyancy
  PressureSums, ///< waves, grids and media: the pressure sums
};

/// Turns the sums into a result. `origin` is the frame origin (world); its y is the water-plane
/// height used for stiffness. `hasWaterplane` false for media without a free surface.
HydrostaticsResult finishHydrostatics(const WettedSums& sums, const Eigen::Vector3d& origin, double density,
                                      const HydrostaticsQuery& query, ForceModel forceModel, bool hasWaterplane);

/// The wetted sums a backend added up outside core (FlatWettedSums.cpp), with no pressure sums.
WettedSums wettedSumsOf(const FlatWettedSums& in);

}  // namespace hydrotex::detail
