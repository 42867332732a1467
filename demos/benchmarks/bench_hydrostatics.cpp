// SPDX-License-Identifier: Zlib
// Hydrostatics speed (one core): texture path on a flat surface with the tile hierarchy and by
// brute force, the exact polyhedral path per triangle, and the texture path under Gerstner waves
// (hierarchy, and per texel). Prints two tables and writes them as CSV (argv[1], default
// bench_hydrostatics.csv, and the waves table beside it as *_waves.csv); `--waves` as argv[2]
// runs the waves table alone, `--exact-waves` the exact path under waves against flat water
// alone (printed, no CSV). Every figure is the median over several runs of the mean time of a
// batch of queries.
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

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

/// One row of the waves table: a 256^2 body under a sea against the same body in flat water.
struct WavesRow {
  std::string body, sea;
  double flatMicroseconds, wavesMicroseconds, ratio, perTexelMicroseconds, largestVolumeDifference;
};

/// The hierarchy under waves (issue 19 item 1, goal: at most 2x the flat-water cost): flat and
/// wavy queries timed in alternation, so that both see the same load on a shared machine, the
/// ratio the median of the rounds' ratios; the per-texel answer (TexelTraversal::BruteForce)
/// timed once; the largest volume difference from it over 24 poses and phases, of the body's
/// volume.
std::vector<WavesRow> wavesTable(int rounds) {
  std::vector<std::pair<std::string, GerstnerWaves>> seas;
  seas.push_back({"swell, 3 Gerstner", GerstnerWaves({GerstnerWave{0.10, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                                                      GerstnerWave{0.05, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5},
                                                      GerstnerWave{0.02, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3}})});
  seas.push_back({"log_waves, 2 Gerstner", GerstnerWaves({GerstnerWave{0.3, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                                                          GerstnerWave{0.1, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5}},
                                                         0.0, 1025.0)});
  const std::vector<std::pair<std::string, Mesh>> bodies = {{"uv sphere r 1 m", primitives::uvSphere(1.0, 96, 48)},
                                                            {"torus 1 m x 0.4 m", primitives::torus(1.0, 0.4, 64, 32)}};
  std::vector<WavesRow> rows;
  for (const auto& [bodyName, mesh] : bodies) {
    BakeSettings settings;
    settings.width = settings.height = 256;
    const auto bake = bakeSurface(mesh, mesh.uv, settings);
    if (!bake) return rows;
    const SurfaceTextures textures = evaluateSurface(*bake, mesh, mesh.uv);
    const auto body = TextureHydrostatics::build(*bake, textures);
    if (!body) return rows;
    const FlatSurface water(0.0);
    HydrostaticsQuery query;  // at the origin, half submerged, t = 0
    for (const auto& [seaName, waves] : seas) {
      std::vector<double> flat, wavy, ratios;
      for (int round = 0; round < rounds; ++round) {
        flat.push_back(medianSecondsPerCall([&] { sink = sink + body->query(water, query)->submergedVolume; }, 3));
        wavy.push_back(medianSecondsPerCall([&] { sink = sink + body->query(waves, query)->submergedVolume; }, 3));
        ratios.push_back(wavy.back() / flat.back());
      }
      const double perTexel = medianSecondsPerCall(
          [&] { sink = sink + body->query(waves, query, TexelTraversal::BruteForce)->submergedVolume; }, 3, 0.2);
      double largest = 0.0;
      std::mt19937 rng(11);
      std::normal_distribution<double> normal(0.0, 1.0);
      std::uniform_real_distribution<double> unit(-1.0, 1.0);
      for (int i = 0; i < 24; ++i) {
        HydrostaticsQuery posed;
        posed.pose.rotation =
            Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix();
        posed.pose.translation = Eigen::Vector3d(3.0 * unit(rng), 0.9 * unit(rng), 3.0 * unit(rng));
        posed.time = 5.0 + 5.0 * unit(rng);
        const auto h = body->query(waves, posed), t = body->query(waves, posed, TexelTraversal::BruteForce);
        if (h && t) largest = std::max(largest, std::abs(h->submergedVolume - t->submergedVolume) / body->enclosedVolume());
      }
      auto median = [](std::vector<double> values) {
        std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
        return values[values.size() / 2];
      };
      rows.push_back({bodyName + " 256^2", seaName, median(flat) * 1e6, median(wavy) * 1e6, median(ratios),
                      perTexel * 1e6, largest});
    }
  }
  return rows;
}

/// The exact path under waves (issue 19 item 2) against the same body in flat water: a 12-triangle
/// box, a ~300- and a ~3000-triangle sphere half submerged and tilted, flat and wavy queries timed
/// in alternation (the same load on a shared machine), medians over the rounds; the plain path
/// (the surface linear between vertices) and the prepared one (PreparedPolyhedron: local surface
/// models over its triangle nodes, what the controller runs); and a surfaceHeight call alone,
/// which the plain wavy query makes once per vertex that may be wet.
void exactWavesTable(int rounds) {
  const GerstnerWaves swell({GerstnerWave{0.10, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                             GerstnerWave{0.05, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5},
                             GerstnerWave{0.02, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3}});
  const FlatSurface water(0.0);
  HydrostaticsQuery query;
  query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(20, 10, 5), Eigen::Vector3d(0.0, 0.1, 0.0));
  query.time = 3.0;
  const std::vector<std::pair<std::string, Mesh>> bodies = {{"box 1 x 0.5 x 1", primitives::box({1.0, 0.5, 1.0})},
                                                            {"icosphere 2", primitives::icosphere(1.0, 2)},
                                                            {"uv sphere 48 x 32", primitives::uvSphere(1.0, 48, 32)},
                                                            {"uv sphere 96 x 48", primitives::uvSphere(1.0, 96, 48)}};
  std::printf("%-20s %10s %10s %10s %10s %7s %12s %12s %7s\n", "exact path", "triangles", "vertices", "flat us",
              "waves us", "ratio", "prep flat us", "prep waves", "ratio");
  for (const auto& [name, mesh] : bodies) {
    const PreparedPolyhedron prepared = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(mesh)).value();
    std::vector<double> flat, wavy, preparedFlat, preparedWavy;
    for (int round = 0; round < rounds; ++round) {
      flat.push_back(medianSecondsPerCall([&] { sink = sink + polyhedralHydrostaticsUnchecked(mesh, water, query)->submergedVolume; }, 3));
      wavy.push_back(medianSecondsPerCall([&] { sink = sink + polyhedralHydrostaticsUnchecked(mesh, swell, query)->submergedVolume; }, 3));
      preparedFlat.push_back(medianSecondsPerCall([&] { sink = sink + polyhedralHydrostatics(prepared, water, query)->submergedVolume; }, 3));
      preparedWavy.push_back(medianSecondsPerCall([&] { sink = sink + polyhedralHydrostatics(prepared, swell, query)->submergedVolume; }, 3));
    }
    const auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2] * 1e6;
    };
    const double f = median(flat), w = median(wavy), pf = median(preparedFlat), pw = median(preparedWavy);
    std::printf("%-20s %10zu %10zu %10.2f %10.2f %7.2f %12.2f %12.2f %7.2f\n", name.c_str(), mesh.triangles.size(),
                mesh.positions.size(), f, w, w / f, pf, pw, pw / pf);
  }
  double x = 0.0;
  const double seconds = medianSecondsPerCall([&] {
    for (int i = 0; i < 1000; ++i) sink = sink + swell.surfaceHeight(x + 0.01 * i, 0.3 * i, 0.0);
    x += 0.1;
  });
  std::printf("Gerstner surfaceHeight (3 waves): %.1f ns per call\n", seconds * 1e9 / 1000);
}

}  // namespace

