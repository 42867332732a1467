// SPDX-License-Identifier: Zlib
// Liquid surfaces against their defining formulas: Gerstner waves (Tessendorf 2001, eq. 9) as a sum
// of cosines for steepness 0 and as the parametric trochoid for steepness > 0, deep-water
// dispersion, orbital velocity decay; height grids (bilinear interpolation, clamping); the uniform
// medium's pressure as the integral of rho g; validate() for every bad parameter.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "TestSurfaces.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"

using namespace hydrotex;

namespace {

constexpr double kTwoPi = 6.28318530717958647692;
constexpr double kGravity = 9.81;

/// The parametric Gerstner surface point of rest point (x0, z0), written out from Tessendorf's
/// eq. 9 independently of the implementation: x = x0 - sum Q A d sin(theta), y = mean + sum A cos(theta).
Eigen::Vector3d trochoidPoint(const std::vector<GerstnerWave>& waves, double mean, double x0, double z0, double t) {
  Eigen::Vector3d p(x0, mean, z0);
  for (const GerstnerWave& w : waves) {
    const double k = kTwoPi / w.wavelength;
    const double omega = std::sqrt(kGravity * k);
    const Eigen::Vector2d d = w.direction.normalized();
    const double theta = k * (d.x() * x0 + d.y() * z0) - omega * t + w.phase;
    p.x() -= w.steepness * w.amplitude * d.x() * std::sin(theta);
    p.z() -= w.steepness * w.amplitude * d.y() * std::sin(theta);
    p.y() += w.amplitude * std::cos(theta);
  }
  return p;
}

std::vector<GerstnerWave> threeWaves(double steepness) {
  // sum Q k A = steepness * (0.52 * 0.6 + 1.26 * 0.25 + 2.73 * 0.1) ~ 0.9 steepness: single-valued.
  return {{0.6, 12.0, Eigen::Vector2d(1.0, 0.0), 0.3, steepness},
          {0.25, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, steepness},
          {0.1, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, steepness}};
}

}  // namespace

TEST_CASE("Gerstner waves with steepness 0 are a sum of cosines", "[liquid][gerstner]") {
  const std::vector<GerstnerWave> waves = threeWaves(0.0);
  const GerstnerWaves sea(waves, 0.7);
  REQUIRE(sea.validate().ok());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(-50.0, 50.0), time(0.0, 30.0);
  for (int i = 0; i < 200; ++i) {
    const double x = coordinate(rng), z = coordinate(rng), t = time(rng);
    double expected = 0.7;
    for (const GerstnerWave& w : waves) {
      const double k = kTwoPi / w.wavelength;
      const Eigen::Vector2d d = w.direction.normalized();
      expected += w.amplitude * std::cos(k * (d.x() * x + d.y() * z) - std::sqrt(kGravity * k) * t + w.phase);
    }
    // No horizontal displacement: the search stops at once; only double rounding remains.
    CHECK(sea.surfaceHeight(x, z, t) == Approx(expected).margin(1e-12));
  }
}

TEST_CASE("Gerstner waves with steepness > 0 lie on the parametric trochoid", "[liquid][gerstner]") {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> coordinate(-50.0, 50.0), time(0.0, 30.0);
  for (double steepness : {0.3, 0.7, 1.0}) {
    const std::vector<GerstnerWave> waves = threeWaves(steepness);
    const GerstnerWaves sea(waves, -0.4);
    REQUIRE(sea.validate().ok());
    const auto [lowest, highest] = sea.heightRange(0.0);
    double amplitudeSlope = 0.0;  // sum of k A
    for (const GerstnerWave& w : waves) amplitudeSlope += w.amplitude * kTwoPi / w.wavelength;
    for (int i = 0; i < 200; ++i) {
      const double t = time(rng);
      const Eigen::Vector3d p = trochoidPoint(waves, -0.4, coordinate(rng), coordinate(rng), t);
      // The class's bound, sum(k A) kHorizontalTolerance (~1.2e-9 m here): the search stops on
      // a horizontal step under kHorizontalTolerance, or takes its last step without an
      // evaluation where Newton's convergence allows; plus 1e-13 m for rounding: phases k d.x of
      // up to ~100 rad carry ~1e-14 rad, times amplitudes < 1 m.
      CHECK(std::abs(sea.surfaceHeight(p.x(), p.z(), t) - p.y()) <=
            amplitudeSlope * GerstnerWaves::kHorizontalTolerance + 1e-13);
      CHECK(p.y() >= lowest);
      CHECK(p.y() <= highest);
    }
    CHECK(lowest == Approx(-0.4 - 0.95).margin(1e-12));
    CHECK(highest == Approx(-0.4 + 0.95).margin(1e-12));
  }
}

