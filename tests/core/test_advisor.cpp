// SPDX-License-Identifier: Zlib
// The advisor (Advisor.hpp): its sample of poses against closed forms, its error measures, and
// that the advice it gives holds at poses it did not sample.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "hydrotex/hydrostatics/Advisor.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/mesh/Primitives.hpp"

using namespace hydrotex;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Fast timing: these tests check what is measured, not how fast.
AdvisorSettings quickSettings() {
  AdvisorSettings settings;
  settings.timing.runs = 3;
  settings.timing.batchSeconds = 0.002;
  return settings;
}

/// Worst errors of the texture path at `resolution` against the exact path over `sampling`.
HydrostaticsErrors textureErrors(const Mesh& mesh, int resolution, const QuerySampling& sampling) {
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = resolution;
  Expected<BodyGeometry> body = prepareBodyGeometry(mesh, settings);
  REQUIRE(body);
  Expected<TextureHydrostatics> texture = TextureHydrostatics::build(body->bake, body->textures);
  REQUIRE(texture);
  const FlatSurface water(0.0);
  ErrorScales scales;
  scales.totalVolume = polyhedralMassProperties(mesh, 1.0)->volume;
  scales.size = meshSize(mesh);
  HydrostaticsErrors worst;
  for (const HydrostaticsQuery& query : sampleHydrostaticsQueries(mesh, sampling)) {
    Expected<HydrostaticsResult> exact = polyhedralHydrostatics(mesh, water, query);
    Expected<HydrostaticsResult> approx = texture->query(water, query);
    REQUIRE(exact);
    REQUIRE(approx);
    worst.keepMax(hydrostaticsErrors(*approx, *exact, scales));
  }
  return worst;
}

/// Every texture candidate's error estimate, whichever method wins, against the worst errors over
/// the same sample recomputed here (the same bake, the exact path as reference). Only the order of
/// the texel sums may differ (hierarchy or brute force: 1e-9 of the total volume, test_texture_
/// hydrostatics), so 1e-8 absolute on errors relative to the total volume and the size.
void checkTextureEstimates(const Mesh& mesh, const Advice& advice, const QuerySampling& sampling) {
  int checked = 0;
  for (const MethodMeasurement& candidate : advice.candidates) {
    if (candidate.method == HydrostaticsMethod::Exact) continue;
    CAPTURE(methodName(candidate.method), candidate.resolution);
    const HydrostaticsErrors measured = textureErrors(mesh, candidate.resolution, sampling);
    CHECK(measured.worst() > 0.0);
    CHECK(candidate.maxErrors.volume == Approx(measured.volume).margin(1e-8));
    CHECK(candidate.maxErrors.centerOfBuoyancy == Approx(measured.centerOfBuoyancy).margin(1e-8));
    CHECK(candidate.maxErrors.force == Approx(measured.force).margin(1e-8));
    ++checked;
  }
  CHECK(checked > 0);
}

}  // namespace

TEST_CASE("the sampled poses put the water at the stated fractions of the body's height", "[advisor]") {
  const double radius = 1.0;
  const Mesh sphere = primitives::uvSphere(radius, 96, 48);
  QuerySampling sampling;
  sampling.depthCount = 3;
  sampling.orientationCount = 2;
  const std::vector<HydrostaticsQuery> queries = sampleHydrostaticsQueries(sphere, sampling);
  REQUIRE(queries.size() == 6);
  const FlatSurface water(0.0);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    // Water at (k + 1) / 4 of the height: a cap of depth d = 2 r (k + 1) / 4, V = pi d^2 (3r - d) / 3
    // (docs/references.md). The mesh is a polyhedron inscribed in the sphere: its volume is short by
    // about (2 pi / 96)^2 / 2 = 0.2 %, so 1 % of the sphere's volume bounds the difference.
    const double depth = 2.0 * radius * double(i % 3 + 1) / 4.0;
    const double cap = kPi * depth * depth * (3.0 * radius - depth) / 3.0;
    Expected<HydrostaticsResult> exact = polyhedralHydrostatics(sphere, water, queries[i]);
    REQUIRE(exact);
    CHECK(exact->submergedVolume == Approx(cap).margin(0.01 * 4.0 / 3.0 * kPi));
  }
  CHECK(meshSize(sphere) == Approx(2.0 * std::sqrt(3.0)).epsilon(1e-9));  // the bounding cube's diagonal
  CHECK(sampleHydrostaticsQueries(sphere, QuerySampling{0, 1}).empty());
  CHECK(sampleHydrostaticsQueries(sphere, QuerySampling{1, 9}).empty());
  CHECK(sampleHydrostaticsQueries(Mesh{}, QuerySampling{}).empty());
}

