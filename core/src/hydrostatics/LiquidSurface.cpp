// SPDX-License-Identifier: Zlib
/// @file LiquidSurface.cpp
/// Flat plane, Gerstner waves, height grid and uniform medium behind LiquidSurface.

#include "hydrotex/hydrostatics/LiquidSurface.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <string>

namespace hydrotex {

namespace {
constexpr double kTwoPi = 6.28318530717958647692;

bool positiveFinite(double value) { return std::isfinite(value) && value > 0.0; }
}  // namespace

// ---- LiquidSurface defaults -------------------------------------------------------------------

Eigen::Vector3d LiquidSurface::velocity(const Eigen::Vector3d& /*worldPoint*/, double /*time*/) const {
  return Eigen::Vector3d::Zero();
}

Eigen::Vector3d LiquidSurface::velocityBelow(const Eigen::Vector3d& worldPoint, double /*surfaceHeight*/,
                                             double time) const {
  return velocity(worldPoint, time);
}

void LiquidSurface::velocitiesBelow(std::span<const Eigen::Vector3d> points, std::span<const double> surfaceHeights,
                                    double time, std::span<Eigen::Vector3d> out) const {
  if (surfaceHeights.size() != points.size() || out.size() != points.size()) return;
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = velocityBelow(points[i], surfaceHeights[i], time);
}

void LiquidSurface::surfaceHeights(std::span<const double> x, std::span<const double> z, double time,
                                   std::span<double> out) const {
  if (z.size() != x.size() || out.size() != x.size()) return;
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = surfaceHeight(x[i], z[i], time);
}

double LiquidSurface::pressure(const Eigen::Vector3d& worldPoint, double time, double gravity) const {
  // Hydrostatic pressure under the local free surface: p = rho g (h - y), 0 above it.
  const double depth = surfaceHeight(worldPoint.x(), worldPoint.z(), time) - worldPoint.y();
  return depth > 0.0 ? densityAt(worldPoint) * gravity * depth : 0.0;
}

std::pair<double, double> LiquidSurface::heightRange(double /*time*/) const {
  return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
}

double LiquidSurface::densityAt(const Eigen::Vector3d& /*worldPoint*/) const { return density(); }

std::optional<SurfaceJet> LiquidSurface::heightJet(double /*x*/, double /*z*/, double /*time*/) const {
  return std::nullopt;
}

void LiquidSurface::heightJets(std::span<const double> x, std::span<const double> z, double time,
                               std::span<std::optional<SurfaceJet>> out) const {
  if (z.size() != x.size() || out.size() != x.size()) return;
  for (std::size_t i = 0; i < x.size(); ++i) out[i] = heightJet(x[i], z[i], time);
}

std::optional<SurfaceSmoothness> LiquidSurface::smoothness(double /*time*/) const { return std::nullopt; }

// ---- FlatSurface ------------------------------------------------------------------------------

FlatSurface::FlatSurface(double height, double density) : height_(height), density_(density) {}

double FlatSurface::surfaceHeight(double /*x*/, double /*z*/, double /*time*/) const { return height_; }

Status FlatSurface::validate() const {
  if (!positiveFinite(density_)) return Error{"flat surface: density " + std::to_string(density_) + " kg/m^3 is not positive"};
  if (!std::isfinite(height_)) return Error{"flat surface: height is not finite"};
  return Ok{};
}

// ---- GerstnerWaves ----------------------------------------------------------------------------
// Tessendorf 2001, "Simulating Ocean Water", eq. 9: a rest point x0 moves to
// x0 - Q A d sin(k d.x0 - w t + phase), y = mean + A cos(k d.x0 - w t + phase), w^2 = g k.

GerstnerWaves::GerstnerWaves(std::vector<GerstnerWave> waves, double meanLevel, double density, double gravity)
    : waves_(std::move(waves)), meanLevel_(meanLevel), density_(density), gravity_(gravity) {
  components_.reserve(waves_.size());
  for (const GerstnerWave& wave : waves_) {
    const double k = wave.wavelength > 0.0 ? kTwoPi / wave.wavelength : 0.0;
    const double norm = wave.direction.norm();
    const Eigen::Vector2d dir = norm > 0.0 ? Eigen::Vector2d(wave.direction / norm) : Eigen::Vector2d(1.0, 0.0);
    components_.push_back({wave.amplitude, k, std::sqrt(std::max(gravity, 0.0) * k), wave.phase, wave.steepness,
                           dir.x(), dir.y()});
  }
  // Newton on X(x0) = x0 + H(x0) = x: with sigma = 1 - sum Q A k (J's smallest singular value at
  // worst) and |D2 X| <= K2 = sum Q A k^2, the error after a step s is |e| <= C (s + |e|)^2,
  // C = K2 / (2 sigma), so |e| <= 3 C s^2 while 2 C s <= 1/2. The height at x0 - s taken as
  // eta0(x0) - g0 . s is off by at most S2 s^2 / 2 (S2 = sum A k^2), and the error e moves it by
  // at most S1 |e| (S1 = sum A k): in all (3 S1 C + S2 / 2) s^2, held to S1 kHorizontalTolerance,
  // the bound of a search that evaluates once more (the class comment). |s| <= |dx| + |dz|.
  const PowerSums sums = powerSums();
  const double s1 = sums.s[1], s2 = sums.s[2], k2 = sums.k[2];
  const double sigma = 1.0 - sums.k[1];
  if (sigma > 0.0 && s1 > 0.0 && std::isfinite(s1 + s2 + k2)) {
    const double c = k2 / (2.0 * sigma);
    const double step = std::sqrt(s1 * kHorizontalTolerance / (3.0 * s1 * c + 0.5 * s2));
    extrapolationStep_ = c > 0.0 ? std::min(step, 0.25 / c) : step;
  }
}

GerstnerWaves::PowerSums GerstnerWaves::powerSums() const {
  PowerSums sums;
  for (const Component& c : components_) {
    double power = 1.0;
    for (int n = 1; n <= 4; ++n) {
      power *= c.waveNumber;
      sums.s[n] += std::abs(c.amplitude) * power;
      sums.k[n] += c.steepness * std::abs(c.amplitude) * power;
    }
  }
  return sums;
}

double GerstnerWaves::surfaceHeight(double x, double z, double time) const {
  return restPoint(x, z, time, kHorizontalTolerance, true, true).height;
}

namespace {
// sin and cos of a small angle |a| <= kRotationLimit by their Taylor series, cut where the first
// term left out is under 1e-17 (a tenth of an ulp of 1): to a^13 and a^12 up to 0.5 rad, to a^5
// and a^6 under 0.01 rad, to a^3 and a^4 under 0.001 rad. A Newton step moves each phase by
// little, so the search turns the last sines and cosines by the step instead of calling sin and
// cos again, and its last steps (micrometres) need the shortest series.
constexpr double kRotationLimit = 0.5;
[[gnu::always_inline]] inline void smallSineCosine(double a, double& sine, double& cosine) {
  const double a2 = a * a;
  if (a2 < 1e-3 * 1e-3) {  // a^5 / 120 < 8.4e-18, a^6 / 720 < 1.4e-21
    sine = a * (1.0 + a2 * (-1.0 / 6));
    cosine = 1.0 + a2 * (-0.5 + a2 * (1.0 / 24));
  } else if (a2 < 0.01 * 0.01) {  // a^7 / 5040 < 2e-18, a^8 / 40320 < 2.5e-21
    sine = a * (1.0 + a2 * (-1.0 / 6 + a2 * (1.0 / 120)));
    cosine = 1.0 + a2 * (-0.5 + a2 * (1.0 / 24 + a2 * (-1.0 / 720)));
  } else {
    sine = a * (1.0 + a2 * (-1.0 / 6 + a2 * (1.0 / 120 + a2 * (-1.0 / 5040 + a2 * (1.0 / 362880 + a2 * (-1.0 / 39916800 + a2 / 6227020800.0))))));
    cosine = 1.0 + a2 * (-0.5 + a2 * (1.0 / 24 + a2 * (-1.0 / 720 + a2 * (1.0 / 40320 + a2 * (-1.0 / 3628800 + a2 / 479001600.0)))));
  }
}
}  // namespace

namespace {
constexpr int kMaxIterations = 24;
constexpr double kMinDeterminant = 0.1;
}  // namespace

void GerstnerWaves::startSearch(Search& search, double x, double z, bool turnPhases, const RestPoint* start) const {
  RestPoint& p = search.p;
  search.stepX = search.stepZ = 0.0;
  search.iteration = 0;
  search.turnPhases = turnPhases && components_.size() <= kCachedWaves;
  // Started from a nearby point's answer: its rest point moved by its Jacobian's inverse times
  // the move of the point asked (X(x0) = x to first order), and its phases turned from where they
  // were evaluated. Else from the point itself (a rest point moves at most sum Q A from it).
  search.warm = search.turnPhases && start != nullptr;
  if (!search.warm) {
    p = RestPoint{};
    p.x = p.x0 = x;
    p.z = p.z0 = z;
    return;
  }
  const RestPoint from = *start;  // `start` may be search.p itself
  p = from;
  p.x = x;
  p.z = z;
  const double dx = x - from.x, dz = z - from.z;
  const double determinant = from.jxx * from.jzz - from.jxz * from.jxz;
  if (determinant > kMinDeterminant) {
    p.x0 = from.x0 + (from.jzz * dx - from.jxz * dz) / determinant;
    p.z0 = from.z0 + (from.jxx * dz - from.jxz * dx) / determinant;
  } else {
    p.x0 = from.x0 + dx;
    p.z0 = from.z0 + dz;
  }
}

bool GerstnerWaves::advanceSearch(Search& search, double time, double tolerance, bool extrapolate) const {
  // The surface point above (x, z) comes from the rest point x0 with F(x0) = x0 + H(x0) - x = 0,
  // H the horizontal displacement. Newton: J = I - sum Q A k cos(theta) d d^T; where J is nearly
  // singular (crests about to loop, sum Q k A near 1) the fixed-point step x0 <- x - H(x0), which
  // contracts while sum Q k A < 1. The height returned is that of the last evaluated rest point,
  // within one (sub-tolerance) step of the solution.
  RestPoint& p = search.p;
  const int iteration = search.iteration;
  double hx = 0.0, hz = 0.0, jxx = 1.0, jxz = 0.0, jzz = 1.0, gx = 0.0, gz = 0.0, height = 0.0;
  // The move of the rest point since the phases were last evaluated: the last step, or from
  // the start's evaluated rest point.
  const double moveX = iteration > 0 ? -search.stepX : p.x0 - p.ex, moveZ = iteration > 0 ? -search.stepZ : p.z0 - p.ez;
  const bool turnable = search.turnPhases && (iteration > 0 || search.warm);
  for (std::size_t w = 0; w < components_.size(); ++w) {
    const Component& c = components_[w];
    double sine, cosine;
    const double turn = turnable ? c.waveNumber * (c.dirX * moveX + c.dirZ * moveZ) : INFINITY;
    if (std::abs(turn) <= kRotationLimit) {
      double s, co;
      smallSineCosine(turn, s, co);
      sine = p.sine[w] * co + p.cosine[w] * s;
      cosine = p.cosine[w] * co - p.sine[w] * s;
    } else {
      const double theta = c.waveNumber * (c.dirX * p.x0 + c.dirZ * p.z0) - c.omega * time + c.phase;
      sine = std::sin(theta);
      cosine = std::cos(theta);
    }
    if (w < kCachedWaves) {
      p.sine[w] = sine;
      p.cosine[w] = cosine;
    }
    const double horizontal = c.steepness * c.amplitude;
    hx -= horizontal * sine * c.dirX;
    hz -= horizontal * sine * c.dirZ;
    height += c.amplitude * cosine;
    const double slope = horizontal * c.waveNumber * cosine;
    jxx -= slope * c.dirX * c.dirX;
    jxz -= slope * c.dirX * c.dirZ;
    jzz -= slope * c.dirZ * c.dirZ;
    const double rise = -c.amplitude * c.waveNumber * sine;
    gx += rise * c.dirX;
    gz += rise * c.dirZ;
  }
  p.ex = p.x0;
  p.ez = p.z0;
  p.height = meanLevel_ + height;
  p.jxx = jxx;
  p.jxz = jxz;
  p.jzz = jzz;
  p.gx = gx;
  p.gz = gz;
  const double rx = p.x0 + hx - p.x, rz = p.z0 + hz - p.z;
  const double determinant = jxx * jzz - jxz * jxz;
  double stepX = rx, stepZ = rz;
  if (determinant > kMinDeterminant) {
    stepX = (jzz * rx - jxz * rz) / determinant;
    stepZ = (jxx * rz - jxz * rx) / determinant;
    if (extrapolate && std::abs(stepX) + std::abs(stepZ) <= extrapolationStep_) {
      p.x0 -= stepX;
      p.z0 -= stepZ;
      p.height -= gx * stepX + gz * stepZ;
      return true;
    }
  }
  if (std::abs(stepX) + std::abs(stepZ) < tolerance) return true;
  search.stepX = stepX;
  search.stepZ = stepZ;
  if (++search.iteration >= kMaxIterations) return true;  // not converged: the last evaluated point's values
  p.x0 -= stepX;
  p.z0 -= stepZ;
  return false;
}

GerstnerWaves::RestPoint GerstnerWaves::restPoint(double x, double z, double time, double tolerance,
                                                  bool turnPhases, bool extrapolate) const {
  Search search;
  startSearch(search, x, z, turnPhases, nullptr);
  while (!advanceSearch(search, time, tolerance, extrapolate)) {
  }
  return search.p;
}

template <class Answer>
void GerstnerWaves::searchAll(std::span<const double> x, std::span<const double> z, double time, double tolerance,
                              bool extrapolate, Answer answer) const {
  // kLanes runs of consecutive points searched side by side, one evaluation of each in turn, so
  // that the processor overlaps their evaluations (each is a chain of dependent operations); each
  // point of a run starts from the one before it. Runs of fewer than kShortestRun points would
  // lose more to cold starts than they gain: then one run.
  constexpr std::size_t kLanes = 4, kShortestRun = 8;
  const std::size_t n = x.size();
  const std::size_t lanes = n >= kLanes * kShortestRun ? kLanes : 1;
  Search search[kLanes];
  std::size_t next[kLanes], first[kLanes], end[kLanes];
  std::size_t active = 0;
  for (std::size_t lane = 0; lane < lanes; ++lane) {
    first[lane] = next[lane] = n * lane / lanes;
    end[lane] = n * (lane + 1) / lanes;
    if (next[lane] < end[lane]) {
      startSearch(search[lane], x[next[lane]], z[next[lane]], true, nullptr);
      ++active;
    }
  }
  while (active > 0) {
    for (std::size_t lane = 0; lane < lanes; ++lane) {
      if (next[lane] >= end[lane] || !advanceSearch(search[lane], time, tolerance, extrapolate)) continue;
      const RestPoint& found = search[lane].p;
      answer(next[lane], found);
      if (++next[lane] == end[lane]) {
        --active;
        continue;
      }
      // Afresh every kFreshPhases-th point of a run (rounding cannot accumulate along it) and after
      // a point that is not finite.
      const bool fresh = (next[lane] - first[lane]) % kFreshPhases == 0 || !std::isfinite(found.x0 + found.z0);
      startSearch(search[lane], x[next[lane]], z[next[lane]], true, fresh ? nullptr : &found);
    }
  }
}

std::optional<SurfaceJet> GerstnerWaves::heightJet(double x, double z, double time) const {
  // eta(x) = eta0(x0(x)) with X(x0) = x0 + H(x0) = x. With J = dX/dx0 (symmetric) and
  // g0 = d eta0 / dx0: grad eta = J^-1 g0; differentiating J dx0/dx = I once more gives
  // Hess eta = sum over waves of (-A k^2 cos - Q A k^2 sin (grad eta . d)) e e^T, e = J^-1 d.
  return jetAt(restPoint(x, z, time, kJetHorizontalTolerance, true), time);
}

void GerstnerWaves::heightJets(std::span<const double> x, std::span<const double> z, double time,
                               std::span<std::optional<SurfaceJet>> out) const {
  if (z.size() != x.size() || out.size() != x.size()) return;
  searchAll(x, z, time, kJetHorizontalTolerance, false,
            [&](std::size_t i, const RestPoint& p) { out[i] = jetAt(p, time); });
}

void GerstnerWaves::surfaceHeights(std::span<const double> x, std::span<const double> z, double time,
                                   std::span<double> out) const {
  if (z.size() != x.size() || out.size() != x.size()) return;
  searchAll(x, z, time, kHorizontalTolerance, true, [&](std::size_t i, const RestPoint& p) { out[i] = p.height; });
}

std::optional<SurfaceJet> GerstnerWaves::jetAt(const RestPoint& p, double time) const {
  SurfaceJet jet;
  jet.height = p.height;
  const double determinant = p.jxx * p.jzz - p.jxz * p.jxz;
  if (!(determinant > 0.0)) return std::nullopt;  // the displacement map folds here
  const double ixx = p.jzz / determinant, ixz = -p.jxz / determinant, izz = p.jxx / determinant;
  jet.slopeX = ixx * p.gx + ixz * p.gz;
  jet.slopeZ = ixz * p.gx + izz * p.gz;
  for (std::size_t w = 0; w < components_.size(); ++w) {
    const Component& c = components_[w];
    double sine, cosine;
    if (w < kCachedWaves) {
      sine = p.sine[w];
      cosine = p.cosine[w];
    } else {
      const double theta = c.waveNumber * (c.dirX * p.x0 + c.dirZ * p.z0) - c.omega * time + c.phase;
      sine = std::sin(theta);
      cosine = std::cos(theta);
    }
    const double k2 = c.amplitude * c.waveNumber * c.waveNumber;
    const double weight = -k2 * cosine - c.steepness * k2 * sine * (jet.slopeX * c.dirX + jet.slopeZ * c.dirZ);
    const double ex = ixx * c.dirX + ixz * c.dirZ, ez = ixz * c.dirX + izz * c.dirZ;
    jet.curvatureXX += weight * ex * ex;
    jet.curvatureXZ += weight * ex * ez;
    jet.curvatureZZ += weight * ez * ez;
  }
  return jet;
}

std::optional<SurfaceSmoothness> GerstnerWaves::smoothness(double /*time*/) const {
  // Along a line x = c + s e (|e| = 1) the rest point y(s) solves J(y) y' = e. With
  // K_n = sum Q A k^n, S_n = sum A k^n and sigma = 1 - K_1 (J's smallest eigenvalue at worst),
  // differentiating J y' = e up to three times bounds |y^(n)| by a_n below; the chain rule on
  // eta0(y(s)) (|D^n eta0| <= S_n) then bounds the height's third and fourth derivatives.
  const PowerSums sums = powerSums();
  const double(&s)[5] = sums.s;
  const double(&k)[5] = sums.k;
  const double sigma = 1.0 - k[1];
  if (!(sigma > 0.0)) return std::nullopt;
  const double a1 = 1.0 / sigma;
  const double a2 = k[2] * a1 * a1 / sigma;
  const double a3 = (3.0 * k[2] * a1 * a2 + k[3] * a1 * a1 * a1) / sigma;
  const double a4 = (3.0 * k[2] * a1 * a3 + 3.0 * (k[3] * a1 * a1 + k[2] * a2) * a2 +
                     (k[4] * a1 * a1 * a1 + 3.0 * k[3] * a1 * a2 + k[2] * a3) * a1) / sigma;
  SurfaceSmoothness out;
  out.third = s[3] * a1 * a1 * a1 + 3.0 * s[2] * a1 * a2 + s[1] * a3;
  out.fourth = s[4] * a1 * a1 * a1 * a1 + 6.0 * s[3] * a1 * a1 * a2 + 3.0 * s[2] * a2 * a2 +
               4.0 * s[2] * a1 * a3 + s[1] * a4;
  return out;
}

std::pair<double, double> GerstnerWaves::heightRange(double /*time*/) const {
  double amplitudes = 0.0;
  for (const Component& c : components_) amplitudes += std::abs(c.amplitude);
  return {meanLevel_ - amplitudes, meanLevel_ + amplitudes};
}

Eigen::Vector3d GerstnerWaves::velocity(const Eigen::Vector3d& worldPoint, double time) const {
  return velocityBelow(worldPoint, surfaceHeight(worldPoint.x(), worldPoint.z(), time), time);
}

Eigen::Vector3d GerstnerWaves::velocityBelow(const Eigen::Vector3d& worldPoint, double surface, double time) const {
  // One point of velocitiesBelow (its own phase, no turn): the law is written once, there.
  Eigen::Vector3d v;
  velocitiesBelow(std::span(&worldPoint, 1), std::span(&surface, 1), time, std::span(&v, 1));
  return v;
}

void GerstnerWaves::velocitiesBelow(std::span<const Eigen::Vector3d> points, std::span<const double> surfaceHeights,
                                    double time, std::span<Eigen::Vector3d> out) const {
  if (surfaceHeights.size() != points.size() || out.size() != points.size() || points.empty()) return;
  for (std::size_t i = 0; i < points.size(); ++i) out[i].setZero();
  const Eigen::Vector3d& first = points[0];
  for (const Component& c : components_) {
    // Linear theory: orbital speeds decay as exp(k (y - surface)) below the surface.
    // theta at the first point by sin and cos; at the others turned by k d . (p - p0) (velocityBelow's law).
    const double theta0 = c.waveNumber * (c.dirX * first.x() + c.dirZ * first.z()) - c.omega * time + c.phase;
    const double sine0 = std::sin(theta0), cosine0 = std::cos(theta0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d& p = points[i];
      if (p.y() > surfaceHeights[i]) continue;  // above the surface: at rest
      const double turn = c.waveNumber * (c.dirX * (p.x() - first.x()) + c.dirZ * (p.z() - first.z()));
      double sine, cosine;
      if (std::abs(turn) <= kRotationLimit) {
        double s, co;
        smallSineCosine(turn, s, co);
        sine = sine0 * co + cosine0 * s;
        cosine = cosine0 * co - sine0 * s;
      } else {
        const double theta = c.waveNumber * (c.dirX * p.x() + c.dirZ * p.z()) - c.omega * time + c.phase;
        sine = std::sin(theta);
        cosine = std::cos(theta);
      }
      const double decay = std::exp(c.waveNumber * (p.y() - surfaceHeights[i]));
      const double horizontal = c.steepness * c.amplitude * c.omega * cosine * decay;
      out[i].x() += horizontal * c.dirX;
      out[i].z() += horizontal * c.dirZ;
      out[i].y() += c.amplitude * c.omega * sine * decay;
    }
  }
}

Status GerstnerWaves::validate() const {
  if (!positiveFinite(density_)) return Error{"Gerstner waves: density " + std::to_string(density_) + " kg/m^3 is not positive"};
  if (!positiveFinite(gravity_)) return Error{"Gerstner waves: gravity " + std::to_string(gravity_) + " m/s^2 is not positive"};
  if (!std::isfinite(meanLevel_)) return Error{"Gerstner waves: mean level is not finite"};
  for (std::size_t i = 0; i < waves_.size(); ++i) {
    const GerstnerWave& w = waves_[i];
    const std::string name = "Gerstner wave " + std::to_string(i);
    if (!positiveFinite(w.wavelength)) return Error{name + ": wavelength is not positive"};
    if (!std::isfinite(w.amplitude) || w.amplitude < 0.0) return Error{name + ": amplitude is negative or not finite"};
    if (!std::isfinite(w.steepness) || w.steepness < 0.0 || w.steepness > 1.0) return Error{name + ": steepness is outside [0, 1]"};
    if (!std::isfinite(w.phase) || !w.direction.allFinite() || w.direction.norm() == 0.0)
      return Error{name + ": phase or direction is not finite (or the direction is zero)"};
  }
  return Ok{};
}

// ---- HeightGrid -------------------------------------------------------------------------------

HeightGrid::HeightGrid(int countX, int countZ, double spacing, double originX, double originZ, double level,
                       double density)
    : countX_(countX), countZ_(countZ), spacing_(spacing), originX_(originX), originZ_(originZ), density_(density) {
  const std::size_t count = countX > 0 && countZ > 0 ? std::size_t(countX) * std::size_t(countZ) : 0;
  heights_.assign(count, level);
  velocities_.assign(count, Eigen::Vector3d::Zero());
}

namespace {
/// Bilinear weights on a clamped regular grid.
struct GridCell {
  std::size_t i00, i10, i01, i11;
  double fx, fz;
};
GridCell locate(double x, double z, int countX, int countZ, double spacing, double originX, double originZ) {
  const double gx = std::clamp((x - originX) / spacing, 0.0, double(countX - 1));
  const double gz = std::clamp((z - originZ) / spacing, 0.0, double(countZ - 1));
  const int ix = std::min(int(gx), countX - 2);
  const int iz = std::min(int(gz), countZ - 2);
  const std::size_t base = std::size_t(iz) * std::size_t(countX) + std::size_t(ix);
  return {base, base + 1, base + std::size_t(countX), base + std::size_t(countX) + 1, gx - ix, gz - iz};
}
}  // namespace

double HeightGrid::surfaceHeight(double x, double z, double /*time*/) const {
  if (std::isnan(x) || std::isnan(z) || heights_.size() < 4) return std::numeric_limits<double>::quiet_NaN();
  const GridCell c = locate(x, z, countX_, countZ_, spacing_, originX_, originZ_);
  return (1 - c.fz) * ((1 - c.fx) * heights_[c.i00] + c.fx * heights_[c.i10]) +
         c.fz * ((1 - c.fx) * heights_[c.i01] + c.fx * heights_[c.i11]);
}

std::pair<double, double> HeightGrid::heightRange(double /*time*/) const {
  if (heights_.empty()) return LiquidSurface::heightRange(0.0);
  const auto [lowest, highest] = std::minmax_element(heights_.begin(), heights_.end());
  return {*lowest, *highest};
}

Eigen::Vector3d HeightGrid::velocity(const Eigen::Vector3d& worldPoint, double time) const {
  if (!(worldPoint.y() <= surfaceHeight(worldPoint.x(), worldPoint.z(), time))) return Eigen::Vector3d::Zero();
  const GridCell c = locate(worldPoint.x(), worldPoint.z(), countX_, countZ_, spacing_, originX_, originZ_);
  return (1 - c.fz) * ((1 - c.fx) * velocities_[c.i00] + c.fx * velocities_[c.i10]) +
         c.fz * ((1 - c.fx) * velocities_[c.i01] + c.fx * velocities_[c.i11]);
}

Status HeightGrid::validate() const {
  if (countX_ < 2 || countZ_ < 2) return Error{"height grid: needs at least 2 x 2 samples, has " + std::to_string(countX_) + " x " + std::to_string(countZ_)};
  if (!positiveFinite(spacing_)) return Error{"height grid: spacing is not positive"};
  if (!positiveFinite(density_)) return Error{"height grid: density " + std::to_string(density_) + " kg/m^3 is not positive"};
  if (!std::isfinite(originX_) || !std::isfinite(originZ_)) return Error{"height grid: origin is not finite"};
  const std::size_t count = std::size_t(countX_) * std::size_t(countZ_);
  if (heights_.size() != count || velocities_.size() != count) return Error{"height grid: sample arrays were resized"};
  for (std::size_t i = 0; i < count; ++i)
    if (!std::isfinite(heights_[i]) || !velocities_[i].allFinite())
      return Error{"height grid: sample " + std::to_string(i) + " is not finite"};
  return Ok{};
}

// ---- UniformMedium ----------------------------------------------------------------------------

UniformMedium::UniformMedium(double densityAtReference, double scaleHeight, double referenceHeight)
    : density0_(densityAtReference), scaleHeight_(scaleHeight), referenceHeight_(referenceHeight) {}

double UniformMedium::surfaceHeight(double /*x*/, double /*z*/, double /*time*/) const {
  return std::numeric_limits<double>::infinity();
}

double UniformMedium::pressure(const Eigen::Vector3d& worldPoint, double /*time*/, double gravity) const {
  // dp/dy = -rho(y) g. Isothermal atmosphere: p = rho0 g H exp(-(y - y0)/H) (zero at +infinity).
  if (std::isinf(scaleHeight_)) return density0_ * gravity * (referenceHeight_ - worldPoint.y());
  return density0_ * gravity * scaleHeight_ * std::exp(-(worldPoint.y() - referenceHeight_) / scaleHeight_);
}

double UniformMedium::densityAt(const Eigen::Vector3d& worldPoint) const {
  if (std::isinf(scaleHeight_)) return density0_;
  return density0_ * std::exp(-(worldPoint.y() - referenceHeight_) / scaleHeight_);
}

Status UniformMedium::validate() const {
  if (!positiveFinite(density0_)) return Error{"uniform medium: density " + std::to_string(density0_) + " kg/m^3 is not positive"};
  if (std::isnan(scaleHeight_) || scaleHeight_ <= 0.0) return Error{"uniform medium: scale height is not positive"};
  if (!std::isfinite(referenceHeight_)) return Error{"uniform medium: reference height is not finite"};
  return Ok{};
}

}  // namespace hydrotex
