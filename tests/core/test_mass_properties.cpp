// SPDX-License-Identifier: Zlib
// Mass properties: the exact polyhedral path against closed forms, and the texture path against
// the exact path (solid, shell, density maps).
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "TestSurfaces.hpp"

using namespace hydrotex;
using hydrotex::test::texturesOf;
namespace prim = hydrotex::primitives;

namespace {

constexpr double kPi = std::numbers::pi;

double relativeMatrixError(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return (a - b).norm() / b.norm(); }

// Mass properties of two bodies together (parallel-axis theorem to the common centre).
MassProperties combine(const MassProperties& a, const MassProperties& b) {
  MassProperties c;
  c.mass = a.mass + b.mass;
  c.volume = a.volume + b.volume;
  c.centerOfMass = (a.mass * a.centerOfMass + b.mass * b.centerOfMass) / c.mass;
  auto shifted = [&](const MassProperties& p) {
    const Eigen::Vector3d d = p.centerOfMass - c.centerOfMass;
    return Eigen::Matrix3d(p.inertia + p.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  c.inertia = shifted(a) + shifted(b);
  return c;
}

}  // namespace

TEST_CASE("exact path: box, prism and pyramid against their closed forms") {
  // These polyhedra are their own closed forms: only double rounding remains (1e-12 relative).
  SECTION("box, also off the origin") {
    const double a = 1.0, b = 2.0, c = 3.0, density = 2.0, m = density * a * b * c;
    Mesh mesh = prim::box({a, b, c});
    const Eigen::Vector3d offset(0.5, -1.0, 20.0);
    for (auto& p : mesh.positions) p += offset;
    const auto mp = polyhedralMassProperties(mesh, density);
    REQUIRE(mp.ok());
    CHECK(mp->mass == Approx(m).epsilon(1e-12));
    CHECK((mp->centerOfMass - offset).norm() < 1e-12 * offset.norm());
    const Eigen::Matrix3d expected =
        Eigen::Vector3d(m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12).asDiagonal();
    CHECK(relativeMatrixError(mp->inertia, expected) < 1e-12);
  }
  SECTION("cylinder as a regular-polygon prism") {
    const int n = 16;
    const double r = 0.5, length = 2.0, density = 3.0, theta = 2.0 * kPi / n;
    const double area = 0.5 * n * r * r * std::sin(theta);
    const double polar = n * std::pow(r, 4) * std::sin(theta) * (2.0 + std::cos(theta)) / 12.0;  // n triangles
    const double m = density * area * length;
    const auto mp = polyhedralMassProperties(prim::cylinder(r, length, n), density);
    REQUIRE(mp.ok());
    CHECK(mp->mass == Approx(m).epsilon(1e-12));
    CHECK(mp->centerOfMass.norm() < 1e-12);
    // A regular polygon's second moment is isotropic: half the polar moment about each axis.
    const double axial = density * length * polar;
    const double across = density * length * (0.5 * polar + area * length * length / 12.0);
    const Eigen::Matrix3d expected = Eigen::Vector3d(across, across, axial).asDiagonal();
    CHECK(relativeMatrixError(mp->inertia, expected) < 1e-12);
  }
  SECTION("cone as a regular-polygon pyramid") {
    const int n = 24;
    const double r = 1.0, h = 2.0, density = 1.0, theta = 2.0 * kPi / n;
    const double area = 0.5 * n * r * r * std::sin(theta);
    const double polar = n * std::pow(r, 4) * std::sin(theta) * (2.0 + std::cos(theta)) / 12.0;
    const double m = density * area * h / 3.0;
    const auto mp = polyhedralMassProperties(prim::cone(r, h, n), density);
    REQUIRE(mp.ok());
    CHECK(mp->mass == Approx(m).epsilon(1e-12));
    CHECK((mp->centerOfMass - Eigen::Vector3d(0.0, h / 4.0, 0.0)).norm() < 1e-12);
    // Sections scale by s = 1 - y/h: polar moment s^4, area s^2. Integrals over y in [0, h]:
    // s^4 -> h/5; s^2 (y - h/4)^2 -> h^3/80.
    const double axial = density * polar * h / 5.0;
    const double across = density * (0.5 * polar * h / 5.0 + area * h * h * h / 80.0);
    const Eigen::Matrix3d expected = Eigen::Vector3d(across, axial, across).asDiagonal();
    CHECK(relativeMatrixError(mp->inertia, expected) < 1e-12);
  }
}

TEST_CASE("exact path: smooth shapes converge to their analytic values") {
  // An inscribed tessellation misses O(1/n^2) of the volume and inertia; doubling the segments
  // divides the error by about 4 (checked between 3 and 5). The finer one is within 1 %
  // (measured: sphere 64 x 32 0.2 %, torus 96 x 32 0.7 %).
  auto check = [](const Mesh& coarse, const Mesh& fine, double volume, const Eigen::Matrix3d& inertiaPerMass) {
    const auto c = polyhedralMassProperties(coarse, 1.0);
    const auto f = polyhedralMassProperties(fine, 1.0);
    REQUIRE((c.ok() && f.ok()));
    const double ec = std::abs(c->volume / volume - 1.0), ef = std::abs(f->volume / volume - 1.0);
    CHECK(ec / ef == Approx(4.0).margin(1.0));
    CHECK(ef < 1e-2);
    const double ic = relativeMatrixError(c->inertia, c->mass * inertiaPerMass);
    const double jf = relativeMatrixError(f->inertia, f->mass * inertiaPerMass);
    CHECK(ic / jf == Approx(4.0).margin(1.0));
    CHECK(jf < 1e-2);
    CHECK(f->centerOfMass.norm() < 1e-12);
  };
  SECTION("sphere") {
    check(prim::uvSphere(1.0, 32, 16), prim::uvSphere(1.0, 64, 32), 4.0 / 3.0 * kPi,
          0.4 * Eigen::Matrix3d::Identity());
  }
  SECTION("torus: axis y, I_axis = m (R^2 + 3/4 r^2), I_across = m (R^2/2 + 5/8 r^2)") {
    const double big = 1.0, small = 0.3;
    const double axial = big * big + 0.75 * small * small, across = 0.5 * big * big + 0.625 * small * small;
    check(prim::torus(big, small, 48, 16), prim::torus(big, small, 96, 32), 2.0 * kPi * kPi * big * small * small,
          Eigen::Vector3d(across, axial, across).asDiagonal());
  }
}

TEST_CASE("exact path: hemispheres of two densities") {
  // Each hemisphere's centroid lies 3r/8 from the flat face; together (densities 1000 and 250)
  // the centre lies at 3r/8 (m1 - m2)/(m1 + m2). A 128 x 32 tessellation misses about 1e-3 of
  // the volume (inscribed polyhedron, O(1/n^2); measured 1.0e-3): tolerance 3e-3 on masses and
  // inertia, 1e-3 on centres (the deficit is nearly uniform over the surface, so the centroid
  // moves less).
  const double r = 2.0;
  const auto up = polyhedralMassProperties(prim::hemisphere(r, 128, 32, true), 1000.0);
  const auto down = polyhedralMassProperties(prim::hemisphere(r, 128, 32, false), 250.0);
  REQUIRE((up.ok() && down.ok()));
  CHECK(up->centerOfMass.y() == Approx(3.0 * r / 8.0).epsilon(1e-3));
  CHECK(down->centerOfMass.y() == Approx(-3.0 * r / 8.0).epsilon(1e-3));
  const double halfVolume = 2.0 / 3.0 * kPi * r * r * r;
  CHECK(up->mass == Approx(1000.0 * halfVolume).epsilon(3e-3));
  const MassProperties both = combine(*up, *down);
  CHECK(both.centerOfMass.y() == Approx(3.0 * r / 8.0 * (1000.0 - 250.0) / 1250.0).epsilon(1e-3));
  CHECK(std::abs(both.centerOfMass.x()) < 1e-12);
  // About the y axis each half has 2/5 m r^2.
  CHECK(both.inertia(1, 1) == Approx(0.4 * both.mass * r * r).epsilon(3e-3));
}

TEST_CASE("exact path: bad input is an error") {
  const Mesh box = prim::box({1.0, 1.0, 1.0});
  CHECK_FALSE(polyhedralMassProperties(box, 0.0).ok());
  CHECK_FALSE(polyhedralMassProperties(box, -1.0).ok());
  CHECK_FALSE(polyhedralMassProperties(box, std::numeric_limits<double>::quiet_NaN()).ok());
  CHECK_FALSE(polyhedralMassProperties(Mesh{}, 1.0).ok());
  Mesh open = box;
  open.triangles.pop_back();
  const auto openResult = polyhedralMassProperties(open, 1.0);
  REQUIRE_FALSE(openResult.ok());
  CHECK(openResult.error().message.find("open") != std::string::npos);
  Mesh nan = box;
  nan.positions[0].x() = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(polyhedralMassProperties(nan, 1.0).ok());
  Mesh inward = box;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  CHECK_FALSE(polyhedralMassProperties(inward, 1.0).ok());
  Mesh flipped = box;  // one triangle flipped: an edge used twice in one direction
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  CHECK_FALSE(polyhedralMassProperties(flipped, 1.0).ok());
}

TEST_CASE("texture path matches the exact path on every primitive and converges") {
  const std::vector<std::pair<std::string, Mesh>> meshes = {
      {"box", prim::box({1.0, 2.0, 3.0})},           {"uv sphere", prim::uvSphere(1.0, 48, 24)},
      {"icosphere", prim::icosphere(1.0, 3)},        {"cylinder", prim::cylinder(0.5, 2.0, 32)},
      {"cone", prim::cone(1.0, 2.0, 32)},            {"torus", prim::torus(1.0, 0.3, 48, 16)},
      {"hemisphere", prim::hemisphere(1.0, 48, 12, true)}, {"wigley", prim::wigleyHull(4.0, 0.4, 0.25, 24, 8)}};
  for (const auto& [name, mesh] : meshes) {
    const auto exact = polyhedralMassProperties(mesh, 1000.0);
    REQUIRE(exact.ok());
    const double size = std::sqrt(exact->inertia.trace() / exact->mass);  // radius of gyration (m)
    for (const Eigen::Vector3d& reference : {Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0.3, -0.2, 0.1)}) {
      INFO(name << ", reference point " << reference.transpose());
      TextureMassModel model;
      model.referencePoint = reference;
      double previousInertiaError = 0.0;
      for (int resolution : {64, 128, 256}) {
        INFO("resolution " << resolution);
        const MassProperties t = textureMassProperties(texturesOf(mesh, resolution), model);
        // Volume: sum of cones, exact up to float storage (1e-6 relative).
        CHECK(t.volume == Approx(exact->volume).epsilon(1e-6));
        CHECK(t.mass == Approx(exact->mass).epsilon(1e-6));
        // Centre and inertia: a texel straddling triangle edges is not flat, an O(h^2) error
        // (h the texel size). Measured at 256: centre within 2e-5 of the size, inertia within
        // 2e-4; bounds 5x that.
        const double inertiaError = relativeMatrixError(t.inertia, exact->inertia);
        if (resolution == 256) {
          CHECK((t.centerOfMass - exact->centerOfMass).norm() / size < 1e-4);
          CHECK(inertiaError < 1e-3);
        }
        // Second order: doubling the resolution divides the inertia error by about 4 or more
        // (required: more than 3).
        if (previousInertiaError > 0.0) CHECK(previousInertiaError / inertiaError > 3.0);
        previousInertiaError = inertiaError;
      }
    }
  }
}

TEST_CASE("texture path: shell of a box") {
  // Six plates of areal density s: mass s * 2(ab + bc + ca); a plate b x c at x = +-a/2 has
  // I_xx = m (b^2 + c^2)/12, I_yy = m (a^2/4 + c^2/12), I_zz = m (a^2/4 + b^2/12).
  const double a = 1.0, b = 2.0, c = 3.0, s = 4.0;
  const Eigen::Vector3d e(a, b, c);
  Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
  double mass = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double plate = s * e[u] * e[v];
    mass += 2.0 * plate;
    expected(axis, axis) += 2.0 * plate * (e[u] * e[u] + e[v] * e[v]) / 12.0;
    expected(u, u) += 2.0 * plate * (e[axis] * e[axis] / 4.0 + e[v] * e[v] / 12.0);
    expected(v, v) += 2.0 * plate * (e[axis] * e[axis] / 4.0 + e[u] * e[u] / 12.0);
  }
  TextureMassModel model;
  model.solidDensity = 0.0;
  model.shellDensity = s;
  const MassProperties t = textureMassProperties(texturesOf(prim::box(e), 200), model);
  // Area is exact (1e-6, float); flat full texels carry their exact covariance, partly covered
  // texels at the face borders an approximate one: 1e-4 relative at 200 texels.
  CHECK(t.mass == Approx(mass).epsilon(1e-6));
  CHECK(t.centerOfMass.norm() < 1e-6);
  CHECK(relativeMatrixError(t.inertia, expected) < 1e-4);
  CHECK(t.volume == Approx(a * b * c).epsilon(1e-6));  // the geometry's volume, whatever the model
}

