// SPDX-License-Identifier: Zlib
/// @file FloatingEquilibrium.cpp
/// Floating equilibrium and righting-lever curve (FloatingEquilibrium.hpp): the heave solved at
/// every orientation, Newton on the condensed hydrostatic stiffness for the angles, a line search
/// on the potential energy.

#include "hydrotex/hydrostatics/FloatingEquilibrium.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>

#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string format(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

/// Angle in (-pi, pi].
double wrapAngle(double angle) {
  const double wrapped = std::remainder(angle, 2.0 * kPi);
  return wrapped == -kPi ? kPi : wrapped;
}

/// Which rotation is applied first (in the world frame): the swept angle of a curve goes first so
/// that the free one keeps a horizontal axis at every swept angle.
enum class Order {
  HeelThenTrim,  ///< R = Rz(trim) Rx(heel)
  TrimThenHeel,  ///< R = Rx(heel) Rz(trim)
};

/// A pose with the heave solved: displacement equals weight.
struct Settled {
  Eigen::Vector2d angles = Eigen::Vector2d::Zero();  ///< heel, trim (rad)
  double height = 0.0;                               ///< m, world y of the centre of mass
  Pose pose;
  HydrostaticsResult result;
  double energy = 0.0;  ///< J, m g y_G - rho g V y_B
};

/// Where a search on the angles ended.
struct Search {
  Settled state;
  int iterations = 0;
  bool converged = false;
  bool startUnstable = false;
};

class Floater {
 public:
  Floater(const Mesh& mesh, const FloatingBody& body, const FloatingSettings& settings,
          const FloatingHydrostatics& answer, Order order, double size)
      : mesh_(mesh), body_(body), settings_(settings), answer_(answer), order_(order), size_(size),
        water_(0.0, settings.fluidDensity), targetVolume_(body.mass / settings.fluidDensity),
        weight_(body.mass * settings.gravity) {}

