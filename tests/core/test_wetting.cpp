// SPDX-License-Identifier: Zlib
// The liquid texture step against closed forms: Fick on a plate and a sphere (across seams),
// Darcy uptake against a constant head, two-stage drying, mass balance, stability at any step.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <random>

#include "TestSurfaces.hpp"
#include "hydrotex/wetting/DiffusionGroups.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/wetting/Wetting.hpp"

using namespace hydrotex;

namespace {

// Flat square plate of side `side` in the plane y = `height`, UVs filling [0,1]^2, facing +y.
Mesh plate(double side, double height = 0.0) { return test::squarePlate(side, height); }

struct Body {
  SurfaceTextures textures;
  Wetting wetting;
};

Body prepare(const Mesh& mesh, int resolution, const WettingSettings& settings) {
  BakeSettings bakeSettings;
  bakeSettings.width = bakeSettings.height = resolution;
  auto bake = bakeSurface(mesh, mesh.uv, bakeSettings);
  REQUIRE(bake.ok());
  SurfaceTextures textures = evaluateSurface(*bake, mesh, mesh.uv);
  auto graph = buildTexelAdjacency(*bake, mesh, mesh.uv);
  REQUIRE(graph.ok());
  auto wetting = Wetting::create(std::move(graph).value(), textures, settings);
  REQUIRE(wetting.ok());
  return Body{std::move(textures), std::move(wetting).value()};
}

LiquidTexture dryTexture(std::size_t n, const WettingMaterial& material = {}) {
  auto texture = makeLiquidTexture(n, material);
  REQUIRE(texture.ok());
  return std::move(texture).value();
}

// Variance along x and z of the liquid distribution (m^2), about its mean.
Eigen::Vector2d variance(const Wetting& w, const LiquidTexture& t) {
  double mass = 0, mx = 0, mz = 0, sxx = 0, szz = 0;
  const auto& g = w.adjacency();
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double m = t.liquid[i] * g.area[i];
    mass += m;
    mx += m * g.centroid[i].x();
    mz += m * g.centroid[i].z();
    sxx += m * g.centroid[i].x() * g.centroid[i].x();
    szz += m * g.centroid[i].z() * g.centroid[i].z();
  }
  mx /= mass;
  mz /= mass;
  return {sxx / mass - mx * mx, szz / mass - mz * mz};
}

// Amplitude of the pattern `shape` in the liquid: sum A phi Y / sum A Y^2 (Y has zero mean on a sphere).
template <class Shape>
double amplitude(const Wetting& w, const LiquidTexture& t, Shape shape) {
  double num = 0, den = 0;
  const auto& g = w.adjacency();
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double y = shape(g.centroid[i].normalized());
    num += g.area[i] * t.liquid[i] * y;
    den += g.area[i] * y * y;
  }
  return num / den;
}

}  // namespace

