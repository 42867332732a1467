// SPDX-License-Identifier: Zlib
// The texture path's tile hierarchy under waves (issue 19 item 1): Gerstner jets and smoothness
// bounds against finite differences, the jet grid's interpolation and local models within their
// error bounds, the hierarchy's answer against the per-texel answer at many poses and phases, the
// flat-surface limit against the flat and exact paths, and the surfaces that keep the per-texel
// path (height grids, media, waves too steep for a bound).
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "hydrostatics/HydrostaticSums.hpp"  // private to core (core/src): the moment corrections
#include "hydrostatics/SurfaceJetGrid.hpp"  // private to core (core/src), for its error bounds
#include "hydrostatics/WaveTexelLanes.hpp"  // private to core (core/src): the texels in SIMD lanes
#include "RandomRotation.hpp"
#include "TestSurfaces.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

using hydrotex::testing::randomRotation;

using hydrotex::test::Sea;
std::vector<Sea> seas() { return hydrotex::test::gerstnerSeas(); }

/// sum over the waves of A k (the height's Lipschitz bound at rest, 1).
double amplitudeSlope(const GerstnerWaves& waves) {
  double sum = 0.0;
  for (const GerstnerWaves::Component& c : waves.components()) sum += c.amplitude * c.waveNumber;
  return sum;
}

TextureHydrostatics buildTexture(const Mesh& mesh, int resolution, const TextureHydrostaticsSettings& settings = {}) {
  return hydrotex::test::textureHydrostaticsOf(mesh, resolution, settings);
}

HydrostaticsResult run(const TextureHydrostatics& body, const LiquidSurface& surface, const HydrostaticsQuery& query,
                       TexelTraversal traversal = TexelTraversal::Hierarchy) {
  const auto r = body.query(surface, query, traversal);
  REQUIRE(r.ok());
  return *r;
}

}  // namespace

TEST_CASE("Gerstner jets: slopes and curvatures are the height's derivatives", "[surfaces][waves][jets]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const Sea& sea : seas()) {
    INFO(sea.name);
    const std::optional<SurfaceSmoothness> smooth = sea.waves.smoothness(0.0);
    REQUIRE(smooth);
    const double s1 = amplitudeSlope(sea.waves);
    for (int i = 0; i < 50; ++i) {
      const double x = 20.0 * unit(rng), z = 20.0 * unit(rng), time = 5.0 + 5.0 * unit(rng);
      const std::optional<SurfaceJet> jet = sea.waves.heightJet(x, z, time);
      REQUIRE(jet);
      auto height = [&](double dx, double dz) { return sea.waves.surfaceHeight(x + dx, z + dz, time); };
      // Both searches stop within their horizontal tolerance (1e-7 m for jets, 1e-9 m), and the
      // height moves by at most sum A k per metre: twice that, for both ends.
      CHECK(std::abs(jet->height - height(0, 0)) <= 2.0 * s1 * GerstnerWaves::kJetHorizontalTolerance);
      // Central differences: truncation h^2/6 M3 (slopes), h^2/12 M4 (curvatures), plus the
      // heights' search error sum A k 1e-9 m divided by h (slopes) or h^2 (curvatures), times 4.
      const double h1 = 1e-3, h2 = 1e-2;
      const double noise = s1 * GerstnerWaves::kHorizontalTolerance;
      const double slopeTolerance = h1 * h1 / 6.0 * smooth->third + 4.0 * noise / h1;
      const double curvatureTolerance = h2 * h2 / 12.0 * smooth->fourth + 4.0 * noise / (h2 * h2);
      CHECK(std::abs(jet->slopeX - (height(h1, 0) - height(-h1, 0)) / (2 * h1)) <= slopeTolerance);
      CHECK(std::abs(jet->slopeZ - (height(0, h1) - height(0, -h1)) / (2 * h1)) <= slopeTolerance);
      const double center = height(0, 0);
      CHECK(std::abs(jet->curvatureXX - (height(h2, 0) - 2 * center + height(-h2, 0)) / (h2 * h2)) <= curvatureTolerance);
      CHECK(std::abs(jet->curvatureZZ - (height(0, h2) - 2 * center + height(0, -h2)) / (h2 * h2)) <= curvatureTolerance);
      const double mixed = (height(h2, h2) - height(h2, -h2) - height(-h2, h2) + height(-h2, -h2)) / (4 * h2 * h2);
      // The mixed difference's truncation is h^2/6 M4 (two third-order terms).
      CHECK(std::abs(jet->curvatureXZ - mixed) <= h2 * h2 / 6.0 * smooth->fourth + 4.0 * noise / (h2 * h2));
    }
  }
}

