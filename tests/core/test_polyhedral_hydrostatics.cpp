// SPDX-License-Identifier: Zlib
// Exact polyhedral hydrostatics against closed forms on the same polyhedra (box at any tilt, N-gon
// cone), against smooth closed forms with the polyhedral approximation error as the tolerance
// (sphere caps, cylinder segments, torus, Wigley hull), property checks on random closed meshes
// and poses, stiffness, and bad input.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "RandomRotation.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRho = 1000.0;
constexpr double kG = 9.81;

using hydrotex::testing::randomRotation;

HydrostaticsResult exact(const Mesh& mesh, double level, const Pose& pose, const Eigen::Vector3d& com = Eigen::Vector3d::Zero()) {
  HydrostaticsQuery query;
  query.pose = pose;
  query.gravity = kG;
  query.centerOfMass = com;
  const auto result = polyhedralHydrostatics(mesh, FlatSurface(level, kRho), query);
  REQUIRE(result.ok());
  return *result;
}

// Box of extents e under pose R: with u uniform in the box, y = t_y + sum g_i U_i (g_i = R(1,i) e_i,
// U_i uniform on [-1/2, 1/2]). The submerged fraction is the CDF of that sum: integrating the
// indicator three times over the box gives the alternating sum of F(z) = z+^3/6 at its corners;
// F = z+^2/2 gives the density (water-plane area), F = z+^4/24 the integral of the volume in h.
double boxCorners(double d, const double g[3], int power) {
  double sum = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    double z = d, sign = 1.0;
    for (int i = 0; i < 3; ++i) {
      const bool plus = (corner >> i) & 1;
      z += (plus ? 0.5 : -0.5) * g[i];
      if (!plus) sign = -sign;
    }
    const double zp = std::max(z, 0.0);
    sum += sign * std::pow(zp, power);
  }
  double factorial = 1.0;
  for (int k = 2; k <= power; ++k) factorial *= k;
  return sum / factorial / (g[0] * g[1] * g[2]);
}

}  // namespace

TEST_CASE("Exact path: a box at any tilt matches the closed form of the clipped box", "[hydrostatics][exact]") {
  const Eigen::Vector3d extents(1.3, 0.7, 2.1);
  const double total = extents.prod();
  const Mesh box = prim::box(extents);
  const Mesh finer = prim::subdividedBox(extents, 4);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Pose pose{randomRotation(rng), Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5)};
    double g[3];
    for (int i = 0; i < 3; ++i) g[i] = std::abs(pose.rotation(1, i)) * extents[i];
    // The closed form divides by g1 g2 g3: keep away from axis-aligned poses where it cancels.
    if (std::min({g[0], g[1], g[2]}) < 0.05) continue;
    const double halfSpan = 0.5 * (g[0] + g[1] + g[2]);
    const double level = pose.translation.y() + (2.0 * unit(rng) - 1.0) * halfSpan;
    const double d = level - pose.translation.y();
    const double volume = total * boxCorners(d, g, 3);
    const double area = total * boxCorners(d, g, 2);
    // Int y dV = Int_{-inf}^{h} s A(s) ds = h V(h) - Int V: the buoyancy height from the same corners.
    const double buoyancyDepth = (d * volume - total * boxCorners(d, g, 4)) / volume;

    const HydrostaticsResult r = exact(box, level, pose);
    // 1e-9 of the total: double round-off on O(10) operations per triangle, far below it.
    CHECK(r.submergedVolume == Approx(volume).margin(1e-9 * total));
    CHECK(r.waterplaneArea == Approx(area).margin(1e-9 * total));
    CHECK(r.centerOfBuoyancy.y() - pose.translation.y() == Approx(buoyancyDepth).margin(1e-9));
    CHECK(r.buoyancyForce.y() == Approx(kRho * kG * volume).epsilon(1e-12));

    // Another triangulation of the same polyhedron: every quantity agrees to round-off.
    const HydrostaticsResult f = exact(finer, level, pose);
    CHECK(f.submergedVolume == Approx(r.submergedVolume).margin(1e-12 * total));
    CHECK((f.centerOfBuoyancy - r.centerOfBuoyancy).norm() < 1e-9);
    CHECK((f.waterplaneCentroid - r.waterplaneCentroid).norm() < 1e-9);
    CHECK((f.stiffness - r.stiffness).norm() < 1e-9 * r.stiffness.norm() + 1e-9);
    CHECK(f.wettedArea == Approx(r.wettedArea).epsilon(1e-12));
    ++checked;
  }
  CHECK(checked > 100);
}

