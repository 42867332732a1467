// SPDX-License-Identifier: Zlib
// The per-texel pressure of a posed surface (TexelPressure.hpp), which soft bodies use, against the
// exact polyhedral path on the same mesh: submerged volume, wetted area and the pressure force,
// and the vertex forces against the texel forces they share out.

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "TestSurfaces.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/TexelPressure.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;

namespace {

struct PosedSurface {
  Mesh mesh;  // world frame
  SurfaceBake bake;
  SurfaceTextures textures;
  std::vector<Eigen::Vector3d> triangleAreaVectors;
};

PosedSurface pose(Mesh mesh, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation, int resolution) {
  for (Eigen::Vector3d& p : mesh.positions) p = rotation * p + translation;
  BakeSettings settings;
  settings.width = settings.height = resolution;
  auto bake = bakeSurface(mesh, mesh.uv, settings);
  REQUIRE(bake.ok());
  PosedSurface out{mesh, std::move(bake).value(), {}, {}};
  out.textures = evaluateSurface(out.bake, out.mesh, out.mesh.uv);
  for (const Eigen::Vector3i& t : out.mesh.triangles) {
    const Eigen::Vector3d& a = out.mesh.positions[std::size_t(t[0])];
    out.triangleAreaVectors.push_back(0.5 * (out.mesh.positions[std::size_t(t[1])] - a)
                                                .cross(out.mesh.positions[std::size_t(t[2])] - a));
  }
  return out;
}

}  // namespace

TEST_CASE("texel pressures of a tilted box agree with the exact path", "[texel_pressure]") {
  const Mesh box = primitives::box({1.0, 0.6, 0.8});
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())).toRotationMatrix();
  const PosedSurface s = pose(box, rotation, {0.2, 0.1, -0.3}, 256);
  const FlatSurface water(0.0, 1000.0);
  const double g = 9.81;
  std::vector<float> pressure(s.textures.position.size()), wet(s.textures.position.size());
  const TexelPressureSums sums = texelPressures(s.textures, water, 0.0, g, pressure, wet);

  HydrostaticsQuery query;  // the mesh is already in the world: identity pose
  query.gravity = g;
  const auto exact = polyhedralHydrostatics(s.mesh, water, query);
  REQUIRE(exact.ok());
  // The enclosed volume is exact from the texels (SurfaceTextures::position), to float rounding.
  CHECK(sums.enclosedVolume == Approx(0.48).epsilon(1e-6));
  // Submerged volume and wetted area: only texels cut by the waterline are approximated, each as
  // a parallelogram under a level surface, which is exact on a planar face; what is left is the
  // texels on chart borders (several pieces, one parallelogram) and float texels. Measured
  // volume 1.1e-7 and area 6.7e-7 relative; bounds 1e-6 and 5e-6.
  CHECK(sums.submergedVolume == Approx(exact->submergedVolume).epsilon(1e-6));
  CHECK(sums.wettedArea == Approx(exact->wettedArea).epsilon(5e-6));

  // The vertex forces sum to -sum p A over the pieces, which is the buoyancy force rho g V up to
  // the waterline texels: measured 4.5e-7 relative, bound 5e-6.
  std::vector<Eigen::Vector3d> vertexForce(s.mesh.positions.size());
  texelPressureVertexForces(s.bake, s.mesh, s.triangleAreaVectors, pressure, vertexForce);
  Eigen::Vector3d total = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  for (std::size_t v = 0; v < vertexForce.size(); ++v) {
    total += vertexForce[v];
    torque += s.mesh.positions[v].cross(vertexForce[v]);
  }
  CHECK((total - exact->buoyancyForce).norm() < 5e-6 * exact->buoyancyForce.norm());
  // Torque about the origin: each texel's force acts at its centroid, whereas the pressure,
  // linear over the texel, acts at a centre shifted by its covariance: over a texel of edges eU,
  // eV that moment is at most rho g A (|eU|^2 + |eV|^2) / 12 (second order in the texel size).
  // Bound: that sum over the wet texels, 0.267 N m here; measured 0.0229 N m (1.5e-5 of F L).
  double covarianceMoment = 0.0;
  for (std::size_t i = 0; i < wet.size(); ++i)
    covarianceMoment += double(wet[i]) * 1000.0 * g * double(s.textures.area[i]) *
                        double(s.textures.edgeU[i].squaredNorm() + s.textures.edgeV[i].squaredNorm()) / 12.0;
  const Eigen::Vector3d exactTorque = exact->centerOfBuoyancy.cross(exact->buoyancyForce);
  CAPTURE(covarianceMoment);
  CHECK((torque - exactTorque).norm() < covarianceMoment);
  // Dry texels carry no pressure; wholly wet ones are wholly wet.
  std::size_t dry = 0, full = 0;
  for (std::size_t i = 0; i < pressure.size(); ++i) {
    if (wet[i] == 0.0f) {
      ++dry;
      CHECK(pressure[i] == 0.0f);
    }
    if (wet[i] == 1.0f) ++full;
  }
  CHECK(dry > 0);
  CHECK(full > 0);
}

