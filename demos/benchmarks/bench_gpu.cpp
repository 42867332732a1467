// SPDX-License-Identifier: Zlib
// Benchmark for issues 7 and 8: the compute backends on one batched step. Rows:
//   hydrostatics: 1,000 bodies (sphere, 256^2 bake each), flat surface, one batched step
//   mass: one body at 1024^2, uniform density, and with a density map uploaded each call
//   bake / upload: the CPU's exact bake and its one-time upload (why the bake is not rasterized)
//   waves: 100 of the bodies under three Gerstner waves, one batched step (texel by texel; the GL
//     backend's heights from its chunks' local surface models where they reach, and again with
//     every texel searched, GlBackendSettings::surfaceModels = false)
//   bake vs upload vs step, 256^2 and 1024^2: bakeSurface + evaluateSurface of one body, its
//     upload (addBody and the table rebuild its first step makes), one hydrostatics step of it
//   wetting at 1024^2: one diffusion sub-step, and one whole liquid texture step (absorb +
//     diffuse + evaporate, default settings, half submerged, rain, dt = 1/60 s) on each backend
// Beside each GPU figure the bandwidth floor: bytes the pass must read over the memory bandwidth
// (argv[2] in GB/s; default: measured host read bandwidth, which is what llvmpipe reads from).
// Prints a table and writes CSV (argv[1], default bench_gpu.csv):
// backend,renderer,what,bodies,texels,median_ms,runs,bytes_read,floor_ms
// Built with hydrotex::gpu when it exists (HYDROTEX_WITH_GPU); otherwise the CPU rows only.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#if defined(HYDROTEX_WITH_GPU)
#include "hydrotex/gpu/GlBackend.hpp"
#include "hydrotex/gpu/GlWetting.hpp"
#include "hydrotex/gpu/GlWettingDiffusion.hpp"
#endif
#include "hydrotex/bake/TexelAdjacency.hpp"
#include "hydrotex/wetting/Wetting.hpp"

#include "BenchmarkTiming.hpp"

using namespace hydrotex;

namespace {

using bench::medianMs;

// Streaming read bandwidth of this host (bytes/s), best of 5 passes over 512 MiB: the floor's
// denominator for llvmpipe, whose "GPU memory" is host memory.
double hostReadBandwidth() {
  std::vector<float> data(std::size_t(1) << 27, 1.0f);
  double best = 0.0;
  volatile float sink = 0.0f;
  for (int pass = 0; pass < 5; ++pass) {
    const auto start = std::chrono::steady_clock::now();
    float lanes[16] = {};
    for (std::size_t i = 0; i < data.size(); i += 16)
      for (int l = 0; l < 16; ++l) lanes[l] += data[i + std::size_t(l)];
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (float lane : lanes) sink = sink + lane;
    best = std::max(best, double(data.size() * sizeof(float)) / seconds);
  }
  return best;
}

struct Row {
  std::string backend, renderer, what;
  std::size_t bodies, texels;
  double medianMs;
  int runs;
  double bytesRead;  // 0: no floor given
};

BodyGeometry prepare(const Mesh& mesh, int resolution) {
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = resolution;
  Expected<BodyGeometry> body = prepareBodyGeometry(mesh, settings);
  if (!body) {
    std::fprintf(stderr, "bench_gpu: %s\n", body.error().message.c_str());
    std::exit(1);
  }
  return std::move(body).value();
}

}  // namespace

