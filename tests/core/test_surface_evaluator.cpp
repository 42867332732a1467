// SPDX-License-Identifier: Zlib
// The per-step path of a deforming body (issue 5): SurfaceEvaluator against the double reference
// evaluateSurface, TextureMassIntegrator::update and TextureHydrostatics::update against fresh
// preparation from the same textures, buffers reused, and bad input.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "TestSurfaces.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/bake/SurfaceEvaluator.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

SurfaceBake bakeAt(const Mesh& mesh, int resolution) { return test::bakeOf(mesh, resolution); }

// A smooth non-uniform deformation (shear, stretch, a bulge) that keeps the surface closed.
Mesh deformed(const Mesh& rest, double amount) {
  Mesh moved = rest;
  for (auto& p : moved.positions) {
    const double bulge = 1.0 + 0.2 * amount * std::sin(2.0 * p.y());
    p = Eigen::Vector3d(bulge * p.x() + 0.3 * amount * p.y(), (1.0 + 0.5 * amount) * p.y(),
                        bulge * p.z() - 0.2 * amount * p.x());
  }
  return moved;
}

double meshSize(const Mesh& mesh) {
  double size = 0.0;
  for (const auto& p : mesh.positions) size = std::max(size, p.norm());
  return size;
}

}  // namespace

TEST_CASE("SurfaceEvaluator matches evaluateSurface on moved vertices") {
  const std::vector<std::pair<std::string, Mesh>> meshes = {{"box", prim::box({1.0, 2.0, 3.0})},
                                                            {"uv sphere", prim::uvSphere(1.0, 32, 16)},
                                                            {"torus", prim::torus(1.0, 0.3, 32, 12)}};
  for (const auto& [name, rest] : meshes) {
    const SurfaceBake bake = bakeAt(rest, 128);
    SurfaceEvaluator evaluator(bake, rest.uv);
    REQUIRE(evaluator.texelCount() == bake.coveredCount());
    SurfaceTextures fast;
    for (double amount : {0.0, 0.7}) {
      const Mesh moved = deformed(rest, amount);
      evaluator.evaluate(moved, fast);
      const SurfaceTextures reference = evaluateSurface(bake, moved, rest.uv);
      REQUIRE(fast.size() == reference.size());
      CHECK(fast.width == reference.width);
      CHECK(fast.height == reference.height);
      // Float sums of a few pieces against double ones rounded to float: positions to a few float
      // ulps of the body's size (the shift along A divides by |A|, which can cost a factor 10:
      // 1e-5 of the size); areas and edges to 1e-5 of the texel's own.
      const double size = meshSize(moved);
      double worstPosition = 0.0, worstArea = 0.0, worstEdge = 0.0;
      double volume = 0.0;
      for (std::size_t i = 0; i < fast.size(); ++i) {
        worstPosition = std::max(worstPosition, double((fast.position[i] - reference.position[i]).norm()) / size);
        const double area = std::max(1e-30, double(reference.area[i]));
        worstArea = std::max(worstArea, double((fast.areaVector[i] - reference.areaVector[i]).norm()) / area);
        worstArea = std::max(worstArea, std::abs(double(fast.area[i] - reference.area[i])) / area);
        const double edge = std::max(1e-30, double(reference.edgeU[i].norm() + reference.edgeV[i].norm()));
        worstEdge = std::max(worstEdge, double((fast.edgeU[i] - reference.edgeU[i]).norm() +
                                               (fast.edgeV[i] - reference.edgeV[i]).norm()) / edge);
        volume += fast.position[i].cast<double>().dot(fast.areaVector[i].cast<double>()) / 3.0;
      }
      // Moment corrections: the same texels; float differences c_k - p of the texel's size h
      // carry the float rounding of positions (~1e-7 of the size), so each entry agrees to about
      // 1e-7 size |A| (measured below 2e-7 with the shift's factor); bound 1e-5 size |A|, as the
      // positions'. Their sum over the body, which the volume sums use: measured at most 1.7e-8
      // of size^3 (the float rounding of thousands of entries, ~3e-8 of the volume, as float
      // texels give anyway); bound 5e-8 size^3.
      CHECK(fast.momentTexel == reference.momentTexel);
      REQUIRE(fast.momentCorrection.size() == reference.momentCorrection.size());
      double worstMoment = 0.0;
      Eigen::Matrix3d fastTotal = Eigen::Matrix3d::Zero(), referenceTotal = Eigen::Matrix3d::Zero();
      for (std::size_t c = 0; c < fast.momentCorrection.size(); ++c) {
        const double scale = size * std::max(1e-30, double(reference.area[reference.momentTexel[c]]));
        worstMoment = std::max(worstMoment, double((fast.momentCorrection[c] - reference.momentCorrection[c]).norm()) / scale);
        fastTotal += fast.momentCorrection[c].cast<double>();
        referenceTotal += reference.momentCorrection[c].cast<double>();
      }
      INFO(name << " deformation " << amount);
      CHECK(worstPosition < 1e-5);
      CHECK(worstArea < 1e-5);
      CHECK(worstEdge < 1e-5);
      CHECK(worstMoment < 1e-5);
      CHECK((fastTotal - referenceTotal).norm() < 5e-8 * size * size * size);
      // The enclosed volume stays exact (the polyhedral volume of the moved mesh) to float rounding.
      const auto exact = polyhedralMassProperties(moved, 1.0);
      REQUIRE(exact.ok());
      CHECK(volume == Approx(exact->volume).epsilon(1e-6));
    }
  }
}