TEST_CASE("Gaussian on a plate: variance grows by 2 D t, volume conserved", "[wetting][diffusion]") {
  WettingSettings settings;
  settings.diffusivity = 1e-4;
  settings.relativeHumidity = 1.0;  // no evaporation
  for (int explicitSubsteps : {8, 0}) {
    settings.maxExplicitSubsteps = explicitSubsteps;
    Body body = prepare(plate(1.0), 128, settings);
    LiquidTexture texture = dryTexture(body.textures.size());
    const double s0 = 0.05;
    const auto& g = body.wetting.adjacency();
    for (std::size_t i = 0; i < texture.size(); ++i)
      texture.liquid[i] = static_cast<float>(1e-3 * std::exp(-(g.centroid[i].x() * g.centroid[i].x() + g.centroid[i].z() * g.centroid[i].z()) / (2 * s0 * s0)));
    const double held0 = texture.heldVolume(g.area);
    const Eigen::Vector2d v0 = variance(body.wetting, texture);
    const double t = 12.5, dt = explicitSubsteps > 0 ? 0.25 : 2.5;
    WettingEnvironment environment;
    for (int k = 0; k < static_cast<int>(std::lround(t / dt)); ++k) {
      auto report = body.wetting.step(texture, environment, dt);
      REQUIRE(report.ok());
      REQUIRE(report->implicitDiffusion == (explicitSubsteps == 0));
    }
    const Eigen::Vector2d v1 = variance(body.wetting, texture);
    CAPTURE(explicitSubsteps);
    // On a uniform grid the discrete Laplacian moves the second moment by exactly 2 D per axis and
    // unit time, for forward and backward Euler alike; what remains is float storage of phi
    // (1e-7 relative per step) and the Gaussian's tail at the plate's edge (10 sigma): 1e-3.
    CHECK(v1.x() - v0.x() == Approx(2 * settings.diffusivity * t).epsilon(1e-3));
    CHECK(v1.y() - v0.y() == Approx(2 * settings.diffusivity * t).epsilon(1e-3));
    // Pair fluxes are antisymmetric: the volume changes only by float rounding of phi (1e-6).
    CHECK(texture.heldVolume(g.area) == Approx(held0).epsilon(1e-6));
  }
}

TEST_CASE("Spherical harmonics on a sphere decay as exp(-l(l+1) D t / R^2) across seams", "[wetting][diffusion]") {
  WettingSettings settings;
  settings.diffusivity = 0.01;
  settings.relativeHumidity = 1.0;
  const double t = 10.0, dt = 0.5;
  struct Case {
    const char* name;
    Mesh mesh;
  };
  for (const Case& c : {Case{"uv sphere", primitives::uvSphere(1.0, 96, 48)}, Case{"icosphere", primitives::icosphere(1.0, 4)}}) {
    Body body = prepare(c.mesh, 256, settings);
    const auto& g = body.wetting.adjacency();
    // l = 1: x (crosses the uv sphere's seam meridian at its maximum); l = 2: x z (changes sign there).
    auto l1 = [](const Eigen::Vector3d& n) { return n.x(); };
    auto l2 = [](const Eigen::Vector3d& n) { return n.x() * n.z(); };
    for (int l : {1, 2}) {
      LiquidTexture texture = dryTexture(body.textures.size());
      for (std::size_t i = 0; i < texture.size(); ++i) {
        const Eigen::Vector3d n = g.centroid[i].normalized();
        texture.liquid[i] = static_cast<float>(1e-3 * (1.0 + 0.5 * (l == 1 ? l1(n) : 2.0 * l2(n))));
      }
      const double a0 = l == 1 ? amplitude(body.wetting, texture, l1) : amplitude(body.wetting, texture, l2);
      WettingEnvironment environment;
      for (int k = 0; k < static_cast<int>(t / dt); ++k) REQUIRE(body.wetting.step(texture, environment, dt).ok());
      const double a1 = l == 1 ? amplitude(body.wetting, texture, l1) : amplitude(body.wetting, texture, l2);
      const double expected = std::exp(-l * (l + 1) * settings.diffusivity * t);  // R = 1
      CAPTURE(c.name, l);
      // Error budget: the polyhedral sphere and the two-point flux on non-orthogonal texels shift
      // the eigenvalue by about 1 %, i.e. 0.2 % (l = 1) and 0.6 % (l = 2) of the ratio; backward
      // Euler at dt = 0.5 adds under 1e-4. Tolerance 1 %.
      CHECK(a1 / a0 == Approx(expected).epsilon(0.01));
    }
  }
}

