// SPDX-License-Identifier: Zlib
// Wetting's diffusion on the GPU (GlWettingDiffusion) against core's Wetting::diffuse on the same
// graph: a UV sphere (pairs across its seam) with a patch of liquid, several steps of explicit
// sub-steps, with and without merged stiff texels and a pigment channel; whole steps (GlWetting:
// absorption, sources, evaporation, diffusion) against Wetting::step, and the GPU's own mass
// balance. Without an EGL context the GL cases WARN and return, and fail under CTest for having no
// assertion (--warn NoAssertions, tests/CMakeLists.txt).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/bake/TexelAdjacency.hpp"
#include "hydrotex/wetting/Wetting.hpp"
#include "hydrotex/gpu/GlWetting.hpp"
#include "hydrotex/gpu/GlWettingDiffusion.hpp"

using namespace hydrotex;

namespace {

struct Graph {
  TexelAdjacency adjacency;
  SurfaceTextures textures;
};

Graph sphereGraph(int resolution) {
  const Mesh mesh = primitives::uvSphere(0.5, 32, 16);
  BakeSettings settings;
  settings.width = settings.height = resolution;
  auto bake = bakeSurface(mesh, mesh.uv, settings);
  REQUIRE(bake.ok());
  auto adjacency = buildTexelAdjacency(*bake, mesh, mesh.uv);
  REQUIRE(adjacency.ok());
  return {std::move(adjacency).value(), evaluateSurface(*bake, mesh, mesh.uv)};
}

double held(const LiquidTexture& t, const std::vector<double>& area) { return t.heldVolume(area); }

// A headless EGL context, or null after a WARN (the case then returns with no assertion, which CTest's
// --warn NoAssertions fails).
std::unique_ptr<gpu::EglContext> openContext() {
  Expected<std::unique_ptr<gpu::EglContext>> context = gpu::EglContext::create();
  if (!context) {
    WARN("GL wetting skipped, no headless EGL context: " << context.error().message);
    return nullptr;
  }
  return std::move(context).value();
}

// The pigment channels of a CPU and a GPU run from the same start: totals (m^3) and the largest
// per-texel difference (m).
struct PigmentComparison {
  double before = 0.0, cpu = 0.0, gpu = 0.0, worst = 0.0;
};
PigmentComparison comparePigment(const LiquidTexture& start, const LiquidTexture& onCpu, const LiquidTexture& onGpu,
                                 const std::vector<double>& area) {
  PigmentComparison c;
  c.before = start.heldPigment(area);
  c.cpu = onCpu.heldPigment(area);
  c.gpu = onGpu.heldPigment(area);
  for (std::size_t i = 0; i < onGpu.size(); ++i)
    c.worst = std::max(c.worst, double(std::abs(onGpu.pigment[i] - onCpu.pigment[i])));
  return c;
}

}  // namespace