int main(int argc, char** argv) {
  // Positional only: an option-like first argument (--help) is not taken for the CSV's path.
  if (argc > 1 && argv[1][0] == '-') {
    std::fprintf(stderr, "usage: bench_gpu [CSV [BANDWIDTH_GBS]] ('%s' is not a file name this bench takes)\n", argv[1]);
    return std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h" ? 0 : 2;
  }
  const std::string csvPath = argc > 1 ? argv[1] : "bench_gpu.csv";
  const double bandwidth = argc > 2 ? std::atof(argv[2]) * 1e9 : hostReadBandwidth();
  if (argc > 2 && !(bandwidth > 0.0)) {
    std::fprintf(stderr, "bench_gpu: bandwidth '%s' GB/s is not a positive number\n", argv[2]);
    return 2;
  }
  constexpr std::size_t kBodies = 1000;
  std::vector<Row> rows;

  const Mesh sphere = primitives::uvSphere(0.5, 64, 32);
  const auto bakeStart = std::chrono::steady_clock::now();
  const BodyGeometry small = prepare(sphere, 256);
  const double bake256 = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - bakeStart).count();
  const auto bigStart = std::chrono::steady_clock::now();
  const BodyGeometry big = prepare(sphere, 1024);
  const double bake1024 = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - bigStart).count();
  rows.push_back({"cpu", "CPU", "prepare+bake 256^2 (once per body)", 1, small.textures.size(), bake256, 1, 0.0});
  rows.push_back({"cpu", "CPU", "prepare+bake 1024^2 (once per body)", 1, big.textures.size(), bake1024, 1, 0.0});

  // 1,000 floating spheres at seeded poses, all in one batch.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-30.0, 30.0), height(-0.2, 0.2);
  std::vector<BackendHydrostaticsQuery> queries(kBodies);
  for (std::size_t i = 0; i < kBodies; ++i) {
    queries[i].body = BackendBodyId(i);
    queries[i].query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(angle(rng), angle(rng), angle(rng)),
                                                 Eigen::Vector3d(double(i % 40), height(rng), double(i / 40)));
  }
  const FlatSurface water(0.0, 1025.0);

  // One backend alive at a time: 1,000 bodies hold gigabytes of texels.
  std::vector<std::function<std::unique_ptr<ComputeBackend>()>> makers = {[] { return makeCpuBackend(); }};
#if defined(HYDROTEX_WITH_GPU)
  makers.push_back([]() -> std::unique_ptr<ComputeBackend> {
    Expected<std::unique_ptr<ComputeBackend>> gl = gpu::makeGlBackend();
    if (gl) return std::move(gl).value();
    std::fprintf(stderr, "bench_gpu: GL backend skipped: %s\n", gl.error().message.c_str());
    return nullptr;
  });
#endif

  std::vector<std::vector<HydrostaticsResult>> answers, waveAnswers;
  for (auto& make : makers) {
    std::unique_ptr<ComputeBackend> backend = make();
    if (!backend) continue;
    const std::string name = backend->name(), renderer = backend->renderer();
    const auto addStart = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < kBodies; ++i)
      if (!backend->addBody(small.bake, small.textures, Eigen::Vector3d::Zero())) return 1;
    const double addMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - addStart).count();
    rows.push_back({name, renderer, "add 1000 bodies 256^2 (once)", kBodies, kBodies * small.textures.size(), addMs, 1, 0.0});

    std::vector<HydrostaticsResult> results(kBodies);
    Status status = backend->hydrostatics(water, queries, results);  // warm-up (tables, shaders)
    if (!status) {
      std::fprintf(stderr, "bench_gpu: %s\n", status.error().message.c_str());
      return 1;
    }
    const int runs = 7;
    const double ms = medianMs(runs, [&] { status = backend->hydrostatics(water, queries, results); });
    // The floor counts what the chunk hierarchy reads: every chunk header and pose, the moments
    // of chunks wholly under the water, the 52-byte texels of chunks crossing it (the GL
    // backend's own count of the last step); "all texels" is the floor of reading every texel.
    double bytesRead = 0.0;
#if defined(HYDROTEX_WITH_GPU)
    if (Expected<gpu::GlHydrostaticsStatistics> stats = gpu::lastHydrostaticsStatistics(*backend)) {
      bytesRead = stats->bytesRead;
      std::printf("gpu chunks: %zu, dry %zu, submerged %zu (moments), crossing %zu (%zu texels of %zu read)\n",
                  stats->chunks, stats->dryChunks, stats->submergedChunks, stats->crossingChunks, stats->texelsRead,
                  kBodies * small.textures.size());
      rows.push_back({name, renderer, "(floor if every texel were read)", kBodies, kBodies * small.textures.size(), 0.0, 0,
                      52.0 * double(kBodies * small.textures.size())});
    }