TEST_CASE("Gerstner smoothness bounds the third and fourth derivatives", "[surfaces][waves][jets]") {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const Sea& sea : seas()) {
    INFO(sea.name);
    const SurfaceSmoothness smooth = *sea.waves.smoothness(0.0);
    const double noise = amplitudeSlope(sea.waves) * GerstnerWaves::kHorizontalTolerance;
    double largestThird = 0.0, largestFourth = 0.0;
    for (int i = 0; i < 400; ++i) {
      const double x = 20.0 * unit(rng), z = 20.0 * unit(rng), time = 5.0 + 5.0 * unit(rng);
      const double angle = 3.14159265358979 * unit(rng);
      const double ex = std::cos(angle), ez = std::sin(angle);
      const double h = 0.02;
      double f[5];
      for (int k = -2; k <= 2; ++k) f[k + 2] = sea.waves.surfaceHeight(x + k * h * ex, z + k * h * ez, time);
      const double third = (f[4] - 2 * f[3] + 2 * f[1] - f[0]) / (2 * h * h * h);
      const double fourth = (f[4] - 4 * f[3] + 6 * f[2] - 4 * f[1] + f[0]) / (h * h * h * h);
      // A difference quotient is a derivative at some point of the stencil (up to the heights'
      // search error, 16 noise / h^n at most): within the bound where the bound holds.
      CHECK(std::abs(third) <= smooth.third + 6.0 * noise / (h * h * h));
      CHECK(std::abs(fourth) <= smooth.fourth + 16.0 * noise / (h * h * h * h));
      largestThird = std::max(largestThird, std::abs(third));
      largestFourth = std::max(largestFourth, std::abs(fourth));
    }
    // Not vacuous: the largest sampled derivatives reach a good part of the bounds (measured 0.4
    // to 0.7 of them for the third, 0.1 to 0.5 for the fourth).
    CHECK(largestThird >= 0.1 * smooth.third);
    CHECK(largestFourth >= 0.02 * smooth.fourth);
  }
  // Crests that may loop (sum Q k A >= 1) have no bound: the texture path then goes per texel.
  GerstnerWave breaking;
  breaking.amplitude = 2.0;
  breaking.wavelength = 10.0;
  breaking.steepness = 1.0;
  CHECK_FALSE(GerstnerWaves({breaking}).smoothness(0.0).has_value());
  CHECK_FALSE(FlatSurface(0.0).heightJet(0, 0, 0).has_value());
}

TEST_CASE("Jet grid: interpolation and local models stay within their error bounds", "[hydrostatics][waves][jets]") {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const Sea& sea : seas()) {
    INFO(sea.name);
    const double time = 3.7;
    const SurfaceSmoothness smooth = *sea.waves.smoothness(time);
    for (double spacing : {0.1, 0.3, 0.6}) {
      INFO("spacing " << spacing);
      // A grid about a far origin, as the texture path lays it about a body 400 m out.
      const double originX = 400.0, originZ = -250.0;
      detail::SurfaceJetGrid grid(sea.waves, time, originX, originZ, -2.0, 2.0, -1.5, 1.5, spacing);
      const detail::HermiteError bound = detail::hermiteError(grid.spacing(), smooth.fourth);
      for (int i = 0; i < 300; ++i) {
        const double x = 2.0 * unit(rng), z = 1.5 * unit(rng);
        SurfaceJet interpolated;
        REQUIRE(grid.interpolate(x, z, interpolated));
        const SurfaceJet exact = *sea.waves.heightJet(originX + x, originZ + z, time);
        CHECK(std::abs(interpolated.height - exact.height) <= bound.height);
        CHECK(std::abs(interpolated.slopeX - exact.slopeX) <= bound.slope);
        CHECK(std::abs(interpolated.slopeZ - exact.slopeZ) <= bound.slope);
        CHECK(std::abs(interpolated.curvatureXX - exact.curvatureXX) <= bound.curvature);
        CHECK(std::abs(interpolated.curvatureXZ - exact.curvatureXZ) <= bound.curvature);
        CHECK(std::abs(interpolated.curvatureZZ - exact.curvatureZZ) <= bound.curvature);
        // The local model about (x, z) over a disc of radius rho (TextureHydrostaticsWaves.cpp).
        for (double rho : {0.05, 0.2}) {
          const double angle = 3.14159265358979 * unit(rng), reach = rho * std::abs(unit(rng));
          const double ux = reach * std::cos(angle), uz = reach * std::sin(angle);
          const double model = interpolated.height + interpolated.slopeX * ux + interpolated.slopeZ * uz +
                               0.5 * (interpolated.curvatureXX * ux * ux + 2 * interpolated.curvatureXZ * ux * uz +
                                      interpolated.curvatureZZ * uz * uz);
          const double modelBound = smooth.third * rho * rho * rho / 6.0 + bound.height + bound.slope * rho +
                                    0.5 * bound.curvature * rho * rho;
          CHECK(std::abs(model - sea.waves.surfaceHeight(originX + x + ux, originZ + z + uz, time)) <= modelBound);
        }
      }
    }
  }
}