TEST_CASE("GL wetting diffusion matches Wetting::diffuse and conserves the liquid", "[gpu][wetting]") {
  const std::unique_ptr<gpu::EglContext> context = openContext();
  if (!context) return;
  const Graph graph = sphereGraph(64);
  WettingSettings settings;
  settings.diffusivity = 1e-4;
  settings.mergeBelowFraction = GENERATE(0.0, 0.1);  // merging off, and the default
  const bool withPigment = GENERATE(false, true);
  settings.maxExplicitSubsteps = 1000;
  CAPTURE(settings.mergeBelowFraction, withPigment);
  auto cpu = Wetting::create(graph.adjacency, graph.textures, settings);
  REQUIRE(cpu.ok());
  // The default merges the squeezed texels at the poles: the GPU must pool and spread them.
  CHECK((cpu->mergedGroupCount() > 0) == (settings.mergeBelowFraction > 0.0));
  auto gl = gpu::GlWettingDiffusion::create(*context, graph.adjacency, settings);
  INFO((gl ? std::string() : gl.error().message));
  REQUIRE(gl.ok());
  CHECK((*gl)->stableTimeStep() == cpu->stableTimeStep());  // the same bound of the same groups

  // Liquid on the texels with x > 0.2 (a cap that touches the seam), saturated; with pigment,
  // at a concentration that varies across the cap so that the upwind transport matters.
  auto texture = makeLiquidTexture(graph.textures.size(), WettingMaterial{}, {}, {}, withPigment);
  REQUIRE(texture.ok());
  for (std::size_t i = 0; i < texture->size(); ++i)
    if (graph.textures.position[i].x() > 0.2f) {
      texture->liquid[i] = texture->capacity[i];
      if (withPigment) texture->pigment[i] = texture->capacity[i] * (0.2f + 0.5f * graph.textures.position[i].y() + 0.25f);
    }
  LiquidTexture onCpu = *texture, onGpu = *texture;
  const double before = held(*texture, graph.adjacency.area);
  REQUIRE(before > 0.0);
  REQUIRE((*gl)->upload(onGpu).ok());
  const double dt = 10.0 * cpu->stableTimeStep();  // 10 sub-steps per step
  for (int step = 0; step < 5; ++step) {
    const int cpuSubsteps = cpu->diffuse(onCpu, dt);
    const Expected<int> gpuSubsteps = (*gl)->diffuse(dt);
    REQUIRE(gpuSubsteps.ok());
    CHECK(*gpuSubsteps == cpuSubsteps);
  }
  REQUIRE((*gl)->download(onGpu).ok());
  // Per texel: the same float operations in another order of each texel's flux sum, over 50
  // sub-steps: 1e-5 of the capacity (float rounding is ~1e-7 per operation). The liquid moved
  // far more than that (checked below), so the comparison is not trivially met.
  const float capacity = texture->capacity[0];
  double worst = 0.0, moved = 0.0;
  for (std::size_t i = 0; i < onGpu.size(); ++i) {
    worst = std::max(worst, double(std::abs(onGpu.liquid[i] - onCpu.liquid[i])));
    moved = std::max(moved, double(std::abs(onCpu.liquid[i] - texture->liquid[i])));
  }
  CHECK(worst <= 1e-5 * capacity);
  CHECK(moved >= 0.01 * capacity);  // the pole texels bound the step, so the front moves slowly elsewhere
  // Mass balance: antisymmetric pair fluxes; what remains is each texel's float sum, 1e-6
  // relative over 50 sub-steps (the CPU's own float path is held to the same). Pooling and
  // spreading a group sum its members in float on the GPU (double on the CPU): within the same.
  CHECK(std::abs(held(onGpu, graph.adjacency.area) - before) <= 1e-6 * before);
  CHECK(std::abs(held(onCpu, graph.adjacency.area) - before) <= 1e-6 * before);
  if (withPigment) {
    // The pigment: the same tolerances (its fluxes are the liquid's times a concentration <= 1).
    const PigmentComparison pigment = comparePigment(*texture, onCpu, onGpu, graph.adjacency.area);
    CHECK(pigment.worst <= 1e-5 * capacity);
    CHECK(std::abs(pigment.gpu - pigment.before) <= 1e-6 * pigment.before);
    CHECK(std::abs(pigment.cpu - pigment.before) <= 1e-6 * pigment.before);
  }
}

