// SPDX-License-Identifier: Zlib
/// @file RigidBodyStep.cpp
/// A rigid body's step (RigidBodyStep.hpp): the out-of-liquid test, the drag sum, the added mass,
/// the implicit velocity update, the rest rule and flooding's momentum: the laws of the phased
/// step, once.

#include "hydrotex/step/RigidBodyStep.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "hydrostatics/BoxHydrostaticsWaves.hpp"
#include "hydrostatics/SphereHydrostaticsWaves.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrostatics/TexelDragLaw.hpp"
#include "step/DragLanes.hpp"
#include "step/RigidBodyDragWithJets.hpp"

namespace hydrotex {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// The part of a stiffness taken implicitly, in the metric of the generalized mass M (so that
/// heave in N/m and roll in N m/rad compare fairly): with M = L L^T, the modes of L^-1 K L^-T.
/// Stable modes (omega^2 > 0) are kept. Capsizing modes (omega^2 < 0) stay explicit, being
/// physical growth, unless they grow faster than the step resolves (|omega^2| dt^2 > 1): such a
/// mode is taken with |omega^2|, so one step turns the body at most about as far as the
/// linearized torque stays meaningful (backward Euler's quasi-static answer) instead of an
/// explicit kick of dt tau / I, which for a tiny inertia (a needle's roll) throws it far past
/// where that torque holds and pumps energy in. M is block diagonal: `heaveMass` (kg) on heave
/// and `rollPitch` (kg m^2, rollPitchInertia) on roll and pitch, so L is sqrt(m) beside the 2 x 2
/// Cholesky factor of rollPitch, and L^-1 K L^-T is written out from it: no general 3 x 3
/// factorization, inverse or product (with rollPitchInertia's two inverses, which its Schur
/// complement replaced, 19 % of a floating box's update in callgrind).
/// `largestRate`: omega^2 (1/s^2) of the stiffest implicit mode.
Eigen::Matrix3d implicitStiffness(const Eigen::Matrix3d& stiffness, double heaveMass, const Eigen::Matrix2d& rollPitch,
                                  double dt, double& largestRate) {
  const Eigen::Matrix3d symmetric = 0.5 * (stiffness + stiffness.transpose());
  // L = diag(l0, [[a, 0], [b, c]]) and its inverse diag(1 / l0, [[1 / a, 0], [-b / (a c), 1 / c]]).
  const double l0 = std::sqrt(heaveMass);
  const double a = std::sqrt(rollPitch(0, 0)), b = rollPitch(1, 0) / a, c = std::sqrt(rollPitch(1, 1) - b * b);
  const double i0 = 1.0 / l0, ia = 1.0 / a, ic = 1.0 / c, ib = -b * ia * ic;
  // Rows of L^-1 applied to K's columns, then L^-T from the right (upper triangle; symmetric).
  Eigen::Matrix3d modes;
  modes(0, 0) = symmetric(0, 0) * i0 * i0;
  modes(0, 1) = i0 * symmetric(0, 1) * ia;
  modes(0, 2) = i0 * (symmetric(0, 1) * ib + symmetric(0, 2) * ic);
  modes(1, 1) = symmetric(1, 1) * ia * ia;
  modes(1, 2) = ia * (symmetric(1, 1) * ib + symmetric(1, 2) * ic);
  modes(2, 2) = ib * ib * symmetric(1, 1) + 2.0 * ib * ic * symmetric(1, 2) + ic * ic * symmetric(2, 2);
  modes(1, 0) = modes(0, 1);
  modes(2, 0) = modes(0, 2);
  modes(2, 1) = modes(1, 2);
  // The closed-form 3x3 solver (trigonometric roots): several times cheaper than the iterative
  // one, and every body's step asks it; its eigenvalues are accurate to ~1e-15 of the largest.
  // When every mode is stable (a body floating upright, the common case) the modal sum below is K
  // itself and only the largest rate is needed, not the eigenvectors. K's leading minors tell
  // (L^-1 K L^-T has K's signs of eigenvalues: Sylvester's law of inertia), so that a body with a
  // mode that is not stable (a sphere's free roll) pays the solver once, as before.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  const double minor1 = symmetric(0, 0), minor2 = minor1 * symmetric(1, 1) - symmetric(0, 1) * symmetric(1, 0);
  if (minor1 > 0.0 && minor2 > 0.0 && symmetric.determinant() > 0.0) {
    solver.computeDirect(modes, Eigen::EigenvaluesOnly);
    largestRate = solver.eigenvalues().maxCoeff();
    return symmetric;
  }
  solver.computeDirect(modes);
  Eigen::Vector3d rates = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const double rate = solver.eigenvalues()[i];
    if (rate > 0.0 || rate * dt * dt < -1.0) rates[i] = std::abs(rate);
  }
  largestRate = rates.maxCoeff();
  Eigen::Matrix3d lower = Eigen::Matrix3d::Zero();
  lower(0, 0) = l0;
  lower(1, 1) = a;
  lower(2, 1) = b;
  lower(2, 2) = c;
  const Eigen::Matrix3d modal = solver.eigenvectors() * rates.asDiagonal() * solver.eigenvectors().transpose();
  return lower * modal * lower.transpose();
}

