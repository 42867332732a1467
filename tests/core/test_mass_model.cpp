// SPDX-License-Identifier: Zlib
// MassModel: solid, shell, density maps replaced at run time, point masses on paths, combined
// with the parallel-axis theorem, and recomputed only when something changed.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "TestSurfaces.hpp"

using namespace hydrotex;
using hydrotex::test::texturesOf;
namespace prim = hydrotex::primitives;

namespace {

Eigen::Matrix3d steiner(double mass, const Eigen::Vector3d& r) {
  return mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
}

}  // namespace

TEST_CASE("mass model: a density map switched at run time to two hemispheres") {
  const double r = 1.0;
  // 64 x 32 sphere at 256^2: the equator (v = 1/2) lies on a texel border, no texel straddles it.
  const Mesh sphere = prim::uvSphere(r, 64, 32);
  const SurfaceTextures tex = texturesOf(sphere, 256);
  MassModel model(tex, Eigen::Vector3d::Zero());
  REQUIRE(model.setSolidDensity(1000.0).ok());
  const auto uniform = model.properties();
  REQUIRE(uniform.ok());
  // Uniform solid: centre at the sphere's centre (symmetric texels: float rounding, 1e-6 r).
  CHECK(uniform->centerOfMass.norm() < 1e-6 * r);

  std::vector<float> map(model.texelCount());
  for (std::size_t i = 0; i < map.size(); ++i) map[i] = tex.position[i].y() > 0.0f ? 1000.0f : 250.0f;
  REQUIRE(model.setTexelDensity(map).ok());
  const auto halves = model.properties();
  INFO((halves.ok() ? std::string() : halves.error().message));
  REQUIRE(halves.ok());
  // Exact reference: the polyhedral hemispheres with the sphere's own rings (cones from the
  // centre fill each half exactly, so the mass agrees to float rounding, 1e-6).
  const auto up = polyhedralMassProperties(prim::hemisphere(r, 64, 16, true), 1000.0);
  const auto down = polyhedralMassProperties(prim::hemisphere(r, 64, 16, false), 250.0);
  REQUIRE((up.ok() && down.ok()));
  const double mass = up->mass + down->mass;
  const Eigen::Vector3d center = (up->mass * up->centerOfMass + down->mass * down->centerOfMass) / mass;
  CHECK(halves->mass == Approx(mass).epsilon(1e-6));
  // Centre: the texel cones' centroids, 1e-4 r at 256^2 (as the uniform integrator test).
  CHECK((halves->centerOfMass - center).norm() < 1e-4 * r);
  // Closed form of smooth hemispheres, 3r/8 (m1 - m2) / (m1 + m2), within the 64 x 32
  // tessellation's error (inscribed polyhedron, 1e-2 relative).
  CHECK(halves->centerOfMass.y() == Approx(3.0 * r / 8.0 * 750.0 / 1250.0).epsilon(1e-2));
  const Eigen::Matrix3d inertia = up->inertia + steiner(up->mass, up->centerOfMass - center) + down->inertia +
                                  steiner(down->mass, down->centerOfMass - center);
  CHECK((halves->inertia - inertia).norm() / inertia.norm() < 1e-3);  // as the integrator's test at 256^2
  CHECK(model.texelPasses() == 2);
}

