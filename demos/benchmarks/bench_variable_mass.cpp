// Benchmark for issue 5 (variable mass, deforming bodies), one core. Per step of a deforming body:
// move the vertices, re-evaluate PT/VAT from the kept bake (evaluateSurface), re-prepare the mass
// pass and run it (MassModel); and for a rigid body whose mass distribution changes every step,
// MassModel's cost next to the bare texel pass (TextureMassIntegrator::evaluate). Prints a table
// and writes CSV (argv[1], default bench_variable_mass.csv):
// what,resolution,triangles,covered_texels,median_ms,runs
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "hydrotex/MassModel.hpp"
#include "hydrotex/Primitives.hpp"
#include "hydrotex/SurfaceBake.hpp"
#include "hydrotex/TextureHydrostatics.hpp"

using namespace hydrotex;

namespace {

double medianMs(int runs, const std::function<void()>& work) {
  std::vector<double> times;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    work();
    times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

struct Row {
  std::string what;
  int resolution;
  std::size_t triangles, covered;
  double medianMs;
  int runs;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string csvPath = argc > 1 ? argv[1] : "bench_variable_mass.csv";
  // A balloon-like envelope: 64 x 32 UV sphere (4k triangles).
  const Mesh rest = primitives::uvSphere(1.0, 64, 32);
  std::vector<Row> rows;
  volatile double sink = 0.0;  // keeps results alive
  constexpr int kRuns = 51;
  for (int resolution : {256, 512}) {
    BakeSettings settings;
    settings.width = settings.height = resolution;
    Expected<SurfaceBake> bake = bakeSurface(rest, rest.uv, settings);
    if (!bake) {
      std::fprintf(stderr, "bench_variable_mass: %s\n", bake.error().message.c_str());
      return 1;
    }
    const std::size_t covered = bake->coveredCount();
    auto add = [&](const std::string& what, const std::function<void()>& work) {
      rows.push_back({what, resolution, rest.triangles.size(), covered, medianMs(kRuns, work), kRuns});
    };
    Mesh moved = rest;
    MassModel model(evaluateSurface(*bake, rest, rest.uv), Eigen::Vector3d::Zero());
    (void)model.setShellDensity(0.05);
    (void)model.setSolidDensity(0.95);
    int step = 0;
    auto moveVertices = [&] {
      const double scale = 1.0 + 0.001 * (++step % 100);
      for (std::size_t i = 0; i < rest.positions.size(); ++i) moved.positions[i] = scale * rest.positions[i];
    };
    SurfaceTextures textures;
    add("evaluate_surface", [&] {
      moveVertices();
      textures = evaluateSurface(*bake, moved, rest.uv);
    });
    add("deform_step_mass (move + evaluate_surface + mass pass)", [&] {
      moveVertices();
      textures = evaluateSurface(*bake, moved, rest.uv);
      (void)model.setGeometry(textures);
      sink = sink + model.properties()->mass;
    });
    add("hydrostatics_rebuild (TextureHydrostatics::build)", [&] {
      sink = sink + double(TextureHydrostatics::build(*bake, textures)->tileCount());
    });

    // A rigid body whose density map changes every step: MassModel against the bare texel pass.
    TextureMassIntegrator integrator(textures, Eigen::Vector3d::Zero());
    TextureMassModel bare;
    bare.texelDensity.assign(integrator.size(), 500.0f);
    add("texel_pass_only (TextureMassIntegrator::evaluate, density map)", [&] {
      bare.texelDensity[0] = float(500 + step++ % 7);
      sink = sink + integrator.evaluate(bare)->mass;
    });
    MassModel rigid(textures, Eigen::Vector3d::Zero());
    PointMass basket;
    basket.mass = 5.0;
    (void)rigid.addPointMass(basket);
    (void)rigid.setTexelDensity(std::vector<float>(rigid.texelCount(), 500.0f));
    std::vector<float> spare(rigid.texelCount(), 500.0f);  // two buffers, swapped every step
    add("variable_map_step (MassModel, new map every step)", [&] {
      spare[0] = float(500 + step++ % 7);  // the animation refills the spare buffer
      (void)rigid.swapTexelDensity(spare);
      sink = sink + rigid.properties()->mass;
    });
    add("point_mass_step (MassModel, a point mass moved)", [&] {
      (void)rigid.setPointMassPosition(0, Eigen::Vector3d(0.0, -1.0, 0.001 * (step++ % 100)));
      sink = sink + rigid.properties()->mass;
    });
    add("unchanged_step (MassModel, nothing changed)", [&] { sink = sink + rigid.properties()->mass; });
  }

  std::printf("%-66s %6s %9s %9s %10s\n", "what", "res", "triangles", "texels", "median ms");
  for (const Row& row : rows) {
    std::printf("%-66s %6d %9zu %9zu %10.4f\n", row.what.c_str(), row.resolution, row.triangles, row.covered,
                row.medianMs);
  }
  std::FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (csv == nullptr) {
    std::fprintf(stderr, "bench_variable_mass: cannot write %s\n", csvPath.c_str());
    return 1;
  }
  std::fprintf(csv, "what,resolution,triangles,covered_texels,median_ms,runs\n");
  for (const Row& row : rows) {
    std::fprintf(csv, "\"%s\",%d,%zu,%zu,%.6f,%d\n", row.what.c_str(), row.resolution, row.triangles, row.covered,
                 row.medianMs, row.runs);
  }
  std::fclose(csv);
  std::printf("wrote %s\n", csvPath.c_str());
  return sink == 0.123456 ? 2 : 0;
}