/// Solves the symmetric system a x = b by LDL^T with Eigen's LDLT's pivoting (the rows and columns
/// taken in the order of their diagonal's size, largest first; a zero pivot's component set to 0),
/// written for the fixed 6 x 6: Eigen's factorization works on dynamic blocks, whose products took
/// 40 % of implicitVelocityUpdate (perf, a floating body's update). Eigen's algorithm with one
/// division a pivot: its answer to rounding (test_rigid_body_step's needle).
Vector6d solveSymmetric(const Matrix6d& a, const Vector6d& b) {
  // The pivot order: Eigen picks at step k the largest |diagonal| of the rows not yet taken, from
  // the original diagonal (its left-looking update changes a row's diagonal only at its turn).
  int order[6] = {0, 1, 2, 3, 4, 5};
  for (int k = 0; k < 6; ++k) {
    int biggest = k;
    for (int i = k + 1; i < 6; ++i)
      if (std::abs(a(order[i], order[i])) > std::abs(a(order[biggest], order[biggest]))) biggest = i;
    std::swap(order[k], order[biggest]);
  }
  double lower[6][6] = {}, diagonal[6], inverse[6];
  for (int k = 0; k < 6; ++k) {
    double pivot = a(order[k], order[k]);
    for (int j = 0; j < k; ++j) pivot -= lower[k][j] * lower[k][j] * diagonal[j];
    diagonal[k] = pivot;
    // One division a pivot. As Eigen's: a zero pivot leaves its column unscaled, and the solve
    // sets the component of a pivot no larger than the smallest normal double to 0.
    const double scale = pivot != 0.0 ? 1.0 / pivot : 1.0;
    inverse[k] = std::abs(pivot) > std::numeric_limits<double>::min() ? scale : 0.0;
    for (int i = k + 1; i < 6; ++i) {
      double sum = a(order[i], order[k]);
      for (int j = 0; j < k; ++j) sum -= lower[i][j] * lower[k][j] * diagonal[j];
      lower[i][k] = sum * scale;
    }
  }
  double y[6];
  for (int i = 0; i < 6; ++i) {
    y[i] = b[order[i]];
    for (int j = 0; j < i; ++j) y[i] -= lower[i][j] * y[j];
  }
  for (int i = 0; i < 6; ++i) y[i] *= inverse[i];
  for (int i = 5; i >= 0; --i)
    for (int j = i + 1; j < 6; ++j) y[i] -= lower[j][i] * y[j];
  Vector6d x;
  for (int i = 0; i < 6; ++i) x[order[i]] = y[i];
  return x;
}

/// The inertia that torques about the world x and z axes meet while the spin about y stays free:
/// the inverse of the (x, z) block of the inverse inertia, which is the Schur complement of I_yy,
/// [[I_xx, I_xz], [I_zx, I_zz]] - [I_xy, I_zy]^T [I_yx, I_yz] / I_yy (no inverse taken). For a
/// needle lying in the water this is its tiny inertia about its own axis, where the diagonal
/// entries I_xx, I_zz see the large transverse one whenever the needle is not exactly along x or z.
Eigen::Matrix2d rollPitchInertia(const Eigen::Matrix3d& inertiaWorld) {
  const Eigen::Matrix3d& i = inertiaWorld;
  const double across = 1.0 / i(1, 1);
  Eigen::Matrix2d block;
  block(0, 0) = i(0, 0) - i(0, 1) * i(1, 0) * across;
  block(0, 1) = i(0, 2) - i(0, 1) * i(1, 2) * across;
  block(1, 0) = i(2, 0) - i(2, 1) * i(1, 0) * across;
  block(1, 1) = i(2, 2) - i(2, 1) * i(1, 2) * across;
  return block;
}

/// The horizontal footprint (m, world) of `set` posed at (rotation, translation): each patch lies
/// within its cluster's radius of the cluster's centre, and the engine's rotation is orthogonal to
/// about 1e-7, so a thousandth more covers it.
detail::Footprint dragFootprint(const DragPatchSet& set, const Eigen::Matrix3d& rotation,
                                const Eigen::Vector3d& translation) {
  detail::Footprint footprint;
  for (const DragPatchSet::Cluster& cluster : set.clusters) {
    const Eigen::Vector3d c = rotation * cluster.center + translation;
    footprint.add(c.x(), c.z(), 1.001 * cluster.radius);
  }
  return footprint;
}

/// Wet patches posed for detail::sumPosedDragLanes, as its columns: kept per thread between calls,
/// so that a step allocates nothing once they have grown.
class PosedDragColumns {
 public:
  /// Room for `capacity` patches (and the padding), none held.
  void reset(std::size_t capacity) {
    for (std::vector<double>* column : columns()) column->resize(capacity + detail::kDragLanePadding);
    count_ = 0;
  }
  std::uint32_t count() const { return count_; }
  /// Adds a patch (at most reset's capacity).
  void add(const Eigen::Vector3d& r, const Eigen::Vector3d& relative, const Eigen::Vector3d& areaVector, double area,
           double wet) {
    const std::uint32_t i = count_++;
    rx_[i] = r.x();
    ry_[i] = r.y();
    rz_[i] = r.z();
    ux_[i] = relative.x();
    uy_[i] = relative.y();
    uz_[i] = relative.z();
    ax_[i] = areaVector.x();
    ay_[i] = areaVector.y();
    az_[i] = areaVector.z();
    area_[i] = area;
    wet_[i] = wet;
  }
  /// The kernel's input: the columns with zeros past the last patch.
  detail::PosedDragInput input(const detail::DragLaneLaw& law) {
    for (std::vector<double>* column : columns())
      std::fill(column->begin() + count_, column->begin() + count_ + detail::kDragLanePadding, 0.0);
    return {rx_.data(), ry_.data(), rz_.data(), ux_.data(), uy_.data(), uz_.data(), ax_.data(), ay_.data(),
            az_.data(), area_.data(), wet_.data(), count_, law};
  }

