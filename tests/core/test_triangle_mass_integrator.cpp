// SPDX-License-Identifier: Zlib
// TriangleMassIntegrator (issue 5, deforming bodies): uniform solids and shells on deformed meshes
// against the exact polyhedral reference, a density map of two hemispheres against the exact
// halves and the closed form, a density map on a deformed mesh against the texel path on a fresh
// evaluation, and bad input.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "TestSurfaces.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/mass/TriangleMassIntegrator.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

SurfaceBake bakeAt(const Mesh& mesh, int resolution) { return test::bakeOf(mesh, resolution); }

TriangleMassIntegrator integratorFor(const SurfaceBake& bake, const Mesh& mesh, const Eigen::Vector3d& reference) {
  auto created = TriangleMassIntegrator::create(bake, mesh.uv, reference);
  INFO((created.ok() ? std::string() : created.error().message));
  REQUIRE(created.ok());
  return std::move(created).value();
}

// Scaled non-uniformly, then twisted about y by `twist` radians per metre of height: vertices
// move, the topology stays, so the surface stays closed.
Mesh scaledAndTwisted(const Mesh& rest, const Eigen::Vector3d& scale, double twist) {
  Mesh moved = rest;
  for (Eigen::Vector3d& p : moved.positions) {
    const Eigen::Vector3d s = p.cwiseProduct(scale);
    const double angle = twist * s.y(), c = std::cos(angle), n = std::sin(angle);
    p = Eigen::Vector3d(c * s.x() + n * s.z(), s.y(), -n * s.x() + c * s.z());
  }
  return moved;
}

double meshSize(const Mesh& mesh) {
  double size = 0.0;
  for (const auto& p : mesh.positions) size = std::max(size, p.norm());
  return size;
}

Eigen::Matrix3d steiner(double mass, const Eigen::Vector3d& r) {
  return mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
}

// Exact shell of areal density `sigma` by an independent rule: the three edge midpoints with
// weights 1/3 integrate every polynomial of degree 2 over a triangle exactly (Strang and Fix,
// An Analysis of the Finite Element Method, 1973, table 4.1), and the second moments are degree 2.
MassProperties shellReference(const Mesh& mesh, double sigma) {
  double mass = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.positions[std::size_t(t[0])];
    const Eigen::Vector3d& b = mesh.positions[std::size_t(t[1])];
    const Eigen::Vector3d& c = mesh.positions[std::size_t(t[2])];
    const double area = 0.5 * (b - a).cross(c - a).norm();
    mass += sigma * area;
    for (const Eigen::Vector3d& m : {Eigen::Vector3d(0.5 * (a + b)), Eigen::Vector3d(0.5 * (b + c)), Eigen::Vector3d(0.5 * (c + a))}) {
      first += sigma * area / 3.0 * m;
      second += sigma * area / 3.0 * m * m.transpose();
    }
  }
  MassProperties result;
  result.mass = mass;
  result.centerOfMass = first / mass;
  const Eigen::Matrix3d central = second - mass * result.centerOfMass * result.centerOfMass.transpose();
  result.inertia = central.trace() * Eigen::Matrix3d::Identity() - central;
  return result;
}

// Two bodies' mass properties combined (parallel-axis theorem).
MassProperties combined(const MassProperties& a, const MassProperties& b) {
  MassProperties result;
  result.mass = a.mass + b.mass;
  result.centerOfMass = (a.mass * a.centerOfMass + b.mass * b.centerOfMass) / result.mass;
  result.inertia = a.inertia + steiner(a.mass, a.centerOfMass - result.centerOfMass) + b.inertia +
                   steiner(b.mass, b.centerOfMass - result.centerOfMass);
  return result;
}

void checkClose(const MassProperties& got, const MassProperties& expected, double relative, double size) {
  CHECK(got.mass == Approx(expected.mass).epsilon(relative));
  CHECK((got.centerOfMass - expected.centerOfMass).norm() <= relative * size);
  CHECK((got.inertia - expected.inertia).norm() <= relative * expected.inertia.norm());
}

}  // namespace

