// SPDX-License-Identifier: Zlib
#pragma once
/// @file TexelDragLaw.hpp
/// The per-element drag law of TexelDrag.hpp (texelDragForceWithFriction), inline: the one
/// definition behind the exported function and the rigid body's drag sum (RigidBodyStep.cpp),
/// which calls it once per wet patch and so must not pay a call through the library's PLT.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "DoubleLanes.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"

namespace hydrotex::detail {

/// Height error (m) allowed where drag interpolates the surface above its patches (rigid bodies)
/// or vertices (soft bodies): a tenth of a millimetre moves a patch's wet fraction (wetFractionOf, a ramp as wide as its radius) by under
/// 1e-4 / (2 radius), 0.5 % for a 1 cm patch and only at the waterline: far under the drag law's
/// own uncertainty (empirical coefficients). Asking for 1e-5 m instead costs a floating box on
/// bench_peers' three waves 52 instead of 42 us of drag (before the batched velocities).
inline constexpr double kDragSurfaceHeightError = 1e-4;

/// What the law needs of its number type, for one element (double) or several at once
/// (DoubleLanes, two in one SSE2 register, and QuadLanes' four in an AVX2 one: the rigid body's
/// drag sum, DragLanes.hpp).
inline double selectPositive(double x, double positive, double otherwise) { return x > 0.0 ? positive : otherwise; }
inline double absolute(double x) { return std::abs(x); }
inline double squareRoot(double x) { return std::sqrt(x); }

/// The law's derivative on one element: d force / d velocity = -(normalRate n n^T + isotropicRate I
/// + tangentialRate t t^T) (N s/m), t the tangential velocity (m/s): the pressure term's
/// rho |A| (q |s| + c_l) n n^T (s = n . u) and the skin friction's kappa (|t| P + t t^T / |t|)
/// (kappa = rho Cf max(area, |A|) / 2, P = I - n n^T), with normalRate = the pressure's rate minus
/// kappa |t| (the friction's P written as I - n n^T). Positive semidefinite: drag only dissipates.
template <class T>
struct DragRates {
  T normalRate, isotropicRate, tangentialRate;
  T tangential[3];
};

/// The law, by components, on elements whose unit normal `normal`, projected area |A| =
/// `projectedArea` and friction area max(area, |A|) = `frictionArea` are known (a prepared patch,
/// DragPatchSet), moving at `velocity` relative to liquid of `density` (> 0): `force` (N), and
/// its derivative into `rates` when given. T is double or DoubleLanes (two elements, lane by lane,
/// the same operations in the same order).
template <class T>
inline void dragLawLanes(const T (&normal)[3], const T& projectedArea, const T& frictionArea, const T (&velocity)[3],
                         double density, double frictionCoefficient, const DragCoefficients& coefficients, T (&force)[3],
                         DragRates<T>* rates = nullptr) {
  const T normalSpeed = velocity[0] * normal[0] + velocity[1] * normal[1] + velocity[2] * normal[2];
  // Quadratic pressure drag per face, as in the per-triangle drag of Kerner ("Water interaction
  // model for boats in video games", Gamasutra 2015) and Hoerner's Fluid-Dynamic Drag, with a
  // linear term for radiation damping (Faltinsen, Sea Loads on Ships and Offshore Structures, ch. 3).
  const T quadratic = selectPositive(normalSpeed, coefficients.advancingPressure, coefficients.retreatingPressure);
  const T pressure = density * (0.5 * quadratic * absolute(normalSpeed) * normalSpeed +
                                coefficients.linearPressureVelocity * normalSpeed);
  const T pressureArea = -pressure * projectedArea;
  for (int k = 0; k < 3; ++k) force[k] = pressureArea * normal[k];
  if (rates) {
    rates->normalRate = density * (quadratic * absolute(normalSpeed) + coefficients.linearPressureVelocity) * projectedArea;
    rates->isotropicRate = 0.0;
    rates->tangentialRate = 0.0;
    for (int k = 0; k < 3; ++k) rates->tangential[k] = 0.0;
  }
  if (frictionCoefficient > 0.0) {
    // Flat-plate skin friction on the tangential velocity: tau = rho/2 Cf |v_t| v_t.
    T tangential[3];
    for (int k = 0; k < 3; ++k) tangential[k] = velocity[k] - normalSpeed * normal[k];
    const T speed = squareRoot(tangential[0] * tangential[0] + tangential[1] * tangential[1] + tangential[2] * tangential[2]);
    const T scale = 0.5 * density * frictionCoefficient * speed * frictionArea;
    for (int k = 0; k < 3; ++k) force[k] -= scale * tangential[k];
    if (rates) {
      const T kappa = 0.5 * density * frictionCoefficient * frictionArea;
      rates->isotropicRate = scale;                    // kappa |t|
      rates->normalRate -= scale;                      // P = I - n n^T
      rates->tangentialRate = kappa / (speed + 1e-300);  // kappa / |t| (t = 0: its t t^T is 0 anyway)
      for (int k = 0; k < 3; ++k) rates->tangential[k] = tangential[k];
    }
  }
}

/// Sums of J^T (rate matrix) J over an element set, J the element's velocity from the body's
/// (v, w): u = v + w x r. T is double or DoubleLanes (lane sums added at the end).
template <class T>
struct DampingSums {
  T outer[21];   ///< upper triangle (row by row) of sum of normalRate g g^T + tangentialRate h h^T,
                 ///< g = (n, r x n), h = (t, r x t)
  T isotropic;   ///< sum of isotropicRate (J^T J's identity block)
  T moment[3];   ///< sum of isotropicRate r
  T second[6];   ///< sum of isotropicRate (|r|^2 I - r r^T): xx, xy, xz, yy, yz, zz
  DampingSums() {
    for (T& x : outer) x = 0.0;
    isotropic = 0.0;
    for (T& x : moment) x = 0.0;
    for (T& x : second) x = 0.0;
  }
};

/// Adds one element at `r` (m, from the centre of mass) with unit normal `n` and the derivative
/// `rates` scaled by `weight` (its wet fraction) to `sums`.
template <class T>
inline void addDragDamping(DampingSums<T>& sums, const T (&n)[3], const T (&r)[3], const DragRates<T>& rates,
                           const T& weight) {
  const T g[6] = {n[0], n[1], n[2], r[1] * n[2] - r[2] * n[1], r[2] * n[0] - r[0] * n[2], r[0] * n[1] - r[1] * n[0]};
  const T* t = rates.tangential;
  const T h[6] = {t[0], t[1], t[2], r[1] * t[2] - r[2] * t[1], r[2] * t[0] - r[0] * t[2], r[0] * t[1] - r[1] * t[0]};
  const T normalRate = weight * rates.normalRate, tangentialRate = weight * rates.tangentialRate;
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    const T gi = normalRate * g[i], hi = tangentialRate * h[i];
    for (int j = i; j < 6; ++j) sums.outer[k++] += gi * g[j] + hi * h[j];
  }
  const T b = weight * rates.isotropicRate;
  sums.isotropic += b;
  for (int i = 0; i < 3; ++i) sums.moment[i] += b * r[i];
  const T rr = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
  sums.second[0] += b * (rr - r[0] * r[0]);
  sums.second[1] -= b * (r[0] * r[1]);
  sums.second[2] -= b * (r[0] * r[2]);
  sums.second[3] += b * (rr - r[1] * r[1]);
  sums.second[4] -= b * (r[1] * r[2]);
  sums.second[5] += b * (rr - r[2] * r[2]);
}

