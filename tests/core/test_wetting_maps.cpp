// SPDX-License-Identifier: Zlib
// Per-texel material from PNG maps (LiquidTexture's porosity and permeability maps, loaded with
// loadImageMap and resampled with resampleToTexels) through the wetting step, against closed
// forms: a half-black permeability map absorbs only on its white half (Darcy's exponential
// uptake there, nothing on the black half); a porosity map bounds every texel's uptake to
// map * porosity * thickness, under water and in the rain; all-black maps stop uptake, all-white
// maps behave exactly as no map.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "TestPaths.hpp"
#include "TestSurfaces.hpp"
#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/wetting/Wetting.hpp"

using namespace hydrotex;

namespace {

constexpr int kResolution = 16;

// Square plate of side 0.2 m in the plane y = `height`, facing +y, UVs filling [0,1]^2 with u
// along x (u = 0 at x = -0.1): image column c covers x in [-0.1 + 0.2 c / 16, -0.1 + 0.2 (c + 1) / 16].
Mesh plate(double height) { return test::squarePlate(0.2, height); }

struct Body {
  SurfaceBake bake;
  SurfaceTextures textures;
  Wetting wetting;
};

Body prepare(const Mesh& mesh, const WettingSettings& settings) {
  BakeSettings bakeSettings;
  bakeSettings.width = bakeSettings.height = kResolution;
  auto bake = bakeSurface(mesh, mesh.uv, bakeSettings);
  REQUIRE(bake.ok());
  SurfaceTextures textures = evaluateSurface(*bake, mesh, mesh.uv);
  auto graph = buildTexelAdjacency(*bake, mesh, mesh.uv);
  REQUIRE(graph.ok());
  auto wetting = Wetting::create(std::move(graph).value(), textures, settings);
  REQUIRE(wetting.ok());
  return Body{std::move(bake).value(), std::move(textures), std::move(wetting).value()};
}

// Writes a 16 x 16 grey PNG whose pixel (row, column) is `value(row, column)` (0..255), loads it
// back and resamples it to the plate's texels (same size: texel (row, column) gets that pixel).
std::vector<float> mapFromPng(const std::string& name, const Body& body, const std::function<int(int, int)>& value) {
  std::vector<std::uint8_t> pixels(kResolution * kResolution);
  for (int row = 0; row < kResolution; ++row)
    for (int column = 0; column < kResolution; ++column)
      pixels[static_cast<std::size_t>(row * kResolution + column)] = static_cast<std::uint8_t>(value(row, column));
  const std::string path = test::outputPath(name);
  REQUIRE(writePng(path, kResolution, kResolution, 1, pixels).ok());
  auto image = loadImageMap(path);
  REQUIRE(image.ok());
  return resampleToTexels(*image, body.bake);
}

int columnOf(const Body& body, std::size_t texel) { return static_cast<int>(body.bake.texelIndex[texel] % kResolution); }

}  // namespace