TEST_CASE("Darcy uptake against a constant head: S = 1 - exp(-t / tau)", "[wetting][absorption]") {
  WettingSettings settings;
  settings.diffusivity = 0.0;
  WettingMaterial material;  // porosity 0.3, 5 mm, k = 1e-12
  const double depth = 0.1;
  Body body = prepare(plate(0.2, -depth), 16, settings);
  FlatSurface water(0.0, 1000.0);
  WettingEnvironment environment;
  environment.liquid = &water;
  const double head = 1000.0 * 9.81 * depth;
  const double capacity = material.porosity * material.layerThickness;
  const double tau = settings.viscosity * material.layerThickness * capacity / (material.permeability * head);
  for (double dt : {0.05 * tau, tau, 5.0 * tau}) {
    LiquidTexture texture = dryTexture(body.textures.size(), material);
    double t = 0.0;
    for (int k = 0; k < 6; ++k) {
      REQUIRE(body.wetting.step(texture, environment, dt).ok());
      t += dt;
      // Integrated exactly per step; float storage of phi: 1e-6.
      REQUIRE(texture.saturation(0) == Approx(1.0 - std::exp(-t / tau)).epsilon(1e-5));
    }
  }
  // docs/references.md: k = 1e-12 m^2, A = 1 cm^2, dp = 1000 Pa, mu = 1e-3, L = 1 cm -> Q = 1e-8 m^3/s.
  // Initial rate per area k dp / (mu L) over a step short against tau (relative error dt / 2 tau).
  material.layerThickness = 0.01;
  LiquidTexture texture = dryTexture(body.textures.size(), material);
  const double dp = 1000.0, shortStep = 1e-6;
  FlatSurface shallow(dp / (1000.0 * 9.81) - depth, 1000.0);
  environment.liquid = &shallow;
  auto report = body.wetting.step(texture, environment, shortStep);
  REQUIRE(report.ok());
  const double area = 0.2 * 0.2;
  CHECK(report->absorbed / shortStep * (1e-4 / area) == Approx(1e-8).epsilon(1e-3));
}

TEST_CASE("Drying: constant rate, then falling rate; nothing evaporates under water", "[wetting][evaporation]") {
  WettingSettings settings;
  settings.diffusivity = 0.0;
  settings.relativeHumidity = 0.2;
  settings.criticalSaturation = 0.4;
  WettingMaterial material;
  Body body = prepare(plate(0.2, 1.0), 16, settings);
  const double capacity = material.porosity * material.layerThickness;
  const double rate = settings.evaporationRate();
  // Hall and Hoff eq. 10 at 20 C, H = 0.2, 5 mm still air: about 7e-8 m/s (0.25 mm/h). The Magnus
  // form of the saturation pressure is within 0.3 % of the steam tables' 2339 Pa here: 5e-3.
  const double vapourDensity = 2339.0 * 0.018015 / (8.314462618 * 293.15);  // 2339 Pa: saturation at 20 C
  CHECK(rate == Approx(2.5e-5 * vapourDensity * 0.8 / 0.005 / 1000.0).epsilon(5e-3));
  const double critical = settings.criticalSaturation * capacity;
  const double t1 = (capacity - critical) / rate;
  auto exact = [&](double t) { return t <= t1 ? capacity - rate * t : critical * std::exp(-(t - t1) * rate / critical); };
  for (double dt : {t1 / 7.0, t1 / 0.9, 4.0 * t1}) {
    LiquidTexture texture = dryTexture(body.textures.size(), material);
    std::fill(texture.liquid.begin(), texture.liquid.end(), static_cast<float>(capacity));
    WettingEnvironment environment;
    double t = 0.0;
    for (int k = 0; k < 10; ++k) {
      REQUIRE(body.wetting.step(texture, environment, dt).ok());
      t += dt;
      CAPTURE(dt, t);
      // Both stages integrated exactly; float storage: relative 1e-5.
      REQUIRE(texture.liquid[3] == Approx(exact(t)).epsilon(1e-5).margin(1e-12));
    }
  }
  // Under water the same texel keeps its liquid.
  FlatSurface water(2.0);
  WettingEnvironment environment;
  environment.liquid = &water;
  LiquidTexture texture = dryTexture(body.textures.size(), material);
  std::fill(texture.liquid.begin(), texture.liquid.end(), static_cast<float>(capacity));
  auto report = body.wetting.step(texture, environment, 1e5);
  REQUIRE(report.ok());
  CHECK(report->evaporated == 0.0);
  CHECK(texture.liquid[3] == static_cast<float>(capacity));
}