TEST_CASE("a deformed mesh re-evaluated from the kept bake equals a fresh bake of the deformed mesh") {
  // The bake clips texels against UV triangles only, so the pieces kept from the rest pose are the
  // pieces of any pose: re-evaluating PT/VAT from moved vertices (SurfaceEvaluator, float) must
  // give a fresh bake's textures (bakeSurface + evaluateSurface of the deformed mesh, double), and
  // the mass model fed per step (MassModel::setGeometry) the fresh model's mass properties.
  const std::vector<std::pair<std::string, Mesh>> meshes = {{"uv sphere", prim::uvSphere(1.0, 48, 24)},
                                                            {"torus", prim::torus(1.0, 0.3, 32, 12)}};
  for (const auto& [name, rest] : meshes) {
    const SurfaceBake bake = bakeAt(rest, 128);
    SurfaceEvaluator evaluator(bake, rest.uv);
    SurfaceTextures kept;
    evaluator.evaluate(rest, kept);
    MassModel perStep(kept, Eigen::Vector3d::Zero());
    REQUIRE(perStep.setSolidDensity(400.0).ok());
    REQUIRE(perStep.setShellDensity(2.0, Conserved::Density).ok());  // as the fresh model's below
    REQUIRE(perStep.properties().ok());
    for (double amount : {0.3, 0.9, 0.5}) {  // not monotonic: the per-step path carries no history
      INFO(name << " deformation " << amount);
      const Mesh moved = deformed(rest, amount);
      evaluator.evaluate(moved, kept);
      REQUIRE(perStep.setGeometry(kept).ok());
      const auto stepped = perStep.properties();
      REQUIRE(stepped.ok());

      const SurfaceBake freshBake = bakeAt(moved, 128);
      REQUIRE(freshBake.texelIndex == bake.texelIndex);  // the same covered texels, in the same order
      const SurfaceTextures fresh = evaluateSurface(freshBake, moved, rest.uv);
      REQUIRE(fresh.size() == kept.size());
      // Float sums of a few pieces against double ones rounded to float, as in the test above:
      // positions to 1e-5 of the body's size, areas and edges to 1e-5 of the texel's own.
      const double size = meshSize(moved);
      double worstPosition = 0.0, worstArea = 0.0, worstEdge = 0.0;
      for (std::size_t i = 0; i < kept.size(); ++i) {
        worstPosition = std::max(worstPosition, double((kept.position[i] - fresh.position[i]).norm()) / size);
        const double area = std::max(1e-30, double(fresh.area[i]));
        worstArea = std::max(worstArea, double((kept.areaVector[i] - fresh.areaVector[i]).norm()) / area);
        worstArea = std::max(worstArea, std::abs(double(kept.area[i] - fresh.area[i])) / area);
        const double edge = std::max(1e-30, double(fresh.edgeU[i].norm() + fresh.edgeV[i].norm()));
        worstEdge = std::max(worstEdge, double((kept.edgeU[i] - fresh.edgeU[i]).norm() +
                                               (kept.edgeV[i] - fresh.edgeV[i]).norm()) / edge);
      }
      CHECK(worstPosition < 1e-5);
      CHECK(worstArea < 1e-5);
      CHECK(worstEdge < 1e-5);

      MassModel freshModel(fresh, Eigen::Vector3d::Zero());
      REQUIRE(freshModel.setSolidDensity(400.0).ok());
      REQUIRE(freshModel.setShellDensity(2.0).ok());
      const auto expected = freshModel.properties();
      REQUIRE(expected.ok());
      // Texel terms that differ by float rounding (above), summed over ~16k texels: mass, volume
      // and inertia to 1e-6, the centre to 1e-6 of the size (the patch covariance terms, which
      // come from edges that agree to 1e-5 only, are themselves ~1e-5 of the inertia).
      CHECK(stepped->mass == Approx(expected->mass).epsilon(1e-6));
      CHECK(stepped->volume == Approx(expected->volume).epsilon(1e-6));
      CHECK((stepped->centerOfMass - expected->centerOfMass).norm() < 1e-6 * size);
      CHECK((stepped->inertia - expected->inertia).norm() < 1e-6 * expected->inertia.norm());
      // And the volume is the deformed polyhedron's, exactly up to float rounding (1e-6).
      const auto exact = polyhedralMassProperties(moved, 1.0);
      REQUIRE(exact.ok());
      CHECK(stepped->volume == Approx(exact->volume).epsilon(1e-6));
    }
  }
}