TEST_CASE("GL wetting's implicit diffusion matches Wetting's backward Euler and conserves the liquid", "[gpu][wetting]") {
  const std::unique_ptr<gpu::EglContext> context = openContext();
  if (!context) return;
  const Graph graph = sphereGraph(64);
  WettingSettings settings;  // defaults: merged stiff texels, at most 4 explicit sub-steps
  settings.diffusivity = 1e-4;
  const bool withPigment = GENERATE(false, true);
  // 40 stable steps: backward Euler on both; 1e6: the liquid is spread evenly in one step.
  const double stableSteps = GENERATE(40.0, 1e6);
  CAPTURE(withPigment, stableSteps);
  auto cpu = Wetting::create(graph.adjacency, graph.textures, settings);
  REQUIRE(cpu.ok());
  auto gl = gpu::GlWettingDiffusion::create(*context, graph.adjacency, settings);
  REQUIRE(gl.ok());
  auto texture = makeLiquidTexture(graph.textures.size(), WettingMaterial{}, {}, {}, withPigment);
  REQUIRE(texture.ok());
  for (std::size_t i = 0; i < texture->size(); ++i)
    if (graph.textures.position[i].x() > 0.2f) {
      texture->liquid[i] = texture->capacity[i];
      if (withPigment) texture->pigment[i] = texture->capacity[i] * (0.45f + 0.5f * graph.textures.position[i].y());
    }
  LiquidTexture onCpu = *texture, onGpu = *texture;
  const std::vector<double>& area = graph.adjacency.area;
  const double before = held(*texture, area);
  REQUIRE((*gl)->upload(onGpu).ok());
  const double dt = stableSteps * cpu->stableTimeStep();
  for (int step = 0; step < 3; ++step) {
    CHECK(cpu->diffuse(onCpu, dt) == 0);  // 0 sub-steps: the implicit solve ran
    const Expected<int> gpuSubsteps = (*gl)->diffuse(dt);
    INFO((gpuSubsteps ? std::string() : gpuSubsteps.error().message));
    REQUIRE(gpuSubsteps.ok());
    CHECK(*gpuSubsteps == 0);
  }
  REQUIRE((*gl)->download(onGpu).ok());
  const float capacity = texture->capacity[0];
  double worst = 0.0, moved = 0.0;
  for (std::size_t i = 0; i < onGpu.size(); ++i) {
    worst = std::max(worst, double(std::abs(onGpu.liquid[i] - onCpu.liquid[i])));
    moved = std::max(moved, double(std::abs(onCpu.liquid[i] - texture->liquid[i])));
  }
  CAPTURE(worst / capacity);
  CHECK(moved >= 0.1 * capacity);  // the liquid moved far: the comparison below means something
  // Per texel: both solve in double to a relative residual of 1e-10, the GPU with float
  // conductances and time step (6e-8 relative each), and store float contents: 1e-6 of the
  // capacity (measured 1.7e-7 on llvmpipe).
  CHECK(worst <= 1e-6 * capacity);
  // Volume: the pair fluxes are antisymmetric whatever the residual: 1e-6 as the explicit path.
  CHECK(std::abs(held(onGpu, area) - before) <= 1e-6 * before);
  if (withPigment) {
    const PigmentComparison pigment = comparePigment(*texture, onCpu, onGpu, area);
    // The pigment moves at the concentration upwind of each flux. At a million stable steps the
    // liquid is level and a pair's flux is dt D g times a difference of two nearly equal
    // solutions, whose sign the solvers' last bits decide: there 1e-4 (measured 2.4e-5).
    CHECK(pigment.worst <= (stableSteps > 100.0 ? 1e-4 : 1e-6) * capacity);
    CHECK(std::abs(pigment.gpu - pigment.before) <= 1e-6 * pigment.before);
  }
}

TEST_CASE("GL wetting diffusion refuses what it does not do, with errors", "[gpu][wetting]") {
  const std::unique_ptr<gpu::EglContext> context = openContext();
  if (!context) return;
  const Graph graph = sphereGraph(32);
  WettingSettings settings;
  settings.diffusivity = 1e-4;
  auto gl = gpu::GlWettingDiffusion::create(*context, graph.adjacency, settings);
  REQUIRE(gl.ok());
  CHECK(!(*gl)->diffuse(std::nan("")).ok());
  LiquidTexture wrong;
  wrong.liquid.assign(3, 0.0f);
  CHECK(!(*gl)->upload(wrong).ok());
  CHECK(!(*gl)->download(wrong).ok());
  // A pigment channel must come back into a texture that has one.
  auto pigmented = makeLiquidTexture(graph.textures.size(), WettingMaterial{}, {}, {}, true);
  REQUIRE(pigmented.ok());
  REQUIRE((*gl)->upload(*pigmented).ok());
  auto plain = makeLiquidTexture(graph.textures.size(), WettingMaterial{});
  REQUIRE(plain.ok());
  CHECK(!(*gl)->download(*plain).ok());
  CHECK((*gl)->download(*pigmented).ok());
  TexelAdjacency bad = graph.adjacency;
  bad.first[0] = std::uint32_t(bad.area.size() + 5);
  CHECK(!gpu::GlWettingDiffusion::create(*context, bad, settings).ok());
}

