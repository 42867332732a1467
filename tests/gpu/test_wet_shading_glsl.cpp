// SPDX-License-Identifier: Zlib
// gpu/shaders/wet_shading.glsl run through GL (llvmpipe on CI) against the C++ reference
// hydrotex/WetShading.hpp and Lekner and Dorf's worked numbers. With no headless context the GL
// case WARNs and returns with no assertion, which CTest's --warn NoAssertions fails (as the other
// GPU suites).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "hydrotex/wetting/WetShading.hpp"
#include "hydrotex/gpu/EglContext.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"
#include "hydrotex/gpu/WetShadingGl.hpp"

using namespace hydrotex;

TEST_CASE("wet_shading.glsl is embedded with every function of the C++ reference", "[wet_shading_glsl]") {
  const std::string_view glsl = gpu::embeddedShader("wet_shading.glsl");
  REQUIRE(!glsl.empty());
  for (const char* name : {"hxAverageInternalReflectance", "hxInternalReflectionProbability", "hxFilmReflectance",
                           "hxWetAlbedo", "hxWetDiffuseRgb", "hxWetSurfaceRgb"})
    CHECK(glsl.find(name) != std::string_view::npos);
  // No version line: users paste it into their own shaders.
  CHECK(glsl.find("#version") == std::string_view::npos);
}

TEST_CASE("wet_shading.glsl on the GPU matches the C++ reference to 1e-3", "[wet_shading_glsl]") {
  auto context = gpu::EglContext::create();
  if (!context) {
    WARN("no headless EGL context on this machine: " << context.error().message);
    return;
  }
  const gpu::EglContext& c = **context;
  INFO("renderer " << c.renderer());

  // Worked numbers (docs/references.md): a = 0.5 under water: p = 0.4719, diffuse 0.3386, total 0.3587.
  gpu::WetShadingSample water;
  water.dryRgb = Eigen::Vector3f(0.5f, 0.4f, 0.2f);
  // Random samples over the range a user feeds: albedo 0..1, saturation 0..1 (and outside, to
  // check the clamp), n 1.2..1.6, transmittance 0.3..1.
  std::vector<gpu::WetShadingSample> samples = {water};
  std::mt19937 random(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int k = 0; k < 500; ++k) {
    gpu::WetShadingSample s;
    s.dryRgb = Eigen::Vector3f(unit(random), unit(random), unit(random));
    s.saturation = -0.2f + 1.4f * unit(random);
    s.refractiveIndex = 1.2f + 0.4f * unit(random);
    s.filmTransmittance = Eigen::Vector3f(0.3f + 0.7f * unit(random), 0.3f + 0.7f * unit(random), 1.0f);
    samples.push_back(s);
  }
  auto results = gpu::evaluateWetShading(c, samples);
  REQUIRE(results.ok());
  REQUIRE(results->size() == samples.size());

  const gpu::WetShadingResult& w = (*results)[0];
  // The worked numbers are given to 4 digits: half a unit of the last.
  CHECK(w.internalReflection == Approx(0.4719).margin(5e-5));
  CHECK(w.redDiffuse == Approx(0.3386).margin(5e-5));
  CHECK(w.redTotal == Approx(0.3587).margin(5e-5));

  // The C++ reference in double; the GLSL in float, whose worst step is the cancellation in R_bar
  // (terms about 40 times the result, float rounding 6e-8 each: about 1e-5). Tolerance 1e-3 as
  // asked of the port; the measured worst difference is printed.
  float worst = 0.0f;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const gpu::WetShadingSample& s = samples[i];
    const gpu::WetShadingResult& r = (*results)[i];
    const double n = s.refractiveIndex;
    const Eigen::Vector3d expected = wetSurfaceRgb(s.dryRgb.cast<double>(), s.saturation, n, s.filmTransmittance.cast<double>());
    const WetAlbedo red = wetAlbedo(s.dryRgb.x(), n, s.filmTransmittance.x());
    CAPTURE(i, n);
    CHECK((r.surfaceRgb.cast<double>() - expected).cwiseAbs().maxCoeff() < 1e-3);
    CHECK(std::abs(r.internalReflection - internalReflectionProbability(n)) < 1e-3);
    CHECK(std::abs(r.averageInternalReflectance - averageInternalReflectance(n)) < 1e-3);
    CHECK(std::abs(r.filmReflectance - filmReflectance(n)) < 1e-3);
    CHECK(std::abs(r.redDiffuse - red.diffuse) < 1e-3);
    CHECK(std::abs(r.redTotal - red.total) < 1e-3);
    worst = std::max(worst, static_cast<float>((r.surfaceRgb.cast<double>() - expected).cwiseAbs().maxCoeff()));
  }
  WARN("wet_shading.glsl vs C++: worst colour difference " << worst << " over " << samples.size() << " samples on "
                                                           << c.renderer());
}

TEST_CASE("a refractive index not above 1 is refused before any GL work", "[wet_shading_glsl]") {
  auto context = gpu::EglContext::create();
  if (!context) return;
  gpu::WetShadingSample bad;
  bad.refractiveIndex = 1.0f;
  auto results = gpu::evaluateWetShading(**context, {bad});
  REQUIRE_FALSE(results.ok());
  CHECK(results.error().message.find("refractive index") != std::string::npos);
}
