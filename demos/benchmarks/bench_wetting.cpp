// SPDX-License-Identifier: Zlib
// bench_wetting: one liquid texture step (absorb + diffuse + evaporate) at several resolutions,
// and the texel graph against the paper's Liquid Density Field on accuracy (harmonic decay on a
// sphere) and time. Prints a table and writes bench_wetting.csv (or argv[1]). Medians of 15 runs
// of the calling thread's CPU time (the machine is shared; wall time counts other jobs' slices).
// `bench_wetting out.csv --steps` runs the step table only; `--profile` runs 200 1024^2 plate steps
// and nothing else (for valgrind --tool=callgrind --toggle-collect='hydrotex::Wetting::step*').
// Built with hydrotex::gpu, it also times the GL step (GlWetting: absorb + evaporate pass, then
// the diffusion sub-steps; download of the volumes moved included) in wall time, medians of 15,
// on whatever EGL opens (llvmpipe without a GPU) (`--gpu` runs that table only).
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hydrotex/wetting/LiquidDensityField.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/wetting/Wetting.hpp"
#ifdef HYDROTEX_WITH_GPU
#include <chrono>

#include "hydrotex/gpu/GlWetting.hpp"
#endif

using namespace hydrotex;

namespace {

Mesh plate(double side) {
  Mesh mesh;
  mesh.sourceName = "plate";
  const double h = 0.5 * side;
  mesh.positions = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
  mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
  mesh.uv.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.uv.uvTriangles = mesh.triangles;
  return mesh;
}

double threadCpuMs() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return 1e3 * static_cast<double>(now.tv_sec) + 1e-6 * static_cast<double>(now.tv_nsec);
}

template <class F>
double medianMs(int runs, F&& f) {
  std::vector<double> ms;
  for (int r = 0; r < runs; ++r) {
    const double t0 = threadCpuMs();
    f();
    ms.push_back(threadCpuMs() - t0);
  }
  std::nth_element(ms.begin(), ms.begin() + runs / 2, ms.end());
  return ms[runs / 2];
}

struct Prepared {
  SurfaceTextures textures;
  TexelAdjacency graph;
};

Prepared prepare(const Mesh& mesh, int resolution) {
  BakeSettings settings;
  settings.width = settings.height = resolution;
  auto bake = bakeSurface(mesh, mesh.uv, settings);
  if (!bake) {
    std::fprintf(stderr, "%s\n", bake.error().message.c_str());
    std::exit(1);
  }
  auto graph = buildTexelAdjacency(*bake, mesh, mesh.uv);
  return {evaluateSurface(*bake, mesh, mesh.uv), std::move(graph).value()};
}

double amplitude(const TexelAdjacency& g, const std::vector<float>& liquid) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < liquid.size(); ++i) {
    const double y = g.centroid[i].normalized().x();
    num += g.area[i] * liquid[i] * y;
    den += g.area[i] * y * y;
  }
  return num / den;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string csvPath = argc > 1 ? argv[1] : "bench_wetting.csv";
  const std::string mode = argc > 2 ? argv[2] : "";
  // --profile / --profile-sphere: 200 1024^2 steps of the plate / the UV sphere only, for a profiler.
  const bool profileSphere = mode == "--profile-sphere", profile = mode == "--profile" || profileSphere, stepsOnly = mode == "--steps" || profile, gpuOnly = mode == "--gpu";
  std::ofstream csv(csvPath);
  csv << "table,case,resolution,texels,pairs,merged_texels,substeps,absorb_ms,diffuse_ms,evaporate_ms,step_ms,error\n";
  const int runs = 15;

  std::printf("One liquid texture step, dt = 1/60 s, D = 1e-6 m^2/s, half submerged, rain (medians of %d)\n", runs);
  // merged: texels pooled into diffusion groups (stiff texels near a UV sphere's poles and slivers).
  std::printf("%-10s %6s %9s %9s %7s %5s %9s %9s %9s %9s\n", "case", "res", "texels", "pairs", "merged", "sub", "absorb",
              "diffuse", "evaporate", "step ms");
  for (const char* name : {"plate", "uv sphere"}) {
    for (int resolution : {256, 512, 1024}) {
      if (gpuOnly) break;
      if (profile && (resolution != 1024 || (std::string(name) == "plate") == profileSphere)) continue;
      const bool isPlate = std::string(name) == "plate";
      const Mesh mesh = isPlate ? plate(1.0) : primitives::uvSphere(0.5, 256, 128);
      Prepared p = prepare(mesh, resolution);
      const std::size_t pairs = p.graph.pairCount();
      WettingSettings settings;
      auto wetting = Wetting::create(std::move(p.graph), p.textures, settings);
      if (!wetting) return 1;
      LiquidTexture texture = *makeLiquidTexture(p.textures.size(), WettingMaterial{});
      for (std::size_t i = 0; i < texture.size(); ++i) texture.liquid[i] = texture.capacity[i] * float(i % 7) / 7.0f;
      FlatSurface water(0.0);
      WettingEnvironment environment;
      environment.liquid = &water;
      // The plate is tilted so that half of it is under water.
      environment.pose = isPlate ? Pose::fromDegreesXYZ(Eigen::Vector3d(0, 0, 30), Eigen::Vector3d::Zero()) : Pose{};
      environment.sources = {LiquidSource{}};
      const double dt = 1.0 / 60.0;
      if (profile) {
        for (int k = 0; k < 200; ++k) (void)wetting->step(texture, environment, dt);
        return 0;
      }
      std::size_t submerged = 0;
      int substeps = 0;
      const double absorbMs = medianMs(runs, [&] { wetting->absorb(texture, environment, dt, submerged); });
      const double diffuseMs = medianMs(runs, [&] { substeps = wetting->diffuse(texture, dt); });
      const double evaporateMs = medianMs(runs, [&] { wetting->evaporate(texture, dt); });
      const double stepMs = medianMs(runs, [&] { (void)wetting->step(texture, environment, dt); });
      const std::size_t merged = wetting->mergedTexelCount();
      std::printf("%-10s %6d %9zu %9zu %7zu %5d %9.3f %9.3f %9.3f %9.3f\n", name, resolution, texture.size(), pairs, merged,
                  substeps, absorbMs, diffuseMs, evaporateMs, stepMs);
      csv << "step," << name << ',' << resolution << ',' << texture.size() << ',' << pairs << ',' << merged << ',' << substeps
          << ',' << absorbMs << ',' << diffuseMs << ',' << evaporateMs << ',' << stepMs << ",\n";
    }
  }

