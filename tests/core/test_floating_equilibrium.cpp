// SPDX-License-Identifier: Zlib
// Floating equilibrium and righting-lever curves (FloatingEquilibrium.hpp) against closed forms:
// box barge draft and GM, the wall-sided GZ formula, a circular cylinder's zero GZ, the square
// log's stable orientations and a cube at 0.6 of the liquid's density (docs/stability.md).

#include <catch2/catch.hpp>
#include <cmath>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/FloatingEquilibrium.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

using namespace hydrotex;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

/// A box of length `length` (x), depth `depth` (y) and beam `beam` (z), centred at the origin, at
/// relative density `s` with its centre of mass `kg` above the keel on the centre line.
struct Barge {
  Mesh mesh;
  FloatingBody body;
  double beam, draft, kg;
};

Barge barge(double length, double depth, double beam, double s, double kg) {
  Barge b;
  b.mesh = primitives::box(Eigen::Vector3d(length, depth, beam));
  b.body.mass = s * 1000.0 * length * depth * beam;
  b.body.centerOfMass = Eigen::Vector3d(0.0, -0.5 * depth + kg, 0.0);
  b.beam = beam;
  b.draft = s * depth;
  b.kg = kg;
  return b;
}

/// GM = KB + BM - KG of a box barge about its length (BM = B^2 / (12 T)).
double boxGm(double beam, double draft, double kg) { return 0.5 * draft + beam * beam / (12.0 * draft) - kg; }

/// Wall-sided righting lever GZ = sin(phi) (GM + BM/2 tan^2(phi)) (Biran, Ship Hydrostatics and
/// Stability, 2003, the wall-sided formula; docs/stability.md).
double wallSidedGz(double phi, double gm, double bm) { return std::sin(phi) * (gm + 0.5 * bm * std::tan(phi) * std::tan(phi)); }

/// Its integral from 0 to phi: GM (1 - cos phi) + BM/2 (sec phi + cos phi - 2).
double wallSidedArea(double phi, double gm, double bm) {
  return gm * (1.0 - std::cos(phi)) + 0.5 * bm * (1.0 / std::cos(phi) + std::cos(phi) - 2.0);
}

/// Angle between the body's up axis and the world's (rad).
double tilt(const Pose& pose) { return std::acos(std::clamp(pose.rotation(1, 1), -1.0, 1.0)); }

// The solver stops when the displaced volume is within 1e-12 of m / rho and the moments within
// 1e-10 m g L (FloatingSettings::tolerance); on these exact polyhedral bodies every closed-form
// quantity below is then met to about 1e-9 (relative) and the tests ask for that.
constexpr double kExact = 1e-9;

}  // namespace

