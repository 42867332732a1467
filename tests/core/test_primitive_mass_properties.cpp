// SPDX-License-Identifier: Zlib
// A solid sphere's mass properties in closed form (PrimitiveMassProperties.hpp): the worked
// numbers, and the exact polyhedral mass properties of a fine icosphere lying between those of its
// in-sphere and its circumsphere.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mass/PrimitiveMassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;

TEST_CASE("solid sphere mass properties: closed form", "[mass][primitive][sphere]") {
  // r = 0.5 m of water: V = pi / 6 = 0.5235988 m^3, m = 523.5988 kg, I = 2/5 m r^2 = 52.35988 kg m^2.
  const Expected<MassProperties> sphere = solidSphereMassProperties(0.5, 1000.0, Eigen::Vector3d(0.1, 0.2, 0.3));
  REQUIRE(sphere.ok());
  CHECK(sphere->volume == Approx(std::numbers::pi / 6.0).epsilon(1e-15));
  CHECK(sphere->mass == Approx(523.5987755982989).epsilon(1e-15));
  CHECK(sphere->centerOfMass == Eigen::Vector3d(0.1, 0.2, 0.3));
  CHECK(sphere->inertia.isApprox(Eigen::Matrix3d::Identity() * 52.35987755982989, 1e-15));
  CHECK_FALSE(solidSphereMassProperties(0.0, 1000.0).ok());
  CHECK_FALSE(solidSphereMassProperties(0.5, -1.0).ok());
  CHECK_FALSE(solidSphereMassProperties(0.5, 1000.0, Eigen::Vector3d(NAN, 0, 0)).ok());
}

TEST_CASE("solid sphere mass properties against a fine icosphere", "[mass][primitive][sphere]") {
  // The icosphere lies inside the sphere through its vertices (r) and contains the sphere of its
  // in-radius (the least distance to a face's plane); volume and the moments of inertia about the
  // centre are integrals of non-negative integrands, hence between the two spheres' values. Its
  // centre of mass is the centre (the icosahedron is centrally symmetric), up to rounding.
  const double r = 0.5, rho = 1000.0;
  const Mesh mesh = primitives::icosphere(r, 5);
  double inRadius = r;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    inRadius = std::min(inRadius, std::abs((b - a).cross(c - a).normalized().dot(a)));
  }
  const Expected<MassProperties> outer = solidSphereMassProperties(r, rho);
  const Expected<MassProperties> inner = solidSphereMassProperties(inRadius, rho);
  const Expected<MassProperties> exact = polyhedralMassProperties(mesh, rho);
  REQUIRE(outer.ok());
  REQUIRE(inner.ok());
  REQUIRE(exact.ok());
  CHECK(exact->volume >= inner->volume);
  CHECK(exact->volume <= outer->volume);
  CHECK(exact->centerOfMass.norm() <= 1e-12);
  for (int axis = 0; axis < 3; ++axis) {
    CHECK(exact->inertia(axis, axis) >= inner->inertia(axis, axis) - 1e-9);
    CHECK(exact->inertia(axis, axis) <= outer->inertia(axis, axis) + 1e-9);
  }
  // The deficit itself: under 1e-3 of the volume at 20,480 faces.
  CHECK(1.0 - exact->volume / outer->volume < 1e-3);
}