int main(int argc, char** argv) {
  // [CSV] [--waves | --exact-waves]: anything else (an option where the CSV path goes, a third
  // argument) prints the usage, so that `--help` never becomes the name of a CSV file.
  const std::string csvArgument = argc > 1 ? argv[1] : "", table = argc > 2 ? argv[2] : "";
  if (argc > 3 || csvArgument.starts_with("-") || (!table.empty() && table != "--waves" && table != "--exact-waves")) {
    std::printf("usage: bench_hydrostatics [CSV (default bench_hydrostatics.csv)] [--waves | --exact-waves]\n");
    return csvArgument == "--help" || csvArgument == "-h" ? 0 : 2;
  }
  if (table == "--exact-waves") {
    exactWavesTable(9);
    return 0;
  }
  const std::string csvPath = csvArgument.empty() ? "bench_hydrostatics.csv" : csvArgument;
  {
    const std::vector<WavesRow> waves = wavesTable(9);
    std::printf("%-24s %-22s %10s %10s %7s %5s %12s %14s\n", "body", "sea", "flat us", "waves us", "ratio", "goal",
                "per-texel us", "max |dV|/V");
    const std::string wavesPath = csvPath.substr(0, csvPath.rfind(".csv")) + "_waves.csv";
    std::ofstream wavesCsv(wavesPath);
    wavesCsv << "body,sea,flat_microseconds,waves_microseconds,ratio,goal,per_texel_microseconds,"
                "largest_volume_difference\n";
    for (const WavesRow& row : waves) {
      std::printf("%-24s %-22s %10.1f %10.1f %7.2f %5.1f %12.1f %14.2e\n", row.body.c_str(), row.sea.c_str(),
                  row.flatMicroseconds, row.wavesMicroseconds, row.ratio, 2.0, row.perTexelMicroseconds,
                  row.largestVolumeDifference);
      wavesCsv << row.body << ',' << row.sea << ',' << row.flatMicroseconds << ',' << row.wavesMicroseconds << ','
               << row.ratio << ',' << 2.0 << ',' << row.perTexelMicroseconds << ',' << row.largestVolumeDifference
               << '\n';
    }
    std::printf("wrote %s\n\n", wavesPath.c_str());
    std::fflush(stdout);
    if (table == "--waves") return 0;
  }
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