 private:
  std::array<std::vector<double>*, 11> columns() {
    return {&rx_, &ry_, &rz_, &ux_, &uy_, &uz_, &ax_, &ay_, &az_, &area_, &wet_};
  }
  std::vector<double> rx_, ry_, rz_, ux_, uy_, uz_, ax_, ay_, az_, area_, wet_;
  std::uint32_t count_ = 0;
};

// Not inlined: inlined into rigidBodyDragOnNodes, GCC took the columns' thread-local address
// (__tls_get_addr, in a shared library) again at every node added, 360 instructions of a box's
// 20-node drag.
[[gnu::noinline]] PosedDragColumns& posedDragScratch() {
  thread_local PosedDragColumns columns;
  return columns;
}

/// A primitive's drag nodes under a flat surface (rigidBodyDrag): one list per thread, reused.
std::vector<detail::WettedNode>& primitiveDragNodes() {
  thread_local std::vector<detail::WettedNode> nodes;
  return nodes;
}

/// The law on one posed element (r from the centre of mass, its velocity relative to the liquid,
/// area vector, area, wet fraction), one at a time, added to `sums`: where the lanes are not
/// built, or the liquid's density varies from place to place.
void addElementDrag(detail::DragLaneSums& sums, const Eigen::Vector3d& r, const Eigen::Vector3d& relative,
                    const Eigen::Vector3d& areaVector, double area, double wetFraction, double density, double friction,
                    const DragCoefficients& coefficients, bool linearized) {
  detail::DragRates<double> rates;
  Eigen::Vector3d normal;
  const Eigen::Vector3d force = wetFraction * detail::texelDragLaw(areaVector, area, relative, density, friction,
                                                                    coefficients, linearized ? &rates : nullptr, &normal);
  if (linearized) {
    const double n[3] = {normal.x(), normal.y(), normal.z()}, rp[3] = {r.x(), r.y(), r.z()};
    detail::addDragDamping(sums.damping, n, rp, rates, wetFraction);
  }
  const Eigen::Vector3d torque = r.cross(force);
  for (int c = 0; c < 3; ++c) {
    sums.force[c] += force[c];
    sums.torque[c] += torque[c];
  }
  sums.wetted += wetFraction * area;
}

/// The drag's totals `sums` into `out` (whose liquidVelocityAtCenter is set): force, torque,
/// wetted area, the law's damping (Linearized) or the secant one, and the rotational damping.
void finishDrag(const DragBody& body, const RigidBodyMotion& motion, double dt, const detail::DragLaneSums& sums,
                DragLoads& out) {
  const Eigen::Vector3d& v = motion.linearVelocity;
  const Eigen::Vector3d& w = motion.angularVelocity;
  const bool linearized = body.damping == DragDamping::Linearized;
  out.force = Eigen::Vector3d(sums.force[0], sums.force[1], sums.force[2]);
  out.torque = Eigen::Vector3d(sums.torque[0], sums.torque[1], sums.torque[2]);
  out.patchesVisited = sums.visited;
  out.wettedArea = sums.wetted;
  if (linearized) out.damping = detail::dampingMatrix(sums.damping);
  if (body.totalPatchArea > 0.0 && body.rotationalDamping > 0.0) {
    const double wetted = out.wettedArea / body.totalPatchArea;
    out.torque -= body.rotationalDamping * wetted * (motion.inertiaWorld * w);
    if (linearized) out.damping.bottomRightCorner<3, 3>() += body.rotationalDamping * wetted * motion.inertiaWorld;
  }
  // The implicit update takes the drag linearized about this step's velocities (backward Euler,
  // F_d(u') = F_d(u) - C (u' - u)). Linearized: C is the full derivative, so every direction of
  // the motion the drag acts on is damped implicitly, including forces across the body's motion
  // that a lopsided patch layout makes (a spinning plate, a rolling needle). Secant: C = lambda M
  // / dt along the relative motion, lambda = -(u.J)/(u.M.u), J = dt (F_d, T_d). Both are positive
  // semidefinite, so the drag can slow a body but never reverse it, at any time step, and at a
  // steady state (terminal velocity) it changes nothing.
  if (!linearized) {
    const Eigen::Vector3d relativeLinear = v - out.liquidVelocityAtCenter;
    const double removed = -dt * (relativeLinear.dot(out.force) + w.dot(out.torque));
    const double kinetic = motion.mass * relativeLinear.squaredNorm() + w.dot(motion.inertiaWorld * w);
    if (removed > 0.0 && kinetic > 0.0) {
      const double rate = removed / kinetic / dt;
      out.damping.topLeftCorner<3, 3>().diagonal().setConstant(rate * motion.mass);
      out.damping.bottomRightCorner<3, 3>() = rate * motion.inertiaWorld;
    }
  }
}

}  // namespace

/// patchWetFraction's rule, inline for the drag sum (the exported function is reached through the PLT).
inline double wetFractionOf(double depth, double radius) {
  return std::clamp(0.5 + 0.5 * depth / std::max(radius, 1e-9), 0.0, 1.0);
}