TEST_CASE("Jet grid: the curvature bound holds over the cells of a box and is not far above the curvature there", "[hydrostatics][waves][jets]") {
  // SurfaceJetGrid::curvatureBound bounds the interpolant's Hessian (Frobenius norm) over the
  // cells meeting a box by its polynomials' coefficients: no interpolated curvature in the box may
  // exceed it (to rounding), and being a sum of magnitudes it overestimates, but within a small
  // factor of the largest found by sampling (measured here: 1.05 to 1.95).
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const Sea& sea : seas()) {
    INFO(sea.name);
    const double time = 1.3;
    for (double spacing : {0.1, 0.3}) {
      INFO("spacing " << spacing);
      detail::SurfaceJetGrid grid(sea.waves, time, 40.0, -25.0, 0.0, 1.2, 0.0, 1.2, spacing);
      const double lowX = 0.2, highX = 0.9, lowZ = 0.1, highZ = 0.7;
      const double bound = grid.curvatureBound(lowX, highX, lowZ, highZ);
      REQUIRE(std::isfinite(bound));
      double largest = 0.0;
      for (int i = 0; i < 2000; ++i) {
        const double x = lowX + (highX - lowX) * unit(rng), z = lowZ + (highZ - lowZ) * unit(rng);
        SurfaceJet jet;
        REQUIRE(grid.interpolate(x, z, jet));
        const double norm = std::sqrt(jet.curvatureXX * jet.curvatureXX + 2.0 * jet.curvatureXZ * jet.curvatureXZ +
                                      jet.curvatureZZ * jet.curvatureZZ);
        largest = std::max(largest, norm);
        CHECK(norm <= bound * (1.0 + 1e-12));
      }
      CHECK(bound <= 4.0 * largest);
    }
  }
  // A box that is not finite has no bound.
  const Sea sea = seas().front();
  detail::SurfaceJetGrid grid(sea.waves, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.2);
  CHECK(std::isinf(grid.curvatureBound(NAN, 1.0, 0.0, 1.0)));
}

TEST_CASE("Jet grid: a cell's kept polynomial is that cell's Hermite patch, whichever cells share its slot, for jets and heights alike",
          "[hydrostatics][waves][jets]") {
  // The grid keeps each cell's patch in a slot chosen by the cell's index modulo a few dozen
  // (SurfaceJetGrid::patch). Every cell is visited twice, the second time after all the others:
  // with fewer slots than cells (here 64 against over a thousand), each second visit finds its
  // slot taken by another cell and must get its own cell's bicubic Hermite patch, written out
  // here from jets asked one by one (heightJet): the same polynomial, on samples that agree to
  // the searches' convergence (the grid asks its samples in batches, each search started from
  // the last): a jet's rest point is found to GerstnerWaves::kJetHorizontalTolerance (1e-7 m),
  // which moves its height by at most that times a slope under 1, hence the bound 1e-7 m
  // (measured: 1.1e-9 m). A neighbouring cell's patch at the same place within it was 3e-6 m
  // off at the least, over these cells.
  const Sea sea = seas().front();
  const double time = 3.7, originX = 400.0, originZ = -250.0, lowX = -2.0, lowZ = -1.5;
  detail::SurfaceJetGrid grid(sea.waves, time, originX, originZ, lowX, 2.0, lowZ, 1.5, 0.1);
  const double s = grid.spacing();
  const auto hermite = [&](double x, double z) {
    const int i = int(std::floor((x - lowX) / s)), j = int(std::floor((z - lowZ) / s));
    const double t = (x - lowX) / s - i, w = (z - lowZ) / s - j;
    const auto basis = [](double u, double (&b)[4]) {  // value 0, slope 0, value 1, slope 1
      b[0] = 2 * u * u * u - 3 * u * u + 1;
      b[1] = u * u * u - 2 * u * u + u;
      b[2] = -2 * u * u * u + 3 * u * u;
      b[3] = u * u * u - u * u;
    };
    double bt[4], bw[4];
    basis(t, bt);
    basis(w, bw);
    double height = 0.0;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const SurfaceJet n = *sea.waves.heightJet(originX + lowX + (i + a) * s, originZ + lowZ + (j + b) * s, time);
        height += bt[2 * a] * (bw[2 * b] * n.height + bw[2 * b + 1] * s * n.slopeZ) +
                  bt[2 * a + 1] * s * (bw[2 * b] * n.slopeX + bw[2 * b + 1] * s * n.curvatureXZ);
      }
    return height;
  };
  // Every cell of the grid, twice over, a point at a different place in each visit.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> inCell(0.05, 0.95);
  const int cellsX = int(4.0 / s), cellsZ = int(3.0 / s);
  double worst = 0.0;
  int heightMismatches = 0;
  for (int pass = 0; pass < 2; ++pass)
    for (int j = 0; j < cellsZ; ++j)
      for (int i = 0; i < cellsX; ++i) {
        const double x = lowX + (i + inCell(rng)) * s, z = lowZ + (j + inCell(rng)) * s;
        SurfaceJet jet;
        REQUIRE(grid.interpolate(x, z, jet));
        worst = std::max(worst, std::abs(jet.height - hermite(x, z)));
        // height() (drag's heights, the texture path's texels without moments) reads the same
        // kept polynomial: the same number, not merely a close one.
        double height = NAN;
        REQUIRE(grid.height(x, z, height));
        if (height != jet.height) ++heightMismatches;
      }
  INFO(cellsX * cellsZ << " cells");
  CHECK(cellsX * cellsZ > 1000);
  CHECK(worst <= 1e-7);
  CHECK(heightMismatches == 0);
}

