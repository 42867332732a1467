// SPDX-License-Identifier: Zlib
// The exact polyhedral path under free surfaces that are not flat (issue 19 item 2): a wall-sided
// box under a sloped planar surface (a height grid, exact for a plane) against closed forms, the
// texture path's per-texel answer under Gerstner seas at many poses and phases, the flat limit
// (zero-amplitude waves) against the flat path, and surfaces that answer NaN.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "RandomRotation.hpp"
#include "TestSurfaces.hpp"
#include "hydrostatics/TriangleQuadrature.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

constexpr double kG = 9.81;

using hydrotex::testing::randomRotation;

Eigen::Matrix3d rotationAboutY(double angle) { return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix(); }

/// The plane h(x, z) = level + slopeX x + slopeZ z sampled on a grid: bilinear interpolation
/// reproduces any function linear in x and z, so the grid is that plane exactly over its extent
/// (+-20 m here, far beyond the bodies).
HeightGrid slopedPlane(double level, double slopeX, double slopeZ, double density) {
  const int count = 41;
  const double spacing = 1.0, origin = -20.0;
  HeightGrid grid(count, count, spacing, origin, origin, 0.0, density);
  for (int j = 0; j < count; ++j)
    for (int i = 0; i < count; ++i)
      grid.heights()[std::size_t(j) * count + i] = level + slopeX * (origin + i * spacing) + slopeZ * (origin + j * spacing);
  return grid;
}

HydrostaticsResult exactAnswer(const Mesh& mesh, const LiquidSurface& surface, const HydrostaticsQuery& query) {
  const auto result = polyhedralHydrostatics(mesh, surface, query);
  INFO((result.ok() ? std::string() : result.error().message));
  REQUIRE(result.ok());
  return *result;
}

using hydrotex::test::Sea;
std::vector<Sea> seas() { return hydrotex::test::gerstnerSeas(); }

TextureHydrostatics buildTexture(const Mesh& mesh, int resolution) { return hydrotex::test::textureHydrostaticsOf(mesh, resolution); }

/// A surface that answers NaN east of x = 0 (a broken external simulation).
class HoleySurface final : public LiquidSurface {
 public:
  double surfaceHeight(double x, double /*z*/, double /*time*/) const override {
    return x > 0.0 ? std::numeric_limits<double>::quiet_NaN() : 0.0;
  }
  double density() const override { return 1000.0; }
  Status validate() const override { return Ok{}; }
};

/// Query i of a sweep: a random orientation, half near the origin at t in [0, 10] s, half 400 m
/// out at t ~ 1000 s, the level within +-`reach` (m) of the mean surface.
HydrostaticsQuery sweepQuery(std::mt19937& rng, int i, double reach) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const bool far = i % 2 == 1;
  HydrostaticsQuery query;
  query.pose = Pose{randomRotation(rng), Eigen::Vector3d(3.0 * unit(rng) + (far ? 400.0 : 0.0), reach * unit(rng),
                                                          3.0 * unit(rng) - (far ? 250.0 : 0.0))};
  query.time = far ? 1000.0 + unit(rng) : 5.0 + 5.0 * unit(rng);
  query.gravity = kG;
  return query;
}

/// Differences of `e` from `t`: volume (of `volume`), force and torque (of `weight`; the torque in
/// m) and V c_B about the body origin (of `volume`, m).
std::array<double, 4> differencesFrom(const HydrostaticsResult& e, const HydrostaticsResult& t, double volume,
                                      double weight, const HydrostaticsQuery& query) {
  return {std::abs(e.submergedVolume - t.submergedVolume) / volume,
          (e.buoyancyForce - t.buoyancyForce).norm() / weight,
          (e.torqueAboutCenterOfMass - t.torqueAboutCenterOfMass).norm() / weight,
          (e.submergedVolume * (e.centerOfBuoyancy - query.pose.translation) -
           t.submergedVolume * (t.centerOfBuoyancy - query.pose.translation)).norm() / volume};
}

}  // namespace