double patchWetFraction(double depth, double radius) { return wetFractionOf(depth, radius); }

double bodySkinFriction(double density, double relativeSpeed, double referenceLength, double viscosity,
                        const DragCoefficients& coefficients) {
  if (!(coefficients.skinFrictionScale > 0.0 && viscosity > 0.0)) return 0.0;
  const double reynolds = density * relativeSpeed * referenceLength / viscosity;
  return coefficients.skinFrictionScale * skinFrictionCoefficient(reynolds);
}

std::size_t DragPatchSet::memoryBytes() const {
  return (x.capacity() + y.capacity() + z.capacity() + ax.capacity() + ay.capacity() + az.capacity() + area.capacity() +
          radius.capacity()) * sizeof(float) +
         inverseRadius.capacity() * sizeof(double) + clusters.capacity() * sizeof(Cluster);
}

DragPatchSet prepareDragPatches(std::span<const DragPatch> patches, std::size_t clusterSize) {
  DragPatchSet set;
  const std::size_t count = patches.size();
  clusterSize = std::max<std::size_t>(clusterSize, 1);
  // Clusters by space and facing: the patches split in halves across the longest side of their
  // bounds in (position, normal x the body's size) until a part holds at most clusterSize, so that
  // faces part first (one face tends to lie wholly above or below the waterline) and then each
  // face's patches by place. (The merge's order jumps across the atlas: consecutive patches lie
  // anywhere on the body.) Deterministic: the split only reads the patches.
  std::vector<std::uint32_t> order(count);
  for (std::size_t i = 0; i < count; ++i) order[i] = std::uint32_t(i);
  Eigen::Vector3f lowest = Eigen::Vector3f::Zero(), highest = Eigen::Vector3f::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    lowest = i == 0 ? patches[i].position : lowest.cwiseMin(patches[i].position);
    highest = i == 0 ? patches[i].position : highest.cwiseMax(patches[i].position);
  }
  const float size = (highest - lowest).maxCoeff();
  std::vector<Eigen::Matrix<float, 6, 1>> key(count);
  for (std::size_t i = 0; i < count; ++i) {
    const float norm = patches[i].areaVector.norm();
    key[i].head<3>() = patches[i].position;
    key[i].tail<3>() = norm > 0.0f ? Eigen::Vector3f(size * patches[i].areaVector / norm) : Eigen::Vector3f::Zero();
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> parts;
  const auto split = [&](auto& self, std::uint32_t begin, std::uint32_t end) -> void {
    if (end - begin <= clusterSize) {
      if (end > begin) parts.emplace_back(begin, end);
      return;
    }
    Eigen::Matrix<float, 6, 1> lower = key[order[begin]], upper = lower;
    for (std::uint32_t k = begin; k < end; ++k) {
      lower = lower.cwiseMin(key[order[k]]);
      upper = upper.cwiseMax(key[order[k]]);
    }
    int axis = 0;
    (upper - lower).maxCoeff(&axis);
    // The half nearest a whole number of lane groups (four patches; two divide it too), so that
    // few lanes of the sum idle past a cluster's end: 82 patches in clusters of 10 and 11 left
    // 17 % of the lanes empty.
    const std::uint32_t half = std::max<std::uint32_t>((end - begin + 4) / 8 * 4, 1);
    const std::uint32_t middle = begin + std::min(half, end - begin - 1);
    std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                     [&](std::uint32_t l, std::uint32_t r) {
                       const float kl = key[l][axis], kr = key[r][axis];
                       return kl < kr || (kl == kr && l < r);
                     });
    self(self, begin, middle);
    self(self, middle, end);
  };
  split(split, 0, std::uint32_t(count));
  // Zeros past the last patch: the sum's lanes may load there.
  static_assert(DragPatchSet::kPadding >= detail::kDragLanePadding);
  for (std::vector<float>* column : {&set.x, &set.y, &set.z, &set.ax, &set.ay, &set.az, &set.area, &set.radius})
    column->resize(count + DragPatchSet::kPadding, 0.0f);
  set.inverseRadius.resize(count + DragPatchSet::kPadding, 0.0);
  for (std::size_t i = 0; i < count; ++i) {
    const DragPatch& patch = patches[order[i]];
    set.x[i] = patch.position.x();
    set.y[i] = patch.position.y();
    set.z[i] = patch.position.z();
    set.ax[i] = patch.areaVector.x();
    set.ay[i] = patch.areaVector.y();
    set.az[i] = patch.areaVector.z();
    set.area[i] = patch.area;
    set.radius[i] = patch.radius;
    set.inverseRadius[i] = 1.0 / std::max(double(patch.radius), 1e-9);
  }
  for (const auto& [begin, end] : parts) {
    DragPatchSet::Cluster cluster;
    cluster.begin = begin;
    cluster.end = end;
    const auto at = [&](std::uint32_t i) { return Eigen::Vector3d(set.x[i], set.y[i], set.z[i]); };
    for (std::uint32_t i = begin; i < end; ++i) cluster.center += at(i);
    cluster.center /= double(end - begin);
    for (std::uint32_t i = begin; i < end; ++i) {
      // A patch is dry while its centre lies max(radius, 1e-9) above the surface, and wholly wet
      // while it lies as deep (wetFractionOf).
      const double reach = (at(i) - cluster.center).norm() + std::max(double(set.radius[i]), 1e-9);
      cluster.radius = std::max(cluster.radius, reach);
    }
    // A margin far above the rounding of the heights compared (m-scale values, 1e-16 relative).
    cluster.radius = cluster.radius * (1.0 + 1e-9) + 1e-9;
    set.clusters.push_back(cluster);
  }
  return set;
}