TEST_CASE("triangle mass integrator: uniform solids and shells on deformed meshes are exactly polyhedral") {
  const std::vector<std::pair<std::string, Mesh>> meshes = {{"torus", prim::torus(1.0, 0.3, 32, 12)},
                                                            {"uv sphere", prim::uvSphere(1.0, 32, 16)},
                                                            {"box", prim::subdividedBox({1.0, 2.0, 3.0}, 4)}};
  const Eigen::Vector3d reference(0.1, -0.2, 0.05);  // any apex: the cones' signed sums do not depend on it
  for (const auto& [name, rest] : meshes) {
    const SurfaceBake bake = bakeAt(rest, 64);
    TriangleMassIntegrator integrator = integratorFor(bake, rest, reference);
    CHECK(integrator.texelCount() == bake.coveredCount());
    CHECK(integrator.triangleCount() == rest.triangles.size());
    CHECK(integrator.pieceCount() == bake.pieces.size());
    for (double amount : {0.0, 0.5, 1.0}) {
      INFO(name << " deformation " << amount);
      const Mesh moved =
          scaledAndTwisted(rest, Eigen::Vector3d(1.0 + 0.5 * amount, 1.0 - 0.3 * amount, 1.0 + 0.2 * amount), 0.6 * amount);
      const double size = meshSize(moved);
      const auto exact = polyhedralMassProperties(moved, 700.0);
      REQUIRE(exact.ok());
      const MassProperties shell = shellReference(moved, 3.0);
      // Sums in double over <= 1.6k triangles of terms of the body's size: rounding ~1e-13
      // relative; 1e-9 leaves room for the references' own rounding, and any texel-size effect
      // (1e-3 and more at 64^2) would show.
      const auto solid = integrator.evaluate(moved, 700.0, 0.0);
      REQUIRE(solid.ok());
      checkClose(*solid, *exact, 1e-9, size);
      CHECK(solid->volume == Approx(exact->volume).epsilon(1e-9));
      CHECK(integrator.volume() == Approx(exact->volume).epsilon(1e-9));
      const auto hull = integrator.evaluate(0.0, 3.0);  // the same mesh, no second update
      REQUIRE(hull.ok());
      checkClose(*hull, shell, 1e-9, size);
      const auto both = integrator.evaluate(700.0, 3.0);
      REQUIRE(both.ok());
      checkClose(*both, combined(*exact, shell), 1e-9, size);
    }
  }
}

TEST_CASE("triangle mass integrator: a uniform density map is the uniform solid (exact piece covariances)") {
  // Every piece's barycentric moments come from its own clipped polygon, so a map of one value
  // reproduces the polyhedral solid up to the pieces' float moments (6e-8 each, summed in double):
  // 1e-6. Means alone without the pieces' covariances would be off in the inertia by the texel
  // covariances, (texel / size)^2 / 6 ~ 2e-3 at 32^2 and 1e-4 at 128^2: far outside.
  const Mesh rest = prim::torus(1.0, 0.3, 32, 12);
  const Mesh moved = scaledAndTwisted(rest, Eigen::Vector3d(1.3, 0.8, 1.1), 0.5);
  const auto exact = polyhedralMassProperties(moved, 640.0);
  REQUIRE(exact.ok());
  for (int resolution : {32, 128}) {
    INFO("resolution " << resolution);
    const SurfaceBake bake = bakeAt(rest, resolution);
    TriangleMassIntegrator integrator = integratorFor(bake, rest, Eigen::Vector3d(0.0, 0.1, 0.0));
    REQUIRE(integrator.setTexelDensity(std::vector<float>(integrator.texelCount(), 640.0f)).ok());
    CHECK(integrator.hasTexelDensity());
    const auto mapped = integrator.evaluate(moved, 123.0, 0.0);  // the map replaces the solid density
    REQUIRE(mapped.ok());
    checkClose(*mapped, *exact, 1e-6, meshSize(moved));
    // Back to the uniform solid.
    REQUIRE(integrator.setTexelDensity({}).ok());
    CHECK_FALSE(integrator.hasTexelDensity());
    const auto uniform = integrator.evaluate(640.0, 0.0);
    REQUIRE(uniform.ok());
    checkClose(*uniform, *exact, 1e-9, meshSize(moved));
  }
}