TEST_CASE("GL wetting steps match Wetting::step and balance absorbed = held + evaporated", "[gpu][wetting]") {
  const std::unique_ptr<gpu::EglContext> context = openContext();
  if (!context) return;
  const Graph graph = sphereGraph(64);
  WettingSettings settings;
  settings.diffusivity = 1e-6;
  settings.capillaryPressure = 500.0;
  settings.relativeHumidity = 0.2;
  settings.mergeBelowFraction = GENERATE(0.0, 0.1);  // merging off, and the default
  const bool withPigment = GENERATE(false, true);
  CAPTURE(settings.mergeBelowFraction, withPigment);
  settings.maxExplicitSubsteps = 1000;
  auto cpu = Wetting::create(graph.adjacency, graph.textures, settings);
  REQUIRE(cpu.ok());
  auto gl = gpu::GlWetting::create(*context, graph.adjacency, graph.textures, settings);
  INFO((gl ? std::string() : gl.error().message));
  REQUIRE(gl.ok());

  auto texture = makeLiquidTexture(graph.textures.size(), WettingMaterial{}, {}, {}, withPigment);
  REQUIRE(texture.ok());
  // Every fill level from dry to 6/7 full, so that both drying stages and Darcy's uptake run.
  for (std::size_t i = 0; i < texture->size(); ++i) texture->liquid[i] = texture->capacity[i] * float(i % 7) / 7.0f;
  if (withPigment)
    for (std::size_t i = 0; i < texture->size(); ++i) texture->pigment[i] = 0.1f * texture->liquid[i];
  LiquidTexture onCpu = *texture, onGpu = *texture;
  REQUIRE((*gl)->upload(onGpu).ok());
  // A third under water (pressure up to 6 kPa: Darcy's tau is about 1 s), rain on the part in the
  // air and a hose on its side.
  FlatSurface water(-0.15);
  // Waves across the sphere (0.1 m crests, 1.5 m long): the host evaluates their pressure per
  // texel for the GPU as the CPU does for itself.
  GerstnerWaves waves({GerstnerWave{0.1, 1.5, Eigen::Vector2d(1.0, 0.3), 0.4, 0.5}}, -0.15);
  const bool wavy = GENERATE(false, true);
  CAPTURE(wavy);
  WettingEnvironment environment;
  environment.liquid = wavy ? static_cast<const LiquidSurface*>(&waves) : &water;
  environment.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(20.0, 0.0, 0.0), Eigen::Vector3d::Zero());
  LiquidSource rain;
  rain.rate = 2e-5;
  LiquidSource hose;
  hose.kind = LiquidSourceKind::Sphere;
  hose.centre = Eigen::Vector3d(0.5, 0.3, 0.0);
  hose.radius = 0.2;
  hose.rate = 1e-4;
  hose.pigment = 0.4;  // a coloured liquid from the hose, clear rain
  environment.sources = {rain, hose};
  const std::vector<double>& area = graph.adjacency.area;
  const double held0 = texture->heldVolume(area);
  const double dt = std::min(0.5, 20.0 * (*gl)->stableTimeStep());
  double absorbedCpu = 0.0, absorbedGpu = 0.0, evaporatedCpu = 0.0, evaporatedGpu = 0.0;
  for (int step = 0; step < 10; ++step) {
    environment.time = step * dt;
    auto a = cpu->step(onCpu, environment, dt);
    auto b = (*gl)->step(environment, dt);
    REQUIRE(a.ok());
    INFO((b ? std::string() : b.error().message));
    REQUIRE(b.ok());
    CHECK(b->diffusionSubsteps == a->diffusionSubsteps);
    // The waterline's texels are decided by the float height on both sides: the same count.
    CHECK(b->submergedTexels == a->submergedTexels);
    absorbedCpu += a->absorbed;
    absorbedGpu += b->absorbed;
    evaporatedCpu += a->evaporated;
    evaporatedGpu += b->evaporated;
  }
  REQUIRE((*gl)->download(onGpu).ok());
  REQUIRE(absorbedCpu > 0.01 * held0);  // the uptake is no rounding: the comparisons below mean something
  REQUIRE(evaporatedCpu > 0.0);
  // Per texel: the same float equations in another order (the diffusion's gather, FMA contraction
  // on the GPU) over 10 steps of ~20 sub-steps: 1e-5 of the capacity (float rounding is 6e-8 per
  // operation).
  double worst = 0.0;
  for (std::size_t i = 0; i < onGpu.size(); ++i) worst = std::max(worst, double(std::abs(onGpu.liquid[i] - onCpu.liquid[i])));
  CHECK(worst <= 1e-5 * texture->capacity[0]);
  // Totals: the GPU sums 64 texels per work group in float before the double sum: 1e-5.
  CHECK(absorbedGpu == Approx(absorbedCpu).epsilon(1e-5));
  CHECK(evaporatedGpu == Approx(evaporatedCpu).epsilon(1e-5));
  // The GPU's own balance: held = held0 + absorbed - evaporated, to the float rounding of the
  // stored contents and of the work groups' float sums (6e-8 relative each, not accumulating
  // coherently): 1e-7 of the volume held (measured 3e-9 on llvmpipe, 2e-9 on the CPU).
  const double heldGpu = onGpu.heldVolume(area);
  CHECK(heldGpu == Approx(held0 + absorbedGpu - evaporatedGpu).margin(1e-7 * held0));
  CHECK(onCpu.heldVolume(area) == Approx(held0 + absorbedCpu - evaporatedCpu).margin(1e-7 * held0));
  if (withPigment) {
    // The hose's pigment came in and spread as on the CPU: per texel within the liquid's
    // tolerance, totals to 1e-6 (float sums of the same additions in another order).
    const PigmentComparison pigment = comparePigment(*texture, onCpu, onGpu, area);
    REQUIRE(pigment.cpu > 1.01 * pigment.before);  // the hose brought pigment: the checks below are not void
    CHECK(pigment.worst <= 1e-5 * texture->capacity[0]);
    CHECK(pigment.gpu == Approx(pigment.cpu).epsilon(1e-6));
  }
}