TEST_CASE("Exact path: an upright N-gon cone matches the pyramid closed forms", "[hydrostatics][exact]") {
  const double radius = 0.8, height = 1.5;
  const int segments = 24;
  const Mesh cone = prim::cone(radius, height, segments);
  const double baseArea = 0.5 * segments * radius * radius * std::sin(2.0 * kPi / segments);
  const Pose pose{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.3, -2.0, 0.1)};
  for (double level = -1.99; level < -0.5; level += 0.0731) {
    const double h = level - pose.translation.y();  // water height above the base
    // A(y) = A0 ((H - y) / H)^2; V = Int_0^h A; Int y A dy = A0/H^2 (H^2 h^2/2 - 2 H h^3/3 + h^4/4).
    const double volume = baseArea * height / 3.0 * (1.0 - std::pow((height - h) / height, 3));
    const double moment = baseArea / (height * height) *
                          (height * height * h * h / 2.0 - 2.0 * height * h * h * h / 3.0 + h * h * h * h / 4.0);
    const double area = baseArea * std::pow((height - h) / height, 2);
    const HydrostaticsResult r = exact(cone, level, pose);
    CHECK(r.submergedVolume == Approx(volume).epsilon(1e-9));
    CHECK(r.centerOfBuoyancy.y() - pose.translation.y() == Approx(moment / volume).epsilon(1e-9));
    CHECK(r.waterplaneArea == Approx(area).epsilon(1e-9));
    // The cone is symmetric about its axis: the centre of buoyancy is on it.
    CHECK(std::abs(r.centerOfBuoyancy.x() - 0.3) < 1e-9);
    CHECK(std::abs(r.centerOfBuoyancy.z() - 0.1) < 1e-9);
    CHECK(std::abs(r.waterplaneCentroid.x() - 0.3) < 1e-9);
  }
}