TEST_CASE("Mass balance over many steps: absorbed = held + evaporated", "[wetting][balance]") {
  WettingSettings settings;
  settings.diffusivity = 1e-4;
  settings.capillaryPressure = 500.0;
  Body body = prepare(primitives::uvSphere(0.5, 48, 24), 128, settings);
  auto made = makeLiquidTexture(body.textures.size(), WettingMaterial{}, {}, {}, true);
  REQUIRE(made.ok());
  LiquidTexture texture = std::move(made).value();
  FlatSurface water(0.0);
  WettingEnvironment environment;
  environment.liquid = &water;
  LiquidSource rain;
  rain.rate = 2e-5;
  rain.pigment = 0.25;
  LiquidSource hose;
  hose.kind = LiquidSourceKind::Sphere;
  hose.centre = Eigen::Vector3d(0.5, 0.3, 0.0);
  hose.radius = 0.2;
  hose.rate = 1e-4;
  hose.pigment = 1.0;
  environment.sources = {rain, hose};
  const auto& area = body.wetting.adjacency().area;
  double absorbed = 0.0, evaporated = 0.0, pigmentIn = 0.0;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> step(0.01, 30.0);
  bool sawImplicit = false, sawExplicit = false;
  for (int k = 0; k < 200; ++k) {
    environment.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(3.0 * k, 0.0, 0.0), Eigen::Vector3d(0.0, 0.2 * std::sin(0.1 * k), 0.0));
    environment.time = k;
    if (k == 120) environment.sources.clear();  // then it dries
    const double pigmentBefore = texture.heldPigment(area);
    // Every fifth step is short enough for explicit sub-steps.
    const double dt = k % 5 == 0 ? 2.0 * body.wetting.stableTimeStep() : step(random);
    auto report = body.wetting.step(texture, environment, dt);
    REQUIRE(report.ok());
    absorbed += report->absorbed;
    evaporated += report->evaporated;
    pigmentIn += texture.heldPigment(area) - pigmentBefore;
    sawImplicit = sawImplicit || report->implicitDiffusion;
    sawExplicit = sawExplicit || report->diffusionSubsteps > 0;
  }
  CHECK(sawImplicit);
  CHECK(sawExplicit);
  REQUIRE(absorbed > 0.0);
  REQUIRE(evaporated > 0.0);
  // Every change of a texel is counted from the stored float values in double; diffusion moves
  // volume by antisymmetric pair fluxes, so only float rounding of phi is left: 1e-5 of the volume
  // that passed through.
  CHECK(texture.heldVolume(area) == Approx(absorbed - evaporated).margin(1e-5 * absorbed));
  for (float phi : texture.liquid) REQUIRE((phi >= 0.0f && std::isfinite(phi)));
  for (std::size_t i = 0; i < texture.size(); ++i) REQUIRE(texture.liquid[i] <= texture.capacity[i] * (1.0f + 1e-5f));
}

TEST_CASE("Stable at a huge time step: implicit diffusion flattens the texture, volume kept", "[wetting][stability]") {
  WettingSettings settings;
  settings.diffusivity = 1e-3;
  settings.relativeHumidity = 1.0;
  Body body = prepare(primitives::icosphere(1.0, 3), 128, settings);
  LiquidTexture texture = dryTexture(body.textures.size());
  std::mt19937 random(3);
  std::uniform_real_distribution<float> value(0.0f, 1e-3f);
  for (float& phi : texture.liquid) phi = value(random);
  const auto& area = body.wetting.adjacency().area;
  const double held0 = texture.heldVolume(area);
  WettingEnvironment environment;
  // 1e7 s: 2e4 times the slowest decay time R^2 / (2 D) = 500 s, and about 1e11 stable explicit steps.
  const double huge = 1e7;
  auto report = body.wetting.step(texture, environment, huge);
  REQUIRE(report.ok());
  CHECK(report->implicitDiffusion);
  CHECK(texture.heldVolume(area) == Approx(held0).epsilon(1e-6));
  // Every pattern has decayed by exp(-2e4): uniform up to the solver's residual (1e-10 of the right
  // side), which the flux reconstruction divides by texel areas down to slivers of 1e-6 of a full
  // texel: measured spread 2e-4 of the mean; tolerance 1e-3.
  const double mean = held0 / std::accumulate(area.begin(), area.end(), 0.0);
  for (std::size_t i = 0; i < texture.size(); ++i)
    if (area[i] > 0.0) REQUIRE(texture.liquid[i] == Approx(mean).epsilon(1e-3));
}