TEST_CASE("triangle mass integrator: two hemispheres of a density map") {
  const double r = 1.0, upper = 1000.0, lower = 250.0;
  const Mesh sphere = prim::uvSphere(r, 64, 32);
  // Exact reference: the polyhedral hemispheres with the sphere's own rings (the cones from the
  // centre over each half's triangles fill that half exactly; its equatorial cap passes through
  // the apex and adds no volume).
  const auto up = polyhedralMassProperties(prim::hemisphere(r, 64, 16, true), upper);
  const auto down = polyhedralMassProperties(prim::hemisphere(r, 64, 16, false), lower);
  REQUIRE((up.ok() && down.ok()));
  const MassProperties halves = combined(*up, *down);
  // 256^2: the equator (v = 1/2) lies on a texel border; 101^2: a row of texels straddles it.
  for (int resolution : {256, 101}) {
    INFO("resolution " << resolution);
    const SurfaceBake bake = bakeAt(sphere, resolution);
    const SurfaceTextures textures = evaluateSurface(bake, sphere, sphere.uv);
    TriangleMassIntegrator integrator = integratorFor(bake, sphere, Eigen::Vector3d::Zero());
    REQUIRE(integrator.update(sphere).ok());
    std::vector<float> map(integrator.texelCount());
    // A texel takes the density of the side its centre (PT) lies on; one that straddles the
    // equator (pieces of triangles above and below) gives its other side's pieces the wrong one.
    double straddling = 0.0;  // Sum of |cone volume| over straddling texels (m^3)
    for (std::size_t i = 0; i < map.size(); ++i) {
      map[i] = textures.position[i].y() > 0.0f ? float(upper) : float(lower);
      bool above = false, below = false;
      for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k) {
        const Eigen::Vector3i& t = sphere.triangles[bake.pieces[k].triangle];
        const double y = sphere.positions[std::size_t(t[0])].y() + sphere.positions[std::size_t(t[1])].y() +
                         sphere.positions[std::size_t(t[2])].y();
        (y > 0.0 ? above : below) = true;
      }
      if (above && below)
        straddling += std::abs(double(textures.position[i].dot(textures.areaVector[i]))) / 3.0;
    }
    if (resolution == 256) CHECK(straddling == 0.0);
    if (resolution == 101) CHECK(straddling > 0.0);
    REQUIRE(integrator.setTexelDensity(map).ok());
    const auto got = integrator.evaluate(0.0, 0.0);
    REQUIRE(got.ok());
    // Tolerances from the straddling texels: at most dm = (upper - lower) straddling kg is on the
    // wrong side, which moves the mass by dm, the centre by at most 2 dm r / M (a first moment of
    // dm r over a mass that changed by dm) and the inertia by at most 2 dm r^2 (in the Frobenius
    // norm, sqrt(2) dm r^2 for a point at radius r, plus the centre's shift); on top, the pieces'
    // float moments (1e-6 relative, as the uniform map above).
    const double dm = (upper - lower) * straddling;
    CHECK(std::abs(got->mass - halves.mass) <= dm + 1e-6 * halves.mass);
    CHECK((got->centerOfMass - halves.centerOfMass).norm() <= 2.0 * dm * r / halves.mass + 1e-6 * r);
    CHECK((got->inertia - halves.inertia).norm() <= 2.0 * dm * r * r + 1e-6 * halves.inertia.norm());
    // Closed form of smooth hemispheres, y = 3r/8 (m1 - m2) / (m1 + m2), within the 64 x 32
    // tessellation's error (inscribed polyhedron: 1e-2 relative, as the texel path's test).
    CHECK(got->centerOfMass.y() == Approx(3.0 * r / 8.0 * (upper - lower) / (upper + lower)).epsilon(1e-2));
    // Off the axis: only the straddling texels (which pick a side around the ring unevenly)
    // and the float moments, as the centre above.
    CHECK(std::abs(got->centerOfMass.x()) <= 2.0 * dm * r / halves.mass + 1e-6 * r);
    CHECK(std::abs(got->centerOfMass.z()) <= 2.0 * dm * r / halves.mass + 1e-6 * r);
  }
}