TEST_CASE("Gerstner waves travel at the deep-water phase speed", "[liquid][gerstner]") {
  // omega^2 = g k gives c = omega / k = sqrt(g lambda / (2 pi)).
  for (double wavelength : {1.0, 7.0, 40.0}) {
    const GerstnerWaves sea({{0.2, wavelength, Eigen::Vector2d(0.0, 2.0), 0.0, 0.6}});
    const double speed = std::sqrt(kGravity * wavelength / kTwoPi);
    for (double t : {0.5, 3.0, 11.0})
      for (double z : {-3.0, 0.2, 5.5})
        // The same crest shape shifted by c t along the direction (here +z): both sides are one
        // search each, 1e-8 m as above.
        CHECK(sea.surfaceHeight(1.0, z + speed * t, t) == Approx(sea.surfaceHeight(1.0, z, 0.0)).margin(1e-8));
  }
}

TEST_CASE("Gerstner orbital velocities decay as exp(k depth) and vanish above the surface", "[liquid][gerstner]") {
  const double wavelength = 10.0, amplitude = 0.3;
  const GerstnerWaves sea({{amplitude, wavelength, Eigen::Vector2d(1.0, 0.0), 0.4, 1.0}});
  const double k = kTwoPi / wavelength, omega = std::sqrt(kGravity * k);
  for (double x : {-2.0, 0.5, 3.3}) {
    const double t = 1.7;
    const double surface = sea.surfaceHeight(x, 0.0, t);
    // Steepness 1: circular orbits of radius A, speed A omega at the surface (linear theory).
    const Eigen::Vector3d atSurface = sea.velocity(Eigen::Vector3d(x, surface, 0.0), t);
    CHECK(atSurface.norm() == Approx(amplitude * omega).epsilon(1e-12));
    CHECK(atSurface.z() == 0.0);
    for (double depth : {0.5, 2.0, 6.0}) {
      const Eigen::Vector3d below = sea.velocity(Eigen::Vector3d(x, surface - depth, 0.0), t);
      CHECK(below.norm() == Approx(amplitude * omega * std::exp(-k * depth)).epsilon(1e-12));
      CHECK(below.normalized().isApprox(atSurface.normalized(), 1e-12));
    }
    CHECK(sea.velocity(Eigen::Vector3d(x, surface + 0.01, 0.0), t).isZero(0.0));
    // Given the surface's height (as the drag's patches hold it), the same bits without a second search.
    for (double depth : {-0.01, 0.0, 0.5, 6.0}) {
      const Eigen::Vector3d p(x, surface - depth, 0.7);
      CHECK(sea.velocityBelow(p, sea.surfaceHeight(p.x(), p.z(), t), t) == sea.velocity(p, t));
    }
  }
  // The default (no velocity field) ignores the height it is given.
  const FlatSurface still(0.0);
  CHECK(still.velocityBelow(Eigen::Vector3d(0.0, -1.0, 0.0), 0.0, 0.0).isZero(0.0));
}

TEST_CASE("Gerstner velocities for a batch of points are velocityBelow's, phases turned from the first", "[liquid][gerstner]") {
  // peers_waves.json's three waves (the shared "swell"). Points near the first (turns under kRotationLimit, where the
  // Taylor rotation replaces sin and cos) and far from it (sin and cos again), below and above
  // the surface. The turned phases differ from fresh ones by rounding: ~1e-16 rad per turn.
  const GerstnerWaves sea = hydrotex::test::gerstnerSeas().front().waves;  // "swell"
  const double t = 3.7;
  std::vector<Eigen::Vector3d> points;
  std::vector<double> heights;
  for (int i = 0; i < 40; ++i) {
    const double spread = i < 30 ? 0.05 : 3.0;  // the last ten far from the first point
    const Eigen::Vector3d p(1.0 + spread * std::cos(1.3 * i), 0.0, -2.0 + spread * std::sin(0.7 * i));
    const double h = sea.surfaceHeight(p.x(), p.z(), t);
    points.emplace_back(p.x(), h - 0.02 * (i % 5) + (i % 11 == 3 ? 0.01 : 0.0), p.z());
    heights.push_back(h);
  }
  std::vector<Eigen::Vector3d> batch(points.size(), Eigen::Vector3d::Constant(7.0));
  sea.velocitiesBelow(points, heights, t, batch);
  double largest = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    CAPTURE(i);
    const Eigen::Vector3d one = sea.velocityBelow(points[i], heights[i], t);
    largest = std::max(largest, one.norm());
    CHECK((batch[i] - one).norm() <= 1e-15 + 1e-14 * one.norm());
    if (points[i].y() > heights[i]) CHECK(batch[i].isZero(0.0));
  }
  CHECK(largest > 0.1);  // the orbital speeds are there: A omega ~ 0.09 + 0.05 + 0.03 m/s
  // Spans of unequal sizes: nothing written.
  std::vector<Eigen::Vector3d> untouched(3, Eigen::Vector3d::Constant(7.0));
  sea.velocitiesBelow(std::span(points).first(3), std::span(heights).first(2), t, untouched);
  CHECK(untouched[0] == Eigen::Vector3d::Constant(7.0));
  // The default loops velocityBelow: a flat, still surface gives zeros.
  const FlatSurface still(0.0);
  still.velocitiesBelow(std::span(points).first(3), std::span(heights).first(3), t, untouched);
  CHECK(untouched[0].isZero(0.0));
}

