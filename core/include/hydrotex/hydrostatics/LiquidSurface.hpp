// SPDX-License-Identifier: Zlib
#pragma once
/// @file LiquidSurface.hpp
/// The liquid a body sits in, behind one injected interface (as btVehicleRaycaster is for
/// vehicles): a flat plane, a sum of Gerstner waves, a height grid fed by an external simulation,
/// or a uniform medium without a free surface (a gas: everything is submerged).
/// World frame, SI units, y up, gravity along -y (docs/design.md "Units and axes").

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "hydrotex/Expected.hpp"

namespace hydrotex {

/// The height of a free surface and its first and second horizontal derivatives at one point: the
/// data of a local quadratic model h + g . u + u^T H u / 2, u the horizontal offset (m) from the
/// point. The texture path's tile hierarchy under waves interpolates these between samples
/// instead of asking the surface once per texel.
struct SurfaceJet {
  double height = 0.0;       ///< surfaceHeight (m)
  double slopeX = 0.0;       ///< d height / dx (dimensionless)
  double slopeZ = 0.0;       ///< d height / dz (dimensionless)
  double curvatureXX = 0.0;  ///< d2 height / dx2 (1/m)
  double curvatureXZ = 0.0;  ///< d2 height / dx dz (1/m)
  double curvatureZZ = 0.0;  ///< d2 height / dz2 (1/m)
};

/// Bounds, over every horizontal point and direction, of the third and fourth directional
/// derivatives of surfaceHeight at one time: what the error bounds of local models need.
struct SurfaceSmoothness {
  double third = 0.0;   ///< max |d3 height / ds3| (1/m^2)
  double fourth = 0.0;  ///< max |d4 height / ds4| (1/m^3)
};

/// Query interface for the liquid. Implementations must be cheap and thread-safe for const calls:
/// the texture path calls surfaceHeight() once per texel that may be wet.
class LiquidSurface {
 public:
  virtual ~LiquidSurface() = default;

  /// Height y (m) of the free surface above the world point (x, z) at `time` (s). A surface
  /// without a free surface (hasFreeSurface() == false) returns +infinity.
  virtual double surfaceHeight(double x, double z, double time) const = 0;

  /// surfaceHeight() above each world point (x[i], z[i]) at `time` (s), into `out` (same size): a
  /// surface may start each point from the one before it (waves: the rest point's search starts
  /// from the last point's answer, its phases turned instead of sin and cos called), so points
  /// ordered with neighbours near each other cost least. Within the surface's own tolerance of
  /// surfaceHeight() (waves: sum(k A) * kHorizontalTolerance). Default: surfaceHeight() per point.
  /// Spans of unequal sizes: nothing.
  virtual void surfaceHeights(std::span<const double> x, std::span<const double> z, double time,
                              std::span<double> out) const;

  /// Velocity of the liquid (m/s, world) at a world point and time. Default: at rest.
  virtual Eigen::Vector3d velocity(const Eigen::Vector3d& worldPoint, double time) const;
  /// velocity(worldPoint, time) for a caller that already holds surfaceHeight(x, z, time) above
  /// the point (m): a surface whose velocity needs that height (waves) skips finding it again.
  /// The same bits as velocity(). Default: velocity(), the height unused.
  virtual Eigen::Vector3d velocityBelow(const Eigen::Vector3d& worldPoint, double surfaceHeight, double time) const;
  /// velocityBelow() for `points.size()` nearby points at once, each with the surface height above
  /// it (m), into `out` (same size): a surface may share work between the points (waves turn each
  /// component's phase from the first point's instead of calling sin and cos; ~1e-16 relative
  /// from velocityBelow()). Default: velocityBelow() per point. Spans of unequal sizes: nothing.
  virtual void velocitiesBelow(std::span<const Eigen::Vector3d> points, std::span<const double> surfaceHeights,
                               double time, std::span<Eigen::Vector3d> out) const;