TEST_CASE("Exact path: sphere caps, cylinder segments, torus and Wigley hull within the meshing error",
          "[hydrostatics][exact]") {
  SECTION("sphere caps at many depths and orientations") {
    const double r = 1.0;
    const Mesh sphere = prim::icosphere(r, 5);  // 20480 triangles
    const double polyVolume = polyhedralMassProperties(sphere, 1.0)->volume;
    // Tolerance: the inscribed icosphere misses (4/3 pi - V_poly) of volume; caps miss at most that.
    const double meshing = 4.0 / 3.0 * kPi - polyVolume;
    REQUIRE(meshing < 3e-3);
    std::mt19937 rng(3);
    for (double depth = 0.05; depth < 2.0; depth += 0.0917) {
      const Pose pose{randomRotation(rng), Eigen::Vector3d(0.2, 0.0, -0.4)};
      const double level = depth - r;
      const HydrostaticsResult res = exact(sphere, level, pose);
      const double volume = kPi * depth * depth * (3 * r - depth) / 3.0;
      const double centroidBelowCentre = 3.0 * std::pow(2 * r - depth, 2) / (4.0 * (3 * r - depth));
      CHECK(res.submergedVolume == Approx(volume).margin(meshing));
      CHECK(res.centerOfBuoyancy.y() == Approx(-centroidBelowCentre).margin(5e-3));
      CHECK(std::abs(res.centerOfBuoyancy.x() - 0.2) < 5e-3);
      // Water-plane area pi (r^2 - (r - d)^2): the cut of the inscribed mesh has its radius^2
      // short by about 2 r sag (sag = l^2 / 8r ~ 1.5e-4 for edges l ~ 0.035): ~1e-3 m^2.
      CHECK(res.waterplaneArea == Approx(kPi * (r * r - (r - depth) * (r - depth))).margin(2e-3));
    }
  }
  SECTION("horizontal cylinder: circular segment") {
    const double r = 0.5, length = 2.0;
    const int segments = 512;
    const Mesh cylinder = prim::cylinder(r, length, segments);
    // The inscribed 512-gon misses (1 - sin(2pi/N)/(2pi/N)) ~ 2.5e-5 of the disc.
    const double meshing = kPi * r * r * length * 3e-5;
    for (double h = -0.49; h < 0.5; h += 0.0613) {
      const double segment = r * r * std::acos(-h / r) + h * std::sqrt(r * r - h * h);
      const HydrostaticsResult res = exact(cylinder, h, Pose{});
      CHECK(res.submergedVolume == Approx(segment * length).margin(meshing));
      // Chord of the 512-gon: off by about r sag / half-chord, sag = r (1 - cos(pi/N)) ~ 1e-5 m.
      CHECK(res.waterplaneArea == Approx(2.0 * std::sqrt(r * r - h * h) * length).margin(5e-4));
    }
  }
  SECTION("torus around y (not convex): Pappus on the circular segment of the tube") {
    const double major = 1.0, minor = 0.3;
    const Mesh torus = prim::torus(major, minor, 256, 96);
    const double polyVolume = polyhedralMassProperties(torus, 1.0)->volume;
    const double meshing = 2.0 * kPi * kPi * major * minor * minor - polyVolume;
    for (double h = -0.29; h < 0.3; h += 0.047) {
      const double segment = minor * minor * std::acos(-h / minor) + h * std::sqrt(minor * minor - h * h);
      const HydrostaticsResult res = exact(torus, h, Pose{});
      CHECK(res.submergedVolume == Approx(2.0 * kPi * major * segment).margin(meshing));
    }
  }
  SECTION("Wigley hull to the deck: V = 4/9 L B T") {
    const double length = 4.0, breadth = 0.4, draft = 0.25;
    const Mesh hull = prim::wigleyHull(length, breadth, draft, 160, 40);
    const HydrostaticsResult res = exact(hull, 0.0, Pose{});
    // Piecewise-linear hull of 160 x 40 segments: O(1/n^2) ~ 1e-3 relative.
    CHECK(res.submergedVolume == Approx(4.0 / 9.0 * length * breadth * draft).epsilon(2e-3));
    CHECK(res.submergedVolume == Approx(polyhedralMassProperties(hull, 1.0)->volume).epsilon(1e-12));
  }
}