TEST_CASE("Gerstner heights and jets for a batch are surfaceHeight's and heightJet's, each search started from the last", "[liquid][gerstner]") {
  // Steep waves (sum Q k A ~ 0.72, the searches take the most steps) and points in a walk that
  // keeps neighbours 1 to 9 cm apart (warm starts with turned phases), jumps of metres (turns
  // over kRotationLimit: sin and cos), a point that is not a number (the next one starts afresh),
  // and more than kFreshPhases points. Each answer is within sum(k A) times the search's horizontal
  // tolerance of the true height (LiquidSurface.hpp), so two answers within twice that. Slopes and
  // curvatures have no useful bound here (smoothness() gives 2.9e3 and 2.3e5 for these steep
  // waves); the largest differences measured are 6.3e-8 and 3.0e-7, checked against 1e-6.
  const GerstnerWaves sea(threeWaves(0.8), 0.2);
  double sumKA = 0.0;
  for (const GerstnerWaves::Component& c : sea.components()) sumKA += c.waveNumber * c.amplitude;
  const double t = 2.1;
  std::vector<double> x, z;
  double px = -1.0, pz = 0.5;
  for (int i = 0; i < 150; ++i) {
    const double step = i % 37 == 36 ? 4.0 : 0.01 + 0.08 * (i % 5) / 4.0;
    px += step * std::cos(0.4 * i);
    pz += step * std::sin(0.3 * i);
    x.push_back(px);
    z.push_back(i == 70 ? std::nan("") : pz);
  }
  std::vector<double> heights(x.size(), 7.0);
  std::vector<std::optional<SurfaceJet>> jets(x.size());
  sea.surfaceHeights(x, z, t, heights);
  sea.heightJets(x, z, t, jets);
  for (std::size_t i = 0; i < x.size(); ++i) {
    CAPTURE(i, x[i], z[i]);
    const double one = sea.surfaceHeight(x[i], z[i], t);
    const std::optional<SurfaceJet> jet = sea.heightJet(x[i], z[i], t);
    if (std::isnan(z[i])) {
      CHECK(std::isnan(heights[i]));
      CHECK((!jets[i] || std::isnan(jets[i]->height)));
      continue;
    }
    CHECK(std::abs(heights[i] - one) <= 2.0 * sumKA * GerstnerWaves::kHorizontalTolerance);
    REQUIRE(jet);
    REQUIRE(jets[i]);
    CHECK(std::abs(jets[i]->height - jet->height) <= 2.0 * sumKA * GerstnerWaves::kJetHorizontalTolerance);
    CHECK(jets[i]->slopeX == Approx(jet->slopeX).margin(1e-6));
    CHECK(jets[i]->slopeZ == Approx(jet->slopeZ).margin(1e-6));
    CHECK(jets[i]->curvatureXX == Approx(jet->curvatureXX).margin(1e-6));
    CHECK(jets[i]->curvatureXZ == Approx(jet->curvatureXZ).margin(1e-6));
    CHECK(jets[i]->curvatureZZ == Approx(jet->curvatureZZ).margin(1e-6));
  }
  // Spans of unequal sizes: nothing written.
  std::vector<double> untouched(3, 7.0);
  sea.surfaceHeights(std::span(x).first(3), std::span(z).first(2), t, untouched);
  CHECK(untouched[0] == 7.0);
  // The default asks surfaceHeight() and heightJet() per point: a height grid's bilinear values,
  // and no jets.
  HeightGrid grid(3, 3, 1.0, 0.0, 0.0, 0.0);
  grid.heights()[4] = 0.5;
  const std::vector<double> gx = {0.5, 1.0, 1.7}, gz = {0.5, 1.0, 0.2};
  grid.surfaceHeights(gx, gz, 0.0, untouched);
  for (std::size_t i = 0; i < gx.size(); ++i) CHECK(untouched[i] == grid.surfaceHeight(gx[i], gz[i], 0.0));
  std::vector<std::optional<SurfaceJet>> none(3, SurfaceJet{});
  grid.heightJets(gx, gz, 0.0, none);
  for (const std::optional<SurfaceJet>& jet : none) CHECK_FALSE(jet);
}

