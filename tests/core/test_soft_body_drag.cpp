// SPDX-License-Identifier: Zlib
// SoftBodyDrag, the drag of a body whose vertices move on their own, against closed forms: a box
// whose vertices all move with one velocity U through still water, under the linear pressure
// term alone, is a rigid body under F = -rho c (2 A_x) U (the two faces across the motion; the
// others see no normal velocity), which the semi-implicit step takes as U' = U / (1 + rho c 2 A_x
// dt / M) with no deformation; vertices at rest in the liquid get nothing; pinned ones nothing.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "TestSurfaces.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/TexelPressure.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/step/SoftBodyDrag.hpp"

using namespace hydrotex;

namespace {

/// Each triangle's area vector (m^2) of `mesh`.
std::vector<Eigen::Vector3d> triangleAreaVectors(const Mesh& mesh) {
  std::vector<Eigen::Vector3d> areaVectors;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.positions[std::size_t(t[0])];
    areaVectors.push_back(0.5 * (mesh.positions[std::size_t(t[1])] - a).cross(mesh.positions[std::size_t(t[2])] - a));
  }
  return areaVectors;
}

/// SoftBodyDrag's input for `geometry` (the spans must outlive it), default coefficients.
SoftBodyDragInput dragInput(const BodyGeometry& geometry, const std::vector<float>& wet,
                            const std::vector<Eigen::Vector3d>& areaVectors, const std::vector<Eigen::Vector3d>& velocity,
                            const std::vector<double>& mass, const LiquidSurface& surface, double dt) {
  SoftBodyDragInput in;
  in.mesh = &geometry.mesh;
  in.bake = &geometry.bake;
  in.textures = &geometry.textures;
  in.wetFraction = wet;
  in.triangleAreaVectors = areaVectors;
  in.vertexVelocity = velocity;
  in.vertexMass = mass;
  in.surface = &surface;
  in.dt = dt;
  return in;
}

/// A 1 x 0.5 x 0.8 m box baked at 64^2, wholly under a flat surface 10 m above it.
struct SubmergedBox {
  BodyGeometry geometry;
  FlatSurface surface{10.0, 1000.0};
  std::vector<float> pressure, wet;
  std::vector<Eigen::Vector3d> areaVectors;

  SubmergedBox() {
    BodyGeometrySettings settings;
    settings.bake.width = settings.bake.height = 64;
    Expected<BodyGeometry> made = prepareBodyGeometry(primitives::box({1.0, 0.5, 0.8}), settings);
    REQUIRE(made.ok());
    geometry = std::move(made).value();
    pressure.resize(geometry.textures.size());
    wet.resize(geometry.textures.size());
    texelPressures(geometry.textures, surface, 0.0, 9.81, pressure, wet);
    areaVectors = triangleAreaVectors(geometry.mesh);
  }

  SoftBodyDragInput input(const std::vector<Eigen::Vector3d>& velocity, const std::vector<double>& mass, double dt) const {
    SoftBodyDragInput in = dragInput(geometry, wet, areaVectors, velocity, mass, surface, dt);
    in.viscosity = 1e-3;
    in.coefficients.advancingPressure = 0.0;
    in.coefficients.retreatingPressure = 0.0;
    in.coefficients.linearPressureVelocity = 0.5;
    in.coefficients.skinFrictionScale = 0.0;
    return in;
  }
};

}  // namespace

TEST_CASE("soft body drag: a translating box slows as the implicit step of its linear damping says", "[step][drag][closed-form]") {
  const SubmergedBox box;
  const std::size_t count = box.geometry.mesh.positions.size();
  const double totalMass = 8.0, dt = 0.01, c = 0.5, rho = 1000.0, facesAcross = 2.0 * 0.5 * 0.8;
  const Eigen::Vector3d u(0.7, 0.0, 0.0);
  const std::vector<Eigen::Vector3d> velocity(count, u);
  const std::vector<double> mass(count, totalMass / double(count));
  std::vector<Eigen::Vector3d> change(count);
  SoftBodyDrag drag;
  const SoftBodyDragResult result = drag.step(box.input(velocity, mass, dt), change);
  // Every texel is under water (wet fraction 1) and the texels tile the faces: the force is the
  // faces' to float rounding of the texel areas (1e-6).
  CHECK(result.texelsVisited == box.geometry.textures.size());
  CHECK(result.force.x() == Approx(-rho * c * facesAcross * u.x()).epsilon(1e-6));
  CHECK(std::abs(result.force.y()) < 1e-6 * std::abs(result.force.x()));
  CHECK(std::abs(result.force.z()) < 1e-6 * std::abs(result.force.x()));
  // Implicit along the motion: U' = U / (1 + k), k = rho c 2 A_x dt / M (here 0.5); no deformation,
  // every vertex the same change (the force's float rounding of the texel areas: 1e-6 of U).
  const double k = rho * c * facesAcross * dt / totalMass;
  const Eigen::Vector3d expected = u / (1.0 + k) - u;
  for (const Eigen::Vector3d& dv : change) CHECK((dv - expected).norm() < 1e-6 * u.norm());
  // The work: the kinetic energy lost, over dt (<= 0).
  const double lost = 0.5 * totalMass * ((u / (1.0 + k)).squaredNorm() - u.squaredNorm()) / dt;
  CHECK(result.power < 0.0);
  CHECK(result.power == Approx(lost).epsilon(1e-5));
}