TEST_CASE("Exact path, sloped surface: a wall-sided box against closed forms",
          "[hydrostatics][polyhedral][waves]") {
  // A box with vertical sides (rotated about y only) whose top stays above and bottom below the
  // surface h = h0 + s . (x, z) over its footprint F (area A, centre c, second moment
  // M = Int u u^T dA / A with u = (x, z) - c). With H = h(c) - y_bottom:
  //   V = Int_F (h - y_b) dA = A H                              (h is linear: its mean is h(c))
  //   (x_B, z_B) = c + M s / H                                  (Int u (s . u) dA = A M s)
  //   y_B = Int_F (h^2 - y_b^2) / 2 dA / V = (h(c)^2 + s^T M s - y_b^2) / (2 H)
  // and with p = rho g (h - y) the pressure force on the closed wetted surface (p = 0 on the cap)
  //   F = -Int p n dA = -Int_V grad p dV = -rho g V (s_x, -1, s_z),
  // a horizontal push down the slope beside Archimedes' rho g V up; its moment is
  //   tau = -Int x x p n dA = -Int_V x x grad p dV = x_B x F.
  // The water plane is the footprint (A, centred at c), the wetted area A + H times the
  // perimeter. The clipping is exact for a planar surface, so only double rounding remains:
  // 1e-9 relative (measured 2e-16 in volume and 5e-16 in force).
  const double density = 1025.0;
  const Eigen::Vector3d extents(1.2, 0.8, 0.6);
  const Mesh box = prim::box(extents);
  struct Case {
    double slopeX, slopeZ, level, yaw;
    Eigen::Vector3d center;
  };
  const Case cases[] = {{0.10, 0.00, 0.00, 0.0, {0.0, 0.0, 0.0}},
                        {0.05, -0.08, 0.20, 0.3, {1.5, 0.1, -2.0}},
                        {-0.12, 0.07, -0.10, 1.1, {-3.0, 0.5, 4.0}},
                        {0.0, 0.0, 0.05, 0.7, {0.4, 0.0, 0.3}}};
  for (const Case& c : cases) {
    INFO("slope (" << c.slopeX << ", " << c.slopeZ << "), yaw " << c.yaw);
    const HeightGrid surface = slopedPlane(c.level, c.slopeX, c.slopeZ, density);
    HydrostaticsQuery query;
    query.pose = Pose{rotationAboutY(c.yaw), c.center};
    query.gravity = kG;
    const HydrostaticsResult r = exactAnswer(box, surface, query);

    const Eigen::Vector2d slope(c.slopeX, c.slopeZ), center(c.center.x(), c.center.z());
    const double yBottom = c.center.y() - 0.5 * extents.y();
    const double surfaceAtCenter = c.level + slope.dot(center);
    const double height = surfaceAtCenter - yBottom;
    const double area = extents.x() * extents.z();
    // The footprint's second moment: diag(Lx^2, Lz^2) / 12 in the box's axes, turned by the yaw
    // (x, z rows of R_y).
    const Eigen::Matrix3d r3 = rotationAboutY(c.yaw);
    Eigen::Matrix2d turn;
    turn << r3(0, 0), r3(0, 2), r3(2, 0), r3(2, 2);
    const Eigen::Matrix2d moment =
        turn * Eigen::Vector2d(extents.x() * extents.x() / 12.0, extents.z() * extents.z() / 12.0).asDiagonal() *
        turn.transpose();
    const double volume = area * height;
    const Eigen::Vector2d horizontal = center + moment * slope / height;
    const double yB = (surfaceAtCenter * surfaceAtCenter + slope.dot(moment * slope) - yBottom * yBottom) / (2.0 * height);
    const Eigen::Vector3d buoyancyCenter(horizontal.x(), yB, horizontal.y());
    const Eigen::Vector3d force = density * kG * volume * Eigen::Vector3d(-c.slopeX, 1.0, -c.slopeZ);
    const Eigen::Vector3d torque = (buoyancyCenter - c.center).cross(force);  // about the centre of mass
    const double wetted = area + height * 2.0 * (extents.x() + extents.z());

    const double weight = density * kG * volume;
    const double size = extents.norm();
    CHECK(std::abs(r.submergedVolume - volume) <= 1e-9 * volume);
    CHECK((r.centerOfBuoyancy - buoyancyCenter).norm() <= 1e-9 * size);
    CHECK((r.buoyancyForce - force).norm() <= 1e-9 * weight);
    CHECK((r.torqueAboutCenterOfMass - torque).norm() <= 1e-9 * weight * size);
    CHECK((r.torqueAboutOrigin - torque).norm() <= 1e-9 * weight * size);
    CHECK(std::abs(r.waterplaneArea - area) <= 1e-9 * area);
    CHECK(std::abs(r.waterplaneCentroid.x() - c.center.x()) <= 1e-9 * size);
    CHECK(std::abs(r.waterplaneCentroid.z() - c.center.z()) <= 1e-9 * size);
    CHECK(std::abs(r.wettedArea - wetted) <= 1e-9 * wetted);
    CHECK(r.stiffness.allFinite());
    CHECK(std::abs(r.stiffness(0, 0) - density * kG * area) <= 1e-9 * density * kG * area);
  }
}

