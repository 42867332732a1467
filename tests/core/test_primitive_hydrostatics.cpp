// SPDX-License-Identifier: Zlib
// Closed-form hydrostatics of a sphere (PrimitiveHydrostatics.hpp): the spherical cap against an
// independent integration, the sphere's hydrostatics against closed forms (Archimedes, the disc
// water plane, the metacentre at the centre), and against the exact path on a fine icosphere
// within bounds that follow from the icosphere lying between its in-sphere and its circumsphere.
// Under waves, the sphere's rule (SphereHydrostaticsWaves.cpp): the closed form in the limit of
// still waves, its own convergence, the whole sphere submerged, the same in-sphere and
// circumsphere bounds on the exact path under waves, and where it declines.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <tuple>

#include <Eigen/Geometry>

#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PrimitiveHydrostatics.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrostatics/BoxHydrostaticsWaves.hpp"
#include "hydrostatics/SphereHydrostaticsWaves.hpp"

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

  // Under a height grid (no smoothness bounds) and in a medium without a free surface: neither the
  // closed form nor the rule under waves.
  const HeightGrid grid(8, 8, 1.0, -4.0, -4.0, 0.0);
  CHECK_FALSE(sphereHydrostatics(0.5, Eigen::Vector3d::Zero(), grid, queryAt(down, Eigen::Vector3d::Zero())).ok());
  const UniformMedium medium(1.2, 0.0, 8000.0);
  CHECK_FALSE(sphereHydrostatics(0.5, Eigen::Vector3d::Zero(), medium, queryAt(down, Eigen::Vector3d::Zero())).ok());
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