namespace {

/// A texel's moment correction as the law states it in the world frame (HydrostaticSums.hpp,
/// MomentCorrectionSums), with dm = R dM R^T: each sum Sum g(x') A_k gains w grad g . dm(:, k),
/// with grad D = (slopeX, -1, slopeZ) and grad (Q/2 - h' D) = y' e_y - h' grad h'. The test's
/// reference, written from the statement and not from the body-frame sums.
void addWorldFrameCorrection(detail::WettedSums& sums, double x, double y, double z, const Eigen::Matrix3d& dm,
                             double w, double depth, double height, double slopeX, double slopeZ) {
  const Eigen::Vector3d along = slopeX * dm.row(0) - dm.row(1) + slopeZ * dm.row(2);  // grad D . dm(:, k)
  const Eigen::Vector3d position(x, y, z);
  Eigen::Matrix3d moment;  // grad (D x'_i) . dm(:, k) = D dm(i, k) + x'_i along_k
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) moment(i, k) = depth * dm(i, k) + position[i] * along[k];
  for (int k = 0; k < 3; ++k) sums.sumDA[k] += w * along[k];
  const Eigen::Vector3d torque(moment(1, 2) - moment(2, 1), moment(2, 0) - moment(0, 2), moment(0, 1) - moment(1, 0));
  for (int k = 0; k < 3; ++k) sums.sumDxA[k] += w * torque[k];
  sums.sumDXAy += w * moment(0, 1);
  sums.sumDZAy += w * moment(2, 1);
  sums.sumYB += w * (y * dm(1, 1) - height * (slopeX * dm(0, 1) + slopeZ * dm(2, 1)));
  sums.sumXAy += w * dm(0, 1);
  sums.sumZAy += w * dm(2, 1);
  sums.sumXXAy += w * 2.0 * x * dm(0, 1);
  sums.sumXZAy += w * (x * dm(2, 1) + z * dm(0, 1));
  sums.sumZZAy += w * 2.0 * z * dm(2, 1);
}

}  // namespace

TEST_CASE("Moment corrections summed in the body frame equal the law texel by texel in the world frame",
          "[hydrostatics][texture][waves]") {
  // MomentCorrectionSums rotates the sums once instead of each texel's dm = R dM R^T: the terms
  // are linear in dM, so the two agree to rounding for any R (here rotations perturbed by 1e-7,
  // as the engine's are orthogonal only to about that). Tolerance: 1e-12 of the sums' scale
  // (moments ~1e-3 m^3, positions ~1 m, 8 texels: sums ~1e-2).
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix3d r = randomRotation(rng);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r(i, j) += 1e-7 * unit(rng);
    detail::MomentCorrectionSums bodyFrame;
    detail::WettedSums perTexel;
    for (int texel = 0; texel < 8; ++texel) {
      float moment[3][3];
      Eigen::Matrix3d m;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m(i, j) = moment[i][j] = float(1e-3 * unit(rng));
      const double x = unit(rng), y = unit(rng), z = unit(rng), height = 0.3 * unit(rng), weight = 0.5 + 0.5 * unit(rng);
      const double slopeX = 0.3 * unit(rng), slopeZ = 0.3 * unit(rng), depth = height - y;
      bodyFrame.add(x, y, z, moment, weight, depth, height, slopeX, slopeZ, r);
      addWorldFrameCorrection(perTexel, x, y, z, r * m * r.transpose(), weight, depth, height, slopeX, slopeZ);
    }
    detail::WettedSums rotatedOnce;
    bodyFrame.addTo(rotatedOnce, r);
    const double tolerance = 1e-14;  // 1e-12 of the sums' scale ~1e-2
    for (int k = 0; k < 3; ++k) {
      CHECK(rotatedOnce.sumDA[k] == Approx(perTexel.sumDA[k]).margin(tolerance));
      CHECK(rotatedOnce.sumDxA[k] == Approx(perTexel.sumDxA[k]).margin(tolerance));
    }
    CHECK(rotatedOnce.sumDXAy == Approx(perTexel.sumDXAy).margin(tolerance));
    CHECK(rotatedOnce.sumDZAy == Approx(perTexel.sumDZAy).margin(tolerance));
    CHECK(rotatedOnce.sumYB == Approx(perTexel.sumYB).margin(tolerance));
    CHECK(rotatedOnce.sumXAy == Approx(perTexel.sumXAy).margin(tolerance));
    CHECK(rotatedOnce.sumZAy == Approx(perTexel.sumZAy).margin(tolerance));
    CHECK(rotatedOnce.sumXXAy == Approx(perTexel.sumXXAy).margin(tolerance));
    CHECK(rotatedOnce.sumXZAy == Approx(perTexel.sumXZAy).margin(tolerance));
    CHECK(rotatedOnce.sumZZAy == Approx(perTexel.sumZZAy).margin(tolerance));
  }
}