TEST_CASE("Bad inputs are refused with a message, the texture untouched", "[wetting][errors]") {
  WettingSettings bad;
  bad.relativeHumidity = 1.5;
  CHECK_FALSE(bad.validate().ok());
  WettingMaterial material;
  material.porosity = -0.1;
  CHECK_FALSE(makeLiquidTexture(4, material).ok());
  CHECK_FALSE(makeLiquidTexture(4, WettingMaterial{}, {0.5f, 0.5f}).ok());
  CHECK_FALSE(makeLiquidTexture(2, WettingMaterial{}, {0.5f, 2.0f}).ok());
  Body body = prepare(plate(1.0), 16, WettingSettings{});
  LiquidTexture texture = dryTexture(body.textures.size());
  texture.liquid[0] = 1e-3f;
  const LiquidTexture before = texture;
  WettingEnvironment environment;
  CHECK_FALSE(body.wetting.step(texture, environment, std::nan("")).ok());
  CHECK_FALSE(body.wetting.step(texture, environment, -1.0).ok());
  environment.pose.translation.x() = INFINITY;
  CHECK_FALSE(body.wetting.step(texture, environment, 1.0).ok());
  environment.pose = Pose{};
  LiquidSource source;
  source.rate = -1.0;
  environment.sources = {source};
  auto result = body.wetting.step(texture, environment, 1.0);
  REQUIRE_FALSE(result.ok());
  CHECK(result.error().message.find("source") != std::string::npos);
  LiquidTexture small = dryTexture(3);
  CHECK_FALSE(body.wetting.step(small, WettingEnvironment{}, 1.0).ok());
  CHECK(texture.liquid == before.liquid);
}