TEST_CASE("SurfaceEvaluator reuses the output buffers and survives a mismatched mesh") {
  const Mesh rest = prim::uvSphere(1.0, 24, 12);
  const SurfaceBake bake = bakeAt(rest, 64);
  SurfaceEvaluator evaluator(bake, rest.uv);
  SurfaceTextures out;
  evaluator.evaluate(rest, out);
  const void* position = out.position.data();
  const void* areaData = out.area.data();
  evaluator.evaluate(deformed(rest, 0.5), out);
  CHECK(out.position.data() == position);  // no reallocation on the per-step path
  CHECK(out.area.data() == areaData);

  // A mesh with fewer triangles than the bake: pieces naming missing triangles carry nothing.
  Mesh half = rest;
  half.triangles.resize(rest.triangles.size() / 2);
  evaluator.evaluate(half, out);
  double area = 0.0, expected = 0.0;
  for (float a : out.area) area += a;
  for (const auto& t : half.triangles)
    expected += 0.5 * (half.positions[t[1]] - half.positions[t[0]]).cross(half.positions[t[2]] - half.positions[t[0]]).norm();
  CHECK(area == Approx(expected).epsilon(1e-5));  // float sums over ~3k texels
  // An empty evaluator gives empty textures.
  SurfaceEvaluator nothing;
  nothing.evaluate(rest, out);
  CHECK(out.size() == 0);
}