DragLoads rigidBodyDrag(const DragBody& body, const RigidBodyMotion& motion, const DragLiquid& liquid, double dt) {
  return detail::rigidBodyDrag(body, motion, liquid, dt, nullptr);
}

DragLoads detail::rigidBodyDrag(const DragBody& body, const RigidBodyMotion& motion, const DragLiquid& liquid, double dt,
                                SurfaceJetGrid* jets) {
  const LiquidSurface& surface = *liquid.surface;
  // A sphere or a box under a flat free surface: the law on the nodes of its wetted surface.
  if ((body.sphereRadius || body.boxHalfExtents) && surface.hasFreeSurface()) {
    if (const std::optional<double> level = surface.flatHeight()) {
      std::vector<detail::WettedNode>& nodes = primitiveDragNodes();
      if (body.sphereRadius)
        detail::flatSphereDragNodes(*body.sphereRadius, motion.meshPose.translation, *level, nodes);
      else
        detail::flatBoxDragNodes(*body.boxHalfExtents, motion.meshPose.rotation, motion.meshPose.translation, *level,
                                 nodes);
      return rigidBodyDragOnNodes(body, motion, liquid, dt, nodes);
    }
  }
  DragLoads out;
  const Eigen::Matrix3d& rotation = motion.meshPose.rotation;
  const Eigen::Vector3d& translation = motion.meshPose.translation;
  const Eigen::Vector3d& center = motion.center;
  const Eigen::Vector3d& v = motion.linearVelocity;
  const Eigen::Vector3d& w = motion.angularVelocity;
  out.liquidVelocityAtCenter = liquid.current + surface.velocity(center, liquid.time);
  // Per-body constants, once: a still, flat, uniform liquid needs no per-patch surface, velocity
  // or density calls.
  const double density = surface.density();
  const std::optional<double> flatLevel = surface.flatHeight();
  const bool still = flatLevel.has_value() && liquid.current.isZero();
  const bool freeSurface = surface.hasFreeSurface();
  const double friction = bodySkinFriction(density, (v - out.liquidVelocityAtCenter).norm(), body.referenceLength,
                                           liquid.viscosity, body.coefficients);
  // The patches as a structure of arrays in clusters (the model's set, or one for this call).
  std::optional<DragPatchSet> local;
  if (body.prepared == nullptr) local = prepareDragPatches(body.patches);
  const DragPatchSet& set = body.prepared != nullptr ? *body.prepared : *local;
  // Each patch is posed in the world, as the engine's rotation gives it: that rotation comes from
  // single precision and is orthogonal only to about 1e-7, so the sum in the mesh frame (R^T for
  // R^-1) moves a resting body's small residual torques by that much, which a body balanced on
  // its contacts (test_scene_world's clay pot) turns into a walk of millimetres.
  const Eigen::Vector3d up = rotation.row(1).transpose();  // world height of a mesh point: up . p + t_y
  const double upReach = std::max(1.0, up.norm());         // |up . (p - c)| <= upReach |p - c|
  const bool flat = flatLevel.has_value() && freeSurface;  // dry clusters skipped by their sphere
  const bool uniform = still && freeSurface;               // the fast path: flat level, no per-patch calls
  const double levelAboveOrigin = flatLevel ? *flatLevel - translation.y() : 0.0;
  // Under waves: clusters above the highest crest are dry without asking the surface, and the
  // height above each other patch comes from a bicubic Hermite interpolant of a few surface jets
  // over the body's footprint (SurfaceJetGrid, as the texture path's hierarchy uses), where its
  // error bound meets kDragSurfaceHeightError. A Gerstner height is a Newton search: asked per
  // patch it was 80 % of a floating box's step (bench_peers' box on three waves, 113 us of drag).
  const bool waves = freeSurface && !flatLevel;
  const double highestCrest = waves ? surface.heightRange(liquid.time).second - translation.y() : INFINITY;
  detail::SurfaceHeights heights(surface, liquid.time, waves ? dragFootprint(set, rotation, translation) : detail::Footprint{},
                                 detail::kDragSurfaceHeightError, INFINITY, waves ? jets : nullptr);
  // The grid's samples that the patches below the highest crest need, asked of the surface at
  // once, each started from the last (drag probe on peers_waves: box 36 -> 30 jets, 10.66 ->
  // 10.56 us; hull 36 -> 23 jets, 11.9 -> 11.3 us). The patches are posed here and again below:
  // 9 products each, against ~150 ns a jet.
  if (waves && heights.interpolated()) {
    for (const DragPatchSet::Cluster& cluster : set.clusters) {
      if (up.dot(cluster.center) - upReach * cluster.radius > highestCrest) continue;
      for (std::uint32_t i = cluster.begin; i < cluster.end; ++i) {
        const Eigen::Vector3d p = rotation * Eigen::Vector3d(double(set.x[i]), double(set.y[i]), double(set.z[i])) + translation;
        heights.mark(p.x(), p.z());
      }
    }
    heights.sampleMarked();
  }
  // The law's derivative, for the implicit update, when the body asks for it (DragDamping).
  const bool linearized = body.damping == DragDamping::Linearized;
  // The totals, which the lanes and the scalar path below add to.
  detail::DragLaneSums sums;
  // The law several patches at a time in SIMD lanes (DragLanes.hpp): in a still, flat, uniform
  // liquid the patches are posed and tested wet there too, the spans of the clusters not skipped
  // handed over in batches; in any other liquid with a free surface (one density) they are posed
  // and asked the surface here, and handed over posed.
#ifdef HYDROTEX_DOUBLE_LANES
  const bool lanes = uniform && density > 0.0;
  const bool posedLanes = !lanes && freeSurface && density > 0.0;
#else
  const bool lanes = false, posedLanes = false;
#endif
  const detail::DragLaneLaw law{density, friction, &body.coefficients, linearized};
  detail::UniformDragSpan spans[64];
  detail::UniformDragInput laneInput{set.x.data(), set.y.data(), set.z.data(), set.ax.data(), set.ay.data(),
                                     set.az.data(), set.area.data(), set.inverseRadius.data(), spans, 0,
                                     {}, {}, {}, {}, {}, flatLevel.value_or(0.0), law};
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) laneInput.rotation[row][col] = rotation(row, col);
    laneInput.translation[row] = translation[row];
    laneInput.center[row] = center[row];
    laneInput.linear[row] = v[row];
    laneInput.angular[row] = w[row];
  }
  PosedDragColumns* posed = posedLanes ? &posedDragScratch() : nullptr;
  if (posed) posed->reset(set.size());
  const auto sumSpans = [&] {
#ifdef HYDROTEX_DOUBLE_LANES
    if (!detail::sumUniformDragAvx2(laneInput, sums)) detail::sumUniformDragLanes<detail::DoubleLanes>(laneInput, sums);
#endif
    laneInput.spanCount = 0;
  };
  for (const DragPatchSet::Cluster& cluster : set.clusters) {
    const double clusterDepth = flat ? levelAboveOrigin - up.dot(cluster.center) : 0.0;
    if (flat && clusterDepth < -upReach * cluster.radius) continue;  // wholly dry
    if (waves && up.dot(cluster.center) - upReach * cluster.radius > highestCrest) continue;  // above every crest
    const bool whollyWet = uniform && clusterDepth > upReach * cluster.radius;  // every patch's ramp at 1
    if (lanes) {
      spans[laneInput.spanCount++] = {cluster.begin, cluster.end, whollyWet};
      if (laneInput.spanCount == std::size(spans)) sumSpans();
      continue;
    }
    std::uint32_t i = cluster.begin;
    // Any other liquid, in chunks: each patch posed and tested wet, then the liquid's velocity for the
    // chunk's wet patches at once (velocitiesBelow: waves turn their phases from the first
    // patch's instead of calling sin and cos per patch), then the law.
    constexpr std::uint32_t kChunk = 16;
    Eigen::Vector3d points[kChunk], liquidVelocities[kChunk];
    double levels[kChunk], wetFractions[kChunk];
    std::uint32_t indices[kChunk];
    while (i < cluster.end) {
      std::uint32_t count = 0;
      for (; i < cluster.end && count < kChunk; ++i) {
        const Eigen::Vector3d p = rotation * Eigen::Vector3d(double(set.x[i]), double(set.y[i]), double(set.z[i])) + translation;
        double wetFraction = 1.0, level = INFINITY;  // the surface above the patch, when asked: its velocity needs it too
        if (freeSurface && !whollyWet) {
          level = flatLevel ? *flatLevel : heights.at(p.x(), p.z());
          wetFraction = wetFractionOf(level - p.y(), double(set.radius[i]));
          if (wetFraction <= 0.0) continue;
        }
        points[count] = p;
        levels[count] = level;
        wetFractions[count] = wetFraction;
        indices[count] = i;
        ++count;
      }
      sums.visited += count;
      if (still) {
        for (std::uint32_t k = 0; k < count; ++k) liquidVelocities[k] = liquid.current;
      } else if (freeSurface) {  // not wholly wet (that needs a still liquid): every level was asked
        surface.velocitiesBelow(std::span(points, count), std::span(levels, count), liquid.time,
                                std::span(liquidVelocities, count));
        for (std::uint32_t k = 0; k < count; ++k) liquidVelocities[k] += liquid.current;
      } else {
        for (std::uint32_t k = 0; k < count; ++k)
          liquidVelocities[k] = surface.velocity(points[k], liquid.time) + liquid.current;
      }
      for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint32_t patch = indices[k];
        const Eigen::Vector3d r = points[k] - center;
        const Eigen::Vector3d relative = v + w.cross(r) - liquidVelocities[k];
        const Eigen::Vector3d areaVector =
            rotation * Eigen::Vector3d(double(set.ax[patch]), double(set.ay[patch]), double(set.az[patch]));
        if (posedLanes) {
          posed->add(r, relative, areaVector, double(set.area[patch]), wetFractions[k]);
          continue;
        }
        addElementDrag(sums, r, relative, areaVector, double(set.area[patch]), wetFractions[k],
                       freeSurface ? density : surface.densityAt(points[k]), friction, body.coefficients, linearized);
      }
    }
  }
  if (laneInput.spanCount > 0) sumSpans();