TEST_CASE("mass model: point masses combine by the parallel-axis theorem and follow paths") {
  const Eigen::Vector3d extents(2.0, 1.0, 1.5);
  const Mesh box = prim::box(extents);
  MassModel model(texturesOf(box, 64), Eigen::Vector3d::Zero());
  REQUIRE(model.setSolidDensity(500.0).ok());
  const auto solid = model.properties();
  REQUIRE(solid.ok());
  // A box is tiled exactly by its flat texels: mass to float rounding (1e-6), inertia 1e-5.
  const double boxMass = 500.0 * extents.prod();
  CHECK(solid->mass == Approx(boxMass).epsilon(1e-6));

  PointMass cargo;
  cargo.mass = 300.0;
  cargo.path = {{0.0, {0.0, 0.5, 0.0}}, {2.0, {0.8, 0.5, 0.0}}, {3.0, {0.8, 0.5, 0.6}}};
  REQUIRE(model.addPointMass(cargo).ok());
  CHECK(pathPosition(cargo.path, -1.0).isApprox(Eigen::Vector3d(0.0, 0.5, 0.0)));
  CHECK(pathPosition(cargo.path, 1.0).isApprox(Eigen::Vector3d(0.4, 0.5, 0.0)));
  CHECK(pathPosition(cargo.path, 2.5).isApprox(Eigen::Vector3d(0.8, 0.5, 0.3)));
  CHECK(pathPosition(cargo.path, 9.0).isApprox(Eigen::Vector3d(0.8, 0.5, 0.6)));

  model.advanceTo(1.0);
  const auto moved = model.properties();
  REQUIRE(moved.ok());
  const Eigen::Vector3d p(0.4, 0.5, 0.0);
  // Combination in double of the texel part and the point mass: exact to 1e-12.
  const double total = solid->mass + 300.0;
  const Eigen::Vector3d center = (solid->mass * solid->centerOfMass + 300.0 * p) / total;
  CHECK(moved->mass == Approx(total).epsilon(1e-12));
  CHECK((moved->centerOfMass - center).norm() < 1e-12);
  const Eigen::Matrix3d expected =
      solid->inertia + steiner(solid->mass, solid->centerOfMass - center) + steiner(300.0, p - center);
  CHECK((moved->inertia - expected).norm() < 1e-9 * expected.norm());
  CHECK(model.texelPasses() == 1);  // only the point mass moved: no texel pass

  REQUIRE(model.setPointMassPosition(0, Eigen::Vector3d(-0.5, 0.0, 0.0)).ok());
  model.advanceTo(2.5);  // the path was dropped: stays where it was put
  CHECK(model.pointMasses()[0].position.isApprox(Eigen::Vector3d(-0.5, 0.0, 0.0)));
}

TEST_CASE("mass model: nothing is recomputed when nothing changed") {
  const Mesh box = prim::box({1.0, 1.0, 1.0});
  MassModel model(texturesOf(box, 32), Eigen::Vector3d::Zero());
  PointMass still;
  still.mass = 10.0;
  still.path = {{0.0, {0.1, 0.0, 0.0}}, {1.0, {0.2, 0.0, 0.0}}};
  REQUIRE(model.addPointMass(still).ok());
  REQUIRE(model.properties().ok());
  const std::uint64_t revision = model.revision();
  for (int i = 0; i < 10; ++i) {
    model.advanceTo(2.0 + i);            // past the path's end: held at the last key
    REQUIRE(model.setSolidDensity(1000.0).ok());  // the value it already has
    REQUIRE(model.setShellDensity(0.0).ok());
    REQUIRE(model.properties().ok());
  }
  // advanceTo(2) moved it once (from 0.1 to 0.2), then nothing.
  CHECK(model.revision() == revision + 1);
  CHECK(model.texelPasses() == 1);
  CHECK(model.combinations() == 2);
  REQUIRE(model.setShellDensity(2.0).ok());
  REQUIRE(model.properties().ok());
  CHECK(model.texelPasses() == 2);
}

TEST_CASE("mass model: a deformed surface changes the volume, the mass follows") {
  const Mesh box = prim::box({1.0, 1.0, 1.0});
  BakeSettings settings;
  settings.width = settings.height = 32;
  auto bake = bakeSurface(box, box.uv, settings);
  REQUIRE(bake.ok());
  MassModel model(evaluateSurface(*bake, box, box.uv), Eigen::Vector3d::Zero());
  REQUIRE(model.setShellDensity(3.0, Conserved::Density).ok());  // the areal density is kept
  Mesh scaled = box;
  for (Eigen::Vector3d& p : scaled.positions) p = p.cwiseProduct(Eigen::Vector3d(2.0, 1.0, 1.5));
  REQUIRE(model.setGeometry(evaluateSurface(*bake, scaled, box.uv)).ok());
  const auto after = model.properties();
  REQUIRE(after.ok());
  // 2 x 1 x 1.5 box: volume 3, area 2 (2 + 3 + 1.5) = 13; PT/VAT exact on flat texels (1e-6).
  CHECK(model.volume() == Approx(3.0).epsilon(1e-6));
  CHECK(after->mass == Approx(1000.0 * 3.0 + 3.0 * 13.0).epsilon(1e-6));
}