#endif
    rows.push_back({name, renderer, "hydrostatics 1000 x 256^2, one batched step", kBodies,
                    kBodies * small.textures.size(), ms, runs, bytesRead});
    answers.push_back(results);

    // Waves: the pressure integrated texel by texel over every chunk under the crests' height
    // (no pre-summed moments); the CPU backend's heights from its tile hierarchy's local models,
    // the GL backend's from its chunks' models where they reach, else a Newton search per texel:
    // 100 bodies keep the CPU run short.
    {
      const GerstnerWaves waves({GerstnerWave{0.3, 12.0, Eigen::Vector2d(1.0, 0.2), 0.0, 0.6},
                                 GerstnerWave{0.15, 5.0, Eigen::Vector2d(-0.3, 1.0), 1.0, 0.7},
                                 GerstnerWave{0.05, 2.0, Eigen::Vector2d(0.6, -0.8), 2.0, 0.5}},
                                0.0, 1025.0);
      constexpr std::size_t kWaveBodies = 100;
      std::vector<BackendHydrostaticsQuery> some(queries.begin(), queries.begin() + kWaveBodies);
      for (BackendHydrostaticsQuery& q : some) q.query.time = 2.5;
      std::vector<HydrostaticsResult> waveResults(kWaveBodies);
      status = backend->hydrostatics(waves, some, waveResults);  // warm-up
      if (!status) {
        std::fprintf(stderr, "bench_gpu: %s\n", status.error().message.c_str());
        return 1;
      }
      const double wavesMs = medianMs(5, [&] { status = backend->hydrostatics(waves, some, waveResults); });
      double waveBytes = 0.0;
#if defined(HYDROTEX_WITH_GPU)
      if (Expected<gpu::GlHydrostaticsStatistics> stats = gpu::lastHydrostaticsStatistics(*backend))
        waveBytes = stats->bytesRead;
#endif
      rows.push_back({name, renderer, "hydrostatics 100 x 256^2, 3 Gerstner waves", kWaveBodies,
                      kWaveBodies * small.textures.size(), wavesMs, 5, waveBytes});
      waveAnswers.push_back(waveResults);
#if defined(HYDROTEX_WITH_GPU)
      // The same on a GL backend that searches every texel: what the chunks' models save.
      if (gpu::lastHydrostaticsStatistics(*backend)) {
        gpu::GlBackendSettings perTexel;
        perTexel.surfaceModels = false;
        if (Expected<std::unique_ptr<ComputeBackend>> searched = gpu::makeGlBackend(perTexel)) {
          ComputeBackend& other = **searched;
          for (std::size_t i = 0; i < kWaveBodies; ++i)
            if (!other.addBody(small.bake, small.textures, Eigen::Vector3d::Zero())) return 1;
          std::vector<HydrostaticsResult> searchedResults(kWaveBodies);
          status = other.hydrostatics(waves, some, searchedResults);  // warm-up
          if (!status) {
            std::fprintf(stderr, "bench_gpu: %s\n", status.error().message.c_str());
            return 1;
          }
          const double searchedMs = medianMs(5, [&] { status = other.hydrostatics(waves, some, searchedResults); });
          rows.push_back({name, renderer, "hydrostatics 100 x 256^2, 3 Gerstner waves, every texel searched", kWaveBodies,
                          kWaveBodies * small.textures.size(), searchedMs, 5, waveBytes});
        }
      }
#endif
    }

    const BackendBodyId id = BackendBodyId(backend->addBody(big.bake, big.textures, Eigen::Vector3d::Zero()).value());
    TextureMassModel uniform;
    MassProperties mass;
    if (!backend->massProperties({&id, 1}, {&uniform, 1}, {&mass, 1})) return 1;  // warm-up
    const double massMs = medianMs(15, [&] { (void)backend->massProperties({&id, 1}, {&uniform, 1}, {&mass, 1}); });
    rows.push_back({name, renderer, "mass 1024^2 one body, uniform", 1, big.textures.size(), massMs, 15,
                    name == "cpu" ? 0.0 : 16.0 * double(big.textures.size())});
    TextureMassModel mapped;
    mapped.texelDensity.assign(big.textures.size(), 900.0f);
    const double mapMs = medianMs(15, [&] { (void)backend->massProperties({&id, 1}, {&mapped, 1}, {&mass, 1}); });
    rows.push_back({name, renderer, "mass 1024^2 one body, density map uploaded", 1, big.textures.size(), mapMs, 15,
                    name == "cpu" ? 0.0 : 20.0 * double(big.textures.size())});
  }

  // Bake on the CPU, uploaded once, or bake on the GPU (issue 7: "measure and choose"): per
  // resolution the exact bake and evaluation of one body, the upload of their result and one
  // per-step hydrostatics pass of that body (floating sphere, flat water) on each backend.
  for (const BodyGeometry* body : {&small, &big}) {
    const std::string res = std::to_string(body->bake.width) + "^2";
    BakeSettings settings;
    settings.width = body->bake.width;
    settings.height = body->bake.height;
    settings.tileSize = body->bake.tileSize;
    const double bakeMs = medianMs(3, [&] {
      Expected<SurfaceBake> bake = bakeSurface(body->mesh, body->atlas.layout, settings);
      if (bake) (void)evaluateSurface(*bake, body->mesh, body->atlas.layout);
    });
    rows.push_back({"cpu", "CPU", "bake+evaluate " + res + " (once per body)", 1, body->textures.size(), bakeMs, 3, 0.0});
    BackendHydrostaticsQuery floating;
    floating.query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(10.0, 20.0, 5.0), Eigen::Vector3d(0.0, 0.1, 0.0));
    HydrostaticsResult one;
    for (auto& make : makers) {
      std::unique_ptr<ComputeBackend> backend = make();
      if (!backend) continue;
      const auto added = backend->addBody(body->bake, body->textures, Eigen::Vector3d::Zero());
      if (!added) return 1;
      floating.body = *added;
      (void)backend->hydrostatics(water, {&floating, 1}, {&one, 1});
      const double stepMs = medianMs(7, [&] { (void)backend->hydrostatics(water, {&floating, 1}, {&one, 1}); });
      // Each upload run adds another copy of the body (its first step rebuilds the tables).
      const double uploadAndStepMs = medianMs(3, [&] {
        const auto copy = backend->addBody(body->bake, body->textures, Eigen::Vector3d::Zero());
        BackendHydrostaticsQuery q = floating;
        q.body = copy ? *copy : floating.body;
        (void)backend->hydrostatics(water, {&q, 1}, {&one, 1});
      });
      rows.push_back({backend->name(), backend->renderer(), "upload " + res + " (addBody + first step - step)", 1,
                      body->textures.size(), std::max(0.0, uploadAndStepMs - stepMs), 3, 0.0});
      rows.push_back({backend->name(), backend->renderer(), "hydrostatics one body " + res + " (per step)", 1,
                      body->textures.size(), stepMs, 7, 0.0});
    }
  }

  // Deforming body at 1024^2 on the GPU: vertices up, re-evaluation, then one hydrostatics query
  // (its read-back waits for the passes); and the liquid texture's diffusion at 1024^2 (one
  // explicit sub-step, the same merged groups on both sides; CPU Wetting::diffuse beside it).
  {
    WettingSettings wetting;
    wetting.maxExplicitSubsteps = 1;
    Expected<TexelAdjacency> graph = buildTexelAdjacency(big.bake, big.mesh, big.atlas.layout);
    Expected<Wetting> cpuWetting = graph ? Wetting::create(*graph, big.textures, wetting) : Expected<Wetting>(graph.error());
    Expected<LiquidTexture> liquid = makeLiquidTexture(big.textures.size(), WettingMaterial{});
    if (cpuWetting && liquid) {
      for (std::size_t i = 0; i < liquid->size(); ++i)
        if (big.textures.position[i].x() > 0.0f) liquid->liquid[i] = liquid->capacity[i];
      const double dt = cpuWetting->stableTimeStep();
      LiquidTexture onCpu = *liquid;
      const double cpuMs = medianMs(7, [&] { (void)cpuWetting->diffuse(onCpu, dt); });
      // Read: per texel its liquid and row start, per pair end a neighbour, a conductance and the
      // neighbour's liquid (4 bytes each); written: the liquid.
      const double pairEnds = 2.0 * double(graph->pairCount());
      const double bytes = 12.0 * double(liquid->size()) + 12.0 * pairEnds;
      rows.push_back({"cpu", "CPU", "wetting diffusion 1024^2, one sub-step", 1, liquid->size(), cpuMs, 7, 0.0});
      {
        Expected<Wetting> stepper = Wetting::create(*graph, big.textures, WettingSettings{});
        FlatSurface level(0.0);
        WettingEnvironment environment;
        environment.liquid = &level;
        environment.sources = {LiquidSource{}};
        LiquidTexture stepped = *liquid;
        const double cpuStepMs =
            stepper ? medianMs(7, [&] { (void)stepper->step(stepped, environment, 1.0 / 60.0); }) : 0.0;
        rows.push_back({"cpu", "CPU", "wetting step 1024^2 (absorb+diffuse+evaporate)", 1, liquid->size(), cpuStepMs, 7,
                        0.0});
      }
#if defined(HYDROTEX_WITH_GPU)
      if (Expected<std::unique_ptr<gpu::EglContext>> context = gpu::EglContext::create()) {
        const std::string renderer = (*context)->renderer();
        if (auto gl = gpu::GlWettingDiffusion::create(**context, *graph, wetting); gl && (*gl)->upload(*liquid)) {
          LiquidTexture back = *liquid;
          (void)(*gl)->diffuse(dt);
          const double syncMs = medianMs(7, [&] { (void)(*gl)->download(back); });
          const double stepMs = medianMs(7, [&] {
            (void)(*gl)->diffuse(dt);
            (void)(*gl)->download(back);
          });
          rows.push_back({"gpu", renderer, "wetting diffusion 1024^2, one sub-step", 1, liquid->size(),
                          std::max(0.0, stepMs - syncMs), 7, bytes});
        }
        // The whole liquid texture step of issue 8's goal (absorb + diffuse + evaporate, default
        // settings, half under a flat surface, rain, dt = 1/60 s); the step reads its few volume
        // partials back, so the time includes the GPU finishing.
        WettingSettings defaults;
        if (auto gl = gpu::GlWetting::create(**context, *graph, big.textures, defaults); gl && (*gl)->upload(*liquid)) {
          FlatSurface level(0.0);
          WettingEnvironment environment;
          environment.liquid = &level;
          environment.sources = {LiquidSource{}};
          (void)(*gl)->step(environment, 1.0 / 60.0);
          const double glStepMs = medianMs(7, [&] { (void)(*gl)->step(environment, 1.0 / 60.0); });
          rows.push_back({"gpu", renderer, "wetting step 1024^2 (absorb+diffuse+evaporate)", 1, liquid->size(), glStepMs,
                          7, 0.0});
        }
        Expected<std::unique_ptr<ComputeBackend>> backend = gpu::makeGlBackend(std::move(context).value());
        if (backend) {
          ComputeBackend& b = **backend;
          const BackendBodyId id = BackendBodyId(b.addBody(big.bake, big.textures, Eigen::Vector3d::Zero()).value());
          if (gpu::enableGpuDeformation(b, id, big.bake, big.mesh, big.atlas.layout)) {
            std::vector<Eigen::Vector3d> moved = big.mesh.positions;
            BackendHydrostaticsQuery q;
            q.body = id;
            HydrostaticsResult result;
            (void)b.hydrostatics(water, {&q, 1}, {&result, 1});
            const double queryMs = medianMs(7, [&] { (void)b.hydrostatics(water, {&q, 1}, {&result, 1}); });
            int frame = 0;
            const double deformMs = medianMs(7, [&] {
              const double scale = 1.0 + 0.01 * (++frame % 3);
              for (std::size_t v = 0; v < moved.size(); ++v) moved[v] = scale * big.mesh.positions[v];
              (void)gpu::updateVerticesOnGpu(b, id, moved);
              (void)b.hydrostatics(water, {&q, 1}, {&result, 1});
            });
            // Read per step: the vertices, the pieces (20 B) with their texels' piece starts, the
            // triangle frames (80 B per piece); written: the 52-byte texels.
            const double deformBytes = 12.0 * double(moved.size()) + 100.0 * double(big.bake.pieces.size()) +
                                       56.0 * double(big.textures.size());
            rows.push_back({"gpu", b.renderer(), "deform 1024^2: vertices up, re-evaluate (no query)", 1,
                            big.textures.size(), std::max(0.0, deformMs - queryMs), 7, deformBytes});
          }
        }
      }
#endif
    }
  }

  std::printf("%-8s %-34s %-46s %8s %10s %12s %12s\n", "backend", "renderer", "what", "bodies", "texels", "median ms",
              "floor ms");
  for (const Row& r : rows) {
    char floor[32] = "-";
    if (r.bytesRead > 0.0) std::snprintf(floor, sizeof floor, "%.3f", 1e3 * r.bytesRead / bandwidth);
    std::printf("%-8s %-34.34s %-46s %8zu %10zu %12.3f %12s\n", r.backend.c_str(), r.renderer.c_str(), r.what.c_str(),
                r.bodies, r.texels, r.medianMs, floor);
  }
  std::printf("bandwidth for the floor: %.1f GB/s (%s)\n", bandwidth / 1e9, argc > 2 ? "given" : "measured host read");
  if (answers.size() == 2) {
    double worstVolume = 0.0, worstCentre = 0.0;
    for (std::size_t i = 0; i < kBodies; ++i) {
      const HydrostaticsResult& c = answers[0][i];
      const HydrostaticsResult& g = answers[1][i];
      if (c.submergedVolume > 0.0)
        worstVolume = std::max(worstVolume, std::abs(g.submergedVolume - c.submergedVolume) / c.submergedVolume);
      worstCentre = std::max(worstCentre, (g.centerOfBuoyancy - c.centerOfBuoyancy).norm() / 1.0);
    }
    std::printf("gpu vs cpu over the 1000 bodies: volume %.2e relative, centre of buoyancy %.2e of the size\n",
                worstVolume, worstCentre);
  }
  if (waveAnswers.size() == 2) {
    double worstVolume = 0.0, worstForce = 0.0, worstCentre = 0.0;
    for (std::size_t i = 0; i < waveAnswers[0].size(); ++i) {
      const HydrostaticsResult& c = waveAnswers[0][i];
      const HydrostaticsResult& g = waveAnswers[1][i];
      if (!(c.submergedVolume > 0.0)) continue;
      worstVolume = std::max(worstVolume, std::abs(g.submergedVolume - c.submergedVolume) / c.submergedVolume);
      worstForce = std::max(worstForce, (g.buoyancyForce - c.buoyancyForce).norm() / c.buoyancyForce.norm());
      worstCentre = std::max(worstCentre, (g.centerOfBuoyancy - c.centerOfBuoyancy).norm() / 1.0);
    }
    std::printf("gpu vs cpu under waves (100 bodies): volume %.2e, force %.2e relative, centre %.2e of the size\n",
                worstVolume, worstForce, worstCentre);
  }

  FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (csv == nullptr) {
    std::fprintf(stderr, "bench_gpu: cannot write %s\n", csvPath.c_str());
    return 1;
  }
  std::fprintf(csv, "backend,renderer,what,bodies,texels,median_ms,runs,bytes_read,floor_ms\n");
  for (const Row& r : rows)
    std::fprintf(csv, "%s,\"%s\",\"%s\",%zu,%zu,%.4f,%d,%.0f,%.4f\n", r.backend.c_str(), r.renderer.c_str(), r.what.c_str(),
                 r.bodies, r.texels, r.medianMs, r.runs, r.bytesRead, r.bytesRead > 0.0 ? 1e3 * r.bytesRead / bandwidth : 0.0);
  std::fclose(csv);
  return 0;
}