TEST_CASE("error measures are the stated ratios", "[advisor]") {
  HydrostaticsResult reference, answer;
  reference.submergedVolume = 1.0;
  answer.submergedVolume = 1.1;
  reference.centerOfBuoyancy = Eigen::Vector3d(0, -0.5, 0);
  answer.centerOfBuoyancy = Eigen::Vector3d(0.03, -0.46, 0);  // 0.05 m away
  reference.buoyancyForce = Eigen::Vector3d(0, 1000 * 9.81, 0);
  answer.buoyancyForce = Eigen::Vector3d(0, 1100 * 9.81, 0);
  ErrorScales scales{2.0, 10.0, 1000.0, 9.81};
  const HydrostaticsErrors errors = hydrostaticsErrors(answer, reference, scales);
  CHECK(errors.volume == Approx(0.05));           // 0.1 m^3 of 2 m^3
  CHECK(errors.centerOfBuoyancy == Approx(0.005));// 0.05 m of 10 m
  CHECK(errors.force == Approx(0.05));            // 100 g N of rho g 2 m^3
  CHECK(errors.worst() == Approx(0.05));

  MassProperties exact, approx;
  exact.mass = 4.0;
  approx.mass = 3.0;
  exact.centerOfMass = Eigen::Vector3d(1, 0, 0);
  approx.centerOfMass = Eigen::Vector3d(1, 0.2, 0);
  exact.inertia = Eigen::Matrix3d::Identity() * 2.0;
  approx.inertia = Eigen::Matrix3d::Identity() * 2.2;
  const MassErrors mass = massErrors(approx, exact, 4.0);
  CHECK(mass.mass == Approx(0.25));
  CHECK(mass.centerOfMass == Approx(0.05));
  CHECK(mass.inertia == Approx(0.1));
}

TEST_CASE("texture errors fall with resolution", "[advisor]") {
  // The waterline term is O(texel size): four times the resolution must cut the worst error by
  // well over half; a factor 2 leaves room for how the texel grid meets the waterline.
  const Mesh sphere = primitives::uvSphere(1.0, 64, 32);
  const QuerySampling sampling{3, 3};
  const HydrostaticsErrors coarse = textureErrors(sphere, 32, sampling);
  const HydrostaticsErrors fine = textureErrors(sphere, 128, sampling);
  INFO("coarse " << coarse.worst() << " fine " << fine.worst());
  CHECK(fine.worst() < coarse.worst() / 2.0);
  CHECK(fine.force < coarse.force / 2.0);
}

TEST_CASE("advice meets the target, is the cheapest resolution, and holds at unsampled poses", "[advisor]") {
  const Mesh sphere = primitives::uvSphere(1.0, 128, 64);  // 16k triangles: the exact path is not free
  AdvisorSettings settings = quickSettings();
  settings.resolutions = {32, 64, 128, 256};
  const double target = 2e-4;  // between the 64^2 and 128^2 errors of this sphere (about 2.5e-4 and 7e-5)
  Expected<Advice> advice = adviseHydrostatics(sphere, target, settings);
  REQUIRE(advice);
  REQUIRE(!advice->candidates.empty());
  CHECK(advice->candidates.front().method == HydrostaticsMethod::Exact);
  CHECK(advice->candidates.front().maxErrors.worst() == 0.0);
  CHECK(advice->best.maxErrors.worst() <= target);
  for (const MethodMeasurement& candidate : advice->candidates) {
    CHECK(candidate.microsecondsPerQuery > 0.0);
    CHECK(candidate.bytes > 0);
    if (candidate.maxErrors.worst() <= target) CHECK(candidate.microsecondsPerQuery >= advice->best.microsecondsPerQuery);
  }
  checkTextureEstimates(sphere, *advice, settings.sampling);
  if (advice->best.method != HydrostaticsMethod::Exact) {
    // Cheapest: the next lower resolution misses the target (over the same sample).
    if (advice->best.resolution > 32) {
      const HydrostaticsErrors lower = textureErrors(sphere, advice->best.resolution / 2, settings.sampling);
      CHECK(lower.worst() > target);
    }
    // Holds elsewhere: 7 depths and 8 orientations, most of them not sampled. Errors vary
    // smoothly with the pose, so the sampled maximum bounds them within a small factor (2).
    const HydrostaticsErrors elsewhere = textureErrors(sphere, advice->best.resolution, QuerySampling{7, 8});
    CHECK(elsewhere.worst() <= 2.0 * target);
  }
}