TEST_CASE("Height grid interpolates bilinearly and clamps outside", "[liquid][grid]") {
  HeightGrid grid(7, 5, 0.5, -1.0, 2.0, 0.0, 1025.0);
  // A bilinear field a + b x + c z + d x z is reproduced exactly by bilinear interpolation.
  auto field = [](double x, double z) { return 0.3 + 0.2 * x - 0.1 * z + 0.05 * x * z; };
  auto velocityField = [](double x, double z) { return Eigen::Vector3d(0.1 * x, -0.2, 0.3 * z + x); };
  for (int j = 0; j < grid.countZ(); ++j)
    for (int i = 0; i < grid.countX(); ++i) {
      const double x = -1.0 + 0.5 * i, z = 2.0 + 0.5 * j;
      grid.heights()[std::size_t(j * grid.countX() + i)] = field(x, z);
      grid.velocities()[std::size_t(j * grid.countX() + i)] = velocityField(x, z);
    }
  REQUIRE(grid.validate().ok());
  CHECK(grid.density() == 1025.0);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> gx(-1.0, 2.0), gz(2.0, 4.0);
  for (int n = 0; n < 200; ++n) {
    const double x = gx(rng), z = gz(rng);
    // Exact up to double rounding of values of order 1.
    CHECK(grid.surfaceHeight(x, z, 0.0) == Approx(field(x, z)).margin(1e-12));
    const Eigen::Vector3d under(x, field(x, z) - 0.3, z);
    CHECK((grid.velocity(under, 0.0) - velocityField(x, z)).norm() < 1e-12);
    CHECK(grid.velocity(Eigen::Vector3d(x, field(x, z) + 0.01, z), 0.0).isZero(0.0));
  }
  // Outside, the nearest edge value holds: clamp the coordinates to the grid.
  for (const Eigen::Vector2d& outside : {Eigen::Vector2d(-5.0, 3.0), Eigen::Vector2d(9.0, 1.0),
                                         Eigen::Vector2d(0.3, 40.0), Eigen::Vector2d(-3.0, -3.0)}) {
    const double cx = std::clamp(outside.x(), -1.0, 2.0), cz = std::clamp(outside.y(), 2.0, 4.0);
    CHECK(grid.surfaceHeight(outside.x(), outside.y(), 0.0) == Approx(field(cx, cz)).margin(1e-12));
  }
  const auto [lowest, highest] = grid.heightRange(0.0);
  CHECK(lowest == *std::min_element(grid.heights().begin(), grid.heights().end()));
  CHECK(highest == *std::max_element(grid.heights().begin(), grid.heights().end()));
  CHECK(std::isnan(grid.surfaceHeight(std::nan(""), 3.0, 0.0)));
}

TEST_CASE("Flat surface pressure is rho g depth below and zero above", "[liquid][flat]") {
  const FlatSurface water(1.5, 1025.0);
  CHECK(water.pressure(Eigen::Vector3d(3.0, -0.5, 2.0), 0.0, kGravity) == Approx(1025.0 * kGravity * 2.0).epsilon(1e-15));
  CHECK(water.pressure(Eigen::Vector3d(0.0, 1.6, 0.0), 0.0, kGravity) == 0.0);
  CHECK(water.flatHeight() == 1.5);
  CHECK(water.heightRange(7.0) == std::pair<double, double>(1.5, 1.5));
}