#ifdef HYDROTEX_DOUBLE_LANES
  if (posed && posed->count() > 0) {
    const detail::PosedDragInput input = posed->input(law);
    if (!detail::sumPosedDragAvx2(input, sums)) detail::sumPosedDragLanes<detail::DoubleLanes>(input, sums);
  }
#endif
  finishDrag(body, motion, dt, sums, out);
  return out;
}

DragLoads detail::rigidBodyDragOnNodes(const DragBody& body, const RigidBodyMotion& motion, const DragLiquid& liquid,
                                       double dt, std::span<const WettedNode> nodes) {
  DragLoads out;
  const LiquidSurface& surface = *liquid.surface;
  const Eigen::Vector3d& center = motion.center;
  const Eigen::Vector3d& v = motion.linearVelocity;
  const Eigen::Vector3d& w = motion.angularVelocity;
  out.liquidVelocityAtCenter = liquid.current + surface.velocity(center, liquid.time);
  const double density = surface.density();
  const double friction = bodySkinFriction(density, (v - out.liquidVelocityAtCenter).norm(), body.referenceLength,
                                           liquid.viscosity, body.coefficients);
  const bool linearized = body.damping == DragDamping::Linearized;
  detail::DragLaneSums sums;
  sums.visited = nodes.size();
#ifdef HYDROTEX_DOUBLE_LANES
  PosedDragColumns& posed = posedDragScratch();
  posed.reset(nodes.size());
#endif
  // The liquid's velocity below the surface at the nodes in chunks (velocitiesBelow turns the
  // waves' phases from the chunk's first node; a flat surface is still, as rigidBodyDrag takes
  // it), then the law on each node, wholly wet.
  const bool still = surface.flatHeight().has_value();
  constexpr std::size_t kChunk = 16;
  Eigen::Vector3d points[kChunk], liquidVelocities[kChunk];
  double levels[kChunk];
  for (std::size_t first = 0; first < nodes.size(); first += kChunk) {
    const std::size_t count = std::min(kChunk, nodes.size() - first);
    if (still) {
      for (std::size_t k = 0; k < count; ++k) liquidVelocities[k].setZero();
    } else {
      for (std::size_t k = 0; k < count; ++k) {
        points[k] = nodes[first + k].position;
        levels[k] = nodes[first + k].surfaceHeight;
      }
      surface.velocitiesBelow(std::span(points, count), std::span(levels, count), liquid.time,
                              std::span(liquidVelocities, count));
    }
    for (std::size_t k = 0; k < count; ++k) {
      const WettedNode& node = nodes[first + k];
      const Eigen::Vector3d r = node.position - center;
      const Eigen::Vector3d relative = v + w.cross(r) - liquidVelocities[k] - liquid.current;
#ifdef HYDROTEX_DOUBLE_LANES
      posed.add(r, relative, node.areaVector, node.area, 1.0);
#else
      addElementDrag(sums, r, relative, node.areaVector, node.area, 1.0, density, friction, body.coefficients,
                     linearized);
#endif
    }
  }
#ifdef HYDROTEX_DOUBLE_LANES
  if (posed.count() > 0) {
    const detail::PosedDragInput input = posed.input(detail::DragLaneLaw{density, friction, &body.coefficients, linearized});
    if (!detail::sumPosedDragAvx2(input, sums)) detail::sumPosedDragLanes<detail::DoubleLanes>(input, sums);
  }
#endif
  finishDrag(body, motion, dt, sums, out);
  return out;
}