TEST_CASE("a target no texture resolution reaches picks the exact path", "[advisor]") {
  const Mesh box = primitives::box(Eigen::Vector3d(2.0, 1.0, 0.5));
  AdvisorSettings settings = quickSettings();
  settings.resolutions = {32, 64};
  settings.includeBruteForce = true;
  Expected<Advice> advice = adviseHydrostatics(box, 1e-14, settings);
  REQUIRE(advice);
  CHECK(advice->best.method == HydrostaticsMethod::Exact);
  CHECK(advice->best.resolution == 0);
  CHECK(methodName(advice->best.method) == "exact");
  // The exact path won because the texture estimates are right, not because they are broken.
  checkTextureEstimates(box, *advice, settings.sampling);
}

TEST_CASE("the advisor rejects bad targets, open meshes and bad settings with a message", "[advisor]") {
  const Mesh box = primitives::box(Eigen::Vector3d(1.0, 1.0, 1.0));
  const AdvisorSettings settings = quickSettings();
  for (double target : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Expected<Advice> advice = adviseHydrostatics(box, target, settings);
    REQUIRE(!advice);
    CHECK(advice.error().message.find("target error") != std::string::npos);
  }
  Mesh open = box;
  open.triangles.pop_back();
  Expected<Advice> openAdvice = adviseHydrostatics(open, 0.01, settings);
  CHECK(!openAdvice);

  AdvisorSettings tiny = settings;
  tiny.resolutions = {8};
  Expected<Advice> tinyAdvice = adviseHydrostatics(box, 0.01, tiny);
  REQUIRE(!tinyAdvice);
  CHECK(tinyAdvice.error().message.find("resolution 8") != std::string::npos);

  AdvisorSettings badSampling = settings;
  badSampling.sampling.orientationCount = 0;
  CHECK(!adviseHydrostatics(box, 0.01, badSampling));
}

TEST_CASE("timing reports a positive median per call", "[advisor]") {
  int calls = 0;
  const double seconds = medianSecondsPerCall([&] { ++calls; }, TimingSettings{3, 0.001});
  CHECK(seconds > 0.0);
  CHECK(std::isfinite(seconds));
  CHECK(calls >= 2 + 3);  // warm-up, probe, then at least one call per run
}

TEST_CASE("modeled times: the same advice on every run, from the cost model's figures", "[advisor][model]") {
  // The model's own closed forms (Advisor.hpp): in flat water exact 0.01 + 0.05 sqrt(T) us,
  // hierarchy 0.9 + 0.089 R us, brute force 10 + 0.0045 R^2; under waves 30 + 0.35 sqrt(T),
  // 10 + 0.3 R and 100 + 0.055 R^2 (a waterline factor of 1).
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, 10000, 0) == Approx(5.01));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureHierarchy, 12, 256) == Approx(23.684));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureBruteForce, 12, 64) == Approx(10.0 + 0.0045 * 64 * 64));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, 10000, 0, true) == Approx(65.0));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureHierarchy, 12, 256, true) == Approx(86.8));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureBruteForce, 12, 64, true) == Approx(100.0 + 0.055 * 64 * 64));
  // A 32,256-triangle sphere at 64^2: the texture path is modeled cheaper (6.6 against 9.0 us;
  // measured 5.9 against 9.1 at the model's pose), so a target it meets makes it the advice,
  // whatever the machine's load; twice the same.
  const Mesh sphere = primitives::uvSphere(1.0, 256, 64);
  REQUIRE(sphere.triangles.size() > 32000);
  AdvisorSettings settings;
  settings.resolutions = {64};
  settings.timing.modeled = true;
  const Expected<Advice> first = adviseHydrostatics(sphere, 1e-2, settings);
  const Expected<Advice> second = adviseHydrostatics(sphere, 1e-2, settings);
  REQUIRE(first);
  REQUIRE(second);
  REQUIRE(first->candidates.size() == 2);
  const double factor = waterlineFactor(sphere);  // 1 to rounding: the waterline of a sphere
  CHECK(factor == Approx(1.0).epsilon(1e-3));
  CHECK(first->candidates[0].microsecondsPerQuery ==
        modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, sphere.triangles.size(), 0, false, factor));
  CHECK(first->candidates[1].microsecondsPerQuery ==
        modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureHierarchy, 0, 64, false, factor));
  CHECK(first->candidates[1].maxErrors.worst() <= 1e-2);
  CHECK(first->best.method == HydrostaticsMethod::TextureHierarchy);
  CHECK(second->best.method == first->best.method);
  CHECK(second->candidates[1].maxErrors.worst() == first->candidates[1].maxErrors.worst());
  // A target the texture path misses at 64^2 leaves the exact path, which always meets it.
  const Expected<Advice> strict = adviseHydrostatics(sphere, 1e-9, settings);
  REQUIRE(strict);
  CHECK(strict->best.method == HydrostaticsMethod::Exact);
}