TEST_CASE("a box barge floats upright at draft T = s D with GM = KB + BM - KG", "[floating]") {
  // Barge 2 x 1 (beam) x 0.5 m at relative density 0.4, centre of mass at mid-depth:
  // T = 0.2, KB = 0.1, BM_T = 1 / 2.4, BM_L = 4 / 2.4, KG = 0.25.
  const Barge b = barge(2.0, 0.5, 1.0, 0.4, 0.25);
  Expected<FloatingEquilibrium> eq = findFloatingEquilibrium(b.mesh, b.body);
  REQUIRE(eq);
  CHECK(eq->converged);
  CHECK(eq->stable);
  CHECK_FALSE(eq->startUnstable);
  CHECK(eq->draft == Approx(0.2).epsilon(kExact));
  CHECK(std::abs(eq->heel) < kExact);
  CHECK(std::abs(eq->trim) < kExact);
  CHECK(eq->hydrostatics.submergedVolume == Approx(0.4).epsilon(kExact));
  CHECK(eq->hydrostatics.waterplaneArea == Approx(2.0).epsilon(kExact));
  CHECK(eq->hydrostatics.centerOfBuoyancy.y() == Approx(-0.1).epsilon(kExact));
  CHECK(eq->gmTransverse == Approx(boxGm(1.0, 0.2, 0.25)).epsilon(kExact));
  CHECK(eq->gmTransverse == Approx(0.26666666667).epsilon(1e-9));  // REFERENCES' value
  CHECK(eq->gmLongitudinal == Approx(boxGm(2.0, 0.2, 0.25)).epsilon(kExact));
  // The mesh origin is the box centre: 0.25 - 0.2 = 0.05 m above the surface.
  CHECK(eq->pose.translation.y() == Approx(0.05).epsilon(kExact));

  SECTION("a lower centre of mass raises GM by as much") {
    const Barge low = barge(2.0, 0.5, 1.0, 0.4, 0.1);
    Expected<FloatingEquilibrium> lowEq = findFloatingEquilibrium(low.mesh, low.body);
    REQUIRE(lowEq);
    CHECK(lowEq->gmTransverse == Approx(boxGm(1.0, 0.2, 0.1)).epsilon(kExact));
    CHECK(lowEq->draft == Approx(0.2).epsilon(kExact));
  }
  SECTION("an off-centre weight heels it until B is under G, as the wall-sided formula says") {
    // Move G sideways by d: equilibrium where GZ(phi) measured from the centre line equals
    // d cos(phi): sin(phi) (GM + BM/2 tan^2 phi) = d cos(phi) (wall-sided, small enough heel).
    Barge shifted = b;
    const double d = 0.02;
    shifted.body.centerOfMass.z() = d;
    Expected<FloatingEquilibrium> heeled = findFloatingEquilibrium(shifted.mesh, shifted.body);
    REQUIRE(heeled);
    const double gm = boxGm(1.0, 0.2, 0.25), bm = 1.0 / 2.4;
    const double phi = std::abs(heeled->heel);
    CHECK(phi > 1.0 * kDeg);
    CHECK(wallSidedGz(phi, gm, bm) == Approx(d * std::cos(phi)).epsilon(kExact));
    // The weight on the +z side takes +z down: Rx(phi) maps +z to -y sin(phi), a positive heel.
    CHECK(heeled->heel > 0.0);
  }
}

TEST_CASE("the righting lever of a box follows the wall-sided formula until the bilge emerges", "[floating]") {
  SECTION("barge 2 x 1 (beam) x 0.5 m at s = 0.4: bilge emerges at 21.8 deg") {
    const Barge b = barge(2.0, 0.5, 1.0, 0.4, 0.25);
    StabilityCurveSettings settings;
    settings.maxAngle = 20.0 * kDeg;
    settings.step = 1.0 * kDeg;
    Expected<RightingLeverCurve> curve = rightingLeverCurve(b.mesh, b.body, settings);
    REQUIRE(curve);
    REQUIRE(curve->angles.size() == 21);
    const double gm = boxGm(1.0, 0.2, 0.25), bm = 1.0 / 2.4;
    for (std::size_t k = 0; k < curve->angles.size(); ++k) {
      INFO("heel " << curve->angles[k] / kDeg << " deg");
      CHECK(curve->levers[k] == Approx(wallSidedGz(curve->angles[k], gm, bm)).margin(1e-9));
      CHECK(std::abs(curve->otherAngles[k]) < 1e-9);  // the symmetric box does not trim
    }
    CHECK(curve->gm == Approx(gm).epsilon(kExact));
  }
  SECTION("a deep box (wall-sided to 45 deg): areas to 30 and 40 deg, GM from the slope at 0") {
    // Beam 2, draft 1, depth 3, KG 0.6: bilge emerges at atan(2 T / B) = 45 deg, deck edge at 63 deg.
    const Barge b = barge(6.0, 3.0, 2.0, 1.0 / 3.0, 0.6);
    const double gm = boxGm(2.0, 1.0, 0.6), bm = 4.0 / 12.0;
    StabilityCurveSettings settings;
    settings.maxAngle = 44.0 * kDeg;
    settings.step = 1.0 * kDeg;
    Expected<RightingLeverCurve> curve = rightingLeverCurve(b.mesh, b.body, settings);
    REQUIRE(curve);
    for (std::size_t k = 0; k < curve->angles.size(); ++k)
      CHECK(curve->levers[k] == Approx(wallSidedGz(curve->angles[k], gm, bm)).margin(1e-9));
    CHECK(curve->gm == Approx(gm).epsilon(kExact));
    // Trapezoids of width h on [0, a]: error at most a h^2 / 12 max|GZ''|; GZ'' of the formula is
    // below 1.7 m/rad^2 on [0, 40 deg] (1.64 from second differences on a 1e-4 rad grid).
    const double h = 1.0 * kDeg;
    REQUIRE(curve->area30);
    REQUIRE(curve->area40);
    CHECK(*curve->area30 == Approx(wallSidedArea(30.0 * kDeg, gm, bm)).margin(30.0 * kDeg * h * h / 12.0 * 1.7));
    CHECK(*curve->area40 == Approx(wallSidedArea(40.0 * kDeg, gm, bm)).margin(40.0 * kDeg * h * h / 12.0 * 1.7));
    // GZ grows all the way to 44 deg: no vanishing angle within the sweep, the maximum at the end.
    CHECK_FALSE(curve->angleOfVanishingStability);
    CHECK(curve->angleOfMaxLever == Approx(44.0 * kDeg).epsilon(1e-12));
  }
}