  Eigen::Matrix3d rotation(const Eigen::Vector2d& angles) const {
    const Eigen::Matrix3d heel = Eigen::AngleAxisd(angles[0], Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Matrix3d trim = Eigen::AngleAxisd(angles[1], Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return order_ == Order::HeelThenTrim ? Eigen::Matrix3d(trim * heel) : Eigen::Matrix3d(heel * trim);
  }

  /// World axes of the heel and trim rotations (columns): d R / d angle = [axis]x R.
  Eigen::Matrix<double, 3, 2> axes(const Eigen::Vector2d& angles) const {
    Eigen::Matrix<double, 3, 2> a;
    if (order_ == Order::HeelThenTrim) {
      a.col(0) = Eigen::AngleAxisd(angles[1], Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
      a.col(1) = Eigen::Vector3d::UnitZ();
    } else {
      a.col(0) = Eigen::Vector3d::UnitX();
      a.col(1) = Eigen::AngleAxisd(angles[0], Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ();
    }
    return a;
  }

  /// The heave at `angles`: the height of G at which the displaced volume is m / rho.
  Expected<Settled> settle(const Eigen::Vector2d& angles, double heightGuess) const {
    Settled s;
    s.angles = angles;
    const Eigen::Matrix3d r = rotation(angles);
    const Eigen::Vector3d& g = body_.centerOfMass;
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const Eigen::Vector3d& p : mesh_.positions) {
      const double y = r.row(1).dot(p - g);
      low = std::min(low, y);
      high = std::max(high, y);
    }
    // Heights of G between `submerged` (top vertex at the surface) and `dry` (bottom vertex there).
    double submerged = -high, dry = -low;
    double height = std::isfinite(heightGuess) ? std::clamp(heightGuess, submerged, dry) : 0.5 * (submerged + dry);
    const double volumeTolerance = 1e-2 * settings_.tolerance * targetVolume_;
    double excess = 0.0;
    for (int iteration = 0; iteration < 200; ++iteration) {
      Expected<HydrostaticsResult> result = query(r, height);
      if (!result) return result.error();
      s.result = *result;
      s.height = height;
      excess = result->submergedVolume - targetVolume_;
      if (std::abs(excess) <= volumeTolerance) break;
      (excess > 0.0 ? submerged : dry) = height;  // too deep: G must rise
      if (dry - submerged <= 1e-15 * size_) break;
      const double newton = height + excess / result->waterplaneArea;  // dV/dy = -A_wp
      height = (result->waterplaneArea > 0.0 && newton > submerged && newton < dry) ? newton : 0.5 * (submerged + dry);
    }
    if (std::abs(excess) > 1e-6 * targetVolume_)
      return Error{"floating equilibrium: no height displaces " + format(targetVolume_) +
                   " m^3 (the body sinks: it is not lighter than the liquid it can displace)"};
    s.pose.rotation = r;
    s.pose.translation = Eigen::Vector3d(g.x(), s.height, g.z()) - r * g;
    s.energy = weight_ * s.height -
               settings_.fluidDensity * settings_.gravity * s.result.submergedVolume * s.result.centerOfBuoyancy.y();
    return s;
  }

  /// Generalized moments of the buoyancy about G along the heel and trim axes (N m): positive
  /// pushes the angle up. (Gravity has no moment about G.)
  Eigen::Vector2d moments(const Settled& s) const {
    return axes(s.angles).transpose() * s.result.torqueAboutCenterOfMass;
  }

  /// Hessian of the energy in (heel, trim) with the heave condensed out (N m/rad): the stiffness's
  /// roll and pitch are rotations about the world x and z axes, the heel and trim axes are
  /// horizontal (a yaw part has no hydrostatic effect).
  Eigen::Matrix2d condensedStiffness(const Settled& s) const {
    const Eigen::Matrix<double, 3, 2> a = axes(s.angles);
    Eigen::Matrix3d t = Eigen::Matrix3d::Zero();
    t(0, 0) = 1.0;
    for (int c = 0; c < 2; ++c) {
      t(1, c + 1) = a(0, c);
      t(2, c + 1) = a(2, c);
    }
    const Eigen::Matrix3d h = t.transpose() * s.result.stiffness * t;
    Eigen::Matrix2d condensed = h.bottomRightCorner<2, 2>();
    if (h(0, 0) > 0.0) condensed -= h.block<2, 1>(1, 0) * h.block<1, 2>(0, 1) / h(0, 0);
    return condensed;
  }

  /// Minimizes the energy over the free angles from `start` (see the header's method).
  Expected<Search> minimize(Settled start, bool freeHeel, bool freeTrim) const {
    const Eigen::Vector2d mask(freeHeel ? 1.0 : 0.0, freeTrim ? 1.0 : 0.0);
    const double scale = weight_ * size_;  // N m: moments and stiffnesses are measured against it
    const double momentTolerance = settings_.tolerance * scale;
    const double energyNoise = 1e-12 * scale;
    const double stableThreshold = -1e-9 * scale;
    Search search;
    search.state = std::move(start);
    for (; search.iterations < settings_.maxIterations; ++search.iterations) {
      Settled& s = search.state;
      const Eigen::Vector2d gradient = -moments(s).cwiseProduct(mask);
      Eigen::Matrix2d hessian = condensedStiffness(s);
      // Fixed angles: decoupled with unit stiffness, and no gradient, so they never move.
      for (int i = 0; i < 2; ++i)
        if (mask[i] == 0.0) {
          hessian.row(i).setZero();
          hessian.col(i).setZero();
          hessian(i, i) = scale;
        }
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(hessian);
      Eigen::Vector2d direction;
      if (gradient.cwiseAbs().maxCoeff() <= momentTolerance) {
        if (eigen.eigenvalues()[0] >= stableThreshold) {
          search.converged = true;
          break;
        }
        // An unstable equilibrium: leave it along the most negative curvature.
        if (search.iterations == 0) search.startUnstable = true;
        direction = eigen.eigenvectors().col(0).cwiseProduct(mask).normalized() * 0.5;
      } else {
        // Newton with the curvature's sign flipped where negative: always downhill.
        const Eigen::Vector2d floored = eigen.eigenvalues().cwiseAbs().cwiseMax(1e-8 * scale);
        direction = -eigen.eigenvectors() * (eigen.eigenvectors().transpose() * gradient).cwiseQuotient(floored);
        const double largest = direction.cwiseAbs().maxCoeff();
        if (largest > 0.5) direction *= 0.5 / largest;  // at most ~30 degrees a step
      }
      const double slope = std::min(0.0, gradient.dot(direction));
      bool accepted = false;
      double step = 1.0;
      for (int halving = 0; halving < 40 && !accepted; ++halving, step *= 0.5) {
        Expected<Settled> trial = settle(s.angles + step * direction, s.height);
        if (!trial) return trial.error();
        if (trial->energy <= s.energy + 1e-4 * step * slope + energyNoise && trial->energy < s.energy + energyNoise) {
          search.state = std::move(*trial);
          accepted = true;
        }
      }
      if (!accepted) {
        // No lower energy along a descent direction: a minimum as this hydrostatics resolves it.
        search.converged = true;
        break;
      }
    }
    return search;
  }

  double weight() const { return weight_; }

 private:
  Expected<HydrostaticsResult> query(const Eigen::Matrix3d& r, double height) const {
    HydrostaticsQuery q;
    q.pose.rotation = r;
    const Eigen::Vector3d& g = body_.centerOfMass;
    q.pose.translation = Eigen::Vector3d(g.x(), height, g.z()) - r * g;
    q.gravity = settings_.gravity;
    q.centerOfMass = g;
    q.mass = body_.mass;
    if (answer_) return answer_(q);
    return polyhedralHydrostaticsUnchecked(mesh_, water_, q);
  }

  const Mesh& mesh_;
  FloatingBody body_;
  FloatingSettings settings_;
  const FloatingHydrostatics& answer_;
  Order order_;
  double size_;
  FlatSurface water_;
  double targetVolume_;
  double weight_;
};

/// Checks the input; the diagonal of the mesh's bounding box (m) on success.
Expected<double> checkInput(const Mesh& mesh, const FloatingBody& body, const FloatingSettings& settings) {
  const std::string name = mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName;
  if (!(std::isfinite(body.mass) && body.mass > 0.0))
    return Error{"floating equilibrium: the mass " + format(body.mass) + " kg is not positive and finite"};
  if (!body.centerOfMass.allFinite()) return Error{"floating equilibrium: the centre of mass is not finite"};
  if (!(std::isfinite(settings.fluidDensity) && settings.fluidDensity > 0.0))
    return Error{"floating equilibrium: the fluid density " + format(settings.fluidDensity) + " kg/m^3 is not positive"};
  if (!(std::isfinite(settings.gravity) && settings.gravity > 0.0))
    return Error{"floating equilibrium: gravity " + format(settings.gravity) + " m/s^2 is not positive"};
  if (!(settings.tolerance > 0.0 && settings.tolerance < 1.0) || settings.maxIterations < 1)
    return Error{"floating equilibrium: the tolerance must lie in (0, 1) and the iteration limit be at least 1"};
  if (!std::isfinite(settings.startHeel) || !std::isfinite(settings.startTrim))
    return Error{"floating equilibrium: the start heel and trim must be finite"};
  if (Status closed = checkClosedMesh(mesh); !closed) return closed.error();
  Expected<MassProperties> solid = polyhedralMassProperties(mesh, 1.0);
  if (!solid) return solid.error();  // its messages start with the mesh's name
  Eigen::Vector3d low = mesh.positions.front(), high = low;
  for (const Eigen::Vector3d& p : mesh.positions) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const double size = (high - low).norm();
  const Eigen::Vector3d& g = body.centerOfMass;
  if ((g.array() < low.array() - 1e-12 * size).any() || (g.array() > high.array() + 1e-12 * size).any())
    return Error{"floating equilibrium: the centre of mass (" + format(g.x()) + ", " + format(g.y()) + ", " +
                 format(g.z()) + ") lies outside the bounds of " + name};
  const double liquidMass = settings.fluidDensity * solid->volume;
  if (body.mass >= liquidMass)
    return Error{"no floating equilibrium: the body's " + format(body.mass) + " kg is not less than the " +
                 format(liquidMass) + " kg of liquid its whole volume (" + format(solid->volume) +
                 " m^3) displaces: it sinks"};
  return size;
}

double deepestDraft(const Mesh& mesh, const Pose& pose) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : mesh.positions) lowest = std::min(lowest, pose.apply(p).y());
  return -lowest;
}

/// Parabola through three points: the abscissa and value of its vertex, or the middle point when
/// it opens upwards or its vertex leaves [x0, x2].
std::pair<double, double> parabolaPeak(double x0, double y0, double x1, double y1, double x2, double y2) {
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
  const double a = (d12 - d01) / (x2 - x0);
  if (!(a < 0.0)) return {x1, y1};
  // Newton form p(x) = y0 + d01 (x - x0) + a (x - x0)(x - x1); p'(x) = 0 at its vertex.
  const double x = 0.5 * (x0 + x1) - d01 / (2.0 * a);
  if (x < x0 || x > x2) return {x1, y1};
  return {x, y0 + d01 * (x - x0) + a * (x - x0) * (x - x1)};
}

/// Trapezoid integral of the sampled curve from its first abscissa to `limit`.
std::optional<double> areaUpTo(const std::vector<double>& x, const std::vector<double>& y, double limit) {
  if (x.empty() || x.back() < limit - 1e-12) return std::nullopt;
  double area = 0.0;
  for (std::size_t i = 0; i + 1 < x.size() && x[i] < limit; ++i) {
    const double end = std::min(x[i + 1], limit);
    const double yEnd = y[i] + (y[i + 1] - y[i]) * (end - x[i]) / (x[i + 1] - x[i]);
    area += 0.5 * (y[i] + yEnd) * (end - x[i]);
  }
  return area;
}

}  // namespace

