// SPDX-License-Identifier: Zlib
// Wet appearance against Lekner and Dorf's worked numbers (docs/references.md).
#include <catch2/catch.hpp>

#include "hydrotex/wetting/WetShading.hpp"

using namespace hydrotex;

namespace {
double hsvSaturation(const Eigen::Vector3d& rgb) { return (rgb.maxCoeff() - rgb.minCoeff()) / rgb.maxCoeff(); }
}  // namespace

TEST_CASE("Water (n = 1.33): R_bar, p, R1 and the wet albedo of a = 0.5", "[wet_shading]") {
  // The worked numbers are given to 6 digits: tolerance half a unit of the last digit.
  CHECK(averageInternalReflectance(1.33) == Approx(0.065931).margin(5e-7));
  CHECK(internalReflectionProbability(1.33) == Approx(0.471949).margin(5e-7));
  CHECK(filmReflectance(1.33) == Approx(0.020059).margin(5e-7));
  const WetAlbedo wet = wetAlbedo(0.5, 1.33);
  CHECK(wet.total == Approx(0.35870).margin(5e-6));
  CHECK(wet.diffuse == Approx(0.33864).margin(5e-6));
}

TEST_CASE("RGB darkens and saturates; a film reflects more than a very dark surface", "[wet_shading]") {
  const Eigen::Vector3d dry(0.6, 0.4, 0.2);
  const Eigen::Vector3d wet = wetDiffuseRgb(dry, 1.33);
  // Worked numbers to 3 digits.
  CHECK(wet.x() == Approx(0.433).margin(5e-4));
  CHECK(wet.y() == Approx(0.255).margin(5e-4));
  CHECK(wet.z() == Approx(0.114).margin(5e-4));
  CHECK(hsvSaturation(wet) > hsvSaturation(dry));
  // Darker channels darken more (relative), as in the paper's figure 7.
  CHECK(wet.z() / dry.z() < wet.y() / dry.y());
  CHECK(wet.y() / dry.y() < wet.x() / dry.x());
  // Below a dry albedo of about 0.04 the total wet albedo exceeds the dry one (docs/references.md).
  CHECK(wetAlbedo(0.03, 1.33).total > 0.03);
  CHECK(wetAlbedo(0.05, 1.33).total < 0.05);
  // A dry texel keeps its colour, a saturated one takes the wet colour.
  CHECK((wetSurfaceRgb(dry, 0.0, 1.33) - dry).norm() < 1e-15);
  CHECK((wetSurfaceRgb(dry, 1.0, 1.33) - wet).norm() < 1e-15);
  // A coloured liquid (less red transmitted) darkens red further; T = 1 is the clear case.
  const Eigen::Vector3d tea = wetDiffuseRgb(dry, 1.33, Eigen::Vector3d(0.8, 0.9, 1.0));
  CHECK(tea.x() < wet.x());
  CHECK(tea.z() == wet.z());
}