  /// Gauge pressure (Pa) at a world point: rho g (surfaceHeight - y) below a free surface, 0 above
  /// it; for a medium without a free surface, the integral of rho(y) g from the point upwards (a
  /// constant offset does not change the force on a closed body). `gravity` in m/s^2 (> 0).
  virtual double pressure(const Eigen::Vector3d& worldPoint, double time, double gravity) const;

  /// Density (kg/m^3) at a world point; the default returns density().
  virtual double densityAt(const Eigen::Vector3d& worldPoint) const;

  /// Nominal density of the liquid (kg/m^3), e.g. 1000 for fresh water, 1025 for sea water,
  /// 1.225 for air at sea level. Used for stiffness and wherever one number is needed.
  virtual double density() const = 0;

  /// The plane's height (m) when the surface is a flat horizontal plane at every time; empty
  /// otherwise. A flat surface enables the tile hierarchy and the exact polyhedral path.
  virtual std::optional<double> flatHeight() const { return std::nullopt; }

  /// False for a uniform medium (a gas): every point is submerged.
  virtual bool hasFreeSurface() const { return true; }

  /// Bounds {lowest, highest} (m) of surfaceHeight() over every (x, z) at `time` (s). The texture
  /// path skips the texels above the highest without querying the surface. Default: unbounded.
  virtual std::pair<double, double> heightRange(double time) const;

  /// Height, slopes and curvatures (see SurfaceJet) at the world point (x, z) at `time` (s); empty
  /// when the surface does not offer them (then the texture path asks surfaceHeight per texel).
  virtual std::optional<SurfaceJet> heightJet(double x, double z, double time) const;
  /// heightJet() at each world point (x[i], z[i]) at `time` (s), into `out` (same size), each point
  /// started from the one before it as in surfaceHeights() (waves: within sum(k A) times their
  /// kJetHorizontalTolerance of heightJet()). Default: heightJet() per point. Spans of unequal
  /// sizes: nothing.
  virtual void heightJets(std::span<const double> x, std::span<const double> z, double time,
                          std::span<std::optional<SurfaceJet>> out) const;

  /// Derivative bounds of surfaceHeight at `time` (s) (see SurfaceSmoothness); empty when the
  /// surface has none (not smooth, or unknown). Needed beside heightJet for the tile hierarchy.
  virtual std::optional<SurfaceSmoothness> smoothness(double time) const;

  /// One-line reason when the surface's parameters are unusable (non-positive density, NaN, ...).
  virtual Status validate() const = 0;
};

/// A still, flat liquid surface: the plane y = height.
class FlatSurface final : public LiquidSurface {
 public:
  /// Plane at `height` (m) of liquid of `density` (kg/m^3, default fresh water).
  explicit FlatSurface(double height = 0.0, double density = 1000.0);

  /// Returns height() everywhere.
  double surfaceHeight(double x, double z, double time) const override;
  /// Nominal density (kg/m^3).
  double density() const override { return density_; }
  /// Always the plane's height (m).
  std::optional<double> flatHeight() const override { return height_; }
  /// Error when the density is not positive and finite or the height is not finite.
  Status validate() const override;
  /// {height, height} (m).
  std::pair<double, double> heightRange(double /*time*/) const override { return {height_, height_}; }

  /// The plane's height (m).
  double height() const { return height_; }
  /// Moves the plane (m); e.g. a tide or a test sweeping the water level.
  void setHeight(double height) { height_ = height; }