TEST_CASE("Waves: the hierarchy's answer against the per-texel answer at many poses and phases",
          "[hydrostatics][texture][waves][hierarchy]") {
  // Bodies at 256^2 (the size): the bench's sphere, a torus (non-convex), a box (flat
  // faces, sharp edges, a small volume for its water-plane area).
  const std::vector<std::pair<std::string, Mesh>> meshes = {{"sphere", prim::uvSphere(1.0, 96, 48)},
                                                            {"torus", prim::torus(1.0, 0.4, 64, 32)},
                                                            {"box", prim::box(Eigen::Vector3d(1.0, 0.6, 0.4))}};
  for (const auto& [meshName, mesh] : meshes) {
    const TextureHydrostatics body = buildTexture(mesh, 256);
    const double volume = body.enclosedVolume();
    // The bound: the submerged volume within 1e-5 of the body's volume of the per-texel
    // answer; measured at most 6.5e-6 on the sphere and 3.3e-6 on the torus over these poses. The
    // box is held to 3e-5 (measured 1.45e-5): its flat faces under the swell's 2.3 m wave add up the
    // interpolation's error (s^4 f^(4) / 720 on average, one sign over a face) where a curved
    // hull averages it out, and its volume is small for its water-plane area.
    const double volumeBound = meshName == "box" ? 3e-5 : 1e-5;
    for (const Sea& sea : seas()) {
      INFO(meshName << " under " << sea.name);
      const double weight = sea.waves.density() * 9.81 * volume;  // N, rho g V
      std::mt19937 rng(11);
      std::uniform_real_distribution<double> unit(-1.0, 1.0);
      double largest[6] = {0, 0, 0, 0, 0, 0};
      for (int i = 0; i < 24; ++i) {
        // Half near the origin at t in [0, 10] s, half 400 m out at t ~ 1000 s (phases of
        // thousands of radians); levels from barely touching to wholly under.
        const bool far = i % 2 == 1;
        HydrostaticsQuery query;
        query.pose = Pose{randomRotation(rng), Eigen::Vector3d(3.0 * unit(rng) + (far ? 400.0 : 0.0), 0.9 * unit(rng),
                                                                3.0 * unit(rng) - (far ? 250.0 : 0.0))};
        query.time = far ? 1000.0 + unit(rng) : 5.0 + 5.0 * unit(rng);
        const HydrostaticsResult h = run(body, sea.waves, query);
        const HydrostaticsResult t = run(body, sea.waves, query, TexelTraversal::BruteForce);
        INFO("pose " << i << ": volume " << t.submergedVolume << " of " << volume);
        const double differences[6] = {
            std::abs(h.submergedVolume - t.submergedVolume) / volume,
            (h.buoyancyForce - t.buoyancyForce).norm() / weight,
            (h.torqueAboutCenterOfMass - t.torqueAboutCenterOfMass).norm() / weight,  // m
            (h.submergedVolume * (h.centerOfBuoyancy - query.pose.translation) -
             t.submergedVolume * (t.centerOfBuoyancy - query.pose.translation)).norm() / volume,  // m
            std::abs(h.waterplaneArea - t.waterplaneArea),                                     // m^2
            std::abs(h.wettedArea - t.wettedArea) / std::max(t.wettedArea, 1e-2)};
        for (int k = 0; k < 6; ++k) largest[k] = std::max(largest[k], differences[k]);
        CHECK(differences[0] <= volumeBound);
        // The same depths give the force and torque (the torque's quadratic part taken at each
        // model's centre), and the centre of buoyancy's moment V (c_B - t): measured at most
        // 2.4e-5 rho g V, 7.4e-6 rho g V m and 4.4e-6 V m; bounds about 3 times those.
        CHECK(differences[1] <= 8e-5);
        CHECK(differences[2] <= 3e-5);
        CHECK(differences[3] <= 1.5e-5);
        // Water-plane and wetted areas come from the waterline texels, whose heights the models
        // give within their bounds: measured 4.4e-5 m^2 and 5.1e-4 relative (of at least 0.01 m^2,
        // the box's edges under the steep sea).
        CHECK(differences[4] <= 1.5e-4);
        CHECK(differences[5] <= 1e-3);
      }
      WARN(meshName << " under " << sea.name << ", largest differences: volume " << largest[0] << " V, force "
                    << largest[1] << " rho g V, torque " << largest[2] << " rho g V m, V c_B " << largest[3]
                    << " V m, water plane " << largest[4] << " m^2, wetted " << largest[5]);
    }
  }
}

