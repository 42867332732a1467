// SPDX-License-Identifier: Zlib
// Closed-form hydrostatics of a sphere (PrimitiveHydrostatics.hpp): the spherical cap against an
// independent integration, the sphere's hydrostatics against closed forms (Archimedes, the disc
// water plane, the metacentre at the centre), and against the exact path on a fine icosphere
// within bounds that follow from the icosphere lying between its in-sphere and its circumsphere.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PrimitiveHydrostatics.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG = 9.81;

/// Composite Simpson's rule of f over [a, b] with n (even) intervals: exact for cubics, so for the
/// cap's integrands (pi (r^2 - y^2), y pi (r^2 - y^2)) the only error is rounding.
template <class F>
double simpson(F f, double a, double b, int n) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

HydrostaticsQuery queryAt(const Pose& pose, const Eigen::Vector3d& centerOfMass, std::optional<double> mass = {}) {
  HydrostaticsQuery query;
  query.pose = pose;
  query.gravity = kG;
  query.centerOfMass = centerOfMass;
  query.mass = mass;
  return query;
}

}  // namespace

TEST_CASE("spherical cap: volume and centroid against slices of the sphere", "[hydrostatics][primitive][sphere]") {
  const double r = 0.5;
  for (const double plane : {-0.6, -0.5, -0.3, -0.01, 0.0, 0.2, 0.49, 0.5, 0.7}) {
    CAPTURE(plane);
    const SphericalCap cap = sphericalCap(r, plane);
    const double top = std::min(plane, r);
    // The sphere sliced at height y (from its centre) is a disc of area pi (r^2 - y^2).
    const double volume = top > -r ? simpson([&](double y) { return kPi * (r * r - y * y); }, -r, top, 200) : 0.0;
    const double moment = top > -r ? simpson([&](double y) { return y * kPi * (r * r - y * y); }, -r, top, 200) : 0.0;
    // Rounding only (Simpson is exact for these cubics): 1e-12 of the sphere's volume and moment.
    CHECK(cap.volume == Approx(volume).margin(1e-12 * r * r * r));
    if (volume > 0.0) CHECK(-cap.centroidDepthBelowCenter * cap.volume == Approx(moment).margin(1e-12 * r * r * r * r));
    const double a2 = std::max(r * r - plane * plane, 0.0);
    CHECK(cap.waterplaneRadius == Approx(std::abs(plane) < r ? std::sqrt(a2) : 0.0).margin(1e-12));
    CHECK(cap.wettedArea == Approx(2.0 * kPi * r * std::clamp(r + plane, 0.0, 2.0 * r)).margin(1e-12));
  }
  // docs/references.md: half immersed, V = 2/3 pi r^3 and the centre of buoyancy 3 r / 8 below.
  const SphericalCap half = sphericalCap(r, 0.0);
  CHECK(half.volume == Approx(2.0 / 3.0 * kPi * r * r * r).epsilon(1e-14));
  CHECK(half.centroidDepthBelowCenter == Approx(3.0 * r / 8.0).epsilon(1e-14));
  CHECK(half.wettedArea == Approx(2.0 * kPi * r * r).epsilon(1e-14));
}

