/// @file LiquidSurface.cpp
/// Flat plane, Gerstner waves, height grid and uniform medium behind LiquidSurface.

#include "hydrotex/LiquidSurface.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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

double LiquidSurface::pressure(const Eigen::Vector3d& worldPoint, double time, double gravity) const {
  // Hydrostatic pressure under the local free surface: p = rho g (h - y), 0 above it.
  const double depth = surfaceHeight(worldPoint.x(), worldPoint.z(), time) - worldPoint.y();
  return depth > 0.0 ? densityAt(worldPoint) * gravity * depth : 0.0;
}

double LiquidSurface::densityAt(const Eigen::Vector3d& /*worldPoint*/) const { return density(); }

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
}

Eigen::Vector3d GerstnerWaves::displacement(double x0, double z0, double time) const {
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (const Component& c : components_) {
    const double theta = c.waveNumber * (c.dirX * x0 + c.dirZ * z0) - c.omega * time + c.phase;
    const double horizontal = -c.steepness * c.amplitude * std::sin(theta);
    d.x() += horizontal * c.dirX;
    d.z() += horizontal * c.dirZ;
    d.y() += c.amplitude * std::cos(theta);
  }
  return d;
}

double GerstnerWaves::surfaceHeight(double x, double z, double time) const {
  // The surface point above (x, z) comes from the rest point x0 with x0 + dx(x0) = x; the
  // fixed-point iteration x0 <- x - dx(x0) contracts while Q k A < 1 (no looping crests).
  double x0 = x, z0 = z;
  Eigen::Vector3d d = displacement(x0, z0, time);
  for (int iteration = 0; iteration < 16; ++iteration) {
    const double nextX = x - d.x(), nextZ = z - d.z();
    const bool converged = std::abs(nextX - x0) + std::abs(nextZ - z0) < 1e-10;
    x0 = nextX;
    z0 = nextZ;
    d = displacement(x0, z0, time);
    if (converged) break;
  }
  return meanLevel_ + d.y();
}

Eigen::Vector3d GerstnerWaves::velocity(const Eigen::Vector3d& worldPoint, double time) const {
  const double surface = surfaceHeight(worldPoint.x(), worldPoint.z(), time);
  if (worldPoint.y() > surface) return Eigen::Vector3d::Zero();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (const Component& c : components_) {
    const double theta = c.waveNumber * (c.dirX * worldPoint.x() + c.dirZ * worldPoint.z()) - c.omega * time + c.phase;
    // Linear theory: orbital speeds decay as exp(k (y - surface)) below the surface.
    const double decay = std::exp(c.waveNumber * (worldPoint.y() - surface));
    const double horizontal = c.steepness * c.amplitude * c.omega * std::cos(theta) * decay;
    v.x() += horizontal * c.dirX;
    v.z() += horizontal * c.dirZ;
    v.y() += c.amplitude * c.omega * std::sin(theta) * decay;
  }
  return v;
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