TEST_CASE("Stiff texels of a UV sphere are merged: explicit steps at a usable dt, volume and decay kept", "[wetting][merge]") {
  WettingSettings settings;
  settings.diffusivity = 0.01;
  settings.relativeHumidity = 1.0;
  WettingSettings unmergedSettings = settings;
  unmergedSettings.mergeBelowFraction = 0.0;
  const Mesh sphere = primitives::uvSphere(1.0, 96, 48);
  Body merged = prepare(sphere, 256, settings);
  Body unmerged = prepare(sphere, 256, unmergedSettings);
  CHECK(unmerged.wetting.mergedGroupCount() == 0);
  REQUIRE(merged.wetting.mergedGroupCount() > 0);
  // Only the squeezed texels near the poles and slivers merge: a minority of the texture.
  CHECK(merged.wetting.mergedTexelCount() < merged.textures.size() / 5);
  // Every group now meets the threshold: 0.1 of the median bound (the threshold's definition).
  const auto& g = merged.wetting.adjacency();
  std::vector<double> bounds;
  for (std::size_t i = 0; i < g.area.size(); ++i)
    if (g.area[i] > 0.0 && g.conductanceSum[i] > 0.0) bounds.push_back(g.area[i] / (settings.diffusivity * g.conductanceSum[i]));
  std::nth_element(bounds.begin(), bounds.begin() + static_cast<std::ptrdiff_t>(bounds.size() / 2), bounds.end());
  const double median = bounds[bounds.size() / 2];
  CHECK(merged.wetting.stableTimeStep() >= settings.mergeBelowFraction * median);
  CHECK(merged.wetting.stableTimeStep() > 10.0 * unmerged.wetting.stableTimeStep());

  LiquidTexture texture = dryTexture(merged.textures.size());
  auto l1 = [](const Eigen::Vector3d& n) { return n.x(); };
  for (std::size_t i = 0; i < texture.size(); ++i) texture.liquid[i] = static_cast<float>(1e-3 * (1.0 + 0.5 * l1(g.centroid[i].normalized())));
  const double held0 = texture.heldVolume(g.area);
  const double a0 = amplitude(merged.wetting, texture, l1);
  const double dt = merged.wetting.stableTimeStep();
  const int steps = static_cast<int>(std::ceil(5.0 / dt));
  WettingEnvironment environment;
  for (int k = 0; k < steps; ++k) {
    auto report = merged.wetting.step(texture, environment, dt);
    REQUIRE(report.ok());
    REQUIRE(report->diffusionSubsteps == 1);
  }
  // Float rounding of phi per step (1e-7) over a few hundred steps: 1e-5.
  CHECK(texture.heldVolume(g.area) == Approx(held0).epsilon(1e-5));
  // Same 1 % budget as the unmerged harmonic test: merging coarsens only near the poles, where
  // the l = 1 pattern x is small.
  const double t = steps * dt;
  CHECK(amplitude(merged.wetting, texture, l1) / a0 == Approx(std::exp(-2.0 * settings.diffusivity * t)).epsilon(0.01));
}

TEST_CASE("A step with merged groups equals its parts: absorb, evaporate, then diffuse", "[wetting][merge]") {
  // step() runs the exchange and the first diffusion sweep in one pass and pools each merged group
  // as soon as its members are exchanged; absorb(), evaporate() and diffuse() run them one after
  // another over the whole texture. Without sources a texel either absorbs (submerged) or
  // evaporates (exposed), so both orders do the same arithmetic on every texel; a group pooled
  // late (after a neighbour read its holder) would be off by a whole flux, 1e-3 of the contents.
  WettingSettings settings;
  settings.diffusivity = 0.01;
  settings.capillaryPressure = 500.0;
  Body body = prepare(primitives::uvSphere(1.0, 96, 48), 256, settings);
  REQUIRE(body.wetting.mergedGroupCount() > 0);
  LiquidTexture fused = dryTexture(body.textures.size());
  for (std::size_t i = 0; i < fused.size(); ++i) fused.liquid[i] = fused.capacity[i] * float(i % 7) / 7.0f;
  LiquidTexture parts = fused;
  FlatSurface water(0.1);
  WettingEnvironment environment;
  environment.liquid = &water;
  const double dt = 2.5 * body.wetting.stableTimeStep();  // three explicit sub-steps
  for (int k = 0; k < 5; ++k) {
    auto report = body.wetting.step(fused, environment, dt);
    REQUIRE(report.ok());
    REQUIRE(report->diffusionSubsteps == 3);
    std::size_t submerged = 0;
    const double absorbed = body.wetting.absorb(parts, environment, dt, submerged);
    const double evaporated = body.wetting.evaporate(parts, dt);
    REQUIRE(body.wetting.diffuse(parts, dt) == 3);
    CHECK(report->submergedTexels == submerged);
    // Totals summed in double over chunks in one order and whole passes in the other: 1e-9.
    CHECK(report->absorbed == Approx(absorbed).epsilon(1e-9));
    CHECK(report->evaporated == Approx(evaporated).epsilon(1e-9));
  }
  // The same float operations in the same order per texel: equal to float rounding (1e-6 of the
  // capacity covers a differently contracted multiply-add).
  float worst = 0.0f;
  for (std::size_t i = 0; i < fused.size(); ++i) worst = std::max(worst, std::abs(fused.liquid[i] - parts.liquid[i]) / fused.capacity[i]);
  CHECK(worst < 1e-6f);
}