Expected<FloatingEquilibrium> findFloatingEquilibrium(const Mesh& mesh, const FloatingBody& body,
                                                      const FloatingSettings& settings,
                                                      const FloatingHydrostatics& answer) {
  Expected<double> size = checkInput(mesh, body, settings);
  if (!size) return size.error();
  const Floater floater(mesh, body, settings, answer, Order::HeelThenTrim, *size);
  Expected<Settled> start = floater.settle(Eigen::Vector2d(settings.startHeel, settings.startTrim),
                                           std::numeric_limits<double>::quiet_NaN());
  if (!start) return start.error();
  FloatingEquilibrium out;
  out.startGmTransverse = start->result.stiffness(1, 1) / floater.weight();
  out.startGmLongitudinal = start->result.stiffness(2, 2) / floater.weight();
  Expected<Search> search = floater.minimize(*start, true, true);
  if (!search) return search.error();
  const Settled& s = search->state;
  out.pose = s.pose;
  out.heel = wrapAngle(s.angles[0]);
  out.trim = wrapAngle(s.angles[1]);
  out.draft = deepestDraft(mesh, s.pose);
  out.hydrostatics = s.result;
  out.gmTransverse = s.result.stiffness(1, 1) / floater.weight();
  out.gmLongitudinal = s.result.stiffness(2, 2) / floater.weight();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(floater.condensedStiffness(s));
  out.stable = eigen.eigenvalues()[0] >= -1e-9 * floater.weight() * *size;
  out.startUnstable = search->startUnstable;
  out.residualMoment = floater.moments(s).cwiseAbs().maxCoeff();
  out.converged = search->converged;
  out.iterations = search->iterations;
  return out;
}