Expected<RigidBodyVelocities> implicitVelocityUpdate(const RigidBodyMotion& motion, const ImplicitUpdateInput& input,
                                                     double dt) {
  // Generalized velocity u = (v, w) at the centre of mass; the engine integrates positions with the
  // u' returned. Linearizing F(x + dt u') = F(x) - K dt u' gives
  //   (M + theta dt^2 K) u' = M u + dt (m g + F) ,
  // K acting on (heave v_y, roll w_x, pitch w_z) (Hydrostatics.hpp; the reference point lies
  // vertically above the centre of mass, so these rates are the body's own). theta = min(1, a),
  // a = (omega dt)^2 of the stiffest mode: almost symplectic (energy kept) for ordinary bodies,
  // fully implicit (dissipative, unconditionally stable) for light ones; every theta > 0 has
  // determinant 1/(1 + theta a) < 1 per step, so the hydrostatic oscillation never gains energy.
  // The rates are those of the modes, not of the diagonal entries: a needle lying in the water
  // has I_xx ~ its transverse inertia unless it points exactly along x, yet rolls about its own
  // axis with an inertia 5e5 times smaller (rollPitchInertia); measured by I_xx its 100 rad/s
  // roll looked slow, stayed explicit at omega dt = 1.6 and gained energy (issue 11).
  // M is m' I on v and the inertia on w, K acts on (v_y, w_x, w_z) and the drag's damping C on
  // all of u = (v, w): one 6 x 6 symmetric positive definite system (LDLT; without drag the rows
  // of v_x and v_z are diagonal, and they decouple).
  const double mass = motion.mass;
  const Eigen::Matrix3d& inertiaWorld = motion.inertiaWorld;
  const Eigen::Vector3d& v = motion.linearVelocity;
  const Eigen::Vector3d& w = motion.angularVelocity;
  const double effectiveMass = mass + input.addedMass;
  Matrix6d system = Matrix6d::Zero();
  system.topLeftCorner<3, 3>().diagonal().setConstant(effectiveMass);
  system.bottomRightCorner<3, 3>() = inertiaWorld;
  Vector6d rhs;
  rhs.head<3>() = effectiveMass * v + dt * (mass * input.gravity + input.force);
  rhs.tail<3>() = inertiaWorld * w + dt * input.torque;
  if (input.dragDamping.allFinite() && !input.dragDamping.isZero(0.0)) {
    Vector6d u;
    u << v, w;
    const Matrix6d c = 0.5 * dt * (input.dragDamping + input.dragDamping.transpose());
    system += c;
    rhs += c * u;
  }
  const bool stiff = !input.stiffness.isZero(0.0) && input.stiffness.allFinite();
  if (stiff) {
    double rate = 0.0;
    const Eigen::Matrix3d implicitPart =
        implicitStiffness(input.stiffness, effectiveMass, rollPitchInertia(inertiaWorld), dt, rate);
    const double theta = std::min(1.0, rate * dt * dt);
    static constexpr int kIndex[3] = {1, 3, 5};  // heave -> v_y, roll -> w_x, pitch -> w_z (in u)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) system(kIndex[i], kIndex[j]) += theta * dt * dt * implicitPart(i, j);
  }
  // LDLT with its diagonal pivoting, not a plain Cholesky (LLT): a needle's system spans many
  // orders of magnitude (its roll inertia, 1 mm across, against its mass), and with LLT
  // test_hard_cases' needle spun up to 126 rad/s under double-precision Bullet (bound 110).
  const Vector6d solved = solveSymmetric(system, rhs);
  const RigidBodyVelocities next{solved.head<3>(), solved.tail<3>()};
  if (!next.linear.allFinite() || !next.angular.allFinite())
    return Error{"implicit velocity update: the step's system gave non-finite velocities"};
  return next;
}