TEST_CASE("texture path: density maps") {
  const double r = 1.0;
  // 64 x 32 sphere: the equator is a ring of vertices at v = 1/2, which falls on a texel border
  // at even resolutions, so no texel straddles y = 0.
  const Mesh sphere = prim::uvSphere(r, 64, 32);
  const SurfaceTextures tex = texturesOf(sphere, 256);
  const TextureMassIntegrator integrator(tex, Eigen::Vector3d::Zero());

  SECTION("uniform map equals the solid") {
    TextureMassModel solid;
    solid.solidDensity = 800.0;
    TextureMassModel mapped = solid;
    mapped.texelDensity.assign(tex.size(), 800.0f);
    const auto a = integrator.evaluate(solid);
    const auto b = integrator.evaluate(mapped);
    REQUIRE((a.ok() && b.ok()));
    // Same float terms, same order: equal to rounding of the density product (1e-6).
    CHECK(b->mass == Approx(a->mass).epsilon(1e-6));
    CHECK((b->centerOfMass - a->centerOfMass).norm() < 1e-6 * r);
    CHECK(relativeMatrixError(b->inertia, a->inertia) < 1e-6);
  }
  SECTION("two densities split at y = 0 are two hemispheres") {
    TextureMassModel model;  // reference point at the centre: cones stay within their half
    model.texelDensity.resize(tex.size());
    for (std::size_t i = 0; i < tex.size(); ++i) model.texelDensity[i] = tex.position[i].y() > 0.0f ? 1000.0f : 250.0f;
    const auto t = integrator.evaluate(model);
    REQUIRE(t.ok());
    // The exact reference: the two polyhedral hemispheres with the sphere's own rings.
    const auto up = polyhedralMassProperties(prim::hemisphere(r, 64, 16, true), 1000.0);
    const auto down = polyhedralMassProperties(prim::hemisphere(r, 64, 16, false), 250.0);
    REQUIRE((up.ok() && down.ok()));
    const MassProperties both = combine(*up, *down);
    CHECK(t->mass == Approx(both.mass).epsilon(1e-6));  // cones fill each half exactly
    CHECK((t->centerOfMass - both.centerOfMass).norm() < 1e-4 * r);  // as the uniform case at 256
    CHECK(relativeMatrixError(t->inertia, both.inertia) < 1e-3);
    // And the closed form of two smooth hemispheres, within the tessellation error (1e-2).
    CHECK(t->centerOfMass.y() == Approx(3.0 * r / 8.0 * 750.0 / 1250.0).epsilon(1e-2));
  }
  SECTION("bad maps are errors") {
    TextureMassModel model;
    model.texelDensity.assign(tex.size() - 1, 1000.0f);
    CHECK_FALSE(integrator.evaluate(model).ok());
    CHECK(std::isnan(textureMassProperties(tex, model).mass));
    model.texelDensity.assign(tex.size(), 1000.0f);
    model.texelDensity[17] = -1.0f;
    CHECK_FALSE(integrator.evaluate(model).ok());
    model.texelDensity[17] = std::numeric_limits<float>::quiet_NaN();
    CHECK_FALSE(integrator.evaluate(model).ok());
    TextureMassModel negative;
    negative.solidDensity = -5.0;
    CHECK_FALSE(integrator.evaluate(negative).ok());
  }
}