TEST_CASE("Exact path under waves: against the texture path's per-texel answer at many poses and phases",
          "[hydrostatics][polyhedral][waves]") {
  // The two paths approximate the surface differently: the exact path linearizes it between the
  // mesh's vertices (a second-order error in the edge: the next test measures 7.0e-5 V on a 96 x 48
  // sphere under the steep sea, falling four-fold per halving, so about 1.8e-5 V at 192 x 96),
  // the texture path takes it locally level over each texel at the true height above the texel's
  // centre and has its own resolution error at 256^2 (about 1e-5 V under flat water,
  // test_texture_hydrostatics). Both errors change sign along the waves and partly cancel over
  // the water plane. Measured over these poses (the WARN below), the largest differences:
  // volume 1.7e-5 V (sphere), 2.6e-5 V (torus), 1.8e-5 V (box); force 2.1e-5, 3.0e-5, 1.8e-5
  // rho g V; torque 4.4e-7, 2.1e-5, 2.4e-5 rho g V m; V c_B 1.1e-5, 2.7e-5, 1.2e-5 V m. The
  // bounds are about twice the largest over the three bodies and seas.
  struct Body {
    std::string name;
    Mesh mesh;
    double volumeBound, forceBound, torqueBound;
  };
  const std::vector<Body> bodies = {{"sphere", prim::uvSphere(1.0, 192, 96), 5e-5, 6e-5, 5e-5},
                                    {"torus", prim::torus(1.0, 0.4, 192, 96), 5e-5, 6e-5, 5e-5},
                                    {"box", prim::subdividedBox(Eigen::Vector3d(1.0, 0.6, 0.4), 64), 5e-5, 6e-5, 5e-5}};
  for (const Body& b : bodies) {
    const TextureHydrostatics texture = buildTexture(b.mesh, 256);
    const double volume = texture.enclosedVolume();
    for (const Sea& sea : seas()) {
      INFO(b.name << " under " << sea.name);
      const double weight = sea.waves.density() * kG * volume;
      std::mt19937 rng(21);
      double largest[4] = {0, 0, 0, 0};
      for (int i = 0; i < 16; ++i) {
        // Levels from barely touching to wholly under.
        const HydrostaticsQuery query = sweepQuery(rng, i, 0.9);
        const HydrostaticsResult e = exactAnswer(b.mesh, sea.waves, query);
        const auto t = texture.query(sea.waves, query, TexelTraversal::BruteForce);
        REQUIRE(t.ok());
        INFO("pose " << i << ": volume " << t->submergedVolume << " of " << volume);
        const std::array<double, 4> differences = differencesFrom(e, *t, volume, weight, query);
        for (int k = 0; k < 4; ++k) largest[k] = std::max(largest[k], differences[k]);
        CHECK(differences[0] <= b.volumeBound);
        CHECK(differences[1] <= b.forceBound);
        CHECK(differences[2] <= b.torqueBound);
        CHECK(differences[3] <= b.torqueBound);
        // The same frame, force model and water-plane convention as the texture path.
        CHECK(e.stiffness.allFinite());
        CHECK(std::abs(e.waterplaneArea - t->waterplaneArea) <= 2e-3 * std::max(t->waterplaneArea, 0.1));
      }
      WARN(b.name << " under " << sea.name << ", largest exact - per-texel differences: volume " << largest[0]
                  << " V, force " << largest[1] << " rho g V, torque " << largest[2] << " rho g V m, V c_B "
                  << largest[3] << " V m");
    }
  }
}

TEST_CASE("Exact path on a prepared mesh under waves: local surface models against the per-texel answer",
          "[hydrostatics][polyhedral][prepared][waves]") {
  // A prepared mesh's triangle nodes under local quadratic models of the surface
  // (PolyhedralHydrostaticsWaves.cpp), not linear between the mesh's vertices: coarse meshes see
  // the waves across their faces. Against the texture path's per-texel answer (the true surface at
  // every texel's centre; its own resolution error is about 1e-5 V at 256^2) at many poses and
  // phases. The plain exact path on the same coarse meshes is off by up to 2.8e-2 V (the 12-
  // triangle box under bench_peers' swell, against a mesh subdivided to 2 cm edges; the prepared
  // path 2.3e-5). Measured over these poses (the WARN below), the largest differences: volume
  // 4.4e-5 V, force 9.4e-5 rho g V, torque 1.03e-4 rho g V m (the Wigley hull under log_waves'
  // 0.3 m waves; 9.6e-5 while each part wholly under a covering model took its first moments
  // about its own centre, not the covering node's), V c_B 3.9e-5 V m (under the swell), water
  // plane 1.3e-3 of its area (the box).
  // The bounds are about twice those. The log's sides are slivers (3 m by 5 cm): split into n^2
  // similar pieces (at most 16^2), under the steep sea they found no model and took the surface
  // linear between their corners 3 m apart, 4.4e-2 V off; cut into strips, 4.9e-6 V.
  struct Body {
    std::string name;
    Mesh mesh;
  };
  const std::vector<Body> bodies = {{"box", prim::box(Eigen::Vector3d(1.0, 0.5, 1.0))},
                                    {"icosphere", prim::icosphere(0.5, 3)},
                                    {"torus", prim::torus(1.0, 0.4, 24, 12)},
                                    {"Wigley hull", prim::wigleyHull(4.0, 0.4, 0.25, 64, 16)},
                                    // A log of 32 sides, each two slivers 3 m by 5 cm: cut into strips
                                    // across their length, not into n^2 similar slivers.
                                    {"log", prim::cylinder(0.25, 3.0, 32)}};
  double largestOverall[4] = {0, 0, 0, 0};
  for (const Body& b : bodies) {
    const TextureHydrostatics texture = buildTexture(b.mesh, 256);
    const double volume = texture.enclosedVolume();
    const Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(b.mesh));
    REQUIRE(prepared.ok());
    for (const Sea& sea : seas()) {
      INFO(b.name << " under " << sea.name);
      const double weight = sea.waves.density() * kG * volume;
      std::mt19937 rng(23);
      double largest[4] = {0, 0, 0, 0};
      for (int i = 0; i < 12; ++i) {
        const HydrostaticsQuery query = sweepQuery(rng, i, 0.6);
        const Expected<HydrostaticsResult> e = polyhedralHydrostatics(*prepared, sea.waves, query);
        REQUIRE(e.ok());
        const auto t = texture.query(sea.waves, query, TexelTraversal::BruteForce);
        REQUIRE(t.ok());
        INFO("pose " << i << ": volume " << t->submergedVolume << " of " << volume);
        const std::array<double, 4> differences = differencesFrom(*e, *t, volume, weight, query);
        for (int k = 0; k < 4; ++k) largest[k] = std::max(largest[k], differences[k]);
        CHECK(differences[0] <= 1e-4);
        CHECK(differences[1] <= 2e-4);
        CHECK(differences[2] <= 2e-4);
        CHECK(differences[3] <= 7e-5);
        CHECK(e->stiffness.allFinite());
        CHECK(std::abs(e->waterplaneArea - t->waterplaneArea) <= 3e-3 * std::max(t->waterplaneArea, 0.1));
      }
      for (int k = 0; k < 4; ++k) largestOverall[k] = std::max(largestOverall[k], largest[k]);
      WARN(b.name << " under " << sea.name << ", largest prepared exact - per-texel differences: volume " << largest[0]
                  << " V, force " << largest[1] << " rho g V, torque " << largest[2] << " rho g V m, V c_B "
                  << largest[3] << " V m");
    }
  }
  WARN("overall largest: volume " << largestOverall[0] << ", force " << largestOverall[1] << ", torque "
                                  << largestOverall[2] << ", V c_B " << largestOverall[3]);
}