TEST_CASE("Waves: a coarse bake's tiles no local model covers take the samples' interpolated heights",
          "[hydrostatics][texture][waves][hierarchy]") {
  // At 64^2 a tile spans ~10 cm, where a quadratic model's Taylor bound (M3 rho^3 / 6) passes the
  // tolerance under the seas' short waves: those tiles are summed texel by texel, with heights from
  // the jet grid's interpolant (its bound a thirtieth of the tolerance) instead of a Newton search
  // a texel. Against the per-texel answer (the surface's own heights) at many poses, as at 256^2.
  const std::vector<std::pair<std::string, Mesh>> meshes = {{"sphere", prim::uvSphere(1.0, 48, 24)},
                                                            {"box", prim::box(Eigen::Vector3d(1.0, 0.6, 0.4))}};
  for (const auto& [meshName, mesh] : meshes) {
    const TextureHydrostatics body = buildTexture(mesh, 64);
    const double volume = body.enclosedVolume();
    for (const Sea& sea : seas()) {
      INFO(meshName << " under " << sea.name);
      const double weight = sea.waves.density() * 9.81 * volume;
      std::mt19937 rng(5);
      std::uniform_real_distribution<double> unit(-1.0, 1.0);
      double largest[3] = {0, 0, 0};
      for (int i = 0; i < 16; ++i) {
        HydrostaticsQuery query;
        query.pose = Pose{randomRotation(rng), Eigen::Vector3d(3.0 * unit(rng), 0.9 * unit(rng), 3.0 * unit(rng))};
        query.time = 5.0 + 5.0 * unit(rng);
        const HydrostaticsResult h = run(body, sea.waves, query);
        const HydrostaticsResult t = run(body, sea.waves, query, TexelTraversal::BruteForce);
        const double differences[3] = {std::abs(h.submergedVolume - t.submergedVolume) / volume,
                                       (h.buoyancyForce - t.buoyancyForce).norm() / weight,
                                       (h.torqueAboutCenterOfMass - t.torqueAboutCenterOfMass).norm() / weight};
        for (int k = 0; k < 3; ++k) largest[k] = std::max(largest[k], differences[k]);
        // The 256^2 case's bounds (the volume's 3e-5 for the box, 1e-5 for the rest), but the
        // torque's: 5e-5, the box under log_waves reaching 3.4e-5 rho g V m both with these
        // heights and with the surface's own (its coarse tiles' models, not the interpolation).
        // Measured: volume at most 2.1e-5 (box) and 3.3e-6 (sphere), force 2.7e-5.
        CHECK(differences[0] <= (meshName == "box" ? 3e-5 : 1e-5));
        CHECK(differences[1] <= 8e-5);
        CHECK(differences[2] <= 5e-5);
      }
      WARN(meshName << " at 64^2 under " << sea.name << ", largest differences: volume " << largest[0] << " V, force "
                    << largest[1] << " rho g V, torque " << largest[2] << " rho g V m");
    }
  }
}

TEST_CASE("Waves: in the limit of a flat surface the hierarchy gives the flat and exact answers",
          "[hydrostatics][texture][waves][hierarchy]") {
  const Mesh mesh = prim::uvSphere(1.0, 48, 24);
  const TextureHydrostatics body = buildTexture(mesh, 128);
  std::mt19937 rng(12);
  for (int i = 0; i < 10; ++i) {
    HydrostaticsQuery query;
    query.pose = Pose{randomRotation(rng), Eigen::Vector3d(0.3, 0.1 * i - 0.5, -0.2)};
    const double level = 0.1;
    const HydrostaticsResult flat = run(body, FlatSurface(level), query);
    const auto exact = polyhedralHydrostatics(mesh, FlatSurface(level), query);
    REQUIRE(exact.ok());
    for (double amplitude : {0.0, 1e-7, 1e-5}) {
      INFO("pose " << i << ", amplitude " << amplitude);
      GerstnerWave calm;
      calm.amplitude = amplitude;
      const HydrostaticsResult waves = run(body, GerstnerWaves({calm}, level), query);
      // The surface lies within the amplitude of the plane: the volume moves by at most the
      // amplitude times the water-plane area (pi here) ...
      CHECK(std::abs(waves.submergedVolume - flat.submergedVolume) <= amplitude * 3.2 + 1e-12 * body.enclosedVolume());
      CHECK((waves.centerOfBuoyancy - flat.centerOfBuoyancy).norm() <= 10.0 * amplitude + 1e-9);
      // ... and the pressure sums are the per-texel path's: to round-off for a calm sea (flat for
      // every model: zero bound, zero slope); else within the models' error, which for a 20 m
      // wave is under a hundredth of the amplitude (A (k rho)^3 / 6, rho < 1 m), over the
      // body's area (4 pi m^2).
      const HydrostaticsResult perTexel = run(body, GerstnerWaves({calm}, level), query, TexelTraversal::BruteForce);
      const double modelShare = 1000 * 9.81 * 4 * 3.1416 * 1e-2 * amplitude;
      CHECK((waves.buoyancyForce - perTexel.buoyancyForce).norm() <=
            1e-9 * perTexel.buoyancyForce.norm() + 1e-9 + modelShare);
      CHECK((waves.torqueAboutCenterOfMass - perTexel.torqueAboutCenterOfMass).norm() <=
            1e-9 * perTexel.buoyancyForce.norm() + 1e-9 + modelShare);
      // Against the exact path: the texture path's own accuracy at 128^2 (test_texture_hydrostatics,
      // 2e-4 of the body's volume), plus the amplitude's share.
      CHECK(std::abs(waves.submergedVolume - exact->submergedVolume) <=
            2e-4 * body.enclosedVolume() + amplitude * 3.2);
    }
  }
}

