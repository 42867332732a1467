// SPDX-License-Identifier: Zlib
// The exact path on a prepared mesh (PreparedPolyhedron.hpp) gives the same bits as the exact path
// on the plain mesh, on every surface, at random poses, for convex and non-convex meshes; and it
// refuses at preparation what polyhedralHydrostatics refuses per call.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>

#include "RandomRotation.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;

namespace {

void requireSameBits(const HydrostaticsResult& a, const HydrostaticsResult& b) {
  CHECK(a.submergedVolume == b.submergedVolume);
  CHECK(a.centerOfBuoyancy == b.centerOfBuoyancy);
  CHECK(a.buoyancyForce == b.buoyancyForce);
  CHECK(a.torqueAboutCenterOfMass == b.torqueAboutCenterOfMass);
  CHECK(a.torqueAboutOrigin == b.torqueAboutOrigin);
  CHECK(a.waterplaneArea == b.waterplaneArea);
  CHECK(a.waterplaneCentroid == b.waterplaneCentroid);
  CHECK(a.wettedArea == b.wettedArea);
  CHECK(a.stiffness == b.stiffness);
  CHECK(a.fluidDensity == b.fluidDensity);
}

}  // namespace

TEST_CASE("prepared polyhedron: the same bits as the plain exact path", "[hydrostatics][exact][prepared]") {
  const FlatSurface water(0.2, 1025.0);
  const GerstnerWaves waves({GerstnerWave{0.1, 6.0, Eigen::Vector2d(1.0, 0.3), 0.0, 0.5}}, 0.2);
  const UniformMedium air;
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> height(-1.2, 1.2);
  for (const Mesh& source : {primitives::box({1.0, 0.5, 1.0}), primitives::icosphere(0.5, 2),
                             primitives::torus(1.0, 0.25, 24, 12)}) {
    auto mesh = std::make_shared<const Mesh>(source);
    const Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(mesh);
    REQUIRE(prepared.ok());
    CHECK(prepared->memoryBytes() == mesh->triangles.size() * 13 * sizeof(double));
    for (int i = 0; i < 60; ++i) {
      HydrostaticsQuery query;
      query.pose.rotation = hydrotex::testing::randomRotation(rng);
      query.pose.translation = Eigen::Vector3d(0.3 * i, 0.2 + height(rng), -0.1 * i);
      query.centerOfMass = Eigen::Vector3d(0.02, -0.05, 0.01);
      if (i % 2) query.mass = 300.0;
      for (const LiquidSurface* surface : {static_cast<const LiquidSurface*>(&water),
                                           static_cast<const LiquidSurface*>(&waves),
                                           static_cast<const LiquidSurface*>(&air)}) {
        const Expected<HydrostaticsResult> plain = polyhedralHydrostaticsUnchecked(*mesh, *surface, query);
        const Expected<HydrostaticsResult> fast = polyhedralHydrostatics(*prepared, *surface, query);
        REQUIRE(plain.ok());
        REQUIRE(fast.ok());
        requireSameBits(*plain, *fast);
      }
    }
  }
}

TEST_CASE("prepared polyhedron: refusals at preparation and per call", "[hydrostatics][exact][prepared]") {
  CHECK_FALSE(PreparedPolyhedron::prepare(nullptr).ok());
  Mesh open = primitives::box({1, 1, 1});
  open.triangles.pop_back();
  CHECK_FALSE(PreparedPolyhedron::prepare(std::make_shared<const Mesh>(open)).ok());
  Mesh outOfRange = primitives::box({1, 1, 1});
  outOfRange.triangles[0][1] = 99;
  CHECK_FALSE(PreparedPolyhedron::prepare(std::make_shared<const Mesh>(outOfRange)).ok());
  Mesh notFinite = primitives::box({1, 1, 1});
  notFinite.positions[3].x() = NAN;
  CHECK_FALSE(PreparedPolyhedron::prepare(std::make_shared<const Mesh>(notFinite)).ok());
  CHECK_FALSE(PreparedPolyhedron::prepare(std::make_shared<const Mesh>(Mesh{})).ok());

  const Expected<PreparedPolyhedron> box = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(primitives::box({1, 1, 1})));
  REQUIRE(box.ok());
  HydrostaticsQuery query;
  query.gravity = 0.0;
  CHECK_FALSE(polyhedralHydrostatics(*box, FlatSurface(), query).ok());
}