TEST_CASE("A half-black permeability map absorbs only on its white half", "[wetting][maps]") {
  WettingSettings settings;
  settings.diffusivity = 0.0;       // each texel on its own: the closed form per texel
  settings.relativeHumidity = 1.0;  // and nothing evaporates
  const double depth = 0.1;
  Body body = prepare(plate(-depth), settings);
  const std::vector<float> permeability =
      mapFromPng("wetting_permeability_half.png", body, [](int, int column) { return column < kResolution / 2 ? 0 : 255; });
  WettingMaterial material;  // porosity 0.3, 5 mm, k = 1e-12 m^2
  auto texture = makeLiquidTexture(body.textures.size(), material, {}, permeability);
  REQUIRE(texture.ok());
  FlatSurface water(0.0, 1000.0);
  WettingEnvironment environment;
  environment.liquid = &water;
  // Darcy against the back-pressure (Wetting.hpp): S = 1 - exp(-t / tau), tau = mu L C / (k P).
  const double capacity = material.porosity * material.layerThickness;
  const double tau = settings.viscosity * material.layerThickness * capacity / (material.permeability * 1000.0 * 9.81 * depth);
  double absorbed = 0.0;
  for (int k = 0; k < 4; ++k) {
    auto report = body.wetting.step(*texture, environment, 0.25 * tau);
    REQUIRE(report.ok());
    REQUIRE(report->submergedTexels == body.textures.size());
    absorbed += report->absorbed;
  }
  const double saturation = 1.0 - std::exp(-1.0);
  double whiteArea = 0.0;
  for (std::size_t i = 0; i < texture->size(); ++i) {
    CAPTURE(i, columnOf(body, i));
    if (columnOf(body, i) < kResolution / 2) {
      CHECK(texture->liquid[i] == 0.0f);  // k = 0 exactly: nothing enters
    } else {
      // Integrated exactly per step; float storage of phi: 1e-5.
      CHECK(texture->saturation(i) == Approx(saturation).epsilon(1e-5));
      whiteArea += body.wetting.adjacency().area[i];
    }
  }
  // The white half is half of the plate (8 of 16 columns), and only it took liquid.
  CHECK(whiteArea == Approx(0.5 * 0.2 * 0.2).epsilon(1e-9));
  CHECK(absorbed == Approx(whiteArea * capacity * saturation).epsilon(1e-5));
  CHECK(texture->heldVolume(body.wetting.adjacency().area) == Approx(absorbed).epsilon(1e-6));
}

TEST_CASE("A porosity map limits every texel's uptake to map * porosity * thickness", "[wetting][maps]") {
  WettingSettings settings;
  settings.diffusivity = 0.0;
  settings.relativeHumidity = 1.0;
  WettingMaterial material;
  // 16 grey levels across the columns, 0 (black) to 255 (white).
  auto grey = [](int, int column) { return 17 * column; };
  const double capacityOfWhite = material.porosity * material.layerThickness;

  SECTION("under water, for 30 time constants of the most open texel") {
    const double depth = 0.1;
    Body body = prepare(plate(-depth), settings);
    const std::vector<float> porosity = mapFromPng("wetting_porosity_ramp.png", body, grey);
    auto texture = makeLiquidTexture(body.textures.size(), material, porosity);
    REQUIRE(texture.ok());
    FlatSurface water(0.0, 1000.0);
    WettingEnvironment environment;
    environment.liquid = &water;
    // tau grows with the capacity; the white texels' is the longest.
    const double tau = settings.viscosity * material.layerThickness * capacityOfWhite / (material.permeability * 1000.0 * 9.81 * depth);
    double absorbed = 0.0, expected = 0.0;
    for (int k = 0; k < 30; ++k) {
      auto report = body.wetting.step(*texture, environment, tau);
      REQUIRE(report.ok());
      absorbed += report->absorbed;
      // Never above its own capacity (the float the texture stores, checked below against
      // map * porosity * thickness).
      for (std::size_t i = 0; i < texture->size(); ++i) REQUIRE(texture->liquid[i] <= texture->capacity[i]);
    }
    for (std::size_t i = 0; i < texture->size(); ++i) {
      const double bound = (17.0 * columnOf(body, i) / 255.0) * capacityOfWhite;
      CHECK(texture->capacity[i] == Approx(bound).epsilon(1e-6));  // float storage
      // After 30 tau every texel is full to exp(-30) = 1e-13; float storage: 1e-6 relative.
      CHECK(texture->liquid[i] == Approx(bound).epsilon(1e-6));
      expected += bound * body.wetting.adjacency().area[i];
    }
    CHECK(absorbed == Approx(expected).epsilon(1e-6));
  }

  SECTION("in the rain, whatever the supply") {
    Body body = prepare(plate(1.0), settings);
    const std::vector<float> porosity = mapFromPng("wetting_porosity_ramp.png", body, grey);
    auto texture = makeLiquidTexture(body.textures.size(), material, porosity);
    REQUIRE(texture.ok());
    WettingEnvironment environment;
    LiquidSource rain;
    rain.rate = 1e-4;  // 0.36 m/h: the white texels (1.5 mm) fill in 15 s
    environment.sources = {rain};
    double absorbed = 0.0, expected = 0.0;
    for (int k = 0; k < 40; ++k) {
      auto report = body.wetting.step(*texture, environment, 1.0);
      REQUIRE(report.ok());
      absorbed += report->absorbed;
    }
    for (std::size_t i = 0; i < texture->size(); ++i) {
      const double bound = (17.0 * columnOf(body, i) / 255.0) * capacityOfWhite;
      // Supply 4 mm over the run, more than any capacity: every texel exactly full (the min with
      // the float capacity), what did not fit ran off.
      CHECK(texture->liquid[i] == texture->capacity[i]);
      CHECK(texture->capacity[i] == Approx(bound).epsilon(1e-6));
      expected += bound * body.wetting.adjacency().area[i];
    }
    CHECK(absorbed == Approx(expected).epsilon(1e-6));
  }
}