TEST_CASE("Waves: height grids, media and waves without bounds keep the per-texel answer",
          "[hydrostatics][texture][waves][surfaces]") {
  const Mesh mesh = prim::uvSphere(0.5, 32, 16);
  const TextureHydrostatics body = buildTexture(mesh, 128);
  std::mt19937 rng(13);
  HeightGrid grid(21, 21, 0.1, -1.0, -1.0, 0.0);
  for (int j = 0; j < grid.countZ(); ++j)
    for (int i = 0; i < grid.countX(); ++i)
      grid.heights()[std::size_t(j * grid.countX() + i)] = 0.05 * std::sin(1.3 * i) * std::cos(0.7 * j);
  GerstnerWave breaking;  // sum Q k A = 1.26: no smoothness bound
  breaking.amplitude = 2.0;
  breaking.wavelength = 10.0;
  breaking.steepness = 1.0;
  const GerstnerWaves loops({breaking});
  const UniformMedium air(1.2, 8400.0);
  for (int i = 0; i < 5; ++i) {
    HydrostaticsQuery query;
    query.pose = Pose{randomRotation(rng), Eigen::Vector3d(0.1 * i, 0.05 * i - 0.1, -0.1 * i)};
    for (const LiquidSurface* surface : {static_cast<const LiquidSurface*>(&grid), static_cast<const LiquidSurface*>(&loops),
                                         static_cast<const LiquidSurface*>(&air)}) {
      const HydrostaticsResult h = run(body, *surface, query);
      const HydrostaticsResult t = run(body, *surface, query, TexelTraversal::BruteForce);
      // The very same per-texel sums: equal to the last bit.
      CHECK(h.submergedVolume == t.submergedVolume);
      CHECK(h.buoyancyForce == t.buoyancyForce);
      CHECK(h.torqueAboutCenterOfMass == t.torqueAboutCenterOfMass);
    }
  }
}

TEST_CASE("Waves: the hierarchy's settings are checked", "[hydrostatics][texture][waves][errors]") {
  const Mesh mesh = prim::box({1, 1, 1});
  const auto bake = bakeSurface(mesh, mesh.uv, BakeSettings{});
  REQUIRE(bake.ok());
  const SurfaceTextures textures = evaluateSurface(*bake, mesh, mesh.uv);
  TextureHydrostaticsSettings settings;
  settings.surfaceSampleSpacing = -0.1;
  CHECK_FALSE(TextureHydrostatics::build(*bake, textures, settings).ok());
  settings.surfaceSampleSpacing = 0.0;
  settings.surfaceModelTolerance = NAN;
  CHECK_FALSE(TextureHydrostatics::build(*bake, textures, settings).ok());
  settings.surfaceModelTolerance = 1e-3;
  CHECK(TextureHydrostatics::build(*bake, textures, settings).ok());
}