/// The 6 x 6 damping on (v, w) of `sums` (plain doubles).
inline Eigen::Matrix<double, 6, 6> dampingMatrix(const DampingSums<double>& sums) {
  Eigen::Matrix<double, 6, 6> c;
  int k = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = i; j < 6; ++j) c(i, j) = c(j, i) = sums.outer[k++];
  // J^T J = [[I, -[r]x], [[r]x, |r|^2 I - r r^T]] summed with the isotropic rates.
  const double* s = sums.moment;
  Eigen::Matrix3d cross;
  cross << 0.0, -s[2], s[1], s[2], 0.0, -s[0], -s[1], s[0], 0.0;
  Eigen::Matrix3d second;
  second << sums.second[0], sums.second[1], sums.second[2], sums.second[1], sums.second[3], sums.second[4],
      sums.second[2], sums.second[4], sums.second[5];
  c.topLeftCorner<3, 3>() += sums.isotropic * Eigen::Matrix3d::Identity();
  c.topRightCorner<3, 3>() -= cross;
  c.bottomLeftCorner<3, 3>() += cross;
  c.bottomRightCorner<3, 3>() += second;
  return c;
}

/// The law on one element of known unit normal, projected and friction areas (dragLawLanes).
inline Eigen::Vector3d dragLawOnNormal(const Eigen::Vector3d& normal, double projectedArea, double frictionArea,
                                       const Eigen::Vector3d& relativeVelocity, double density, double frictionCoefficient,
                                       const DragCoefficients& coefficients, DragRates<double>* rates = nullptr) {
  const double n[3] = {normal.x(), normal.y(), normal.z()};
  const double u[3] = {relativeVelocity.x(), relativeVelocity.y(), relativeVelocity.z()};
  double f[3];
  dragLawLanes(n, projectedArea, frictionArea, u, density, frictionCoefficient, coefficients, f, rates);
  return {f[0], f[1], f[2]};
}

/// texelDragForceWithFriction: the law on the element's area vector.
/// With `rates` (and `unitNormal`) given, also the law's derivative (zero for an element without
/// projected area or liquid).
inline Eigen::Vector3d texelDragLaw(const Eigen::Vector3d& areaVector, double area, const Eigen::Vector3d& relativeVelocity,
                                    double density, double frictionCoefficient, const DragCoefficients& coefficients,
                                    DragRates<double>* rates = nullptr, Eigen::Vector3d* unitNormal = nullptr) {
  const double projectedArea = areaVector.norm();
  if (!(projectedArea > 0.0) || !(density > 0.0)) {
    if (rates) *rates = DragRates<double>{0.0, 0.0, 0.0, {0.0, 0.0, 0.0}};
    if (unitNormal) unitNormal->setZero();
    return Eigen::Vector3d::Zero();
  }
  const Eigen::Vector3d normal = areaVector / projectedArea;
  if (unitNormal) *unitNormal = normal;
  return dragLawOnNormal(normal, projectedArea, std::max(area, projectedArea), relativeVelocity, density,
                         frictionCoefficient, coefficients, rates);
}

}  // namespace hydrotex::detail