TEST_CASE("Exact path on a prepared mesh under waves far shorter than its faces: the plain path's linearization",
          "[hydrostatics][polyhedral][prepared][waves]") {
  // 0.3 m waves under a 10 m box: no split of its 10 m faces into at most 16^2 pieces gives each
  // a model within the tolerance (third derivative ~ A k^3 = 0.02 x 21^3 = 185 1/m^2: a piece
  // would need a radius under 3 cm), so each triangle takes the surface's own heights at its
  // corners, linear between them, as the plain path does: a finite answer at bounded cost, the
  // same as the plain path's where the plain path asks the surface itself (no smoothness bound).
  const GerstnerWaves chop({GerstnerWave{0.02, 0.3, Eigen::Vector2d(1.0, 0.2), 0.0, 0.5}});
  const hydrotex::test::SurfaceWithoutSmoothness plainChop(chop);
  const Mesh box = prim::box(Eigen::Vector3d(10.0, 2.0, 10.0));
  const Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(box));
  REQUIRE(prepared.ok());
  std::mt19937 rng(24);
  for (int i = 0; i < 4; ++i) {
    const HydrostaticsQuery query = sweepQuery(rng, i, 0.5);
    const Expected<HydrostaticsResult> fast = polyhedralHydrostatics(*prepared, chop, query);
    REQUIRE(fast.ok());
    const HydrostaticsResult plain = exactAnswer(box, plainChop, query);
    CHECK(std::isfinite(fast->submergedVolume));
    CHECK(fast->submergedVolume == Approx(plain.submergedVolume).epsilon(1e-9));
    CHECK((fast->buoyancyForce - plain.buoyancyForce).norm() <= 1e-9 * plain.buoyancyForce.norm() + 1e-6);
  }
}

TEST_CASE("Exact path under a height grid: against the texture path's per-texel answer",
          "[hydrostatics][polyhedral][waves][grid]") {
  // A grid of 0.25 m cells holding two crossing sines (0.15 m at 6 m, 0.05 m at 3 m), interpolated
  // bilinearly: a surface with kinks along the cell lines, which neither path models between its
  // samples (vertices, texel centres), both sampling the same bilinear heights. A 192 x 96 sphere
  // (edges of 33 mm, under a cell) at 256^2: measured at most 2.0e-5 V apart in volume, 2.0e-5
  // rho g V in force (the WARN); bounds 2.5 times those.
  HeightGrid grid(161, 161, 0.25, -20.0, -20.0, 0.0, 1025.0);
  for (int j = 0; j < 161; ++j)
    for (int i = 0; i < 161; ++i) {
      const double x = -20.0 + 0.25 * i, z = -20.0 + 0.25 * j;
      grid.heights()[std::size_t(j) * 161 + i] =
          0.15 * std::sin(2.0 * std::numbers::pi * x / 6.0) + 0.05 * std::sin(2.0 * std::numbers::pi * (0.6 * x + 0.8 * z) / 3.0);
    }
  const Mesh sphere = prim::uvSphere(1.0, 192, 96);
  const TextureHydrostatics texture = buildTexture(sphere, 256);
  const double volume = texture.enclosedVolume(), weight = 1025.0 * kG * volume;
  std::mt19937 rng(24);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double largest[2] = {0, 0};
  for (int i = 0; i < 12; ++i) {
    HydrostaticsQuery query;
    query.pose = Pose{randomRotation(rng), Eigen::Vector3d(5.0 * unit(rng), 0.9 * unit(rng), 5.0 * unit(rng))};
    query.gravity = kG;
    const HydrostaticsResult e = exactAnswer(sphere, grid, query);
    const auto t = texture.query(grid, query, TexelTraversal::BruteForce);
    REQUIRE(t.ok());
    const double volumeDifference = std::abs(e.submergedVolume - t->submergedVolume) / volume;
    const double forceDifference = (e.buoyancyForce - t->buoyancyForce).norm() / weight;
    largest[0] = std::max(largest[0], volumeDifference);
    largest[1] = std::max(largest[1], forceDifference);
    CHECK(volumeDifference <= 5e-5);
    CHECK(forceDifference <= 5e-5);
  }
  WARN("height grid, largest exact - per-texel differences: volume " << largest[0] << " V, force " << largest[1]
                                                                     << " rho g V");
}

