// Wetting's diffusion on the GPU (GlWettingDiffusion) against core's Wetting::diffuse on the same
// graph: a UV sphere (pairs across its seam) with a patch of liquid, several steps of explicit
// sub-steps, merging off on both sides. The GL cases are skipped with a WARN only when no EGL
// context can be opened.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "hydrotex/Primitives.hpp"
#include "hydrotex/SurfaceBake.hpp"
#include "hydrotex/TexelAdjacency.hpp"
#include "hydrotex/Wetting.hpp"
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

}  // namespace

TEST_CASE("GL wetting diffusion matches Wetting::diffuse and conserves the liquid", "[gpu][wetting]") {
  Expected<std::unique_ptr<gpu::EglContext>> context = gpu::EglContext::create();
  if (!context) {
    WARN("GL wetting skipped, no headless EGL context: " << context.error().message);
    return;
  }
  const Graph graph = sphereGraph(64);
  WettingSettings settings;
  settings.diffusivity = 1e-4;
  settings.mergeBelowFraction = 0.0;  // the GPU has no merged groups yet
  settings.maxExplicitSubsteps = 1000;
  auto cpu = Wetting::create(graph.adjacency, graph.textures, settings);
  REQUIRE(cpu.ok());
  auto gl = gpu::GlWettingDiffusion::create(**context, graph.adjacency, settings);
  INFO((gl ? std::string() : gl.error().message));
  REQUIRE(gl.ok());
  CHECK((*gl)->stableTimeStep() == Approx(cpu->stableTimeStep()).epsilon(1e-12));  // the same bound

  // Liquid on the texels with x > 0.2 (a cap that touches the seam), saturated.
  auto texture = makeLiquidTexture(graph.textures.size(), WettingMaterial{});
  REQUIRE(texture.ok());
  for (std::size_t i = 0; i < texture->size(); ++i)
    if (graph.textures.position[i].x() > 0.2f) texture->liquid[i] = texture->capacity[i];
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
  // relative over 50 sub-steps (the CPU's own float path is held to the same).
  CHECK(std::abs(held(onGpu, graph.adjacency.area) - before) <= 1e-6 * before);
  CHECK(std::abs(held(onCpu, graph.adjacency.area) - before) <= 1e-6 * before);
}

TEST_CASE("GL wetting diffusion refuses what it does not do, with errors", "[gpu][wetting]") {
  Expected<std::unique_ptr<gpu::EglContext>> context = gpu::EglContext::create();
  if (!context) {
    WARN("GL wetting skipped, no headless EGL context: " << context.error().message);
    return;
  }
  const Graph graph = sphereGraph(32);
  WettingSettings merging;  // default: merging on
  CHECK(!gpu::GlWettingDiffusion::create(**context, graph.adjacency, merging).ok());
  WettingSettings settings;
  settings.mergeBelowFraction = 0.0;
  settings.diffusivity = 1e-4;
  auto gl = gpu::GlWettingDiffusion::create(**context, graph.adjacency, settings);
  REQUIRE(gl.ok());
  CHECK(!(*gl)->diffuse(1e6 * (*gl)->stableTimeStep()).ok());  // would need the implicit solve
  CHECK(!(*gl)->diffuse(std::nan("")).ok());
  LiquidTexture wrong;
  wrong.liquid.assign(3, 0.0f);
  CHECK(!(*gl)->upload(wrong).ok());
  CHECK(!(*gl)->download(wrong).ok());
  TexelAdjacency bad = graph.adjacency;
  bad.first[0] = std::uint32_t(bad.area.size() + 5);
  CHECK(!gpu::GlWettingDiffusion::create(**context, bad, settings).ok());
}