TEST_CASE("texel pressures in a medium are the medium's pressure, wholly wet", "[texel_pressure]") {
  const PosedSurface s = pose(primitives::box({1.0, 1.0, 1.0}), Eigen::Matrix3d::Identity(), {0.0, 5.0, 0.0}, 64);
  const UniformMedium air(1.225, std::numeric_limits<double>::infinity());
  std::vector<float> pressure(s.textures.position.size()), wet(s.textures.position.size());
  const TexelPressureSums sums = texelPressures(s.textures, air, 0.0, 9.81, pressure, wet);
  CHECK(sums.submergedVolume == sums.enclosedVolume);
  CHECK(sums.enclosedVolume == Approx(1.0).epsilon(1e-6));
  for (std::size_t i = 0; i < pressure.size(); ++i) {
    CHECK(wet[i] == 1.0f);
    CHECK(pressure[i] == float(air.pressure(s.textures.position[i].cast<double>(), 0.0, 9.81)));
  }
}

TEST_CASE("texel pressures under waves: the surface interpolated above the texels within its bound",
          "[texel_pressure][waves]") {
  // A 0.5 m icosphere floating in the shared "swell" at 64^2 (~3,000 texels, far more than the
  // jets over its footprint): the surface above each texel is interpolated within
  // kExactWaveHeightError (3.3e-6 m). Each texel's wet depth then moves by at most that, so its
  // pressure by rho g e (0.03 Pa) beside float rounding, and the submerged volume by at most e
  // times the water-plane area (pi r^2). Against the same sea asked per texel.
  const GerstnerWaves sea = hydrotex::test::gerstnerSeas().front().waves;
  const hydrotex::test::SurfaceWithoutSmoothness perTexel(sea);
  const double g = 9.81, time = 5.3, radius = 0.5;
  const Eigen::Vector3d center(1.0, sea.surfaceHeight(1.0, 2.0, time) - 0.1, 2.0);
  const PosedSurface s = pose(primitives::icosphere(radius, 3), Eigen::Matrix3d::Identity(), center, 64);
  const std::size_t count = s.textures.position.size();
  REQUIRE(count > 2000);
  std::vector<float> pressure(count), wet(count), askedPressure(count), askedWet(count);
  const TexelPressureSums interpolated = texelPressures(s.textures, sea, time, g, pressure, wet);
  const TexelPressureSums asked = texelPressures(s.textures, perTexel, time, g, askedPressure, askedWet);
  const double e = kExactWaveHeightError, rhoG = sea.density() * g;
  REQUIRE(asked.submergedVolume > 0.1);
  CHECK(interpolated.submergedVolume != asked.submergedVolume);  // interpolated: not the per-texel bits
  CHECK(std::abs(interpolated.submergedVolume - asked.submergedVolume) <= e * 3.14159265 * radius * radius);
  double worst = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const double difference = std::abs(double(pressure[i]) - double(askedPressure[i]));
    worst = std::max(worst, difference);
    CHECK(difference <= rhoG * e + 1e-6 * std::abs(double(askedPressure[i])));
  }
  WARN("texel pressures under waves, interpolated surface against per texel: worst " << worst << " Pa (bound "
                                                                                     << rhoG * e << " Pa)");
  // A texel whose position is NaN (a soft body torn apart) is not looked up in the grid (a NaN
  // point has no cell): it gets what asking the surface per texel gives it, and the others keep
  // their interpolated pressures.
  SurfaceTextures broken = s.textures;
  const std::size_t bad = count / 2;
  broken.position[bad] = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  std::vector<float> brokenPressure(count), brokenWet(count), brokenAsked(count), brokenAskedWet(count);
  texelPressures(broken, sea, time, g, brokenPressure, brokenWet);
  texelPressures(broken, perTexel, time, g, brokenAsked, brokenAskedWet);
  CHECK(std::isnan(brokenPressure[bad]) == std::isnan(brokenAsked[bad]));
  if (!std::isnan(brokenAsked[bad])) CHECK(brokenPressure[bad] == brokenAsked[bad]);
  CHECK(brokenWet[bad] == brokenAskedWet[bad]);
  CHECK(brokenPressure[bad + 1] == pressure[bad + 1]);
  CHECK(brokenPressure[0] == pressure[0]);
}