TEST_CASE("Exact path under waves: the linearization's error falls as the square of the edge",
          "[hydrostatics][polyhedral][waves]") {
  // Against a very fine mesh (384 x 192: edges of 16 mm) as the reference, the volume's
  // difference of a 24 x 12, 48 x 24 and 96 x 48 sphere (the faceted volume's own share removed
  // by comparing fractions of each mesh's whole volume) falls about four-fold per halving of the
  // edge, a second-order error, the linearization's: measured 1.23e-3, 3.0e-4, 7.0e-5 under the
  // steep sea (ratios 4.1, 4.3). Bounds: each at most half the previous, the last 1.5e-4.
  const Sea sea = seas()[2];  // steep
  const Mesh reference = prim::uvSphere(1.0, 384, 192);
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double errors[3] = {0, 0, 0};
  const int resolutions[3] = {24, 48, 96};
  for (int i = 0; i < 6; ++i) {
    HydrostaticsQuery query;
    query.pose = Pose{randomRotation(rng), Eigen::Vector3d(3.0 * unit(rng), 0.3 * unit(rng), 3.0 * unit(rng))};
    query.time = 5.0 + 5.0 * unit(rng);
    const double fine = exactAnswer(reference, sea.waves, query).submergedVolume;
    for (int k = 0; k < 3; ++k) {
      const Mesh mesh = prim::uvSphere(1.0, resolutions[k], resolutions[k] / 2);
      const double v = exactAnswer(mesh, sea.waves, query).submergedVolume;
      // The faceted sphere's own volume loss, removed by comparing fractions of the whole.
      HydrostaticsQuery deep = query;
      deep.pose.translation.y() = -10.0;
      const double whole = exactAnswer(mesh, sea.waves, deep).submergedVolume;
      const double wholeFine = exactAnswer(reference, sea.waves, deep).submergedVolume;
      errors[k] = std::max(errors[k], std::abs(v / whole - fine / wholeFine));
    }
  }
  WARN("largest volume-fraction error against 384 x 192: " << errors[0] << ", " << errors[1] << ", " << errors[2]);
  CHECK(errors[1] <= 0.5 * errors[0]);
  CHECK(errors[2] <= 0.5 * errors[1]);
  CHECK(errors[2] <= 1.5e-4);
}

TEST_CASE("Exact path under waves: zero amplitude gives the flat path's answer", "[hydrostatics][polyhedral][waves]") {
  // A calm Gerstner sea is a plane everywhere, but not flatHeight(): it takes the wave branch
  // (pressure sums) and must give the flat branch's Archimedes answer. Both integrate the same
  // clipped polygons exactly, so they differ by rounding: 1e-12 relative to each quantity's scale
  // (measured at most 2.7e-14 of the volume in volume and force, 1.3e-15 in stiffness).
  const std::vector<std::pair<std::string, Mesh>> meshes = {{"sphere", prim::uvSphere(1.0, 32, 16)},
                                                            {"torus", prim::torus(1.0, 0.4, 32, 16)},
                                                            {"box", prim::box(Eigen::Vector3d(1.0, 0.6, 0.4))}};
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const auto& [name, mesh] : meshes) {
    for (int i = 0; i < 12; ++i) {
      INFO(name << ", pose " << i);
      const double level = 0.3 * unit(rng);
      GerstnerWave calm;
      calm.amplitude = 0.0;
      const GerstnerWaves waves({calm}, level, 1025.0);
      const FlatSurface flat(level, 1025.0);
      HydrostaticsQuery query;
      query.pose = Pose{randomRotation(rng), Eigen::Vector3d(2.0 * unit(rng), level + 0.9 * unit(rng), 2.0 * unit(rng))};
      query.centerOfMass = Eigen::Vector3d(0.1 * unit(rng), 0.1 * unit(rng), 0.1 * unit(rng));
      query.time = 3.0;
      query.mass = 100.0;
      const HydrostaticsResult w = exactAnswer(mesh, waves, query);
      const HydrostaticsResult f = exactAnswer(mesh, flat, query);
      const double volume = std::max(f.submergedVolume, 1e-3);
      const double weight = 1025.0 * kG * volume;
      CHECK(std::abs(w.submergedVolume - f.submergedVolume) <= 1e-12 * volume);
      CHECK((w.centerOfBuoyancy - f.centerOfBuoyancy).norm() <= 1e-12 * 3.0);
      CHECK((w.buoyancyForce - f.buoyancyForce).norm() <= 1e-12 * weight);
      CHECK((w.torqueAboutCenterOfMass - f.torqueAboutCenterOfMass).norm() <= 1e-12 * weight * 3.0);
      CHECK((w.torqueAboutOrigin - f.torqueAboutOrigin).norm() <= 1e-12 * weight * 3.0);
      CHECK(std::abs(w.waterplaneArea - f.waterplaneArea) <= 1e-12 * 4.0);
      // The centroid is a ratio: only where the water plane is not a round-off sliver.
      if (f.waterplaneArea > 1e-3) CHECK((w.waterplaneCentroid - f.waterplaneCentroid).norm() <= 1e-12 * 3.0);
      CHECK(std::abs(w.wettedArea - f.wettedArea) <= 1e-12 * 20.0);
      const double stiffnessScale = 1025.0 * kG * 4.0 * 3.0;  // rho g x area x arm
      CHECK((w.stiffness - f.stiffness).norm() <= 1e-12 * stiffnessScale);
    }
  }
}