TEST_CASE("soft body drag: vertices at rest in the liquid and pinned vertices get nothing", "[step][drag]") {
  const SubmergedBox box;
  const std::size_t count = box.geometry.mesh.positions.size();
  std::vector<Eigen::Vector3d> change(count);
  SoftBodyDrag drag;
  // Moving with the current: no relative velocity, no force, no change (exactly).
  const Eigen::Vector3d current(0.3, 0.0, -0.2);
  const std::vector<Eigen::Vector3d> withCurrent(count, current);
  const std::vector<double> unit(count, 1.0);
  SoftBodyDragInput input = box.input(withCurrent, unit, 0.01);  // spans: the vectors must outlive it
  input.current = current;
  const SoftBodyDragResult still = drag.step(input, change);
  CHECK(still.force.norm() == 0.0);
  CHECK(still.power == 0.0);
  for (const Eigen::Vector3d& dv : change) CHECK(dv.norm() == 0.0);
  // A pinned vertex (mass 0) is left as it is while the others slow down.
  std::vector<double> mass(count, 1.0);
  mass[0] = 0.0;
  const std::vector<Eigen::Vector3d> velocity(count, Eigen::Vector3d(0.0, -0.4, 0.0));
  drag.step(box.input(velocity, mass, 0.01), change);
  CHECK(change[0].norm() == 0.0);
  for (std::size_t n = 1; n < count; ++n) CHECK(change[n].y() > 0.0);  // slowed: against the downward motion
}

TEST_CASE("soft body drag under waves: the surface interpolated above the vertices within its bound", "[step][drag][waves]") {
  // A 642-vertex icosphere (radius 0.5 m) held 0.8 m under peers_waves.json's three waves, its
  // vertices at rest: the drag is the orbital motion's. The surface above each vertex comes from
  // jets over the footprint (bound kDragSurfaceHeightError, 1e-4 m) instead of a Newton search per
  // vertex; the orbital velocities' decay exp(k (y - h)) then moves by at most k 1e-4 = 2.7e-4
  // (k of the 2.3 m wave), so force and velocity changes stay within 1e-3 of the per-vertex answer.
  const GerstnerWaves sea = hydrotex::test::gerstnerSeas().front().waves;  // "swell"
  const hydrotex::test::SurfaceWithoutSmoothness perVertex(sea);
  const double time = 2.6;
  Mesh ball = primitives::icosphere(0.5, 3);
  for (Eigen::Vector3d& p : ball.positions) p += Eigen::Vector3d(1.5, -0.8, -0.7);
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = 32;
  Expected<BodyGeometry> made = prepareBodyGeometry(ball, settings);
  REQUIRE(made.ok());
  const BodyGeometry& geometry = *made;
  const std::size_t count = geometry.mesh.positions.size();
  REQUIRE(count > 600);
  std::vector<float> pressure(geometry.textures.size()), wet(geometry.textures.size());
  texelPressures(geometry.textures, sea, time, 9.81, pressure, wet);
  const std::vector<Eigen::Vector3d> areaVectors = triangleAreaVectors(geometry.mesh);
  const std::vector<Eigen::Vector3d> velocity(count, Eigen::Vector3d::Zero());
  const std::vector<double> mass(count, 50.0 / double(count));
  SoftBodyDragInput input = dragInput(geometry, wet, areaVectors, velocity, mass, sea, 1.0 / 60.0);
  input.time = time;
  std::vector<Eigen::Vector3d> interpolatedChange(count), askedChange(count);
  SoftBodyDrag drag;
  input.surface = &sea;
  const SoftBodyDragResult interpolated = drag.step(input, interpolatedChange);
  input.surface = &perVertex;
  const SoftBodyDragResult asked = drag.step(input, askedChange);
  REQUIRE(asked.force.norm() > 0.1);  // the orbital speeds 0.8 m down: a few cm/s
  const double error = (interpolated.force - asked.force).norm() / asked.force.norm();
  CHECK(error > 0.0);  // the heights were interpolated: not the per-vertex bits
  CHECK(error <= 1e-3);
  double largest = 0.0, difference = 0.0;
  for (std::size_t n = 0; n < count; ++n) {
    largest = std::max(largest, askedChange[n].norm());
    difference = std::max(difference, (interpolatedChange[n] - askedChange[n]).norm());
  }
  CHECK(difference <= 1e-3 * largest);
  WARN("soft body drag under waves, interpolated surface against per vertex: force difference " << error);
}