TEST_CASE("Uniform medium pressure is the integral of rho g", "[liquid][medium]") {
  // p(y1) - p(y2) = Int_y1^y2 rho(y) g dy, by composite Simpson (error ~ (h/H)^4, far below 1e-10).
  auto simpson = [](const UniformMedium& medium, double y1, double y2) {
    const int n = 2000;
    const double h = (y2 - y1) / n;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double weight = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      sum += weight * medium.densityAt(Eigen::Vector3d(0.0, y1 + i * h, 0.0));
    }
    return sum * h / 3.0 * kGravity;
  };
  const UniformMedium air(1.225, 8400.0, 100.0);
  REQUIRE(air.validate().ok());
  CHECK_FALSE(air.hasFreeSurface());
  CHECK(std::isinf(air.surfaceHeight(0.0, 0.0, 0.0)));
  for (const auto& [y1, y2] : {std::pair(0.0, 50.0), std::pair(-300.0, 2000.0), std::pair(5000.0, 9000.0)}) {
    const double difference = air.pressure(Eigen::Vector3d(0, y1, 0), 0.0, kGravity) -
                              air.pressure(Eigen::Vector3d(0, y2, 0), 0.0, kGravity);
    CHECK(difference == Approx(simpson(air, y1, y2)).epsilon(1e-10));
  }
  // Closed form at the reference height: rho0 g H (zero pressure at +infinity).
  CHECK(air.pressure(Eigen::Vector3d(0, 100.0, 0), 0.0, kGravity) == Approx(1.225 * kGravity * 8400.0).epsilon(1e-14));
  CHECK(air.densityAt(Eigen::Vector3d(0, 100.0 + 8400.0, 0)) == Approx(1.225 / std::exp(1.0)).epsilon(1e-14));

  const UniformMedium constant(800.0, std::numeric_limits<double>::infinity(), 2.0);
  REQUIRE(constant.validate().ok());
  CHECK(constant.pressure(Eigen::Vector3d(0, -1.0, 0), 0.0, kGravity) -
            constant.pressure(Eigen::Vector3d(0, 4.0, 0), 0.0, kGravity) ==
        Approx(800.0 * kGravity * 5.0).epsilon(1e-14));
  CHECK(constant.densityAt(Eigen::Vector3d(0, -1e4, 0)) == 800.0);
}

TEST_CASE("validate() names each bad parameter", "[liquid][errors]") {
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  auto fails = [](const LiquidSurface& surface, const std::string& word) {
    const Status status = surface.validate();
    REQUIRE_FALSE(status.ok());
    INFO(status.error().message);
    CHECK(status.error().message.find(word) != std::string::npos);
  };
  CHECK(FlatSurface().validate().ok());
  fails(FlatSurface(0.0, 0.0), "density");
  fails(FlatSurface(0.0, -1.0), "density");
  fails(FlatSurface(0.0, nan), "density");
  fails(FlatSurface(inf), "height");

  auto sea = [](GerstnerWave wave) { return GerstnerWaves({wave}); };
  CHECK(sea(GerstnerWave{}).validate().ok());
  GerstnerWave w;
  w.wavelength = 0.0;
  fails(sea(w), "wavelength");
  w = {};
  w.amplitude = -0.1;
  fails(sea(w), "amplitude");
  w = {};
  w.steepness = 1.5;
  fails(sea(w), "steepness");
  w = {};
  w.steepness = nan;
  fails(sea(w), "steepness");
  w = {};
  w.phase = nan;
  fails(sea(w), "phase");
  w = {};
  w.direction = Eigen::Vector2d::Zero();
  fails(sea(w), "direction");
  fails(GerstnerWaves({GerstnerWave{}}, 0.0, 0.0), "density");
  fails(GerstnerWaves({GerstnerWave{}}, 0.0, 1000.0, 0.0), "gravity");
  fails(GerstnerWaves({GerstnerWave{}}, nan), "mean level");

  CHECK(HeightGrid(2, 2, 1.0, 0.0, 0.0).validate().ok());
  fails(HeightGrid(1, 5, 1.0, 0.0, 0.0), "2 x 2");
  fails(HeightGrid(4, 4, 0.0, 0.0, 0.0), "spacing");
  fails(HeightGrid(4, 4, 1.0, 0.0, 0.0, 0.0, -5.0), "density");
  fails(HeightGrid(4, 4, 1.0, nan, 0.0), "origin");
  HeightGrid grid(4, 4, 1.0, 0.0, 0.0);
  grid.heights()[5] = nan;
  fails(grid, "sample 5");
  HeightGrid resized(4, 4, 1.0, 0.0, 0.0);
  resized.heights().pop_back();
  fails(resized, "resized");

  CHECK(UniformMedium().validate().ok());
  fails(UniformMedium(0.0), "density");
  fails(UniformMedium(1.2, 0.0), "scale height");
  fails(UniformMedium(1.2, nan), "scale height");
  fails(UniformMedium(1.2, 8400.0, nan), "reference height");
}