namespace {

/// bench_peers' sea (data/scenes/peers_waves.json): three Gerstner waves of 12, 5 and 2.3 m.
GerstnerWaves peersWaves() {
  return GerstnerWaves({GerstnerWave{0.10, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                        GerstnerWave{0.05, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5},
                        GerstnerWave{0.02, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3}});
}

/// A pose of the sphere's body frame for case i: tilted, moved across the sea, its centre from
/// 0.6 m under to 0.6 m over the mean level (so that some poses leave the rule to the exact path).
HydrostaticsQuery seaQuery(int i) {
  const double degrees = 20.0 * std::sin(1.3 * i);
  HydrostaticsQuery query = queryAt(Pose::fromDegreesXYZ(Eigen::Vector3d(degrees, 2.0 * degrees, -degrees),
                                                         Eigen::Vector3d(0.37 * i, 0.6 * std::sin(0.9 * i), 0.13 * i)),
                                    Eigen::Vector3d(0.01, -0.05, 0.02), 250.0);
  query.time = 0.1 * i;
  return query;
}

}  // namespace

TEST_CASE("sphere under waves: the rule in the limit of still waves is the closed form", "[hydrostatics][primitive][sphere][waves]") {
  // Waves of zero amplitude are flat, but take the rule (a surface with smoothness bounds, not
  // flatHeight()): the closed form's cap, disc and stiffness within the rule's own error, that of
  // 8 Gauss nodes on each meridian's arc under a plane (measured over these 18 poses: volume,
  // force and torque 3.5e-9, water plane 9e-12; the centre of buoyancy 7.3e-8 r and the
  // stiffness 7.0e-8 rho g pi r^2, from the first moments, at the sphere all but submerged).
  const double r = 0.5, rho = 1000.0, volume = 4.0 / 3.0 * kPi * r * r * r, weight = rho * kG * volume;
  const GerstnerWaves still({GerstnerWave{0.0, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5}}, 0.0, rho);
  const FlatSurface water(0.0, rho);
  for (const double plane : {-0.45, -0.2, 0.0, 0.1, 0.3, 0.45}) {
    for (const double degrees : {0.0, 17.0, 41.0}) {
      CAPTURE(plane, degrees);
      const Pose pose = Pose::fromDegreesXYZ(Eigen::Vector3d(degrees, 2.0 * degrees, 0.5 * degrees), Eigen::Vector3d(0.3, -plane, -0.7));
      const HydrostaticsQuery query = queryAt(pose, Eigen::Vector3d(0.01, -0.05, 0.02), 250.0);
      const Expected<HydrostaticsResult> rule = sphereHydrostatics(r, Eigen::Vector3d::Zero(), still, query);
      const Expected<HydrostaticsResult> closed = sphereHydrostatics(r, Eigen::Vector3d::Zero(), water, query);
      REQUIRE(rule.ok());
      REQUIRE(closed.ok());
      const double tolerance = 1e-8, momentTolerance = 2e-7;
      CHECK(std::abs(rule->submergedVolume - closed->submergedVolume) <= tolerance * volume);
      CHECK((rule->buoyancyForce - closed->buoyancyForce).norm() <= tolerance * weight);
      CHECK((rule->torqueAboutCenterOfMass - closed->torqueAboutCenterOfMass).norm() <= tolerance * weight * r);
      CHECK((rule->centerOfBuoyancy - closed->centerOfBuoyancy).norm() <= momentTolerance * r);
      CHECK(std::abs(rule->waterplaneArea - closed->waterplaneArea) <= tolerance * kPi * r * r);
      CHECK(std::abs(rule->wettedArea - closed->wettedArea) <= tolerance * 4.0 * kPi * r * r);
      CHECK((rule->stiffness - closed->stiffness).norm() <= momentTolerance * rho * kG * kPi * r * r);
    }
  }
}

TEST_CASE("sphere under waves: the rule converges, takes the whole sphere under, and declines near a pole", "[hydrostatics][primitive][sphere][waves]") {
  const GerstnerWaves sea = peersWaves();
  // Against the same rule with 256 azimuths and 48 nodes on each meridian: the default (16 x 8 for
  // a 0.5 m sphere under these waves, 24 x 9 for a 1 m one) measured 7.4e-7 V, 1.2e-6 rho g V and
  // 1.0e-7 rho g V r over these poses at 0.5 m (20 of the 24 taken: the others near a pole), 2.1e-7,
  // 7.2e-7 and 3.9e-8 at 1 m (24 taken); the bounds are 2.5 to 3 times the larger, far under the
  // heights' interpolation bound (3.3e-5 m over the water plane: 5e-5 V).
  for (const auto& [radius, azimuths, polarNodes, leastTaken] :
       {std::tuple{0.5, 16, 8, 16}, std::tuple{1.0, 24, 9, 20}}) {
    CAPTURE(radius);
    const double r = radius, rho = 1000.0, volume = 4.0 / 3.0 * kPi * r * r * r, weight = rho * kG * volume;
    int taken = 0;
    for (int i = 0; i < 24; ++i) {
      CAPTURE(i);
      const HydrostaticsQuery query = seaQuery(i);
      detail::SphereQuadrature used;
      const std::optional<Expected<HydrostaticsResult>> rule =
          detail::waveSphereHydrostatics(r, Eigen::Vector3d::Zero(), sea, query, nullptr, {}, &used);
      if (!rule) continue;
      ++taken;
      const std::optional<Expected<HydrostaticsResult>> fine =
          detail::waveSphereHydrostatics(r, Eigen::Vector3d::Zero(), sea, query, nullptr, {256, 48});
      REQUIRE(fine);
      REQUIRE(rule->ok());
      REQUIRE(fine->ok());
      CHECK(used.azimuths == azimuths);
      CHECK(used.polarNodes == polarNodes);
      const HydrostaticsResult& a = **rule;
      const HydrostaticsResult& b = **fine;
      CHECK(std::abs(a.submergedVolume - b.submergedVolume) <= 2.2e-6 * volume);
      CHECK((a.buoyancyForce - b.buoyancyForce).norm() <= 3.5e-6 * weight);
      CHECK((a.torqueAboutCenterOfMass - b.torqueAboutCenterOfMass).norm() <= 2.5e-7 * weight * r);
      // sphereHydrostatics answers the same.
      const Expected<HydrostaticsResult> api = sphereHydrostatics(r, Eigen::Vector3d::Zero(), sea, query);
      REQUIRE(api.ok());
      CHECK(api->submergedVolume == a.submergedVolume);
    }
    CHECK(taken >= leastTaken);  // the water line away from the poles at most of these poses
  }

  const double r = 0.5, volume = 4.0 / 3.0 * kPi * r * r * r;
  // Wholly under the waves: the whole sphere, its centroid at the centre, whatever the tilt, within
  // the rule's error above (the volume is the integral of (y - h) n_y over the sphere, h the waves:
  // measured 6.8e-7 V, the centre 2.0e-6 r off); its wetted area whole to rounding.
  const HydrostaticsQuery deep = queryAt(Pose::fromDegreesXYZ(Eigen::Vector3d(10.0, 20.0, 30.0), Eigen::Vector3d(0.4, -1.5, 0.2)),
                                         Eigen::Vector3d::Zero());
  const std::optional<Expected<HydrostaticsResult>> under = detail::waveSphereHydrostatics(r, Eigen::Vector3d::Zero(), sea, deep);
  REQUIRE(under);
  REQUIRE(under->ok());
  CHECK((*under)->submergedVolume == Approx(volume).epsilon(2.2e-6));
  CHECK(((*under)->centerOfBuoyancy - Eigen::Vector3d(0.4, -1.5, 0.2)).norm() <= 6e-6 * r);
  CHECK((*under)->wettedArea == Approx(4.0 * kPi * r * r).epsilon(1e-9));
  CHECK((*under)->waterplaneArea == Approx(0.0).margin(1e-9));

  // The top 1 cm under the surface above the centre: the water line may pass near the upper pole
  // (within its curvature's reach), so the rule declines and sphereHydrostatics says so.
  const double top = sea.surfaceHeight(0.4, 0.2, 0.0) - 0.01 - r;
  const HydrostaticsQuery nearPole = queryAt(Pose::fromDegreesXYZ(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.4, top, 0.2)),
                                             Eigen::Vector3d::Zero());
  CHECK_FALSE(detail::waveSphereHydrostatics(r, Eigen::Vector3d::Zero(), sea, nearPole));
  const Expected<HydrostaticsResult> declined = sphereHydrostatics(r, Eigen::Vector3d::Zero(), sea, nearPole);
  REQUIRE_FALSE(declined.ok());
  CHECK(declined.error().message.find("pole") != std::string::npos);
}