TEST_CASE("mass model: a growing body keeps its mass or its density, as its setters asked", "[closed-form]") {
  // A 1 m cube grown to s = 1.2 (volume s^3, area s^2): a solid given by its mass keeps m, by its
  // density m s^3; a shell keeps its mass sigma A (an envelope stretching thinner) unless asked
  // to keep sigma (sigma A s^2). The texel path is exact on flat texels (PT/VAT: 1e-6), the
  // triangle path polyhedral (double sums: 1e-9).
  const Mesh cube = prim::box({1.0, 1.0, 1.0});
  const double s = 1.2, solidMass = 500.0, sigma = 3.0, area = 6.0;
  Mesh grown = cube;
  for (Eigen::Vector3d& p : grown.positions) p *= s;
  BakeSettings settings;
  settings.width = settings.height = 32;
  auto bake = bakeSurface(cube, cube.uv, settings);
  REQUIRE(bake.ok());
  const bool followTriangles = GENERATE(false, true);
  const double tolerance = followTriangles ? 1e-9 : 1e-6;
  CAPTURE(followTriangles);
  auto model = [&](Conserved solid, Conserved shell) {
    MassModel made(evaluateSurface(*bake, cube, cube.uv), Eigen::Vector3d::Zero());
    if (followTriangles) REQUIRE(made.followTriangles(*bake, cube.uv, cube).ok());
    REQUIRE(made.setSolidDensity(solidMass, solid).ok());  // 1 m^3: density 500 is mass 500
    REQUIRE(made.setShellDensity(sigma, shell).ok());
    return made;
  };
  auto grow = [&](MassModel& m, const Mesh& mesh) {
    REQUIRE((followTriangles ? m.setGeometry(mesh) : m.setGeometry(evaluateSurface(*bake, mesh, cube.uv))).ok());
  };
  MassModel keepsMass = model(Conserved::Mass, Conserved::Mass);
  MassModel keepsDensity = model(Conserved::Density, Conserved::Density);
  CHECK(keepsMass.solidConserved() == Conserved::Mass);
  CHECK(keepsDensity.shellConserved() == Conserved::Density);
  grow(keepsMass, grown);
  grow(keepsDensity, grown);
  const auto kept = keepsMass.properties();
  const auto added = keepsDensity.properties();
  REQUIRE(kept.ok());
  REQUIRE(added.ok());
  CHECK(kept->mass == Approx(solidMass + sigma * area).epsilon(tolerance));
  CHECK(keepsMass.solidDensity() == Approx(solidMass / (s * s * s)).epsilon(tolerance));
  CHECK(keepsMass.shellDensity() == Approx(sigma / (s * s)).epsilon(tolerance));
  CHECK(added->mass == Approx(solidMass * s * s * s + sigma * area * s * s).epsilon(tolerance));
  CHECK(keepsDensity.solidDensity() == solidMass);
  // The default: a solid keeps its density, a shell its mass.
  MassModel defaults(evaluateSurface(*bake, cube, cube.uv), Eigen::Vector3d::Zero());
  if (followTriangles) REQUIRE(defaults.followTriangles(*bake, cube.uv, cube).ok());
  REQUIRE(defaults.setSolidDensity(solidMass).ok());
  REQUIRE(defaults.setShellDensity(sigma).ok());
  grow(defaults, grown);
  const auto byDefault = defaults.properties();
  REQUIRE(byDefault.ok());
  CHECK(byDefault->mass == Approx(solidMass * s * s * s + sigma * area).epsilon(tolerance));
  // The user changes the model on the grown body: the new shell's mass sigma' (s^2 A) is what is
  // kept from then on; shrinking back spreads it over the rest area.
  REQUIRE(keepsMass.setShellDensity(1.0).ok());
  grow(keepsMass, cube);
  const auto shrunk = keepsMass.properties();
  REQUIRE(shrunk.ok());
  CHECK(shrunk->mass == Approx(solidMass + 1.0 * area * s * s).epsilon(tolerance));
  CHECK(keepsMass.shellDensity() == Approx(s * s).epsilon(tolerance));
}

