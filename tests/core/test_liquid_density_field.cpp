// SPDX-License-Identifier: Zlib
// The paper's Liquid Density Field (3D grid diffusion) against the same closed form as the texel
// graph, and its volume conservation.
#include <catch2/catch.hpp>

#include <cmath>

#include "TestSurfaces.hpp"
#include "hydrotex/wetting/LiquidDensityField.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

using namespace hydrotex;

namespace {

Mesh plate(double side) { return test::squarePlate(side); }

TexelAdjacency graphOf(const Mesh& mesh, int resolution) {
  auto graph = buildTexelAdjacency(test::bakeOf(mesh, resolution), mesh, mesh.uv);
  REQUIRE(graph.ok());
  return std::move(graph).value();
}

double held(const std::vector<float>& liquid, const TexelAdjacency& g) {
  double total = 0.0;
  for (std::size_t i = 0; i < liquid.size(); ++i) total += liquid[i] * g.area[i];
  return total;
}

double varianceX(const std::vector<float>& liquid, const TexelAdjacency& g) {
  double m = 0, mx = 0, sxx = 0;
  for (std::size_t i = 0; i < liquid.size(); ++i) {
    const double w = liquid[i] * g.area[i];
    m += w;
    mx += w * g.centroid[i].x();
    sxx += w * g.centroid[i].x() * g.centroid[i].x();
  }
  return sxx / m - (mx / m) * (mx / m);
}

}  // namespace

TEST_CASE("LDF on a plate with voxels the size of texels: variance grows by 2 D t", "[ldf]") {
  const int n = 128;
  const TexelAdjacency g = graphOf(plate(1.0), n);
  auto field = LiquidDensityField::build(g, 1.0 / n);
  REQUIRE(field.ok());
  // One voxel per texel in a single layer.
  CHECK(field->voxelCount() == g.area.size());
  std::vector<float> liquid(g.area.size());
  const double s0 = 0.05, diffusivity = 1e-4, t = 12.5;
  for (std::size_t i = 0; i < liquid.size(); ++i)
    liquid[i] = static_cast<float>(std::exp(-g.centroid[i].squaredNorm() / (2 * s0 * s0)));
  const double v0 = varianceX(liquid, g), m0 = held(liquid, g);
  for (int k = 0; k < 25; ++k) field->diffuse(liquid, diffusivity, t / 25);
  // Same discrete operator as the texel graph on a grid: exact second moment, float storage: 1e-3.
  CHECK(varianceX(liquid, g) - v0 == Approx(2 * diffusivity * t).epsilon(1e-3));
  CHECK(held(liquid, g) == Approx(m0).epsilon(1e-6));
}

TEST_CASE("LDF on a sphere conserves the volume and keeps it non-negative", "[ldf]") {
  const TexelAdjacency g = graphOf(primitives::uvSphere(1.0, 64, 32), 128);
  auto field = LiquidDensityField::build(g, 0.05);
  REQUIRE(field.ok());
  std::vector<float> liquid(g.area.size());
  for (std::size_t i = 0; i < liquid.size(); ++i) liquid[i] = static_cast<float>(1.0 + 0.5 * g.centroid[i].x());
  const double m0 = held(liquid, g);
  const int substeps = field->diffuse(liquid, 0.01, 10.0);
  CHECK(substeps == static_cast<int>(std::ceil(10.0 / field->stableTimeStep(0.01))));
  // Volumes are moved in double and stored as float: 1e-6.
  CHECK(held(liquid, g) == Approx(m0).epsilon(1e-6));
  float lo = 10.0f, hi = 0.0f;
  for (float phi : liquid) lo = std::min(lo, phi), hi = std::max(hi, phi);
  // Not flat: the 3D density evens out the volume per voxel, not the liquid per area, so voxels
  // holding little surface end up with more per area (why Wetting uses the texel graph).
  CHECK(lo >= 0.0f);
  CHECK(std::isfinite(hi));
  CHECK_FALSE(LiquidDensityField::build(g, 0.0).ok());
  CHECK_FALSE(LiquidDensityField::build(g, std::nan("")).ok());
}