TEST_CASE("sphere hydrostatics: Archimedes, the disc water plane and the metacentre at the centre",
          "[hydrostatics][primitive][sphere]") {
  const double r = 0.4, rho = 1025.0, level = 0.25;
  const FlatSurface water(level, rho);
  // The sphere off the body origin, the body turned: only the world centre matters.
  const Eigen::Vector3d center(0.1, -0.2, 0.3);
  for (const double plane : {-0.3, 0.0, 0.15, 0.39}) {
    CAPTURE(plane);
    const Pose pose = Pose::fromDegreesXYZ(Eigen::Vector3d(20.0, 35.0, -10.0), Eigen::Vector3d::Zero());
    Pose placed = pose;
    placed.translation = Eigen::Vector3d(1.0, level - plane, -2.0) - pose.rotation * center;
    const Eigen::Vector3d worldCenter = placed.apply(center);
    REQUIRE(worldCenter.y() == Approx(level - plane));
    // Centre of mass at the sphere's centre, mass rho V (floating): every normal of a sphere passes
    // through its centre, so the metacentre is the centre, GM = 0: no roll or pitch stiffness.
    const Expected<HydrostaticsResult> result = sphereHydrostatics(r, center, water, queryAt(placed, center));
    REQUIRE(result.ok());
    const SphericalCap cap = sphericalCap(r, plane);
    const double volume = cap.volume;
    CHECK(result->submergedVolume == Approx(volume).epsilon(1e-14));
    CHECK(result->buoyancyForce.y() == Approx(rho * kG * volume).epsilon(1e-14));
    CHECK(result->buoyancyForce.x() == 0.0);
    CHECK(result->centerOfBuoyancy.x() == Approx(worldCenter.x()).margin(1e-14));
    CHECK(result->centerOfBuoyancy.y() == Approx(worldCenter.y() - cap.centroidDepthBelowCenter).margin(1e-14));
    CHECK(result->torqueAboutCenterOfMass.norm() == Approx(0.0).margin(1e-9));  // buoyancy through the centre
    const double a2 = r * r - plane * plane;
    CHECK(result->waterplaneArea == Approx(kPi * a2).epsilon(1e-12));
    CHECK(result->waterplaneCentroid.isApprox(Eigen::Vector3d(worldCenter.x(), level, worldCenter.z()), 1e-14));
    CHECK(result->wettedArea == Approx(2.0 * kPi * r * (r + plane)).epsilon(1e-12));
    const double heave = rho * kG * kPi * a2;
    CHECK(result->stiffness(0, 0) == Approx(heave).epsilon(1e-12));
    // Rounding of rho g (pi a^4 / 4 - V e), two terms of size rho g r^4: 1e-12 of that.
    const double scale = rho * kG * r * r * r * r;
    CHECK(result->stiffness(1, 1) == Approx(0.0).margin(1e-12 * scale));
    CHECK(result->stiffness(2, 2) == Approx(0.0).margin(1e-12 * scale));
    CHECK(result->stiffness(0, 1) == Approx(0.0).margin(1e-12 * scale));
    CHECK(result->stiffness(1, 2) == Approx(0.0).margin(1e-12 * scale));

    // Centre of mass 0.1 m under the centre, the same mass: roll and pitch stiffness m g 0.1
    // (GM = 0.1 m), and the buoyancy's couple about G, F x 0 horizontal offset: still none.
    const Eigen::Vector3d lowered = center + pose.rotation.transpose() * Eigen::Vector3d(0.0, -0.1, 0.0);
    const double mass = rho * volume;
    const Expected<HydrostaticsResult> low = sphereHydrostatics(r, center, water, queryAt(placed, lowered, mass));
    REQUIRE(low.ok());
    CHECK(low->stiffness(1, 1) == Approx(mass * kG * 0.1).margin(1e-12 * scale));
    CHECK(low->stiffness(2, 2) == Approx(mass * kG * 0.1).margin(1e-12 * scale));
  }
}

TEST_CASE("sphere hydrostatics: out of the liquid, wholly under, and refusals", "[hydrostatics][primitive][sphere]") {
  const FlatSurface water(0.0, 1000.0);
  const Pose up = Pose::fromDegreesXYZ(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, 0.51, 0.0));
  const Expected<HydrostaticsResult> dry = sphereHydrostatics(0.5, Eigen::Vector3d::Zero(), water, queryAt(up, Eigen::Vector3d::Zero()));
  REQUIRE(dry.ok());
  CHECK(dry->submergedVolume == 0.0);
  CHECK(dry->buoyancyForce.norm() == 0.0);
  CHECK(dry->fluidDensity == 1000.0);

  const Pose down = Pose::fromDegreesXYZ(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.0, -2.0, 0.0));
  const Expected<HydrostaticsResult> under = sphereHydrostatics(0.5, Eigen::Vector3d::Zero(), water, queryAt(down, Eigen::Vector3d::Zero()));
  REQUIRE(under.ok());
  CHECK(under->submergedVolume == Approx(4.0 / 3.0 * kPi * 0.125).epsilon(1e-14));
  CHECK(under->centerOfBuoyancy.isApprox(Eigen::Vector3d(0.0, -2.0, 0.0), 1e-14));
  CHECK(under->waterplaneArea == 0.0);
  CHECK(under->wettedArea == Approx(4.0 * kPi * 0.25).epsilon(1e-14));

  const GerstnerWaves waves({GerstnerWave{}});
  CHECK_FALSE(sphereHydrostatics(0.5, Eigen::Vector3d::Zero(), waves, queryAt(down, Eigen::Vector3d::Zero())).ok());
  CHECK_FALSE(sphereHydrostatics(-1.0, Eigen::Vector3d::Zero(), water, queryAt(down, Eigen::Vector3d::Zero())).ok());
  CHECK_FALSE(sphereHydrostatics(0.5, Eigen::Vector3d(NAN, 0, 0), water, queryAt(down, Eigen::Vector3d::Zero())).ok());
  HydrostaticsQuery bad = queryAt(down, Eigen::Vector3d::Zero());
  bad.gravity = -1.0;
  CHECK_FALSE(sphereHydrostatics(0.5, Eigen::Vector3d::Zero(), water, bad).ok());
}