TEST_CASE("Exact path under waves: a surface that answers NaN is an error naming it",
          "[hydrostatics][polyhedral][waves][errors]") {
  const Mesh box = prim::box(Eigen::Vector3d(1.0, 1.0, 1.0));
  const HoleySurface holey;
  HydrostaticsQuery query;
  // Straddling x = 0: some vertices under a NaN height.
  query.pose.translation = Eigen::Vector3d(-0.2, 0.0, 0.0);
  auto r = polyhedralHydrostatics(box, holey, query);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("surface height") != std::string::npos);
  CHECK(r.error().message.find("not finite") != std::string::npos);
  CHECK_FALSE(polyhedralHydrostaticsUnchecked(box, holey, query).ok());
  // NaN above the centre of mass.
  query.pose.translation = Eigen::Vector3d(2.0, 0.0, 0.0);
  r = polyhedralHydrostaticsUnchecked(box, holey, query);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("surface height") != std::string::npos);
  // Wholly west of x = 0: every height is finite.
  query.pose.translation = Eigen::Vector3d(-2.0, 0.0, 0.0);
  r = polyhedralHydrostatics(box, holey, query);
  REQUIRE(r.ok());
  CHECK(std::abs(r->submergedVolume - 0.5) <= 1e-12);
  // A height grid with a NaN sample is refused by its own validation, naming the sample.
  HeightGrid grid = slopedPlane(0.0, 0.0, 0.0, 1000.0);
  grid.heights()[5] = std::numeric_limits<double>::quiet_NaN();
  r = polyhedralHydrostatics(box, grid, query);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("sample 5") != std::string::npos);
  // A NaN vertex under waves (the unchecked call: the checked one refuses it up front).
  Mesh broken = box;
  broken.positions[0].x() = std::numeric_limits<double>::quiet_NaN();
  const GerstnerWaves waves({GerstnerWave{}});
  query.pose.translation = Eigen::Vector3d(0.0, 0.0, 0.0);
  r = polyhedralHydrostaticsUnchecked(broken, waves, query);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("not finite") != std::string::npos);
}

TEST_CASE("Exact path under waves: vertex heights interpolated from surface jets stay within their bound",
          "[hydrostatics][polyhedral][waves]") {
  // A Wigley hull of 2,113 vertices (bench_peers' mesh: 4 x 0.4 x 0.25 m) needs fewer jets over
  // its footprint than vertices, so its heights are interpolated (kExactWaveHeightError, 3.3e-6
  // m). Each vertex's depth then moves by at most that, and the volume under the linearized
  // surface by at most that times the water-plane area; the force by rho g times it. Against the
  // same surface asked per vertex (no smoothness offered).
  const Mesh hull = prim::wigleyHull(4.0, 0.4, 0.25, 64, 32);
  REQUIRE(hull.positions.size() > 2000);
  std::mt19937 random(19);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0, worstForce = 0.0;
  for (const Sea& sea : seas()) {
    const hydrotex::test::SurfaceWithoutSmoothness perVertex(sea.waves);
    for (int k = 0; k < 6; ++k) {
      INFO(sea.name << " pose " << k);
      HydrostaticsQuery query;
      query.time = 10.0 * unit(random);
      const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.1 * (unit(random) - 0.5), Eigen::Vector3d::UnitX()).toRotationMatrix() *
                                   rotationAboutY(6.3 * unit(random));
      const double x = 5.0 * unit(random), z = -5.0 * unit(random);
      query.pose = Pose{tilt, Eigen::Vector3d(x, sea.waves.surfaceHeight(x, z, query.time) + 0.1 * unit(random), z)};
      query.gravity = kG;
      const HydrostaticsResult interpolated = exactAnswer(hull, sea.waves, query);
      const HydrostaticsResult asked = exactAnswer(hull, perVertex, query);
      REQUIRE(asked.submergedVolume > 0.0);
      const double bound = kExactWaveHeightError * asked.waterplaneArea;
      const double error = std::abs(interpolated.submergedVolume - asked.submergedVolume);
      worst = std::max(worst, error / bound);
      CHECK(error <= bound);
      const double rhoG = sea.waves.density() * kG;
      const double forceError = (interpolated.buoyancyForce - asked.buoyancyForce).norm() / (rhoG * bound);
      worstForce = std::max(worstForce, forceError);
      CHECK(forceError <= 1.0);
    }
  }
  CHECK(worst > 0.0);  // the heights were interpolated: not the per-vertex bits
  WARN("exact path under waves, interpolated vertex heights: worst volume difference " << worst
                                                                                        << " of its bound, force " << worstForce);
}