TEST_CASE("mass model: a point mass's mass changed at run time moves the centre by the lever rule", "[closed-form]") {
  // A 1 m cube of 1000 kg centred at the origin and a point mass m at (1, 0, 0): the centre sits at
  // m / (1000 + m) along x. Changing m is one new revision and no texel pass.
  const Mesh cube = prim::box({1.0, 1.0, 1.0});
  MassModel model(texturesOf(cube, 32), Eigen::Vector3d::Zero());
  PointMass cargo;
  cargo.mass = 100.0;
  cargo.position = Eigen::Vector3d(1.0, 0.0, 0.0);
  const auto index = model.addPointMass(cargo);
  REQUIRE(index.ok());
  REQUIRE(model.properties().ok());
  const std::uint64_t passes = model.texelPasses(), revision = model.revision();
  REQUIRE(model.setPointMassMass(*index, 500.0).ok());
  CHECK(model.revision() == revision + 1);
  const auto heavier = model.properties();
  REQUIRE(heavier.ok());
  // The cube's volume and centre from flat texels: float rounding (1e-6).
  CHECK(heavier->mass == Approx(1500.0).epsilon(1e-6));
  CHECK(heavier->centerOfMass.x() == Approx(500.0 / 1500.0).epsilon(1e-6));
  CHECK(model.texelPasses() == passes);
  CHECK(model.pointMasses()[*index].mass == 500.0);
  // The same mass again changes nothing; bad values are refused and change nothing.
  REQUIRE(model.setPointMassMass(*index, 500.0).ok());
  CHECK(model.revision() == revision + 1);
  CHECK_FALSE(model.setPointMassMass(*index, -1.0).ok());
  CHECK_FALSE(model.setPointMassMass(*index, std::nan("")).ok());
  CHECK_FALSE(model.setPointMassMass(7, 1.0).ok());
  CHECK(model.pointMasses()[*index].mass == 500.0);
}

TEST_CASE("mass model: bad values are errors that name them") {
  const Mesh box = prim::box({1.0, 1.0, 1.0});
  MassModel model(texturesOf(box, 16), Eigen::Vector3d::Zero());
  CHECK_FALSE(model.setSolidDensity(-1.0).ok());
  CHECK_FALSE(model.setShellDensity(std::nan("")).ok());
  CHECK_FALSE(model.setTexelDensity(std::vector<float>(3, 1.0f)).ok());
  std::vector<float> negative(model.texelCount(), 1.0f);
  negative[2] = -4.0f;
  REQUIRE(model.setTexelDensity(negative).ok());  // values are checked by the texel pass
  const auto refused = model.properties();
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().message.find("density map") != std::string::npos);
  REQUIRE(model.setTexelDensity({}).ok());
  PointMass unordered;
  unordered.mass = 1.0;
  unordered.path = {{1.0, Eigen::Vector3d::Zero()}, {0.5, Eigen::Vector3d::Zero()}};
  const auto added = model.addPointMass(unordered);
  REQUIRE_FALSE(added.ok());
  CHECK(added.error().message.find("path[1]") != std::string::npos);
  CHECK_FALSE(model.setPointMassPosition(4, Eigen::Vector3d::Zero()).ok());
  REQUIRE(model.setSolidDensity(0.0).ok());
  CHECK_FALSE(model.properties().ok());  // nothing left: zero mass
}

