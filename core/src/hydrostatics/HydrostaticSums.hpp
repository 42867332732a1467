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
    sumDA[0] += depth * ax;
    sumDA[1] += depth * ay;
    sumDA[2] += depth * az;
    sumDxA[0] += depth * (y * az - z * ay);
    sumDxA[1] += depth * (z * ax - x * az);
    sumDxA[2] += depth * (x * ay - y * ax);
    sumDXAy += depth * x * ay;
    sumDZAy += depth * z * ay;
    sumYB += (0.5 * depthSq - localHeight * depth) * ay;
    const double fay = frac * ay;
    sumAy += fay;
    sumXAy += fay * x;
    sumZAy += fay * z;
    sumXXAy += fay * x * x;
    sumXZAy += fay * x * z;
    sumZZAy += fay * z * z;
    wettedArea += frac * area;
  }

  /// Adds the part of one texel's sums that its single position leaves out when its pieces lie
  /// on several triangles (SurfaceTextures::momentCorrection, here in the world frame:
  /// dm = R dM R^T, m^3), times `weight` (correctionWeight, below). Each sum is Sum g(x) A_k over
  /// the pieces for some g; with c_k = x' + d_k, Sum_k g(c_k) A_k = g(x') A + grad g(x') .
  /// Sum_k d_k A_k + O(d^2) = g(x') A + grad g . dm(:, k): exact for the linear g (the volume and
  /// force under a plane), first order in the texel size for the others. `depth` is the depth
  /// D = h' - y' at the texel's centre, `localHeight` h' and (slopeX, slopeZ) the surface's
  /// slope there (0 under a plane or where the surface gives no slope), so grad D =
  /// (slopeX, -1, slopeZ) and grad (Q/2 - h' D) = grad (y'^2 - h'^2)/2 = y' e_y - h' grad h'.
  inline void addMomentCorrection(double x, double y, double z, const Eigen::Matrix3d& dm, double weight,
                                  double depth, double localHeight, double slopeX, double slopeZ) {
    const double w = weight;
    // grad D . dm(:, k)
    const Eigen::Vector3d along = slopeX * dm.row(0) - dm.row(1) + slopeZ * dm.row(2);
    for (int k = 0; k < 3; ++k) sumDA[k] += w * along[k];
    // D x'_i A_k: grad = D e_i + x'_i grad D; the cross product's components.
    const double position[3] = {x, y, z};
    auto moment = [&](int i, int k) { return depth * dm(i, k) + position[i] * along[k]; };
    sumDxA[0] += w * (moment(1, 2) - moment(2, 1));
    sumDxA[1] += w * (moment(2, 0) - moment(0, 2));
    sumDxA[2] += w * (moment(0, 1) - moment(1, 0));
    sumDXAy += w * moment(0, 1);
    sumDZAy += w * moment(2, 1);
    sumYB += w * (y * dm(1, 1) - localHeight * (slopeX * dm(0, 1) + slopeZ * dm(2, 1)));
    sumXAy += w * dm(0, 1);
    sumZAy += w * dm(2, 1);
    sumXXAy += w * 2.0 * x * dm(0, 1);
    sumXZAy += w * (x * dm(2, 1) + z * dm(0, 1));
    sumZZAy += w * 2.0 * z * dm(2, 1);
  }

  /// addMomentCorrection under a plane at o_y (h' = 0, no slope) for the sums a flat surface's
  /// result reads (finishHydrostatics with ForceModel::Archimedes), which need only the column
  /// dm(:, 1) = `column` (m^3): sumDA[0], sumDA[2] and sumDxA are left as they are (a flat
  /// surface's force and torque come from the volume and the centre of buoyancy).
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

/// The weight of a texel's moment correction (WettedSums::addMomentCorrection): the submerged
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