TEST_CASE("sphere under waves: the exact path on an icosphere lies between the rule's in-sphere and circumsphere", "[hydrostatics][primitive][sphere][waves][exact]") {
  // The icosphere lies between the spheres of its in-radius and of its radius, so its part under
  // the surface holds the first's and lies within the second's: its submerged volume, and the
  // horizontal projection of the surface inside it (the water plane), lie between the rule's for
  // those two radii. The exact path under waves takes the surface linear between vertices 2.4 cm
  // apart (PolyhedralHydrostatics.hpp): within curvature x edge^2 / 8 < 2e-5 m, over the water
  // plane and along the water line, added to the slack with the rule's own error (3e-6). (A rule
  // whose water line lies 1e-3 rad off moves the water plane by about 8e-4 m^2, three times the
  // margins measured here.)
  const double r = 0.5, volume = 4.0 / 3.0 * kPi * r * r * r;
  const Mesh mesh = primitives::icosphere(r, 5);  // 20,480 faces
  double inRadius = r;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    inRadius = std::min(inRadius, std::abs((b - a).cross(c - a).normalized().dot(a)));
  }
  const GerstnerWaves sea = peersWaves();
  int compared = 0;
  for (int i = 0; i < 8; ++i) {
    CAPTURE(i);
    const HydrostaticsQuery query = seaQuery(i);
    const std::optional<Expected<HydrostaticsResult>> outer = detail::waveSphereHydrostatics(r, Eigen::Vector3d::Zero(), sea, query);
    const std::optional<Expected<HydrostaticsResult>> inner =
        detail::waveSphereHydrostatics(inRadius, Eigen::Vector3d::Zero(), sea, query);
    if (!outer || !inner) continue;
    ++compared;
    const Expected<HydrostaticsResult> exact = polyhedralHydrostatics(mesh, sea, query);
    REQUIRE(exact.ok());
    const double slack = 2e-5 * (*outer)->waterplaneArea + 3e-6 * volume;
    CHECK(exact->submergedVolume >= (*inner)->submergedVolume - slack);
    CHECK(exact->submergedVolume <= (*outer)->submergedVolume + slack);
    const double planeSlack = 2e-5 * 2.0 * kPi * r + 3e-6 * kPi * r * r;
    CHECK(exact->waterplaneArea >= (*inner)->waterplaneArea - planeSlack);
    CHECK(exact->waterplaneArea <= (*outer)->waterplaneArea + planeSlack);
  }
  CHECK(compared >= 5);
}