TEST_CASE("a full stability curve of a box: maximum and vanishing angle", "[floating]") {
  // The 2 x 1 x 0.5 m barge at s = 0.4 to 180 deg: GZ rises, peaks after deck-edge immersion (31.0
  // deg) and vanishes at 90 deg, where the section is symmetric about the vertical through G and
  // unstable (on its side: beam 0.5, draft 0.4, GM = 0.2 + 0.25/4.8 - 0.5 < 0); upside down
  // (180 deg) it is symmetric again.
  const Barge b = barge(2.0, 0.5, 1.0, 0.4, 0.25);
  StabilityCurveSettings settings;
  settings.step = 2.0 * kDeg;
  Expected<RightingLeverCurve> curve = rightingLeverCurve(b.mesh, b.body, settings);
  REQUIRE(curve);
  REQUIRE(curve->angles.size() == 91);
  REQUIRE(curve->angleOfVanishingStability);
  const double vanishing = *curve->angleOfVanishingStability;
  CHECK(vanishing == Approx(90.0 * kDeg).margin(1e-6));
  CHECK(curve->angleOfMaxLever > 21.0 * kDeg);
  CHECK(curve->angleOfMaxLever < vanishing);
  CHECK(curve->maxLever >= *std::max_element(curve->levers.begin(), curve->levers.end()));
  CHECK(std::abs(curve->levers.back()) < 1e-9);  // upside down: symmetric again
  // The curve's own sampled slope agrees with the stiffness's GM to the wall-sided cubic term:
  // GZ(2 deg) / sin(2 deg) = GM + BM/2 tan^2(2 deg).
  CHECK(curve->levers[1] / std::sin(2.0 * kDeg) ==
        Approx(curve->gm + 0.5 / 2.4 * std::pow(std::tan(2.0 * kDeg), 2)).epsilon(kExact));
}