bool whollyAboveSurface(const LiquidSurface& surface, const Eigen::Vector3d& sphereCenter, double radius, double time) {
  if (!surface.hasFreeSurface()) return false;
  const std::optional<double> flat = surface.flatHeight();
  // Away from a flat plane the surface may rise within the sphere's footprint; slopes up to 1 are
  // covered by a margin of one radius.
  const double level = flat ? *flat : surface.surfaceHeight(sphereCenter.x(), sphereCenter.z(), time);
  const double margin = flat ? 0.0 : radius;
  return sphereCenter.y() - radius > level + margin;
}

double translationalAddedMass(double coefficient, double fluidDensity, double submergedVolume) {
  return coefficient * fluidDensity * submergedVolume;
}

Expected<RigidBodyStepResult> stepRigidBody(const RigidBodyMotion& motion, const RigidBodyStepInput& input, double dt) {
  RigidBodyStepResult result;
  Eigen::Vector3d buoyancyForce = Eigen::Vector3d::Zero(), buoyancyTorque = Eigen::Vector3d::Zero();
  ImplicitUpdateInput update;
  if (input.hydrostatics != nullptr && input.buoyancy) {
    buoyancyForce = input.hydrostatics->buoyancyForce;
    buoyancyTorque = input.hydrostatics->torqueAboutCenterOfMass;
    update.stiffness = input.hydrostatics->stiffness;
  }
  result.drag.liquidVelocityAtCenter = input.liquid.current;
  if (input.drag != nullptr)
    result.drag = input.dragLoads != nullptr ? *input.dragLoads : rigidBodyDrag(*input.drag, motion, input.liquid, dt);
  if (input.addedMassCoefficient && input.hydrostatics != nullptr) {
    result.addedMass = translationalAddedMass(*input.addedMassCoefficient, input.hydrostatics->fluidDensity,
                                              input.hydrostatics->submergedVolume);
  }
  update.gravity = input.gravity;
  update.force = buoyancyForce + result.drag.force;
  update.torque = buoyancyTorque + result.drag.torque;
  update.addedMass = result.addedMass;
  update.dragDamping = result.drag.damping;
  Expected<RigidBodyVelocities> next = implicitVelocityUpdate(motion, update, dt);
  if (!next) return next.error();
  result.velocities = *next;

  // Rest afloat: balanced and slow, judged on the start of the step (the adapter keeps a body
  // awake until then, whatever its engine's own sleeping thresholds say).
  const double weight = motion.mass * input.gravity.norm();
  const Eigen::Vector3d netForce = motion.mass * input.gravity + buoyancyForce + result.drag.force;
  const Eigen::Vector3d netTorque = buoyancyTorque + result.drag.torque;
  const RestThresholds& rest = input.rest;
  result.atRest = netForce.norm() <= rest.forceFraction * weight &&
                  netTorque.norm() <= rest.forceFraction * weight * input.referenceLength &&
                  (motion.linearVelocity - result.drag.liquidVelocityAtCenter).norm() <= rest.linearSpeed &&
                  motion.angularVelocity.norm() <= rest.angularSpeed;
  return result;
}

Eigen::Vector3d floodingVelocityCorrection(const Eigen::Vector3d& velocity, const Eigen::Vector3d& liquidVelocity,
                                           double massBefore, double massAfter, double density, double inflow,
                                           double outflow) {
  if (massAfter == massBefore || !(massAfter > 0.0) || !(massBefore > 0.0)) return Eigen::Vector3d::Zero();
  // The body's velocity before the change, from the kept momentum m_after v = m_before v_before.
  const Eigen::Vector3d bodyVelocityBefore = velocity * (massAfter / massBefore);
  return density * (inflow * liquidVelocity - outflow * bodyVelocityBefore) / massAfter;
}

}  // namespace hydrotex