 private:
  double height_;
  double density_;
};

/// One Gerstner (trochoidal) wave component (Tessendorf 2001, "Simulating Ocean Water", eq. 9).
struct GerstnerWave {
  double amplitude = 0.5;                                  ///< m (crest height above mean level)
  double wavelength = 20.0;                                ///< m (> 0)
  Eigen::Vector2d direction = Eigen::Vector2d(1.0, 0.0);   ///< travel direction in (x, z); normalised on use
  double phase = 0.0;                                      ///< rad
  double steepness = 0.5;                                  ///< 0 (sine wave) .. 1 (sharp crests); horizontal displacement factor
};

/// A sum of Gerstner waves on deep water over a mean level, with the deep-water dispersion
/// relation omega^2 = g k. surfaceHeight() finds the rest point whose displaced position lies
/// above (x, z) by Newton iteration on the horizontal displacement (fixed-point steps where the
/// Jacobian is nearly singular), stopping when a step is under kHorizontalTolerance, or when a
/// Newton step is small enough that Newton's quadratic convergence puts its end within that
/// without another evaluation (the height then follows the step by its gradient); the height
/// error is at most sum(k A) * kHorizontalTolerance either way (exact for steepness 0).
class GerstnerWaves final : public LiquidSurface {
 public:
  /// Waves over `meanLevel` (m) in liquid of `density` (kg/m^3); `gravity` (m/s^2) sets the
  /// wave speeds.
  GerstnerWaves(std::vector<GerstnerWave> waves, double meanLevel = 0.0, double density = 1000.0,
                double gravity = 9.81);

  /// Horizontal tolerance (m) of the search for the rest point in surfaceHeight().
  static constexpr double kHorizontalTolerance = 1e-9;
  /// Horizontal tolerance (m) of the search in heightJet(): its height error, at most
  /// sum(k A) * 1e-7, is far under what interpolating jets costs (SurfaceJetGrid), and Newton
  /// saves one step of the search.
  static constexpr double kJetHorizontalTolerance = 1e-7;

  /// Surface height (m) above (x, z) at `time` (s).
  double surfaceHeight(double x, double z, double time) const override;
  /// surfaceHeight() per point, each search started from the last point's rest point (predicted
  /// by its Jacobian) with its phases turned by the small move (Taylor series) where the turn is
  /// under half a radian, sin and cos called where it is not and at every kFreshPhases-th point
  /// (so that rounding cannot accumulate along a long chain). Same tolerance as surfaceHeight().
  void surfaceHeights(std::span<const double> x, std::span<const double> z, double time,
                      std::span<double> out) const override;
  /// {mean - sum A, mean + sum A} (m).
  std::pair<double, double> heightRange(double time) const override;
  /// Height, slopes and curvatures above (x, z) (m, 1, 1/m): the rest point by the same search as
  /// surfaceHeight() to kJetHorizontalTolerance, then implicit differentiation of the
  /// displacement map.
  std::optional<SurfaceJet> heightJet(double x, double z, double time) const override;
  /// heightJet() per point, each search started from the last as in surfaceHeights().
  void heightJets(std::span<const double> x, std::span<const double> z, double time,
                  std::span<std::optional<SurfaceJet>> out) const override;
  /// Bounds of the third and fourth directional derivatives of the height (1/m^2, 1/m^3) from
  /// sums of A k^n and Q A k^n over the waves; empty when sum Q k A >= 1 (crests may loop).
  std::optional<SurfaceSmoothness> smoothness(double time) const override;
  /// Orbital velocity of the liquid particle at the surface above the point, decaying as
  /// exp(k (y - surface)) with depth (linear wave theory); zero above the surface.
  Eigen::Vector3d velocity(const Eigen::Vector3d& worldPoint, double time) const override;
  /// velocity() from the given surface height above the point (no second search for it).
  Eigen::Vector3d velocityBelow(const Eigen::Vector3d& worldPoint, double surfaceHeight, double time) const override;
  /// velocityBelow() per point, the phases turned from the first point's where the turn is small.
  void velocitiesBelow(std::span<const Eigen::Vector3d> points, std::span<const double> surfaceHeights, double time,
                       std::span<Eigen::Vector3d> out) const override;
  /// Nominal density (kg/m^3).
  double density() const override { return density_; }
  /// Error for a non-positive wavelength, negative amplitude, steepness outside [0, 1], NaN, or a
  /// non-positive density or gravity.
  Status validate() const override;

  /// The wave components.
  const std::vector<GerstnerWave>& waves() const { return waves_; }
  /// Mean level (m).
  double meanLevel() const { return meanLevel_; }