TEST_CASE("The eight-lane (AVX2) and four-lane passes give the same liquid texture", "[wetting][lanes]") {
  // Where the processor has AVX2 the exchange (absorption, sources, evaporation) and the
  // diffusion sweep run eight texels at a time; HYDROTEX_DISABLE_AVX2 (read every step) selects
  // the four-lane code. The lanes do the same IEEE float operations without fused multiply-adds
  // and every texel sums its fluxes in the same order (a texel that received a seam flux and an
  // in-chart flux from one block of eight could sum them in another order: none on this sphere),
  // so every content must be bit-identical; only the sums of the volumes moved differ: each lane
  // sums up to 16 blocks in float before the double total, so eight lanes round other partial
  // sums (1e-6, the bound the exchange states for its totals). On a processor without AVX2 both
  // runs take four lanes and the test still holds. A waterline, rain, a hose with pigment and
  // both drying stages run (fill levels 0..6/7 of capacity, critical 0.3).
  WettingSettings settings;
  settings.capillaryPressure = 500.0;
  settings.relativeHumidity = 0.2;
  Body body = prepare(primitives::uvSphere(1.0, 64, 32), 128, settings);
  // Without pigment the sweep runs in lanes; with it, texel by texel (the exchange in lanes).
  const bool withPigment = GENERATE(false, true);
  CAPTURE(withPigment);
  auto texture = makeLiquidTexture(body.textures.size(), WettingMaterial{}, {}, {}, withPigment);
  REQUIRE(texture.ok());
  for (std::size_t i = 0; i < texture->size(); ++i) texture->liquid[i] = texture->capacity[i] * float(i % 7) / 7.0f;
  LiquidTexture wide = *texture, narrow = *texture;
  FlatSurface water(0.2);
  WettingEnvironment environment;
  environment.liquid = &water;
  environment.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(15.0, 0.0, 10.0), Eigen::Vector3d::Zero());
  LiquidSource rain, hose;
  rain.rate = 2e-5;
  hose.kind = LiquidSourceKind::Sphere;
  hose.centre = Eigen::Vector3d(1.0, 0.5, 0.0);
  hose.radius = 0.5;
  hose.rate = 1e-4;
  hose.pigment = 0.3;
  environment.sources = {rain, hose};
  const double dt = 0.5;
  for (int k = 0; k < 4; ++k) {
    auto a = body.wetting.step(wide, environment, dt);
    ::setenv("HYDROTEX_DISABLE_AVX2", "1", 1);
    auto b = body.wetting.step(narrow, environment, dt);
    ::unsetenv("HYDROTEX_DISABLE_AVX2");
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(a->submergedTexels == b->submergedTexels);
    CHECK(a->absorbed == Approx(b->absorbed).epsilon(1e-6));
    CHECK(a->evaporated == Approx(b->evaporated).epsilon(1e-6));
  }
  std::size_t differing = 0;
  for (std::size_t i = 0; i < wide.size(); ++i)
    if (wide.liquid[i] != narrow.liquid[i] || (withPigment && wide.pigment[i] != narrow.pigment[i])) ++differing;
  CHECK(differing == 0);
  // The step did something: liquid moved in and out.
  CHECK(wide.heldVolume(body.wetting.adjacency().area) != Approx(texture->heldVolume(body.wetting.adjacency().area)));
}