TEST_CASE("exact path under waves: a node too wide for a model is tested against its wide ancestor's", "[advisor][model]") {
  // A node too wide for a model within the tolerance is skipped when wholly over a model with a
  // wider bound (PolyhedralHydrostaticsWaves.cpp); it asks for one of its own only when its
  // footprint is under kWideRefresh (half) of the nearest such ancestor's, and is otherwise
  // tested against that one. A Wigley hull (6,334 faces) floating at half its draft under a swell,
  // at four poses and times: the walk asks for at most the models below (2,076 with a model for
  // every such node, before kWideRefresh; 1,440 now). Its answers are checked against the
  // per-texel answer in test_polyhedral_hydrostatics_waves.
  const GerstnerWaves sea({GerstnerWave{0.10, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                           GerstnerWave{0.05, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5},
                           GerstnerWave{0.02, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3}},
                          0.0, 1025.0);
  const Expected<PreparedPolyhedron> hull =
      PreparedPolyhedron::prepare(std::make_shared<const Mesh>(primitives::wigleyHull(4.0, 0.4, 0.25, 96, 16)));
  REQUIRE(hull.ok());
  std::size_t models = 0;
  for (int k = 0; k < 4; ++k) {
    HydrostaticsQuery query;
    query.pose.rotation = Eigen::AngleAxisd(0.03 * k, Eigen::Vector3d::UnitX()).toRotationMatrix();
    query.pose.translation = Eigen::Vector3d(0.7 * k, 0.125, 0.0);
    query.time = 0.8 * k;
    ExactWaveWork work;
    REQUIRE(polyhedralHydrostatics(*hull, sea, query, &work).ok());
    models += work.models;
  }
  CHECK(models <= 1700);
}

TEST_CASE("modeled exact time under waves: the counted work of queries at a standard pose", "[advisor][model]") {
  // modeledExactMicroseconds (Advisor.hpp) prices what wavePolyhedralHydrostatics counts
  // (ExactWaveWork): deterministic, and counting does not change the answer.
  const GerstnerWaves sea({GerstnerWave{0.3, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                           GerstnerWave{0.1, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5}},
                          0.0, 1025.0);
  const FlatSurface flat(0.0, 1025.0);
  const auto prepare = [](const Mesh& mesh) {
    Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(std::make_shared<const Mesh>(mesh));
    REQUIRE(prepared.ok());
    return std::move(*prepared);
  };
  const PreparedPolyhedron box = prepare(primitives::box({1.0, 0.5, 1.0}));
  const PreparedPolyhedron log = prepare(primitives::cylinder(0.25, 3.0, 32));

  HydrostaticsQuery query;
  query.pose.translation = Eigen::Vector3d(0.3, 0.05, -0.2);
  query.pose.rotation = Eigen::AngleAxisd(0.2, Eigen::Vector3d(1.0, 0.3, 0.5).normalized()).toRotationMatrix();
  query.time = 1.5;
  ExactWaveWork work, again;
  const Expected<HydrostaticsResult> counted = polyhedralHydrostatics(log, sea, query, &work);
  const Expected<HydrostaticsResult> recounted = polyhedralHydrostatics(log, sea, query, &again);
  const Expected<HydrostaticsResult> plain = polyhedralHydrostatics(log, sea, query);
  REQUIRE(counted.ok());
  REQUIRE(recounted.ok());
  REQUIRE(plain.ok());
  CHECK(counted->submergedVolume == plain->submergedVolume);
  CHECK(counted->buoyancyForce == plain->buoyancyForce);
  CHECK(work.nodes == again.nodes);
  CHECK(work.models == again.models);
  CHECK(work.pieces == again.pieces);
  CHECK(work.clippedTriangles == again.clippedTriangles);
  CHECK(work.jets == again.jets);
  CHECK(work.sampledPieces == again.sampledPieces);
  // The log's sides, 3 m slivers, take a model for each strip: far more than its 128 triangles.
  CHECK(work.models > 500);
  CHECK(work.pieces >= work.models / 2);
  CHECK(work.surfaceHeights == 0);  // every piece found a model within the tolerance
  CHECK(work.jets > 0);
  // The per-unit costs.
  CHECK(modeledExactMicroseconds(work) ==
        Approx(0.05 * double(work.nodes) + 0.10 * double(work.models) + 0.045 * double(work.clippedTriangles) +
               0.31 * double(work.surfaceHeights) + 0.19 * double(work.jets) + 0.05 * double(work.sampledPieces)));

  // Flat water counts only the nodes its own hierarchy visited; nothing of the models is counted
  // there, nor for a body above every crest.
  ExactWaveWork none{1, 1, 1, 1, 1, 1, 1};
  REQUIRE(polyhedralHydrostatics(log, flat, query, &none).ok());
  CHECK(none.nodes > 0);
  CHECK(none.nodes <= log.nodeCount());
  CHECK(none.models + none.pieces + none.clippedTriangles + none.surfaceHeights + none.jets + none.sampledPieces == 0);
  HydrostaticsQuery high = query;
  high.pose.translation.y() = 10.0;
  ExactWaveWork dry;
  REQUIRE(polyhedralHydrostatics(log, sea, high, &dry).ok());
  CHECK(dry.models == 0);
  CHECK(dry.pieces == 0);
  CHECK(dry.clippedTriangles == 0);

  // At the standard pose: the log priced several times a sqrt(T) model's figure; the box (measured
  // 24.5-38 us against the texture path's 48 at 256^2) still under the texture path's price at
  // 256^2, so Auto keeps it exact; flat water keeps the model in sqrt(T).
  const Expected<double> logCost = modeledExactMicroseconds(log, sea);
  const Expected<double> boxCost = modeledExactMicroseconds(box, sea);
  REQUIRE(logCost.ok());
  REQUIRE(boxCost.ok());
  CHECK(*logCost > 4.0 * modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, 128, 0, true));
  CHECK(*boxCost < modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureHierarchy, 12, 256, true,
                                               waterlineFactor(primitives::box({1.0, 0.5, 1.0}))));
  CHECK(*modeledExactMicroseconds(log, sea) == *logCost);
  CHECK(*modeledExactMicroseconds(log, flat) ==
        modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, 128, 0, false, waterlineFactor(log.mesh())));
}