  /// One wave as surfaceHeight() evaluates it (derived once from a GerstnerWave), so that another
  /// evaluator (the GL backend's shader) uses the very same numbers.
  struct Component {
    double amplitude;   ///< A (m)
    double waveNumber;  ///< k = 2 pi / wavelength (1/m)
    double omega;       ///< sqrt(g k) (rad/s)
    double phase;       ///< rad
    double steepness;   ///< Q (horizontal displacement Q A)
    double dirX, dirZ;  ///< unit travel direction
  };
  /// The components, in the order of waves().
  const std::vector<Component>& components() const { return components_; }

 private:
  // The rest point whose displaced position lies above (x, z), with what the last Newton step
  // evaluated there: the height, the Jacobian J of the displacement map and the gradient of the
  // height in rest coordinates; and the phases' sines and cosines for the first kCachedWaves waves.
  // (x, z): the point asked; (ex, ez): the rest point last evaluated, where the Jacobian, the
  // gradient and the phases were taken (x0, z0 may be a step past it).
  static constexpr std::size_t kCachedWaves = 8;
  struct RestPoint {
    double x, z, x0, z0, ex, ez, height, jxx, jxz, jzz, gx, gz;
    double sine[kCachedWaves], cosine[kCachedWaves];
  };
  // A batch calls sin and cos afresh at every kFreshPhases-th point.
  static constexpr std::size_t kFreshPhases = 32;
  // turnPhases: after the first evaluation, turn the sines and cosines by each step instead of
  // calling sin and cos (~1e-16 apart; heightJet and surfaceHeight both turn them).
  // extrapolate (surfaceHeight): a Newton step under extrapolationStep_ is taken without a new
  // evaluation, the height moved along it by its gradient (the Jacobian, gradient and phases
  // stay those of the last evaluated point, which heightJet needs and so never extrapolates).
  RestPoint restPoint(double x, double z, double time, double tolerance = kHorizontalTolerance,
                      bool turnPhases = false, bool extrapolate = false) const;
  // One search for a rest point, advanced one evaluation at a time: restPoint() runs one to its
  // end, the batches (searchAll) several side by side.
  struct Search {
    RestPoint p;
    double stepX, stepZ;  // the last Newton step (m)
    int iteration;
    bool turnPhases, warm;
  };
  // Starts a search for the point (x, z); start (turnPhases only): a nearby point's answer at the
  // same time, to start from (it may be search.p itself).
  void startSearch(Search& search, double x, double z, bool turnPhases, const RestPoint* start) const;
  // One evaluation and Newton step; true when the search has ended (search.p holds the answer).
  bool advanceSearch(Search& search, double time, double tolerance, bool extrapolate) const;
  // The rest points of the points (x[i], z[i]), answer(i, rest point) for each, runs of them side
  // by side, each point started from the one before it in its run.
  template <class Answer>
  void searchAll(std::span<const double> x, std::span<const double> z, double time, double tolerance,
                 bool extrapolate, Answer answer) const;
  // heightJet()'s implicit differentiation at a rest point found to kJetHorizontalTolerance.
  std::optional<SurfaceJet> jetAt(const RestPoint& p, double time) const;

  // S_n = sum |A| k^n and K_n = sum Q |A| k^n for n = 1..4 (index 0 unused): the bounds of the
  // height's and the displacement's derivatives (smoothness(), the Newton search's step bound).
  struct PowerSums {
    double s[5] = {0, 0, 0, 0, 0}, k[5] = {0, 0, 0, 0, 0};
  };
  PowerSums powerSums() const;