namespace {

// bench_peers' three waves (data/scenes/peers_waves.json).
GerstnerWaves peersSea(double scale = 1.0) {
  return GerstnerWaves({GerstnerWave{0.10 * scale, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                        GerstnerWave{0.05 * scale, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5},
                        GerstnerWave{0.02 * scale, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3}});
}

// A floating box's query: bench_peers' 1 x 0.5 x 1 m box at density 500, tilted up to `tilt` rad,
// its centre up to `heave` m off the mean level.
HydrostaticsQuery boxQuery(std::mt19937& rng, double tilt, double heave, double time) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  HydrostaticsQuery query;
  query.gravity = 9.81;
  query.mass = 250.0;
  query.pose = Pose{Eigen::AngleAxisd(tilt * unit(rng), Eigen::Vector3d(unit(rng), 0.3 * unit(rng), unit(rng)).normalized())
                        .toRotationMatrix(),
                    Eigen::Vector3d(5.0 * unit(rng), heave * unit(rng), 5.0 * unit(rng))};
  query.time = time;
  return query;
}

}  // namespace

TEST_CASE("box under waves: the rule in the limit of still waves is the exact path's flat answer",
          "[hydrostatics][primitive][box][waves]") {
  // Waves of no amplitude offer smoothness bounds (so the rule runs) and are flat at their mean
  // level, where the exact path on the box's 12 triangles is exact. The depth is linear along each
  // of the rule's lines and the wet length linear across a face, so its Gauss nodes integrate
  // every sum exactly, piece by piece where the water line leaves a side face through its lower or
  // upper side (the face cut there: these poses cut faces 18 times): the two agree to rounding
  // over the poses taken (a tilt that puts the top or bottom face in the water line declines).
  const GerstnerWaves still = peersSea(0.0);
  const FlatSurface flat(0.0);
  const Eigen::Vector3d half(0.5, 0.25, 0.5);
  const Mesh box = primitives::box(2.0 * half);
  std::mt19937 rng(11);
  const double volume = 8.0 * half.prod(), weight = 1000.0 * 9.81 * volume;
  int taken = 0;
  for (int i = 0; i < 24; ++i) {
    CAPTURE(i);
    const HydrostaticsQuery query = boxQuery(rng, 0.3, 0.12, 0.5 * i);
    const auto rule = detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), still, query);
    if (!rule) continue;
    REQUIRE(*rule);
    ++taken;
    const Expected<HydrostaticsResult> exact = polyhedralHydrostatics(box, flat, query);
    REQUIRE(exact);
    CHECK(std::abs((*rule)->submergedVolume - exact->submergedVolume) <= 1e-12 * volume);
    CHECK(((*rule)->buoyancyForce - exact->buoyancyForce).norm() <= 1e-12 * weight);
    CHECK(((*rule)->torqueAboutCenterOfMass - exact->torqueAboutCenterOfMass).norm() <= 1e-12 * weight);
    CHECK(((*rule)->centerOfBuoyancy - exact->centerOfBuoyancy).norm() <= 1e-10);
    CHECK(((*rule)->stiffness - exact->stiffness).norm() <= 1e-10 * weight);
  }
  CHECK(taken >= 16);
}