TEST_CASE("waterline factor: the waterline's length against a sphere's for the same area", "[advisor][model]") {
  // L / sqrt(pi A) with L cut upright at mid height (Advisor.hpp). A sphere: 2 pi r / sqrt(pi 4 pi
  // r^2) = 1 (its tessellation a little under: clamped to 1). The 1 x 0.5 x 1 m box: L = 4 m,
  // A = 4 m^2, 4 / sqrt(4 pi) = 1.128. A log of radius 0.25 m and length 3 m lying along z: L =
  // 2 x 3 + 2 x 0.5 = 7 m, A = 2 pi 0.25 x 3 + 2 pi 0.25^2 = 5.105 m^2, 1.748 (its 32-gon's area
  // and width 0.3 % under the circle's).
  CHECK(waterlineFactor(primitives::uvSphere(0.5, 64, 32)) == Approx(1.0).epsilon(1e-3));
  CHECK(waterlineFactor(primitives::box({1.0, 0.5, 1.0})) == Approx(4.0 / std::sqrt(4.0 * 3.141592653589793)).epsilon(1e-12));
  CHECK(waterlineFactor(primitives::cylinder(0.25, 3.0, 32)) == Approx(1.748).epsilon(5e-3));
  // It scales the tile hierarchy's term in R and, in flat water, the exact path's in sqrt(T); the
  // exact path's formula under waves (its counted work prices it there) keeps none.
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureHierarchy, 12, 256, true, 2.0) == Approx(10.0 + 0.3 * 512));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureHierarchy, 12, 256, false, 2.0) == Approx(0.9 + 0.089 * 512));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::TextureHierarchy, 12, 256, true, 0.5) == Approx(86.8));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, 10000, 0, false, 2.0) == Approx(0.01 + 0.05 * 200));
  CHECK(modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, 10000, 0, true, 2.0) == Approx(65.0));
}
