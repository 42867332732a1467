// SPDX-License-Identifier: Zlib
// bench_liquid_graph: cost of one liquid graph step (Darcy through the permeable texels, the
// implicit level solve with its active set, levels and free-surface centroids) for a body of 64
// nodes baked at 512^2, with permeability maps from a small hole to a wholly permeable surface;
// and the cost of building the graph. One core. Prints a table, writes CSV (argv[1] or
// bench_liquid_graph.csv).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/flooding/LiquidGraph.hpp"
#include "hydrotex/flooding/LiquidGraphBuilder.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::string csvPath = argc > 1 ? argv[1] : "bench_liquid_graph.csv";
  constexpr int kResolution = 512;
  constexpr int kNodes = 64;
  // A 4 m x 1 m x 1 m hull (many-node graphs want an elongated body), subdivided for the cells' ray test.
  BodyGeometrySettings geometrySettings;
  geometrySettings.bake.width = geometrySettings.bake.height = kResolution;
  auto geometry = prepareBodyGeometry(primitives::subdividedBox(Eigen::Vector3d(4, 1, 1), 8), geometrySettings);
  if (!geometry) {
    std::fprintf(stderr, "%s\n", geometry.error().message.c_str());
    return 1;
  }
  const SurfaceTextures& tex = geometry->textures;
  struct Case {
    const char* name;
    double fraction;  // share of the surface that is permeable (from the bottom up)
  };
  const Case cases[] = {{"hole 1%", 0.01}, {"damage 10%", 0.10}, {"half 50%", 0.50}, {"all white 100%", 1.0}};
  std::ofstream csv(csvPath);
  csv << "case,texels,permeable_texels,nodes,edges,build_ms,step_median_us,step_min_us,active_set_rounds\n";
  std::printf("%-16s %9s %10s %6s %6s %10s %14s %12s\n", "case", "texels", "permeable", "nodes", "edges", "build ms",
              "step median us", "step min us");
  for (const Case& c : cases) {
    // Permeable where the texel lies in the lowest `fraction` of the hull's height range (a
    // stable order: by height, then by texel index).
    std::vector<std::size_t> order(tex.size());
    for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tex.position[a].y() < tex.position[b].y(); });
    std::vector<float> pmt(tex.size(), 0.0f);
    for (std::size_t i = 0; i < std::size_t(c.fraction * double(order.size())); ++i) pmt[order[i]] = 1.0f;
    LiquidGraphBuildSettings settings;
    settings.permeability = 1e-10;
    const auto built = Clock::now();
    auto graph = buildAutomaticLiquidGraph(geometry->mesh, tex, pmt, kNodes, settings);
    const double buildMs = std::chrono::duration<double, std::milli>(Clock::now() - built).count();
    if (!graph) {
      std::fprintf(stderr, "%s\n", graph.error().message.c_str());
      return 1;
    }
    const FlatSurface water(0.0, 1025.0);
    FloodingQuery query;
    query.timeStep = 1.0 / 60.0;
    std::vector<double> perStep;
    int rounds = 0;
    // Five runs of 200 steps, rocking and heaving through the surface; the median run's mean step.
    for (int run = 0; run < 5; ++run) {
      const auto start = Clock::now();
      for (int i = 0; i < 200; ++i) {
        const double t = (run * 200 + i) * query.timeStep;
        query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(8.0 * std::sin(0.9 * t), 0.0, 3.0 * std::sin(0.4 * t)),
                                          Eigen::Vector3d(0.0, 0.1 * std::sin(0.5 * t), 0.0));
        auto step = graph->step(water, query);
        if (!step) {
          std::fprintf(stderr, "%s\n", step.error().message.c_str());
          return 1;
        }
        rounds = std::max(rounds, step->activeSetRounds);
      }
      perStep.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count() / 200.0);
    }
    const double med = median(perStep), best = *std::min_element(perStep.begin(), perStep.end());
    std::printf("%-16s %9zu %10zu %6zu %6zu %10.1f %14.1f %12.1f\n", c.name, tex.size(), graph->permeableTexels().size(),
                graph->nodes().size(), graph->edges().size(), buildMs, med, best);
    csv << c.name << ',' << tex.size() << ',' << graph->permeableTexels().size() << ',' << graph->nodes().size() << ','
        << graph->edges().size() << ',' << buildMs << ',' << med << ',' << best << ',' << rounds << '\n';
  }
  std::printf("goal: a step under 500 us for 64 nodes and a 512^2 PMT; CSV: %s\n", csvPath.c_str());
  return 0;
}