TEST_CASE("Exact path on a prepared mesh under waves: a face that a trough leaves dry in its middle is clipped",
          "[hydrostatics][polyhedral][prepared][waves]") {
  // The top face (4 m x 4 m) of a box lies a few millimetres above the bottom of a trough of a
  // 20 m swell: the corners of its pieces (a model each, ~1 m across) lie under the surface, but a
  // strip along the trough line is dry, where the surface, curving up away from the trough, sags
  // under the straight line between corners. A piece counts as wholly under its model only when
  // its corners lie deeper than the model's curvature times e^2 / 6 (the most a quadratic sags
  // under its linear interpolant over a triangle of longest edge e); the others are clipped.
  // Reference: the plain exact path on the box subdivided to 4 cm edges (its linearization error,
  // curvature x e^2 / 8, about 1e-5 m). Measured: volume and force within 2.5e-5 (V, rho g V),
  // water plane within 0.078 m^2 (of 1.7 to 3.5: the water line grazes the nearly flat trough,
  // so the pieces' depth error of a few tenths of a millimetre moves it by centimetres). Without
  // the margin (pieces counted wholly under on their corners alone) one pose loses its whole dry
  // strip: volume 7.2e-5 V off and no water plane where there are 1.73 m^2. The bounds (4e-5,
  // 0.2 m^2) sit between the two: 1.6 and 2.6 times what the path gives, under what it gives
  // without the margin.
  const GerstnerWaves swell({GerstnerWave{0.5, 20.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5}});
  const Eigen::Vector3d extents(4.0, 1.0, 4.0);
  const Mesh box = prim::box(extents);
  const Mesh fine = prim::subdividedBox(extents, 100);
  const Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(box));
  REQUIRE(prepared.ok());
  // The trough's bottom along z = 0 at t = 0: the lowest height on a 1 cm grid over one wavelength.
  double troughX = 0.0, troughHeight = INFINITY;
  for (int i = 0; i <= 2000; ++i) {
    const double x = -10.0 + 0.01 * i;
    const double h = swell.surfaceHeight(x, 0.0, 0.0);
    if (h < troughHeight) {
      troughHeight = h;
      troughX = x;
    }
  }
  const double volume = extents.prod();
  const double weight = swell.density() * kG * volume;
  double largestVolume = 0.0, largestWaterplane = 0.0;
  for (double above : {0.001, 0.002, 0.004})
    for (double shift : {0.0, 0.13, 0.37}) {
      HydrostaticsQuery query;
      query.pose.translation = Eigen::Vector3d(troughX + shift, troughHeight + above - 0.5 * extents.y(), 0.0);
      query.gravity = kG;
      const Expected<HydrostaticsResult> e = polyhedralHydrostatics(*prepared, swell, query);
      REQUIRE(e.ok());
      const HydrostaticsResult reference = exactAnswer(fine, swell, query);
      INFO("top " << above << " m above the trough, box " << shift << " m off it: volume " << e->submergedVolume
                  << " against " << reference.submergedVolume << ", water plane " << e->waterplaneArea << " against "
                  << reference.waterplaneArea);
      const double volumeDifference = std::abs(e->submergedVolume - reference.submergedVolume) / volume;
      const double forceDifference = (e->buoyancyForce - reference.buoyancyForce).norm() / weight;
      const double waterplaneDifference = std::abs(e->waterplaneArea - reference.waterplaneArea);
      largestVolume = std::max(largestVolume, volumeDifference);
      largestWaterplane = std::max(largestWaterplane, waterplaneDifference);
      CHECK(volumeDifference <= 4e-5);
      CHECK(forceDifference <= 4e-5);
      CHECK(waterplaneDifference <= 0.2);
    }
  WARN("face under a trough, largest prepared exact - subdivided plain differences: volume " << largestVolume
                                                                                           << " V, water plane "
                                                                                           << largestWaterplane << " m^2");
}