TEST_CASE("triangle mass integrator: a density map on a deformed mesh agrees with the texel path") {
  const Eigen::Vector3d reference(0.05, 0.1, -0.05);
  const std::vector<std::pair<std::string, Mesh>> meshes = {{"torus", prim::torus(1.0, 0.3, 48, 16)},
                                                            {"uv sphere", prim::uvSphere(1.0, 48, 24)}};
  for (const auto& [name, rest] : meshes) {
    std::vector<double> centreErrors, inertiaErrors;  // texel path against the triangle path, per resolution
    for (int resolution : {64, 256}) {
      INFO(name << " at " << resolution);
      const SurfaceBake bake = bakeAt(rest, resolution);
      const SurfaceTextures restTextures = evaluateSurface(bake, rest, rest.uv);
      // A smooth map over the rest pose (painted once, carried by the texels as the mesh moves).
      TextureMassModel model;
      model.referencePoint = reference;
      model.texelDensity.resize(restTextures.size());
      for (std::size_t i = 0; i < restTextures.size(); ++i) {
        const Eigen::Vector3d p = restTextures.position[i].cast<double>();
        model.texelDensity[i] = float(600.0 + 250.0 * std::sin(3.0 * p.x()) * std::cos(2.0 * p.z()) + 150.0 * p.y());
      }
      model.shellDensity = 2.0;
      TriangleMassIntegrator integrator = integratorFor(bake, rest, reference);
      REQUIRE(integrator.setTexelDensity(model.texelDensity).ok());
      const Mesh moved = scaledAndTwisted(rest, Eigen::Vector3d(1.4, 0.7, 1.1), 0.8);
      const auto exact = integrator.evaluate(moved, 0.0, model.shellDensity);
      REQUIRE(exact.ok());
      const SurfaceTextures fresh = evaluateSurface(bake, moved, rest.uv);
      const auto texel = TextureMassIntegrator(fresh, reference).evaluate(model);
      REQUIRE(texel.ok());
      // The texel path puts a texel's cone at its PT (the pieces' area-weighted centroid, shifted
      // along the area vector) and approximates its spread by the parallelogram of its edges
      // (weighted by the block's mean density); the triangle path is exact per piece. Both give
      // the same mass (the cone volumes are exact in both, to float rounding). The texel path's
      // approximation is a second-order quantity of the texel: per texel at most its cone mass
      // times its squared diameter (|eu|^2 + |ev|^2), i.e. the bound
      //   B = Sum rho_i |v_i| (|eu_i|^2 + |ev_i|^2)   (kg m^2),
      // against which the second moments (inertia) are checked, and B / M / size for the centre
      // (a second moment divided by a mass and a length). Float rounding: 1e-6 relative.
      double bound = 0.0;
      for (std::size_t i = 0; i < fresh.size(); ++i) {
        const double v = std::abs(double(fresh.position[i].cast<double>().dot(fresh.areaVector[i].cast<double>()) -
                                         reference.dot(fresh.areaVector[i].cast<double>()))) / 3.0;
        bound += double(model.texelDensity[i]) * v *
                 double(fresh.edgeU[i].squaredNorm() + fresh.edgeV[i].squaredNorm());
      }
      const double size = meshSize(moved);
      CHECK(texel->mass == Approx(exact->mass).epsilon(1e-6));
      CHECK(texel->volume == Approx(exact->volume).epsilon(1e-6));
      const double centreError = (texel->centerOfMass - exact->centerOfMass).norm();
      const double inertiaError = (texel->inertia - exact->inertia).norm();
      CHECK(centreError <= bound / exact->mass / size + 1e-6 * size);
      CHECK(inertiaError <= bound + 1e-6 * exact->inertia.norm());
      // The bound is itself second order in the texel size: 1.5e-2 of the inertia at 64^2, 16x
      // less at 256^2 (measured 1.7e-2 and 1.1e-3 on the torus).
      CHECK(bound < 0.03 * (64.0 / resolution) * (64.0 / resolution) * exact->inertia.norm());
      centreErrors.push_back(centreError);
      inertiaErrors.push_back(inertiaError / exact->inertia.norm());
    }
    // And the paths converge to each other at second order (what a texel-size approximation in
    // the texel path gives, and no error of either path's own would): 4x the resolution, ~16x
    // smaller differences (measured 14x to 17x); at least 8x.
    CHECK(centreErrors[0] > 8.0 * centreErrors[1]);
    CHECK(inertiaErrors[0] > 8.0 * inertiaErrors[1]);
  }
}