TEST_CASE("TextureMassIntegrator::update equals a fresh preparation") {
  const Mesh rest = prim::torus(1.0, 0.3, 32, 12);
  const SurfaceBake bake = bakeAt(rest, 128);
  SurfaceEvaluator evaluator(bake, rest.uv);
  SurfaceTextures textures;
  evaluator.evaluate(rest, textures);
  const Eigen::Vector3d reference(0.1, -0.2, 0.05);
  TextureMassIntegrator updated(textures, reference);
  TextureMassModel model;
  model.solidDensity = 700.0;
  model.shellDensity = 3.0;
  for (double amount : {0.4, 0.9}) {
    const Mesh moved = deformed(rest, amount);
    evaluator.evaluate(moved, textures);
    updated.update(textures);
    const TextureMassIntegrator fresh(textures, reference);
    const auto a = updated.evaluate(model);
    const auto b = fresh.evaluate(model);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    // Same inputs, same sums: equal to double rounding of float terms (1e-9 relative).
    CHECK(a->mass == Approx(b->mass).epsilon(1e-9));
    CHECK(a->volume == Approx(b->volume).epsilon(1e-9));
    CHECK((a->centerOfMass - b->centerOfMass).norm() < 1e-9);
    CHECK((a->inertia - b->inertia).norm() < 1e-9 * b->inertia.norm());
    // And the mass follows the moved mesh: solid of the exact volume plus the shell's area.
    const auto exact = polyhedralMassProperties(moved, 1.0);
    REQUIRE(exact.ok());
    double area = 0.0;
    for (float texelArea : textures.area) area += texelArea;
    CHECK(a->mass == Approx(700.0 * exact->volume + 3.0 * area).epsilon(1e-6));  // float volume terms
  }
}

TEST_CASE("TextureHydrostatics::update equals a rebuild from the same textures") {
  const Mesh rest = prim::uvSphere(1.0, 32, 16);
  const SurfaceBake bake = bakeAt(rest, 128);
  SurfaceEvaluator evaluator(bake, rest.uv);
  SurfaceTextures textures;
  evaluator.evaluate(rest, textures);
  auto built = TextureHydrostatics::build(bake, textures);
  REQUIRE(built.ok());
  TextureHydrostatics updated = std::move(built).value();
  const FlatSurface water(0.0);
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (double amount : {0.3, 0.8}) {
    const Mesh moved = deformed(rest, amount);
    evaluator.evaluate(moved, textures);
    REQUIRE(updated.update(textures).ok());
    auto fresh = TextureHydrostatics::build(bake, textures);
    REQUIRE(fresh.ok());
    CHECK(updated.enclosedVolume() == Approx(fresh->enclosedVolume()).epsilon(1e-12));
    CHECK(updated.tileCount() == fresh->tileCount());
    for (int i = 0; i < 8; ++i) {
      HydrostaticsQuery query;
      query.pose.rotation = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
      query.pose.translation = Eigen::Vector3d(0.0, 0.6 * n(rng), 0.0);
      for (TexelTraversal traversal : {TexelTraversal::Hierarchy, TexelTraversal::BruteForce}) {
        const auto a = updated.query(water, query, traversal);
        const auto b = fresh->query(water, query, traversal);
        REQUIRE(a.ok());
        REQUIRE(b.ok());
        // The same texels and tiles: equal up to double rounding (a tile may fall on the texel
        // path instead of its moments because of the bounds' float slack: 1e-9 of the weight).
        const double scale = 1000.0 * 9.81 * updated.enclosedVolume();
        CHECK((a->buoyancyForce - b->buoyancyForce).norm() < 1e-9 * scale);
        CHECK(a->submergedVolume == Approx(b->submergedVolume).margin(1e-12));
      }
    }
  }

  // Bad input: a mismatched size or a NaN is an error, and queries say so until a good update.
  SurfaceTextures wrong = textures;
  wrong.position.pop_back();
  CHECK_FALSE(updated.update(wrong).ok());
  HydrostaticsQuery query;
  CHECK_FALSE(updated.query(water, query).ok());
  SurfaceTextures nan = textures;
  nan.position[nan.size() / 2].x() = std::numeric_limits<float>::quiet_NaN();
  CHECK_FALSE(updated.update(nan).ok());
  CHECK_FALSE(updated.query(water, query).ok());
  REQUIRE(updated.update(textures).ok());
  CHECK(updated.query(water, query).ok());
}