TEST_CASE("Triangle quadrature: the six-point rule integrates every polynomial of degree 4 exactly",
          "[hydrostatics][polyhedral][waves]") {
  // The mean of x^a y^b over the triangle (0, 0), (1, 0), (0, 1) is 2 a! b! / (a + b + 2)!. The
  // rule's tabulated 15 digits give 1e-15; a monomial of degree 5 is missed by far more, so the
  // rule is of degree 4, no more (the sampled wave part's bound takes degree 4, not 5).
  const auto factorial = [](int n) {
    double f = 1.0;
    for (int k = 2; k <= n; ++k) f *= k;
    return f;
  };
  double weights = 0.0;
  for (const detail::TriangleQuadraturePoint& point : detail::kTriangleRuleDegree4) {
    CHECK(point.weight > 0.0);
    CHECK(point.a + point.b + point.c == Approx(1.0).margin(1e-15));
    weights += point.weight;
  }
  CHECK(weights == Approx(1.0).margin(1e-14));
  double worstDegree5 = 0.0;
  for (int degree = 0; degree <= 5; ++degree)
    for (int a = 0; a <= degree; ++a) {
      const int b = degree - a;
      double rule = 0.0;
      for (const detail::TriangleQuadraturePoint& point : detail::kTriangleRuleDegree4)
        rule += point.weight * std::pow(point.b, a) * std::pow(point.c, b);
      const double exact = 2.0 * factorial(a) * factorial(b) / factorial(a + b + 2);
      INFO("x^" << a << " y^" << b << ": rule " << rule << ", exact " << exact);
      if (degree <= 4) CHECK(std::abs(rule - exact) <= 1e-14);
      else worstDegree5 = std::max(worstDegree5, std::abs(rule - exact) / exact);
    }
  CHECK(worstDegree5 > 1e-4);
}

TEST_CASE("Exact path on a prepared mesh under waves: a box wholly under the surface is integrated from sampled heights",
          "[hydrostatics][polyhedral][prepared][waves]") {
  // The 1 x 0.5 x 1 m box wholly under bench_peers' three waves: no face fits one local model (a
  // piece of one would need a radius under 0.165 m), but each of its 12 triangles lies wholly
  // under the surface, so its wave part comes from the jets' interpolant sampled by the six-point
  // rule over similar pieces (PolyhedralHydrostaticsWaves.cpp, addSampled): no piece takes a
  // model, none is clipped. Reference: the plain exact path on the box subdivided to 1 cm edges
  // (its linearization error, curvature x e^2 / 8, about 3e-6 m). The bound on a triangle's mean
  // height is 1e-3 m (kExactSurfaceModelTolerance), so on the box's 4 m^2 the force may be off by
  // 4e-3 m^3 rho g, 8e-3 rho g V: a worst case the waves never reach. Measured (the WARN): volume
  // 9.8e-8 V (the wave part's sums over the closed surface cancel to that), force 6.3e-6 rho g V
  // (the reference's own error is of that order), torque 2.7e-7 rho g V m. The rule over whole
  // triangles (no split) gave 5.1e-7 V and 2.7e-6 rho g V m: the bounds, 3e-7 and 1e-6, sit
  // between.
  const GerstnerWaves sea({GerstnerWave{0.10, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                           GerstnerWave{0.05, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5},
                           GerstnerWave{0.02, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3}});
  const Eigen::Vector3d extents(1.0, 0.5, 1.0);
  const Mesh box = prim::box(extents);
  const Mesh fine = prim::subdividedBox(extents, 100);
  const Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(box));
  REQUIRE(prepared.ok());
  const double volume = extents.prod();
  const double weight = sea.density() * kG * volume;
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double largest[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < 6; ++i) {
    HydrostaticsQuery query;
    // The top 0.3 m or more under the mean level, the troughs at most 0.17 m under it.
    query.pose = Pose{Eigen::AngleAxisd(0.3 * unit(rng), Eigen::Vector3d(unit(rng), 1.0, unit(rng)).normalized())
                          .toRotationMatrix(),
                      Eigen::Vector3d(5.0 * unit(rng), -0.9 + 0.1 * unit(rng), 5.0 * unit(rng))};
    query.time = 3.0 * i;
    query.gravity = kG;
    ExactWaveWork work;
    const Expected<HydrostaticsResult> e = polyhedralHydrostatics(*prepared, sea, query, &work);
    REQUIRE(e.ok());
    const HydrostaticsResult reference = exactAnswer(fine, sea, query);
    INFO("pose " << i << ": sampled pieces " << work.sampledPieces << ", models " << work.models << ", pieces "
                 << work.pieces << ", clipped " << work.clippedTriangles);
    CHECK(work.sampledPieces >= 12);
    CHECK(work.pieces == 0);
    CHECK(work.clippedTriangles == 0);
    CHECK(work.models <= 13);  // the walk's wide one over the root, and one per triangle to find it wholly under
    const double differences[3] = {std::abs(e->submergedVolume - reference.submergedVolume) / volume,
                                   (e->buoyancyForce - reference.buoyancyForce).norm() / weight,
                                   (e->torqueAboutCenterOfMass - reference.torqueAboutCenterOfMass).norm() / weight};
    for (int k = 0; k < 3; ++k) largest[k] = std::max(largest[k], differences[k]);
    CHECK(differences[0] <= 3e-7);
    CHECK(differences[1] <= 2e-5);
    CHECK(differences[2] <= 1e-6);
  }
  WARN("box wholly under the waves, largest sampled - subdivided plain differences: volume " << largest[0]
                                                                                         << " V, force " << largest[1]
                                                                                         << " rho g V, torque "
                                                                                         << largest[2] << " rho g V m");
}