TEST_CASE("box under waves: the rule against the exact path on the box cut fine, its convergence and its declines",
          "[hydrostatics][primitive][box][waves]") {
  // bench_peers' sea and box. Reference: the plain exact path on the box cut into 100 x 100 squares
  // a face (its surface linear over 1 cm edges: curvature x e^2 / 8, about 1e-5 m of height at
  // most). The default rule (6 x 3 a face for this box) against it, over the 16 poses (all
  // taken), measured: 3.1e-6 of the volume, 5.3e-6 rho g V in force, 1.6e-5 rho g V m in torque;
  // against itself at 48 x 24 nodes 6.0e-6 of the volume. The prepared mesh (what the controller
  // took) was 3.3e-5 rho g V off in force in a 40-pose probe.
  const GerstnerWaves sea = peersSea();
  const Eigen::Vector3d half(0.5, 0.25, 0.5);
  const Mesh fine = primitives::subdividedBox(2.0 * half, 100);
  std::mt19937 rng(5);
  const double volume = 8.0 * half.prod(), weight = 1000.0 * 9.81 * volume;
  double worst[4] = {0, 0, 0, 0};
  int taken = 0;
  for (int i = 0; i < 16; ++i) {
    CAPTURE(i);
    const HydrostaticsQuery query = boxQuery(rng, 0.1, 0.05, 0.61 * i);
    detail::BoxQuadrature used;
    const auto rule = detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), sea, query, nullptr, {}, &used);
    if (!rule) continue;
    REQUIRE(*rule);
    ++taken;
    CHECK(used.across == 6);
    CHECK(used.along == 3);
    const Expected<HydrostaticsResult> reference = polyhedralHydrostatics(fine, sea, query);
    REQUIRE(reference);
    const auto converged = detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), sea, query, nullptr, {48, 24});
    REQUIRE(converged);
    REQUIRE(*converged);
    const double differences[4] = {std::abs((*rule)->submergedVolume - reference->submergedVolume) / volume,
                                   ((*rule)->buoyancyForce - reference->buoyancyForce).norm() / weight,
                                   ((*rule)->torqueAboutCenterOfMass - reference->torqueAboutCenterOfMass).norm() / weight,
                                   std::abs((*rule)->submergedVolume - (*converged)->submergedVolume) / volume};
    for (int k = 0; k < 4; ++k) worst[k] = std::max(worst[k], differences[k]);
    // Bounds: about twice the worst measured, each under the prepared mesh's 3.3e-5.
    CHECK(differences[0] <= 1e-5);
    CHECK(differences[1] <= 1e-5);
    CHECK(differences[2] <= 3e-5);
    CHECK(differences[3] <= 1.5e-5);
  }
  CHECK(taken >= 14);
  WARN("box under waves, rule against the box cut fine: volume " << worst[0] << ", force " << worst[1] << ", torque "
                                                                 << worst[2] << "; against 48 x 24 " << worst[3]
                                                                 << " over " << taken << " poses");
  // Declined: the top face level with the surface above its centre (too flat for the depth to
  // fall up it, and cut by the water line).
  HydrostaticsQuery level;
  level.gravity = 9.81;
  level.mass = 400.0;
  level.pose = Pose{Eigen::Matrix3d::Identity(), Eigen::Vector3d(1.0, sea.surfaceHeight(1.0, 2.0, 0.0) - 0.25, 2.0)};
  CHECK_FALSE(detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), sea, level).has_value());
  // Over every crest and deep under: answered (nothing, and the whole box).
  level.pose.translation.y() = 1.0;
  const auto above = detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), sea, level);
  REQUIRE(above);
  REQUIRE(*above);
  CHECK((*above)->submergedVolume == 0.0);
  level.pose.translation.y() = -2.0;
  const auto under = detail::waveBoxHydrostatics(half, Eigen::Vector3d::Zero(), sea, level);
  REQUIRE(under);
  REQUIRE(*under);
  CHECK((*under)->submergedVolume == Approx(volume).epsilon(1e-12));
}