Expected<RightingLeverCurve> rightingLeverCurve(const Mesh& mesh, const FloatingBody& body,
                                                const StabilityCurveSettings& settings,
                                                const FloatingHydrostatics& answer) {
  if (!(settings.maxAngle > 0.0 && settings.maxAngle <= kPi + 1e-12))
    return Error{"stability curve: the largest angle " + format(settings.maxAngle * 180.0 / kPi) +
                 " deg must lie in (0, 180]"};
  if (!(settings.step > 0.0 && settings.step <= settings.maxAngle))
    return Error{"stability curve: the step " + format(settings.step * 180.0 / kPi) +
                 " deg must be positive and at most the largest angle"};
  Expected<double> size = checkInput(mesh, body, settings.floating);
  if (!size) return size.error();
  const bool roll = settings.axis == StabilityAxis::Roll;
  const int swept = roll ? 0 : 1, other = 1 - swept;
  const Floater floater(mesh, body, settings.floating, answer, roll ? Order::HeelThenTrim : Order::TrimThenHeel, *size);

  RightingLeverCurve curve;
  const auto count = static_cast<std::size_t>(std::floor(settings.maxAngle / settings.step + 1e-9));
  for (std::size_t k = 0; k <= count; ++k) curve.angles.push_back(double(k) * settings.step);
  if (settings.maxAngle - curve.angles.back() > 1e-9 * settings.step) curve.angles.push_back(settings.maxAngle);

  double height = std::numeric_limits<double>::quiet_NaN();
  double otherAngle = 0.0;
  for (double angle : curve.angles) {
    Eigen::Vector2d angles;
    angles[swept] = angle;
    angles[other] = otherAngle;
    Expected<Settled> start = floater.settle(angles, height);
    if (!start) return start.error();
    Expected<Search> search = floater.minimize(*start, !roll, roll);
    if (!search) return search.error();
    const Settled& s = search->state;
    curve.levers.push_back(0.0 - floater.moments(s)[swept] / floater.weight());  // 0 - : no -0 printed
    curve.otherAngles.push_back(wrapAngle(s.angles[other]));
    if (angle == 0.0) {
      // The slope of GZ at 0: the stiffness with heave and the other angle free.
      const Eigen::Matrix2d k = floater.condensedStiffness(s);
      const double condensed = k(other, other) > 0.0 ? k(swept, swept) - k(swept, other) * k(other, swept) / k(other, other)
                                                     : k(swept, swept);
      curve.gm = condensed / floater.weight();
    }
    height = s.height;
    otherAngle = s.angles[other];
  }

  const std::vector<double>& x = curve.angles;
  const std::vector<double>& y = curve.levers;
  const std::size_t best = std::size_t(std::max_element(y.begin(), y.end()) - y.begin());
  curve.angleOfMaxLever = x[best];
  curve.maxLever = y[best];
  if (best > 0 && best + 1 < y.size())
    std::tie(curve.angleOfMaxLever, curve.maxLever) = parabolaPeak(x[best - 1], y[best - 1], x[best], y[best], x[best + 1], y[best + 1]);
  // Levers within the solver's tolerance of zero (rounding at symmetric poses) count as zero.
  const double zero = 10.0 * settings.floating.tolerance * *size;
  for (std::size_t k = 1; k < y.size(); ++k)
    if (y[k - 1] > zero && y[k] <= zero) {
      curve.angleOfVanishingStability = x[k - 1] + (x[k] - x[k - 1]) * y[k - 1] / (y[k - 1] - y[k]);
      break;
    }
  curve.area30 = areaUpTo(x, y, 30.0 * kPi / 180.0);
  curve.area40 = areaUpTo(x, y, 40.0 * kPi / 180.0);
  return curve;
}

}  // namespace hydrotex