TEST_CASE("sphere hydrostatics against the exact path on a fine icosphere", "[hydrostatics][primitive][sphere][exact]") {
  // The icosphere's vertices lie on the sphere of radius r, so it lies inside that sphere and
  // contains the sphere of its in-radius r_in (the least distance from the centre to a face's
  // plane). The submerged volume, the moment of the submerged volume about the water plane, the
  // water-plane area and the water plane's second moments are integrals of integrands of one sign
  // over the part under the plane, so each lies between the sphere's value at r_in and at r: the
  // tolerances are those differences (the polygon's volume deficit, cap by cap), plus rounding.
  const double r = 0.5, rho = 1000.0;
  const Mesh mesh = primitives::icosphere(r, 5);  // 20,480 faces
  double inRadius = r;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    inRadius = std::min(inRadius, std::abs((b - a).cross(c - a).normalized().dot(a)));
  }
  REQUIRE(inRadius > 0.999 * r);
  const FlatSurface water(0.0, rho);
  const double rounding = 1e-12;
  for (const double plane : {-0.45, -0.2, 0.0, 0.1, 0.3, 0.48}) {
    for (const double degrees : {0.0, 17.0, 41.0}) {
      CAPTURE(plane, degrees);
      const Pose pose = Pose::fromDegreesXYZ(Eigen::Vector3d(degrees, 2.0 * degrees, 0.5 * degrees), Eigen::Vector3d(0.3, -plane, -0.7));
      const double mass = 250.0;  // given, so that the gravity term of the stiffness is the same
      const HydrostaticsQuery query = queryAt(pose, Eigen::Vector3d::Zero(), mass);
      const Expected<HydrostaticsResult> closed = sphereHydrostatics(r, Eigen::Vector3d::Zero(), water, query);
      const Expected<HydrostaticsResult> exact = polyhedralHydrostatics(mesh, water, query);
      REQUIRE(closed.ok());
      REQUIRE(exact.ok());
      const SphericalCap outer = sphericalCap(r, plane), inner = sphericalCap(inRadius, plane);
      // Volume between the inner and the outer cap.
      const double volumeSlack = outer.volume - inner.volume;
      CHECK(exact->submergedVolume >= inner.volume - rounding);
      CHECK(exact->submergedVolume <= outer.volume + rounding);
      CHECK(std::abs(closed->submergedVolume - exact->submergedVolume) <= volumeSlack + rounding);
      // Moment about the water plane, Int (y - h) dV <= 0: between the outer's and the inner's.
      auto momentAboutPlane = [&](const SphericalCap& cap) { return cap.volume * (-plane - cap.centroidDepthBelowCenter); };
      const double exactMoment = exact->submergedVolume * exact->centerOfBuoyancy.y();
      CHECK(exactMoment >= momentAboutPlane(outer) - rounding);
      CHECK(exactMoment <= momentAboutPlane(inner) + rounding);
      // Horizontally: the inner cap's moment about the centre's vertical is zero (symmetric), the
      // rest (volumeSlack) lies within r of it.
      const Eigen::Vector2d offset(exact->centerOfBuoyancy.x() - 0.3, exact->centerOfBuoyancy.z() + 0.7);
      CHECK(offset.norm() <= r * volumeSlack / exact->submergedVolume + rounding);
      CHECK(closed->centerOfBuoyancy.x() == Approx(0.3).margin(1e-14));
      // Water plane: between the discs of radius sqrt(r_in^2 - s^2) and sqrt(r^2 - s^2); its second
      // moment about a diameter between pi a_in^4 / 4 and pi a^4 / 4 (both in the roll stiffness,
      // with the moment about the plane: K11 = rho g (I + Int (y - h) dV) - m g (y_G - h)).
      const double innerArea = kPi * inner.waterplaneRadius * inner.waterplaneRadius;
      const double outerArea = kPi * outer.waterplaneRadius * outer.waterplaneRadius;
      CHECK(exact->waterplaneArea >= innerArea - rounding);
      CHECK(exact->waterplaneArea <= outerArea + rounding);
      CHECK(std::abs(closed->waterplaneArea - exact->waterplaneArea) <= outerArea - innerArea + rounding);
      const double secondSlack = 0.25 * (outerArea * outer.waterplaneRadius * outer.waterplaneRadius -
                                         innerArea * inner.waterplaneRadius * inner.waterplaneRadius);
      const double momentSlack = momentAboutPlane(inner) - momentAboutPlane(outer);
      const double rollSlack = rho * kG * (secondSlack + momentSlack) + 1e-9;
      CHECK(std::abs(closed->stiffness(0, 0) - exact->stiffness(0, 0)) <= rho * kG * (outerArea - innerArea) + 1e-9);
      CHECK(std::abs(closed->stiffness(1, 1) - exact->stiffness(1, 1)) <= rollSlack);
      CHECK(std::abs(closed->stiffness(2, 2) - exact->stiffness(2, 2)) <= rollSlack);
      CHECK(closed->buoyancyForce.y() == Approx(rho * kG * closed->submergedVolume).epsilon(1e-14));
    }
  }
}