  std::vector<GerstnerWave> waves_;
  std::vector<Component> components_;
  double meanLevel_;
  double density_;
  double gravity_;
  // The largest Newton step (m, |dx| + |dz|) after which the rest point is within reach of the
  // solution without another evaluation (GerstnerWaves' constructor: the bound).
  double extrapolationStep_ = 0.0;
};

/// A regular grid of surface heights and liquid velocities over (x, z), interpolated bilinearly,
/// so that any external liquid simulation can be plugged in. Outside the grid the nearest edge
/// value holds. Sample (i, j) lies at (originX + i * spacing, originZ + j * spacing), stored at
/// index j * countX + i.
class HeightGrid final : public LiquidSurface {
 public:
  /// Grid of countX x countZ samples (>= 2 each) with `spacing` (m, > 0), all heights `level`
  /// (m) and velocities zero.
  HeightGrid(int countX, int countZ, double spacing, double originX, double originZ, double level = 0.0,
             double density = 1000.0);

  /// Bilinear height (m); `time` is ignored (the owner updates the samples each step).
  double surfaceHeight(double x, double z, double time) const override;
  /// Lowest and highest sample (m); O(samples) per call.
  std::pair<double, double> heightRange(double time) const override;
  /// Bilinear surface velocity (m/s), the same at every depth below the surface; zero above.
  Eigen::Vector3d velocity(const Eigen::Vector3d& worldPoint, double time) const override;
  /// Nominal density (kg/m^3).
  double density() const override { return density_; }
  /// Error for a grid smaller than 2 x 2, a non-positive spacing or density, or a NaN sample.
  Status validate() const override;

  /// Samples along x.
  int countX() const { return countX_; }
  /// Samples along z.
  int countZ() const { return countZ_; }
  /// Distance between samples (m).
  double spacing() const { return spacing_; }
  /// x of sample (0, 0) (m).
  double originX() const { return originX_; }
  /// z of sample (0, 0) (m).
  double originZ() const { return originZ_; }
  /// Height samples (m), index j * countX + i; write them each step.
  std::vector<double>& heights() { return heights_; }
  /// Height samples (m).
  const std::vector<double>& heights() const { return heights_; }
  /// Surface velocity samples (m/s, world), same indexing.
  std::vector<Eigen::Vector3d>& velocities() { return velocities_; }
  /// Surface velocity samples (m/s, world).
  const std::vector<Eigen::Vector3d>& velocities() const { return velocities_; }

 private:
  int countX_, countZ_;
  double spacing_, originX_, originZ_, density_;
  std::vector<double> heights_;
  std::vector<Eigen::Vector3d> velocities_;
};

/// A medium with no free surface (a gas, or a body deep under water): every point is submerged.
/// Density rho(y) = rho0 exp(-(y - referenceHeight) / scaleHeight) (isothermal atmosphere, scale
/// height about 8400 m for air); an infinite scale height gives a constant density.
class UniformMedium final : public LiquidSurface {
 public:
  /// Medium of density `densityAtReference` (kg/m^3) at `referenceHeight` (m), decaying with
  /// `scaleHeight` (m, > 0, may be +infinity).
  explicit UniformMedium(double densityAtReference = 1.225, double scaleHeight = 8400.0,
                         double referenceHeight = 0.0);

  /// +infinity: there is no free surface.
  double surfaceHeight(double x, double z, double time) const override;
  /// Gauge pressure (Pa): integral of rho(y') g dy' from y to +infinity for a finite scale height
  /// (rho0 g H exp(-(y - y0)/H)), rho0 g (y0 - y) for a constant density.
  double pressure(const Eigen::Vector3d& worldPoint, double time, double gravity) const override;
  /// rho(y) (kg/m^3).
  double densityAt(const Eigen::Vector3d& worldPoint) const override;
  /// Density at the reference height (kg/m^3).
  double density() const override { return density0_; }
  /// False: no free surface.
  bool hasFreeSurface() const override { return false; }
  /// Error for a non-positive density or scale height, or a NaN.
  Status validate() const override;

  /// Scale height (m).
  double scaleHeight() const { return scaleHeight_; }
  /// Reference height (m).
  double referenceHeight() const { return referenceHeight_; }

 private:
  double density0_, scaleHeight_, referenceHeight_;
};

}  // namespace hydrotex