TEST_CASE("mergeStiffTexels: groups partition the texels, keep the area, join only holders and meet the bound", "[wetting][merge]") {
  // The structure the CPU and the GPU both diffuse on (DiffusionGroups.hpp). A 256^2 UV sphere
  // has squeezed texels at its poles; with the default fraction 0.1 they are merged.
  WettingSettings settings;
  Body body = prepare(primitives::uvSphere(1.0, 96, 48), 256, settings);
  const TexelAdjacency& graph = body.wetting.adjacency();
  const DiffusionGroups groups = mergeStiffTexels(graph, settings.mergeBelowFraction);
  const std::size_t n = graph.area.size();
  REQUIRE(groups.groupCount() > 0);
  REQUIRE(groups.nodeArea.size() == n);
  // Every texel is in at most one group; a group's first member holds it.
  std::vector<int> seen(n, 0);
  std::vector<std::uint8_t> holder(n, 1);
  std::size_t small = 0, memberWithArea = 0, holderWithoutGroupArea = 0;
  for (std::size_t g = 0; g < groups.groupCount(); ++g) {
    if (groups.start[g + 1] - groups.start[g] < 2) ++small;
    double area = 0.0;
    for (std::uint32_t m = groups.start[g]; m < groups.start[g + 1]; ++m) {
      ++seen[groups.members[m]];
      area += graph.area[groups.members[m]];
      if (m != groups.start[g]) {
        holder[groups.members[m]] = 0;
        if (groups.nodeArea[groups.members[m]] != 0.0) ++memberWithArea;
      }
    }
    // The holder carries the group's area (the same additions, maybe in another order: 1e-12).
    if (std::abs(groups.nodeArea[groups.members[groups.start[g]]] - area) > 1e-12 * area) ++holderWithoutGroupArea;
  }
  CHECK(small == 0);
  CHECK(memberWithArea == 0);
  CHECK(holderWithoutGroupArea == 0);
  CHECK(*std::max_element(seen.begin(), seen.end()) == 1);
  // Total area kept.
  const double total = std::accumulate(graph.area.begin(), graph.area.end(), 0.0);
  CHECK(std::accumulate(groups.nodeArea.begin(), groups.nodeArea.end(), 0.0) == Approx(total).epsilon(1e-12));
  // Pairs join two different holders.
  std::vector<double> conductanceSum(n, 0.0);
  std::size_t badPairs = 0;
  for (std::size_t p = 0; p < groups.pairFirst.size(); ++p) {
    const std::uint32_t a = groups.pairFirst[p], b = groups.pairSecond[p];
    if (a == b || !holder[a] || !holder[b]) ++badPairs;
    conductanceSum[a] += groups.pairGeometric[p];
    conductanceSum[b] += groups.pairGeometric[p];
  }
  CHECK(badPairs == 0);
  // The stability bound is the smallest nodeArea / sum g over holders, and merging raised it
  // above the unmerged graph's (that is what it is for).
  double bound = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i)
    if (conductanceSum[i] > 0.0) bound = std::min(bound, groups.nodeArea[i] / conductanceSum[i]);
  CHECK(groups.stableStepTimesDiffusivity == Approx(bound).epsilon(1e-12));
  const DiffusionGroups alone = mergeStiffTexels(graph, 0.0);
  CHECK(alone.groupCount() == 0);
  CHECK(alone.pairFirst.size() == graph.pairCount());
  CHECK(groups.stableStepTimesDiffusivity > 10.0 * alone.stableStepTimesDiffusivity);
}

TEST_CASE("diffusionSubsteps: none, explicit up to the limit, then implicit", "[wetting][merge]") {
  // The rule both backends follow (DiffusionGroups.hpp), on a stable step of 1 s.
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(diffusionSubsteps(0.0, 1.0, 4) == 0);     // no time
  CHECK(diffusionSubsteps(-1.0, 1.0, 4) == 0);
  CHECK(diffusionSubsteps(10.0, inf, 4) == 0);    // no pairs or D = 0: nothing diffuses
  CHECK(diffusionSubsteps(1e-9, 1.0, 4) == 1);    // a short step still takes one sub-step
  CHECK(diffusionSubsteps(2.5, 1.0, 4) == 3);     // ceil(dt / stable)
  CHECK(diffusionSubsteps(4.0, 1.0, 4) == 4);     // at the limit: explicit
  CHECK(diffusionSubsteps(4.001, 1.0, 4) == -1);  // beyond: backward Euler
}