TEST_CASE("Exact path: properties on random closed meshes and poses", "[hydrostatics][exact][property]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Mesh> meshes = {prim::torus(1.0, 0.35, 24, 12), prim::hemisphere(0.7, 16, 6, true),
                              prim::wigleyHull(3.0, 0.5, 0.3, 20, 8), prim::cone(0.5, 1.0, 12)};
  // A random star-shaped (not convex) mesh: an icosphere with every vertex pushed in or out.
  Mesh bumpy = prim::icosphere(1.0, 2);
  for (Eigen::Vector3d& p : bumpy.positions) p *= 0.6 + 0.8 * unit(rng);
  meshes.push_back(bumpy);
  for (const Mesh& mesh : meshes) {
    const double total = polyhedralMassProperties(mesh, 1.0)->volume;
    for (int trial = 0; trial < 10; ++trial) {
      const Pose pose{randomRotation(rng), Eigen::Vector3d(unit(rng), unit(rng), unit(rng))};
      Eigen::Vector3d low = Eigen::Vector3d::Constant(1e30), high = -low;
      for (const Eigen::Vector3d& p : mesh.positions) {
        low = low.cwiseMin(pose.apply(p));
        high = high.cwiseMax(pose.apply(p));
      }
      CHECK(exact(mesh, low.y() - 1e-9, pose).submergedVolume == 0.0);
      CHECK(exact(mesh, high.y() + 1e-9, pose).submergedVolume == Approx(total).epsilon(1e-12));
      double previous = 0.0;
      for (int step = 1; step < 20; ++step) {
        const double level = low.y() + (high.y() - low.y()) * step / 20.0;
        const HydrostaticsResult r = exact(mesh, level, pose);
        CHECK(std::isfinite(r.submergedVolume));
        CHECK(r.stiffness.allFinite());
        CHECK(r.submergedVolume >= previous - 1e-12);  // monotonic in the water level
        previous = r.submergedVolume;
        CHECK(r.buoyancyForce.y() == Approx(kRho * kG * r.submergedVolume).epsilon(1e-12));
        CHECK(r.buoyancyForce.x() == 0.0);
        if (r.submergedVolume > 1e-9 * total) {
          CHECK((r.centerOfBuoyancy.array() >= low.array() - 1e-9).all());
          CHECK((r.centerOfBuoyancy.array() <= high.array() + 1e-9).all());
          CHECK(r.centerOfBuoyancy.y() <= level + 1e-9);
        }
      }
    }
  }
}

TEST_CASE("Exact path: stiffness of a box barge and the heave row by finite differences", "[hydrostatics][exact][stiffness]") {
  SECTION("box barge: K_heave = rho g L B, K_roll = rho g V GM with BM = B^2/(12 T)") {
    const double length = 4.0, depth = 1.0, breadth = 1.5, draft = 0.4;
    const Mesh box = prim::box({length, depth, breadth});
    const Pose pose{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, depth / 2 - draft, 0)};
    const HydrostaticsResult r = exact(box, 0.0, pose);  // centre of mass at the box centre
    const double volume = length * breadth * draft;
    const double kb = draft / 2, kg = depth / 2;
    const double gmRoll = kb + breadth * breadth / (12 * draft) - kg;
    const double gmPitch = kb + length * length / (12 * draft) - kg;
    CHECK(r.stiffness(0, 0) == Approx(kRho * kG * length * breadth).epsilon(1e-12));
    CHECK(r.stiffness(1, 1) == Approx(kRho * kG * volume * gmRoll).epsilon(1e-9));
    CHECK(r.stiffness(2, 2) == Approx(kRho * kG * volume * gmPitch).epsilon(1e-9));
    CHECK(std::abs(r.stiffness(0, 1)) < 1e-6);
    CHECK(std::abs(r.stiffness(1, 2)) < 1e-6);
  }
  SECTION("heave row = -dF_y/dq for heave, roll and pitch about O at a random tilt") {
    const Mesh box = prim::box({1.2, 0.8, 2.0});
    std::mt19937 rng(5);
    for (int trial = 0; trial < 10; ++trial) {
      const Pose pose{randomRotation(rng), Eigen::Vector3d(0.1, 0.05, -0.2)};
      const Eigen::Vector3d com(0.1, -0.05, 0.2);
      const HydrostaticsResult r = exact(box, 0.0, pose, com);
      const Eigen::Vector3d origin(pose.apply(com).x(), 0.0, pose.apply(com).z());
      const double step = 1e-5;
      auto forceAfter = [&](const Eigen::Vector3d& move, const Eigen::Matrix3d& turn) {
        Pose moved;
        moved.rotation = turn * pose.rotation;
        moved.translation = turn * (pose.translation - origin) + origin + move;
        return exact(box, 0.0, moved, com).buoyancyForce.y();
      };
      const Eigen::Matrix3d id = Eigen::Matrix3d::Identity();
      const double heave = (forceAfter({0, step, 0}, id) - forceAfter({0, -step, 0}, id)) / (2 * step);
      const Eigen::Matrix3d rollPlus = Eigen::AngleAxisd(step, Eigen::Vector3d::UnitX()).toRotationMatrix();
      const Eigen::Matrix3d pitchPlus = Eigen::AngleAxisd(step, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      const double roll = (forceAfter({0, 0, 0}, rollPlus) - forceAfter({0, 0, 0}, rollPlus.transpose())) / (2 * step);
      const double pitch = (forceAfter({0, 0, 0}, pitchPlus) - forceAfter({0, 0, 0}, pitchPlus.transpose())) / (2 * step);
      // Central differences of a piecewise-quadratic function: O(step^2) error, ~1e-6 relative.
      const double scale = r.stiffness(0, 0);
      CHECK(-heave == Approx(r.stiffness(0, 0)).margin(1e-5 * scale));
      CHECK(-roll == Approx(r.stiffness(0, 1)).margin(1e-5 * scale));
      CHECK(-pitch == Approx(r.stiffness(0, 2)).margin(1e-5 * scale));
    }
  }
}