TEST_CASE("GL wetting refuses what it cannot do, with errors, and takes long steps and a medium", "[gpu][wetting]") {
  const std::unique_ptr<gpu::EglContext> context = openContext();
  if (!context) return;
  const Graph graph = sphereGraph(32);
  WettingSettings settings;  // defaults: merged stiff texels
  auto gl = gpu::GlWetting::create(*context, graph.adjacency, graph.textures, settings);
  REQUIRE(gl.ok());
  WettingEnvironment environment;
  CHECK_FALSE((*gl)->step(environment, 0.01).ok());  // nothing uploaded
  auto texture = makeLiquidTexture(graph.textures.size(), WettingMaterial{});
  REQUIRE((*gl)->upload(*texture).ok());
  UniformMedium medium(1000.0);
  environment.liquid = &medium;
  const Expected<WettingStepReport> inMedium = (*gl)->step(environment, 0.01);  // no free surface: all under
  REQUIRE(inMedium.ok());
  CHECK(inMedium->submergedTexels > 0);
  environment.liquid = nullptr;
  environment.sources.assign(gpu::GlWetting::kMaxSources + 1, LiquidSource{});
  CHECK_FALSE((*gl)->step(environment, 0.01).ok());
  environment.sources.clear();
  CHECK_FALSE((*gl)->step(environment, std::nan("")).ok());
  CHECK((*gl)->step(environment, 0.01).ok());
  // A step far beyond the explicit bound is not refused: backward Euler, as on the CPU.
  const Expected<WettingStepReport> longStep = (*gl)->step(environment, 1e4 * (*gl)->stableTimeStep());
  REQUIRE(longStep.ok());
  CHECK(longStep->implicitDiffusion);
  CHECK(longStep->diffusionSubsteps == 0);
  CHECK_FALSE(gpu::GlWetting::create(*context, graph.adjacency, SurfaceTextures{}, settings).ok());
}