TEST_CASE("a circular cylinder with its centre of mass on the axis has GZ = 0 at every heel", "[floating]") {
  // Radius 1, length 4 along x, 512 segments, half submerged. The polygon lies between the circles
  // of radius cos(pi/512) and 1, 1.9e-5 apart; the buoyancy's line of action of the polygon prism
  // passes within that gap of the axis (measured: 1.5e-8 m here), so GZ is held to 1.9e-5 m.
  Mesh cylinder = primitives::cylinder(1.0, 4.0, 512);
  const Eigen::Matrix3d toX = Eigen::AngleAxisd(0.5 * kPi, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (Eigen::Vector3d& p : cylinder.positions) p = toX * p;  // axis along x
  const double gap = 1.0 - std::cos(kPi / 512.0);
  FloatingBody body;
  body.mass = 0.5 * 1000.0 * kPi * 4.0;
  StabilityCurveSettings settings;
  settings.step = 15.0 * kDeg;
  Expected<RightingLeverCurve> curve = rightingLeverCurve(cylinder, body, settings);
  REQUIRE(curve);
  for (std::size_t k = 0; k < curve->angles.size(); ++k) {
    INFO("heel " << curve->angles[k] / kDeg << " deg");
    CHECK(std::abs(curve->levers[k]) < gap);
  }
  // GM = KB + BM - KG = 0 for a circle: B moves on a circle about the axis.
  CHECK(std::abs(curve->gm) < gap);
}

TEST_CASE("a square log floats upright below s = (3 - sqrt 3)/6 and tilts above", "[floating]") {
  // Square section 1 x 1, length 4 along x. Upright GM = s/2 + 1/(12 s) - 1/2 changes sign at
  // s = (3 - sqrt 3)/6 = 0.2113 (and 1 - that). Just above, the wall-sided formula gives the
  // tilted equilibrium tan^2(phi) = -2 GM / BM (valid while tan phi < 2 s: the bilge stays wet);
  // for 9/32 < s < 23/32 the log floats with a diagonal vertical (45 deg): there
  // GM = 4h/3 - sqrt(2)/2 > 0 with h = sqrt(s) the depth of the lowest edge.
  const double threshold = (3.0 - std::sqrt(3.0)) / 6.0;
  auto log = [](double s) { return barge(4.0, 1.0, 1.0, s, 0.5); };
  auto equilibrium = [&](double s) {
    const Barge b = log(s);
    Expected<FloatingEquilibrium> eq = findFloatingEquilibrium(b.mesh, b.body);
    REQUIRE(eq);
    CHECK(eq->converged);
    CHECK(eq->stable);
    CHECK(std::abs(eq->trim) < 1e-7);
    CHECK(eq->hydrostatics.submergedVolume == Approx(4.0 * s).epsilon(kExact));
    return *eq;
  };
  for (double s : {0.15, threshold - 0.01, 1.0 - threshold + 0.01, 0.85}) {
    INFO("s = " << s);
    const FloatingEquilibrium eq = equilibrium(s);
    CHECK(std::abs(eq.heel) < kExact);
    CHECK_FALSE(eq.startUnstable);
    CHECK(eq.gmTransverse == Approx(boxGm(1.0, s, 0.5)).epsilon(kExact));
  }
  for (double s : {threshold + 0.01, 0.23}) {
    INFO("s = " << s);
    const FloatingEquilibrium eq = equilibrium(s);
    CHECK(eq.startUnstable);
    CHECK(eq.startGmTransverse == Approx(boxGm(1.0, s, 0.5)).epsilon(kExact));
    const double expected = std::atan(std::sqrt(-2.0 * boxGm(1.0, s, 0.5) / (1.0 / (12.0 * s))));
    REQUIRE(std::tan(expected) < 2.0 * s);
    CHECK(std::abs(eq.heel) == Approx(expected).epsilon(1e-8));
  }
  for (double s : {0.3, 0.5, 0.7}) {
    INFO("s = " << s);
    const FloatingEquilibrium eq = equilibrium(s);
    CHECK(eq.startUnstable);
    CHECK(std::abs(eq.heel) == Approx(45.0 * kDeg).epsilon(1e-8));
    if (s <= 0.5) CHECK(eq.gmTransverse == Approx(4.0 * std::sqrt(s) / 3.0 - std::sqrt(0.5)).epsilon(1e-8));
  }
}

TEST_CASE("a cube at 0.6 of the liquid's density leaves its unstable upright pose", "[floating]") {
  // Upright: T = 0.6, GM = 0.3 + 1/7.2 - 0.5 = -0.0611 m about both axes; G - B = 0.2 m. Any
  // stable equilibrium has B vertically under G, displacement 0.6 m^3 and G - B below 0.2 m
  // (the energy m g (y_G - y_B) at equal displacement is lower).
  const Mesh cube = primitives::box(Eigen::Vector3d::Ones());
  FloatingBody body;
  body.mass = 600.0;
  Expected<FloatingEquilibrium> eq = findFloatingEquilibrium(cube, body);
  REQUIRE(eq);
  CHECK(eq->startUnstable);
  CHECK(eq->startGmTransverse == Approx(boxGm(1.0, 0.6, 0.5)).epsilon(kExact));
  CHECK(eq->startGmLongitudinal == Approx(boxGm(1.0, 0.6, 0.5)).epsilon(kExact));
  CHECK(eq->converged);
  CHECK(eq->stable);
  CHECK(eq->hydrostatics.submergedVolume == Approx(0.6).epsilon(kExact));
  const Eigen::Vector3d g = eq->pose.translation;  // the cube's centre is its centre of mass
  const Eigen::Vector3d b = eq->hydrostatics.centerOfBuoyancy;
  CHECK(std::abs(b.x() - g.x()) < 1e-8);
  CHECK(std::abs(b.z() - g.z()) < 1e-8);
  CHECK(g.y() - b.y() < 0.2 - 1e-3);
  CHECK(tilt(eq->pose) > 10.0 * kDeg);
  CHECK(eq->gmTransverse > 0.0);
  CHECK(eq->gmLongitudinal > 0.0);
}

TEST_CASE("the texture path finds the barge's equilibrium to its resolution", "[floating]") {
  const Barge b = barge(2.0, 0.5, 1.0, 0.4, 0.25);
  BodyGeometrySettings geometry;
  geometry.bake.width = geometry.bake.height = 128;
  Expected<BodyGeometry> prepared = prepareBodyGeometry(b.mesh, geometry);
  REQUIRE(prepared);
  Expected<TextureHydrostatics> texture = TextureHydrostatics::build(prepared->bake, prepared->textures);
  REQUIRE(texture);
  const FlatSurface water(0.0, 1000.0);
  const FloatingHydrostatics answer = [&](const HydrostaticsQuery& q) { return texture->query(water, q); };
  Expected<FloatingEquilibrium> eq = findFloatingEquilibrium(b.mesh, b.body, {}, answer);
  REQUIRE(eq);
  CHECK(eq->stable);
  // Texels are exact planar pieces cut exactly at the waterline; what remains is their float
  // storage (~1e-7 relative) and the waterline's texel-size moment terms: 1e-4 m on a 2 m body
  // for the draft, 1e-3 m for GM (measured at 128^2: 9e-9 m and 4.5e-4 m).
  CHECK(eq->draft == Approx(0.2).margin(1e-4));
  CHECK(eq->gmTransverse == Approx(boxGm(1.0, 0.2, 0.25)).margin(1e-3));
  CHECK(std::abs(eq->heel) < 1e-3);
}

TEST_CASE("floating equilibrium: bad input is an error naming the value", "[floating]") {
  const Barge b = barge(2.0, 0.5, 1.0, 0.4, 0.25);
  auto message = [&](const FloatingBody& body) {
    Expected<FloatingEquilibrium> eq = findFloatingEquilibrium(b.mesh, body);
    REQUIRE_FALSE(eq);
    return eq.error().message;
  };
  FloatingBody body = b.body;
  body.mass = -1.0;
  CHECK_THAT(message(body), Catch::Contains("mass -1"));
  body.mass = 1000.0;  // the whole box displaces 1000 kg
  CHECK_THAT(message(body), Catch::Contains("no floating equilibrium"));
  body = b.body;
  body.centerOfMass = Eigen::Vector3d(0.0, 1.0, 0.0);
  CHECK_THAT(message(body), Catch::Contains("outside the bounds"));

  Mesh open = b.mesh;
  open.triangles.pop_back();
  Expected<FloatingEquilibrium> openEq = findFloatingEquilibrium(open, b.body);
  REQUIRE_FALSE(openEq);

  StabilityCurveSettings settings;
  settings.step = 0.0;
  Expected<RightingLeverCurve> curve = rightingLeverCurve(b.mesh, b.body, settings);
  REQUIRE_FALSE(curve);
  CHECK_THAT(curve.error().message, Catch::Contains("step 0"));
}