TEST_CASE("Exact path: a uniform medium submerges everything", "[hydrostatics][exact][medium]") {
  const Mesh sphere = prim::icosphere(0.5, 3);
  const double total = polyhedralMassProperties(sphere, 1.0)->volume;
  HydrostaticsQuery query;
  query.pose.translation = Eigen::Vector3d(1, 20, 3);
  const auto constant = polyhedralHydrostatics(sphere, UniformMedium(1.2, INFINITY), query);
  REQUIRE(constant.ok());
  CHECK(constant->submergedVolume == Approx(total).epsilon(1e-12));
  // Constant density: p linear, the centroid rule is exact per triangle.
  CHECK(constant->buoyancyForce.y() == Approx(1.2 * kG * total).epsilon(1e-10));
  CHECK(std::abs(constant->buoyancyForce.x()) < 1e-10);
  CHECK((constant->centerOfBuoyancy - query.pose.translation).norm() < 1e-12);
  // Air: F = g Int rho dV ~ rho(y_c) g V; curvature term ~ (r/H)^2 ~ 1e-9.
  const UniformMedium air(1.225, 8400.0);
  const auto thin = polyhedralHydrostatics(sphere, air, query);
  REQUIRE(thin.ok());
  CHECK(thin->buoyancyForce.y() == Approx(air.densityAt(query.pose.translation) * kG * total).epsilon(1e-6));
  CHECK(thin->waterplaneArea == 0.0);
}

TEST_CASE("Exact path: bad input returns error values", "[hydrostatics][exact][errors]") {
  const Mesh box = prim::box({1, 1, 1});
  const FlatSurface water(0.0);
  HydrostaticsQuery query;
  query.pose.translation.x() = NAN;
  auto r = polyhedralHydrostatics(box, water, query);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("pose") != std::string::npos);
  query.pose.translation = Eigen::Vector3d(0, INFINITY, 0);
  CHECK_FALSE(polyhedralHydrostatics(box, water, query).ok());
  query.pose.translation.setZero();
  r = polyhedralHydrostatics(box, FlatSurface(0.0, -1.0), query);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("density") != std::string::npos);
  CHECK_FALSE(polyhedralHydrostatics(box, FlatSurface(0.0, 0.0), query).ok());
  query.gravity = 0.0;
  CHECK_FALSE(polyhedralHydrostatics(box, water, query).ok());
  query.gravity = 9.81;
  Mesh open = box;
  open.triangles.pop_back();
  r = polyhedralHydrostatics(open, water, query);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("open") != std::string::npos);
  Mesh broken = box;
  broken.triangles[0][1] = 99;
  CHECK_FALSE(polyhedralHydrostatics(broken, water, query).ok());
  CHECK_FALSE(polyhedralHydrostaticsUnchecked(broken, water, query).ok());
  // Waves are served (test_polyhedral_hydrostatics_waves.cpp).
  const GerstnerWaves waves({GerstnerWave{}});
  CHECK(polyhedralHydrostatics(box, waves, query).ok());
  CHECK(polyhedralHydrostatics(box, water, query).ok());
}
