// SPDX-License-Identifier: Zlib
// Hydrostatics speed (one core): texture path on a flat surface with the tile hierarchy and by
// brute force, the exact polyhedral path per triangle, and the texture path under Gerstner waves
// per texel. Prints a table and writes CSV (argv[1], default bench_hydrostatics.csv). Every figure
// is the median over several runs of the mean time of a batch of queries.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hydrotex/LiquidSurface.hpp"
#include "hydrotex/PolyhedralHydrostatics.hpp"
#include "hydrotex/Primitives.hpp"
#include "hydrotex/SurfaceBake.hpp"
#include "hydrotex/TextureHydrostatics.hpp"

using namespace hydrotex;

namespace {

volatile double sink = 0.0;  // keeps the optimiser from dropping the queries

/// Median over `runs` of the mean seconds per call of `work` over batches of ~`budget` seconds.
template <class Work>
double medianSecondsPerCall(Work&& work, int runs = 7, double budget = 0.05) {
  using Clock = std::chrono::steady_clock;
  work();  // warm caches
  auto start = Clock::now();
  work();
  const double once = std::chrono::duration<double>(Clock::now() - start).count();
  const int batch = std::max(1, int(budget / std::max(once, 1e-9)));
  std::vector<double> samples;
  for (int run = 0; run < runs; ++run) {
    start = Clock::now();
    for (int i = 0; i < batch; ++i) work();
    samples.push_back(std::chrono::duration<double>(Clock::now() - start).count() / batch);
  }
  std::nth_element(samples.begin(), samples.begin() + runs / 2, samples.end());
  return samples[std::size_t(runs / 2)];
}

struct Row {
  std::string benchmark, configuration;
  double size, microseconds, perElementNanoseconds;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string csvPath = argc > 1 ? argv[1] : "bench_hydrostatics.csv";
  std::vector<Row> rows;
  std::printf("%-28s %-28s %12s %14s %16s\n", "benchmark", "configuration", "size", "us/query", "ns/element");
  auto report = [&](const Row& row) {
    std::printf("%-28s %-28s %12.0f %14.2f %16.3f\n", row.benchmark.c_str(), row.configuration.c_str(), row.size,
                row.microseconds, row.perElementNanoseconds);
    std::fflush(stdout);
    rows.push_back(row);
  };

  // Texture path: uv sphere of radius 1, half submerged in a flat surface.
  const Mesh sphere = primitives::uvSphere(1.0, 96, 48);
  const FlatSurface water(0.0);
  std::vector<GerstnerWave> swell(3);
  swell[0] = {0.10, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5};
  swell[1] = {0.05, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5};
  swell[2] = {0.02, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3};
  const GerstnerWaves waves(swell);
  HydrostaticsQuery query;
  for (int resolution : {64, 128, 256, 512, 1024, 2048}) {
    BakeSettings settings;
    settings.width = settings.height = resolution;
    const auto bake = bakeSurface(sphere, sphere.uv, settings);
    if (!bake) {
      std::fprintf(stderr, "bake failed: %s\n", bake.error().message.c_str());
      return 1;
    }
    const SurfaceTextures textures = evaluateSurface(*bake, sphere, sphere.uv);
    const auto body = TextureHydrostatics::build(*bake, textures);
    if (!body) {
      std::fprintf(stderr, "build failed: %s\n", body.error().message.c_str());
      return 1;
    }
    const double texels = double(body->texelCount());
    const std::string config = std::to_string(resolution) + "^2 tile " + std::to_string(body->tileSize()) +
                               " group " + std::to_string(body->tileSize() * body->groupSize());
    for (TexelTraversal traversal : {TexelTraversal::Hierarchy, TexelTraversal::BruteForce}) {
      const double seconds = medianSecondsPerCall([&] { sink = sink + body->query(water, query, traversal)->submergedVolume; });
      report({traversal == TexelTraversal::Hierarchy ? "texture flat hierarchy" : "texture flat brute force", config,
              double(resolution) * resolution, seconds * 1e6, seconds * 1e9 / texels});
    }
    if (resolution == 256 || resolution == 1024) {
      // Sweep of (tile, group) sizes in texels per side: the group loop grows as 1/group^2, the
      // waterline band as the tile size. Group 0: one level (each tile its own group).
      for (int tileSize : {2, 4, 8, 16}) {
        for (int groupTexels : {0, 16, 32, 64}) {
          if (groupTexels != 0 && groupTexels <= tileSize) continue;
          const TextureHydrostaticsSettings sweep{tileSize, groupTexels == 0 ? 1 : groupTexels / tileSize};
          const auto swept = TextureHydrostatics::build(*bake, textures, sweep);
          const double seconds = medianSecondsPerCall([&] { sink = sink + swept->query(water, query)->submergedVolume; });
          report({"texture flat tile sweep",
                  std::to_string(resolution) + "^2 tile " + std::to_string(tileSize) + " group " +
                      std::to_string(tileSize * swept->groupSize()),
                  double(resolution) * resolution, seconds * 1e6, seconds * 1e9 / texels});
        }
      }
    }
    if (resolution <= 512) {
      const double seconds = medianSecondsPerCall([&] { sink = sink + body->query(waves, query)->submergedVolume; });
      report({"texture waves (3 Gerstner)", config, double(resolution) * resolution, seconds * 1e6, seconds * 1e9 / texels});
    }
  }
  {
    // The surface query alone, per call: what waves add per texel.
    double x = 0.0;
    const double seconds = medianSecondsPerCall([&] {
      for (int i = 0; i < 1000; ++i) sink = sink + waves.surfaceHeight(x + 0.01 * i, 0.3 * i, 0.0);
      x += 0.1;
    });
    report({"Gerstner surfaceHeight", "3 waves", 1000, seconds * 1e6, seconds * 1e9 / 1000});
  }

  // Exact path: icospheres, half submerged and tilted, from 1k to 1.3M triangles.
  query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(20, 10, 5), Eigen::Vector3d(0.0, 0.1, 0.0));
  for (int subdivisions = 3; subdivisions <= 8; ++subdivisions) {
    const Mesh mesh = primitives::icosphere(1.0, subdivisions);
    const double triangles = double(mesh.triangles.size());
    const double seconds = medianSecondsPerCall(
        [&] { sink = sink + polyhedralHydrostaticsUnchecked(mesh, water, query)->submergedVolume; }, 7, 0.1);
    report({"exact path", "icosphere " + std::to_string(subdivisions), triangles, seconds * 1e6, seconds * 1e9 / triangles});
  }

  std::ofstream csv(csvPath);
  csv << "benchmark,configuration,size,microseconds_per_query,nanoseconds_per_element\n";
  for (const Row& row : rows)
    csv << row.benchmark << ',' << row.configuration << ',' << row.size << ',' << row.microseconds << ','
        << row.perElementNanoseconds << '\n';
  std::printf("wrote %s\n", csvPath.c_str());
  return 0;
}