TEST_CASE("triangle mass integrator: bad input is an error that leaves the last good state") {
  const Mesh rest = prim::uvSphere(1.0, 24, 12);
  const SurfaceBake bake = bakeAt(rest, 32);
  TriangleMassIntegrator integrator = integratorFor(bake, rest, Eigen::Vector3d::Zero());
  CHECK_FALSE(integrator.evaluate(1000.0, 0.0).ok());  // no mesh yet
  REQUIRE(integrator.setTexelDensity(std::vector<float>(integrator.texelCount(), 800.0f)).ok());
  const auto good = integrator.evaluate(rest, 0.0, 0.0);
  REQUIRE(good.ok());

  // Maps: wrong size, negative, NaN, infinite: errors; the previous map stays.
  CHECK_FALSE(integrator.setTexelDensity(std::vector<float>(3, 1.0f)).ok());
  for (float bad : {-1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    INFO("density " << bad);
    std::vector<float> map(integrator.texelCount(), 500.0f);
    map[map.size() / 2] = bad;
    const Status refused = integrator.setTexelDensity(map);
    REQUIRE_FALSE(refused.ok());
    CHECK(refused.error().message.find("density map") != std::string::npos);
    const auto kept = integrator.evaluate(0.0, 0.0);
    REQUIRE(kept.ok());
    CHECK(kept->mass == good->mass);
  }
  // Densities passed to evaluate.
  CHECK_FALSE(integrator.evaluate(-1.0, 0.0).ok());
  CHECK_FALSE(integrator.evaluate(0.0, std::nan("")).ok());

  // Meshes: another triangle count, an index out of range, a non-finite vertex; evaluate is an
  // error until a good mesh comes.
  Mesh fewer = rest;
  fewer.triangles.pop_back();
  CHECK_FALSE(integrator.update(fewer).ok());
  CHECK_FALSE(integrator.evaluate(0.0, 0.0).ok());
  Mesh outOfRange = rest;
  outOfRange.triangles[5][1] = int(rest.positions.size());
  CHECK_FALSE(integrator.update(outOfRange).ok());
  Mesh notFinite = rest;
  notFinite.positions[3].x() = std::numeric_limits<double>::infinity();
  CHECK_FALSE(integrator.update(notFinite).ok());
  CHECK_FALSE(integrator.evaluate(0.0, 0.0).ok());
  REQUIRE(integrator.update(rest).ok());
  REQUIRE(integrator.evaluate(0.0, 0.0).ok());
  CHECK(integrator.evaluate(0.0, 0.0)->mass == good->mass);

  // Preparation: a bake naming a triangle the layout lacks, a UV index out of range, a
  // non-finite reference point.
  UvLayout shorter = rest.uv;
  shorter.uvTriangles.pop_back();
  CHECK_FALSE(TriangleMassIntegrator::create(bake, shorter, Eigen::Vector3d::Zero()).ok());
  UvLayout badIndex = rest.uv;
  badIndex.uvTriangles[0][2] = -1;
  CHECK_FALSE(TriangleMassIntegrator::create(bake, badIndex, Eigen::Vector3d::Zero()).ok());
  CHECK_FALSE(TriangleMassIntegrator::create(bake, rest.uv, Eigen::Vector3d::Constant(std::nan(""))).ok());
  CHECK_FALSE(TriangleMassIntegrator::create(bake, UvLayout{}, Eigen::Vector3d::Zero()).ok());
}