#ifdef HYDROTEX_WITH_GPU
  if (!profile && !(stepsOnly && !gpuOnly)) {
    auto context = gpu::EglContext::create();
    if (!context) {
      std::printf("\nGL step skipped: %s\n", context.error().message.c_str());
    } else {
      std::printf("\nGL liquid texture step on %s (plate, half submerged, rain; default settings; wall ms, medians of %d)\n",
                  (*context)->renderer().c_str(), runs);
      std::printf("%-10s %6s %9s %5s %9s\n", "case", "res", "texels", "sub", "step ms");
      for (int resolution : {256, 512, 1024}) {
        Prepared p = prepare(plate(1.0), resolution);
        WettingSettings settings;
        auto gl = gpu::GlWetting::create(**context, p.graph, p.textures, settings);
        if (!gl) {
          std::fprintf(stderr, "%s\n", gl.error().message.c_str());
          return 1;
        }
        LiquidTexture texture = *makeLiquidTexture(p.textures.size(), WettingMaterial{});
        for (std::size_t i = 0; i < texture.size(); ++i) texture.liquid[i] = texture.capacity[i] * float(i % 7) / 7.0f;
        if (!(*gl)->upload(texture)) return 1;
        FlatSurface water(0.0);
        WettingEnvironment environment;
        environment.liquid = &water;
        environment.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(0, 0, 30), Eigen::Vector3d::Zero());
        environment.sources = {LiquidSource{}};
        int substeps = 0;
        std::vector<double> ms;
        for (int r = 0; r < runs; ++r) {
          const auto t0 = std::chrono::steady_clock::now();
          auto report = (*gl)->step(environment, 1.0 / 60.0);  // reads the partials back: the GPU has finished
          ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
          if (!report) {
            std::fprintf(stderr, "%s\n", report.error().message.c_str());
            return 1;
          }
          substeps = report->diffusionSubsteps;
        }
        std::nth_element(ms.begin(), ms.begin() + runs / 2, ms.end());
        std::printf("%-10s %6d %9zu %5d %9.3f\n", "plate", resolution, texture.size(), substeps, ms[runs / 2]);
        csv << "gl_step,plate," << resolution << ',' << texture.size() << ",,," << substeps << ",,,," << ms[runs / 2] << ",\n";
      }
    }
  }
#endif
  if (stepsOnly || gpuOnly) {
    std::printf("\nCSV: %s\n", csvPath.c_str());
    return 0;
  }
  std::printf("\nTexel graph vs Liquid Density Field: l = 1 pattern on a unit sphere, D = 0.01, t = 10 s (exact decay %.5f)\n",
              std::exp(-0.2));
  std::printf("%-22s %6s %9s %12s %12s\n", "method", "res", "texels", "decay error", "ms per 1 s");
  for (int resolution : {128, 256}) {
    Prepared p = prepare(primitives::uvSphere(1.0, 128, 64), resolution);
    std::vector<float> initial(p.textures.size());
    for (std::size_t i = 0; i < initial.size(); ++i) initial[i] = float(1.0 + 0.5 * p.graph.centroid[i].normalized().x());
    const double exact = std::exp(-0.2);
    const double a0 = amplitude(p.graph, initial);
    for (double voxel : {0.0, 0.05, 0.025}) {
      std::vector<float> liquid = initial;
      double ms = 0.0, error = 0.0;
      std::string method;
      if (voxel == 0.0) {
        WettingSettings settings;
        settings.diffusivity = 0.01;
        settings.relativeHumidity = 1.0;
        auto wetting = Wetting::create(p.graph, p.textures, settings);
        LiquidTexture texture = *makeLiquidTexture(liquid.size(), WettingMaterial{});
        texture.liquid = liquid;
        WettingEnvironment environment;
        ms = medianMs(5, [&] {
          texture.liquid = liquid;
          for (int k = 0; k < 10; ++k) (void)wetting->step(texture, environment, 1.0);
        }) / 10.0;
        error = amplitude(p.graph, texture.liquid) / a0 / exact - 1.0;
        method = "texel graph (implicit)";
      } else {
        auto field = LiquidDensityField::build(p.graph, voxel);
        std::vector<float> work;
        ms = medianMs(5, [&] {
          work = liquid;
          for (int k = 0; k < 10; ++k) field->diffuse(work, 0.01, 1.0);
        }) / 10.0;
        error = amplitude(p.graph, work) / a0 / exact - 1.0;
        method = "LDF voxel " + std::to_string(voxel).substr(0, 5) + " m";
      }
      std::printf("%-22s %6d %9zu %11.2f%% %12.3f\n", method.c_str(), resolution, liquid.size(), 100.0 * error, ms);
      csv << "ldf_compare," << method << ',' << resolution << ',' << liquid.size() << ",,,,,,," << ms << ',' << error << '\n';
    }
  }
  std::printf("\nCSV: %s\n", csvPath.c_str());
  return 0;
}