TEST_CASE("the texels under a wave's local model in SIMD lanes give the texel-by-texel sums", "[texture][waves][lanes]") {
  // Random texels about a waterline under a tilted pose and a curved model: wholly under, wholly
  // over, crossing, and edge-on ones (one edge horizontal: waterlineFractions' 1-D case), in tiles
  // of 1 to 11 texels (the last group of lanes overlaps the one before it; a tile smaller than
  // the lanes is the caller's). The reference is the scalar code's per texel (waterlineFractions, addElement);
  // the lanes compute the same per texel, so only the order of the sums differs: 1e-12 of a
  // bound of the terms' sizes. The SSE2 lanes (this test's instantiation) and the AVX2 ones where present.
  using Texel = TextureHydrostatics::Texel;
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 0.5, 1.0).normalized())).toRotationMatrix();
  const Eigen::Vector3d offset(0.1, -0.05, 0.2);
  const double centerX = 0.05, centerZ = -0.1, h = 0.02, slopeX = 0.08, slopeZ = -0.05, cxx = 0.3, cxz = -0.1, czz = 0.2;
  // The model's highest over the texels (|x - c| <= 0.5 m): a bound, as the tile's range gives.
  const double highest = h + 0.08 * 0.5 + 0.05 * 0.5 + 0.5 * (0.3 + 0.2 + 0.2) * 0.25;
  int crossing = 0, edgeOn = 0, checkedTiles = 0;
  for (std::uint32_t size = 1; size <= 11; ++size) {
    for (int trial = 0; trial < 20; ++trial) {
      // Two texels of padding before the tile: the lanes must read only [begin, end).
      std::vector<Texel> texels(size + 2);
      for (Texel& t : texels) {
        for (int k = 0; k < 3; ++k) {
          t.position[k] = float(0.12 * unit(rng));
          t.areaVector[k] = float(0.002 * unit(rng));
          t.edgeU[k] = float(0.04 * unit(rng));
          t.edgeV[k] = float(0.04 * unit(rng));
        }
        t.area = float(0.003 * (1.5 + unit(rng)));
        if (unit(rng) > 0.6) {  // edge-on: the posed v edge horizontal (R^T e_y . eV = 0)
          const Eigen::Vector3d up = r.row(1).transpose();
          Eigen::Vector3d v(t.edgeV[0], t.edgeV[1], t.edgeV[2]);
          v -= up * up.dot(v);
          for (int k = 0; k < 3; ++k) t.edgeV[k] = float(v[k]);
        }
      }
      detail::WaveTexelInput in{texels.data(), 2, size + 2,
                                {r(0, 0), r(0, 1), r(0, 2)}, {r(1, 0), r(1, 1), r(1, 2)}, {r(2, 0), r(2, 1), r(2, 2)},
                                {offset.x(), offset.y(), offset.z()}, centerX, centerZ, h, slopeX, slopeZ, cxx, cxz, czz,
                                highest};
      detail::WettedSums pairs;
      const std::uint32_t reached = detail::sumWaveTexelLanes<detail::DoubleLanes>(in, pairs);
      CHECK(reached == (size < 2 ? 2u : size + 2));
      // The reference over the texels the lanes took.
      detail::WettedSums reference;
      double scale = 0.0;
      for (std::uint32_t i = 2; i < reached; ++i) {
        const Texel& t = texels[i];
        const Eigen::Vector3d p(t.position[0], t.position[1], t.position[2]);
        const Eigen::Vector3d x = r * p + offset;
        const double a = r.row(1).dot(Eigen::Vector3d(t.edgeU[0], t.edgeU[1], t.edgeU[2]));
        const double b = r.row(1).dot(Eigen::Vector3d(t.edgeV[0], t.edgeV[1], t.edgeV[2]));
        const double ux = x.x() - centerX, uz = x.z() - centerZ;
        const double height = h + slopeX * ux + slopeZ * uz + 0.5 * (cxx * ux * ux + 2.0 * cxz * ux * uz + czz * uz * uz);
        const double d = height - x.y();
        if (!(d > -0.5 * (std::abs(a) + std::abs(b)))) continue;
        const detail::WaterlineFractions f = detail::waterlineFractions(d, a, b);
        if (f.area > 0.0 && f.area < 1.0) ++crossing;
        if (std::abs(b) <= 1e-6 * std::abs(a) && f.area < 1.0) ++edgeOn;
        const Eigen::Vector3d w = r * Eigen::Vector3d(t.areaVector[0], t.areaVector[1], t.areaVector[2]);
        reference.addElement(x.x(), x.y(), x.z(), w.x(), w.y(), w.z(), t.area, f.area, f.depth, f.depthSq, height);
        // A bound of every term's size: (1 + |x'| + |h|)^2 (|A| + area)(1 + |D| + Q).
        const double reach = 1.0 + x.cwiseAbs().sum() + std::abs(height);
        scale += reach * reach * (w.norm() + t.area) * (1.0 + std::abs(f.depth) + std::abs(f.depthSq));
      }
      ++checkedTiles;
      auto compare = [&](const detail::WettedSums& lanes) {
        const double got[] = {lanes.sumDA[0], lanes.sumDA[1], lanes.sumDA[2], lanes.sumDxA[0], lanes.sumDxA[1],
                              lanes.sumDxA[2], lanes.sumDXAy, lanes.sumDZAy, lanes.sumYB, lanes.sumAy, lanes.sumXAy,
                              lanes.sumZAy, lanes.sumXXAy, lanes.sumXZAy, lanes.sumZZAy, lanes.wettedArea};
        const double want[] = {reference.sumDA[0], reference.sumDA[1], reference.sumDA[2], reference.sumDxA[0],
                               reference.sumDxA[1], reference.sumDxA[2], reference.sumDXAy, reference.sumDZAy,
                               reference.sumYB, reference.sumAy, reference.sumXAy, reference.sumZAy,
                               reference.sumXXAy, reference.sumXZAy, reference.sumZZAy, reference.wettedArea};
        for (int k = 0; k < 16; ++k) {
          CAPTURE(size, trial, k);
          CHECK(std::abs(got[k] - want[k]) <= 1e-12 * scale);
        }
      };
      compare(pairs);
      detail::WettedSums quads;
      std::uint32_t quadReached = 0;
      if (detail::sumWaveTexelsAvx2(in, quads, quadReached)) {
        CHECK(quadReached == (size < 4 ? 2u : size + 2));
        if (quadReached == reached) compare(quads);
      }
    }
  }
  // The cases are there.
  CHECK(crossing > 50);
  CHECK(edgeOn > 5);
  CHECK(checkedTiles == 220);
}