TEST_CASE("mass model: a deforming body that follows triangles recomputes per moved mesh, exactly") {
  const Mesh rest = prim::torus(1.0, 0.3, 32, 12);
  BakeSettings settings;
  settings.width = settings.height = 64;
  auto bake = bakeSurface(rest, rest.uv, settings);
  REQUIRE(bake.ok());
  const Eigen::Vector3d reference(0.0, 0.05, 0.0);
  MassModel model(evaluateSurface(*bake, rest, rest.uv), reference);
  REQUIRE(model.setSolidDensity(400.0).ok());
  REQUIRE(model.setShellDensity(2.0, Conserved::Density).ok());  // both densities kept: sums checked against them
  REQUIRE(model.properties().ok());
  CHECK(model.texelPasses() == 1);
  CHECK_FALSE(model.followsTriangles());

  REQUIRE(model.followTriangles(*bake, rest.uv, rest).ok());
  CHECK(model.followsTriangles());
  CHECK(model.texelCount() == bake->coveredCount());
  auto moved = [&](double amount) {
    Mesh out = rest;
    for (Eigen::Vector3d& p : out.positions) p = p.cwiseProduct(Eigen::Vector3d(1.0 + amount, 1.0 - 0.5 * amount, 1.0));
    return out;
  };
  // Solid and shell exactly polyhedral (sums in double over 768 triangles: 1e-9, as in
  // test_triangle_mass_integrator.cpp).
  auto checkExact = [&](const Mesh& mesh, const MassProperties& got) {
    const auto solid = polyhedralMassProperties(mesh, 400.0);
    REQUIRE(solid.ok());
    double area = 0.0;
    for (const Eigen::Vector3i& t : mesh.triangles)
      area += 0.5 * (mesh.positions[std::size_t(t[1])] - mesh.positions[std::size_t(t[0])])
                        .cross(mesh.positions[std::size_t(t[2])] - mesh.positions[std::size_t(t[0])])
                        .norm();
    CHECK(got.mass == Approx(solid->mass + 2.0 * area).epsilon(1e-9));
    CHECK(got.volume == Approx(solid->volume).epsilon(1e-9));
    CHECK(model.volume() == Approx(solid->volume).epsilon(1e-9));
  };
  const auto atRest = model.properties();
  REQUIRE(atRest.ok());
  checkExact(rest, *atRest);
  CHECK(model.trianglePasses() == 1);
  CHECK(model.texelPasses() == 1);  // no texel pass: the triangle sums

  // Nothing changed: nothing recomputed.
  const std::uint64_t revision = model.revision();
  for (int i = 0; i < 5; ++i) REQUIRE(model.properties().ok());
  CHECK(model.revision() == revision);
  CHECK(model.trianglePasses() == 1);

  // A moved mesh: one triangle pass, no texel pass.
  const Mesh stretched = moved(0.4);
  REQUIRE(model.setGeometry(stretched).ok());
  const auto after = model.properties();
  REQUIRE(after.ok());
  checkExact(stretched, *after);
  CHECK(model.trianglePasses() == 2);
  CHECK(model.texelPasses() == 1);
  // The texture geometry is refused once the model follows triangles.
  CHECK_FALSE(model.setGeometry(evaluateSurface(*bake, stretched, rest.uv)).ok());

  // A density map: one pass over the pieces when it is set, none per moved mesh after that.
  REQUIRE(model.setTexelDensity(std::vector<float>(model.texelCount(), 400.0f)).ok());
  const auto mapped = model.properties();
  REQUIRE(mapped.ok());
  // The map of one value is the uniform solid, up to the pieces' float moments (1e-6).
  CHECK(mapped->mass == Approx(after->mass).epsilon(1e-6));
  CHECK(model.texelPasses() == 2);
  CHECK(model.trianglePasses() == 3);
  REQUIRE(model.setGeometry(moved(0.2)).ok());
  REQUIRE(model.properties().ok());
  CHECK(model.texelPasses() == 2);
  CHECK(model.trianglePasses() == 4);

  // A bad map is reported by properties() (as on the texel path), a good one recovers.
  std::vector<float> negative(model.texelCount(), 400.0f);
  negative[7] = -1.0f;
  REQUIRE(model.setTexelDensity(negative).ok());
  const auto refused = model.properties();
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().message.find("density map") != std::string::npos);
  REQUIRE(model.setTexelDensity({}).ok());
  REQUIRE(model.properties().ok());
  // A broken mesh is an error, reported again by properties() until a good one comes.
  Mesh broken = rest;
  broken.positions[0].x() = std::nan("");
  CHECK_FALSE(model.setGeometry(broken).ok());
  CHECK_FALSE(model.properties().ok());
  REQUIRE(model.setGeometry(rest).ok());
  const auto recovered = model.properties();
  REQUIRE(recovered.ok());
  checkExact(rest, *recovered);

  // Without followTriangles the mesh overload is refused; a bake that does not fit is an error.
  MassModel plain(evaluateSurface(*bake, rest, rest.uv), reference);
  CHECK_FALSE(plain.setGeometry(rest).ok());
  UvLayout shorter = rest.uv;
  shorter.uvTriangles.pop_back();
  CHECK_FALSE(plain.followTriangles(*bake, shorter, rest).ok());
  CHECK_FALSE(plain.followsTriangles());
}
