// SPDX-License-Identifier: Zlib
// Benchmark for issue 2: exact texel bake and texture mass properties on a 100k-triangle mesh,
// one core. Prints a table and writes CSV (argv[1], default bench_mass.csv):
// what,resolution,triangles,covered_texels,median_ms,runs
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

#include "BenchmarkTiming.hpp"

using namespace hydrotex;

namespace {

using bench::medianMs;

struct Row {
  std::string what;
  int resolution;
  std::size_t triangles, covered;
  double medianMs;
  int runs;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string csvPath = argc > 1 ? argv[1] : "bench_mass.csv";
  // Torus: 400 x 125 segments = 100,000 triangles, non-convex (cones of both signs).
  const Mesh mesh = primitives::torus(1.0, 0.3, 400, 125);
  std::vector<Row> rows;
  volatile double sink = 0.0;  // keeps results alive
  for (int resolution : {256, 1024}) {
    BakeSettings settings;
    settings.width = settings.height = resolution;
    Expected<SurfaceBake> bake = bakeSurface(mesh, mesh.uv, settings);
    if (!bake) {
      std::fprintf(stderr, "bench_mass: %s\n", bake.error().message.c_str());
      return 1;
    }
    const std::size_t covered = bake->coveredCount();
    auto add = [&](const std::string& what, int runs, const std::function<void()>& work) {
      rows.push_back({what, resolution, mesh.triangles.size(), covered, medianMs(runs, work), runs});
    };
    add("bake", 5, [&] { sink = sink + double(bakeSurface(mesh, mesh.uv, settings)->pieces.size()); });
    SurfaceTextures textures;
    add("evaluate_surface", 5, [&] { textures = evaluateSurface(*bake, mesh, mesh.uv); });
    TextureMassModel model;
    add("mass_prepare", 5, [&] { sink = sink + TextureMassIntegrator(textures, model.referencePoint).volume(); });
    const TextureMassIntegrator integrator(textures, model.referencePoint);
    add("mass_uniform", 51, [&] { sink = sink + integrator.evaluate(model)->mass; });
    TextureMassModel mapped = model;
    mapped.texelDensity.resize(covered);
    for (std::size_t i = 0; i < covered; ++i) mapped.texelDensity[i] = (i % 7 == 0) ? 500.0f : 1000.0f;
    add("mass_density_map", 51, [&] { sink = sink + integrator.evaluate(mapped)->mass; });
    TextureMassModel shell = model;
    shell.shellDensity = 5.0;
    add("mass_solid_and_shell", 51, [&] { sink = sink + integrator.evaluate(shell)->mass; });
    add("mass_one_shot", 5, [&] { sink = sink + textureMassProperties(textures, model).mass; });
  }
  rows.push_back({"polyhedral_exact", 0, mesh.triangles.size(), 0,
                  medianMs(11, [&] { sink = sink + polyhedralMassProperties(mesh, 1000.0)->mass; }), 11});

  std::printf("%-22s %10s %10s %14s %12s %6s\n", "what", "resolution", "triangles", "covered_texels", "median_ms",
              "runs");
  for (const Row& r : rows)
    std::printf("%-22s %10d %10zu %14zu %12.3f %6d\n", r.what.c_str(), r.resolution, r.triangles, r.covered,
                r.medianMs, r.runs);
  if (FILE* csv = std::fopen(csvPath.c_str(), "w")) {
    std::fprintf(csv, "what,resolution,triangles,covered_texels,median_ms,runs\n");
    for (const Row& r : rows)
      std::fprintf(csv, "%s,%d,%zu,%zu,%.4f,%d\n", r.what.c_str(), r.resolution, r.triangles, r.covered, r.medianMs,
                   r.runs);
    std::fclose(csv);
    std::printf("wrote %s\n", csvPath.c_str());
  } else {
    std::fprintf(stderr, "bench_mass: cannot write %s\n", csvPath.c_str());
    return 1;
  }
  return 0;
}