TEST_CASE("All-black maps stop uptake; all-white maps are the material's defaults", "[wetting][maps]") {
  WettingSettings settings;
  settings.diffusivity = 0.0;  // so that what a texel holds is what it took in itself
  settings.relativeHumidity = 0.5;
  // Tilted so that half of the plate is in the air (rain, drying) and half under water (Darcy).
  Body body = prepare(plate(0.0), settings);
  const std::vector<float> black = mapFromPng("wetting_black.png", body, [](int, int) { return 0; });
  const std::vector<float> white = mapFromPng("wetting_white.png", body, [](int, int) { return 255; });
  for (float value : white) REQUIRE(value == 1.0f);
  WettingMaterial material;
  FlatSurface water(0.0, 1000.0);
  WettingEnvironment environment;
  environment.liquid = &water;
  environment.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(0.0, 0.0, 40.0), Eigen::Vector3d::Zero());
  LiquidSource rain;
  rain.rate = 1e-5;
  environment.sources = {rain};
  auto run = [&](const std::vector<float>& porosity, const std::vector<float>& permeability) {
    auto texture = makeLiquidTexture(body.textures.size(), material, porosity, permeability);
    REQUIRE(texture.ok());
    double absorbed = 0.0;
    for (int k = 0; k < 20; ++k) {
      auto report = body.wetting.step(*texture, environment, 2.0);
      REQUIRE(report.ok());
      absorbed += report->absorbed;
    }
    return std::make_pair(std::move(texture).value(), absorbed);
  };
  const auto [plain, plainAbsorbed] = run({}, {});
  REQUIRE(plainAbsorbed > 0.0);
  // All white: every value is 1 exactly, so the texture is the default one, bit for bit.
  const auto [whiteBoth, whiteAbsorbed] = run(white, white);
  CHECK(whiteBoth.liquid == plain.liquid);
  CHECK(whiteAbsorbed == plainAbsorbed);
  // All-black porosity: capacity 0, nothing is held, neither from the water nor from the rain.
  const auto [noPores, noPoresAbsorbed] = run(black, {});
  for (float phi : noPores.liquid) CHECK(phi == 0.0f);
  CHECK(noPoresAbsorbed == 0.0);
  // All-black permeability: nothing enters under water; the rain still wets the part in the air
  // (sources fill the pores from outside, not through Darcy's law).
  const auto [sealed, sealedAbsorbed] = run({}, black);
  std::size_t wetUnder = 0;
  for (std::size_t i = 0; i < sealed.size(); ++i)
    if (body.wetting.submergedMask()[i]) wetUnder += sealed.liquid[i] > 0.0f;
  CHECK(wetUnder == 0);
  CHECK(sealedAbsorbed > 0.0);
  CHECK(sealedAbsorbed < plainAbsorbed);
}
