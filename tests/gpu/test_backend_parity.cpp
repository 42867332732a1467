// SPDX-License-Identifier: Zlib
// The same test bodies run against every compute backend (CPU, and GL on whatever headless EGL
// gives: llvmpipe on CI): closed forms and the exact polyhedral path first, then the GL backend
// against the CPU backend on the same inputs (issue 7's parity: 1e-5 relative on volume and force,
// 1e-4 of the body's size on centres), batching rules, storage segments, deforming surfaces.
// Without an EGL context the GL cases WARN and return; a case left with no assertion then fails
// under CTest (--warn NoAssertions, tests/CMakeLists.txt), so a machine with no EGL fails the suite.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <utility>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "OpenTopBox.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/mesh/MeshRepair.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/gpu/GlBackend.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

constexpr int kResolution = 128;  // enough texels per body for the closed forms below, quick on llvmpipe

struct TestBody {
  std::string name;
  BodyGeometry geometry;
  double size;                       // largest extent (m): the scale of the centre tolerances
  Eigen::Vector3d centroid;          // exact (m, body frame): mass reference point
  double volume;                     // exact enclosed volume (m^3)
};

const std::vector<TestBody>& testBodies() {
  static const std::vector<TestBody> bodies = [] {
    std::vector<TestBody> out;
    auto add = [&](const std::string& name, Mesh mesh, double size) {
      BodyGeometrySettings settings;
      settings.bake.width = settings.bake.height = kResolution;
      Expected<BodyGeometry> geometry = prepareBodyGeometry(std::move(mesh), settings);
      REQUIRE(geometry.ok());
      const Expected<MassProperties> exact = polyhedralMassProperties(geometry->mesh, 1.0);
      REQUIRE(exact.ok());
      out.push_back({name, std::move(geometry).value(), size, exact->centerOfMass, exact->volume});
    };
    add("box", prim::box(Eigen::Vector3d(2.0, 1.0, 1.5)), 2.0);
    add("sphere", prim::uvSphere(0.6, 32, 16), 1.2);
    add("torus", prim::torus(1.0, 0.3, 32, 16), 2.6);
    add("wigley", prim::wigleyHull(3.0, 0.6, 0.4, 24, 8), 3.0);
    return out;
  }();
  return bodies;
}

// Every backend this machine can run; the CPU one always comes first (the reference).
std::vector<std::unique_ptr<ComputeBackend>> allBackends(const gpu::GlBackendSettings& settings = {}) {
  std::vector<std::unique_ptr<ComputeBackend>> out;
  out.push_back(makeCpuBackend());
  // Only a missing context skips the GL cases; a context whose backend fails (a shader that does
  // not compile) fails the test.
  Expected<std::unique_ptr<gpu::EglContext>> context = gpu::EglContext::create();
  if (!context) {
    WARN("GL backend skipped, no headless EGL context: " << context.error().message);
    return out;
  }
  Expected<std::unique_ptr<ComputeBackend>> gl = gpu::makeGlBackend(std::move(context).value(), settings);
  INFO((gl ? std::string() : gl.error().message));
  REQUIRE(gl.ok());
  out.push_back(std::move(gl).value());
  return out;
}

void addBodies(ComputeBackend& backend) {
  for (const TestBody& body : testBodies()) {
    Expected<BackendBodyId> id = backend.addBody(body.geometry.bake, body.geometry.textures, body.centroid);
    REQUIRE(id.ok());
  }
}

// A batch of every test body at a few seeded poses around floating.
std::vector<std::vector<BackendHydrostaticsQuery>> poseBatches() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-35.0, 35.0), height(-0.15, 0.15);
  std::vector<std::vector<BackendHydrostaticsQuery>> batches;
  for (int batch = 0; batch < 4; ++batch) {
    std::vector<BackendHydrostaticsQuery> queries;
    for (BackendBodyId id = 0; id < testBodies().size(); ++id) {
      BackendHydrostaticsQuery q;
      q.body = id;
      q.query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(angle(rng), angle(rng), angle(rng)),
                                          Eigen::Vector3d(3.0 * id, height(rng), -1.0));
      q.query.centerOfMass = testBodies()[id].centroid;
      queries.push_back(q);
    }
    batches.push_back(queries);
  }
  return batches;
}

std::vector<HydrostaticsResult> runBatch(ComputeBackend& backend, const LiquidSurface& surface,
                                         const std::vector<BackendHydrostaticsQuery>& queries) {
  std::vector<HydrostaticsResult> results(queries.size());
  const Status status = backend.hydrostatics(surface, queries, results);
  INFO(backend.name() << ": " << (status ? std::string() : status.error().message));
  REQUIRE(status.ok());
  return results;
}

// |value - reference| / |reference|; 0 when both are 0 (a body out of the liquid).
double relative(double value, double reference) {
  return value == reference ? 0.0 : std::abs(value - reference) / std::abs(reference);
}

}  // namespace

TEST_CASE("every backend: a box at rest matches the closed form", "[backend]") {
  // Box 2 x 1 x 1.5 with its centre 0.2 m above the surface: draft 0.3 m, V = 2 * 1.5 * 0.3,
  // centre of buoyancy 0.15 m below the surface, water plane 2 x 1.5. The texel sums are exact
  // for flat faces up to float rounding of the texels (1e-6 relative).
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name() << " on " << backend->renderer());
    addBodies(*backend);
    FlatSurface water(0.25, 1025.0);
    BackendHydrostaticsQuery q;
    q.query.pose.translation = Eigen::Vector3d(1.0, 0.45, -2.0);
    const HydrostaticsResult r = runBatch(*backend, water, {q})[0];
    const double volume = 2.0 * 1.5 * 0.3;
    CHECK(relative(r.submergedVolume, volume) < 1e-6);
    CHECK(relative(r.buoyancyForce.y(), 1025.0 * 9.81 * volume) < 1e-6);
    CHECK((r.centerOfBuoyancy - Eigen::Vector3d(1.0, 0.25 - 0.15, -2.0)).norm() < 1e-6);
    CHECK(relative(r.waterplaneArea, 3.0) < 1e-6);
    CHECK(relative(r.wettedArea, 3.0 + 2.0 * (2.0 + 1.5) * 0.3) < 1e-6);
    CHECK(r.torqueAboutCenterOfMass.norm() < 1e-6 * r.buoyancyForce.norm());
  }
}

TEST_CASE("every backend: tilted bodies against the exact polyhedral path", "[backend]") {
  // Texture sums at 128^2 converge to the exact polyhedral integrals as O(h^2) on curved surfaces
  // (bench_hydrostatics, test_texture_hydrostatics); 2e-3 of the volume and 2e-3 of the body size
  // hold at this resolution for these shapes with a margin of about 3.
  FlatSurface water(0.0);
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    for (const auto& batch : poseBatches()) {
      const std::vector<HydrostaticsResult> results = runBatch(*backend, water, batch);
      for (std::size_t i = 0; i < batch.size(); ++i) {
        const TestBody& body = testBodies()[batch[i].body];
        INFO(body.name);
        const Expected<HydrostaticsResult> exact = polyhedralHydrostatics(body.geometry.mesh, water, batch[i].query);
        REQUIRE(exact.ok());
        CHECK(std::abs(results[i].submergedVolume - exact->submergedVolume) < 2e-3 * body.volume);
        CHECK((results[i].centerOfBuoyancy - exact->centerOfBuoyancy).norm() < 2e-3 * body.size);
      }
    }
  }
}

TEST_CASE("GL backend matches the CPU backend on the same inputs", "[backend][parity]") {
  auto backends = allBackends();
  if (backends.size() < 2) return;
  for (auto& backend : backends) addBodies(*backend);
  FlatSurface water(0.0, 1025.0);
  for (const auto& batch : poseBatches()) {
    const auto cpu = runBatch(*backends[0], water, batch);
    const auto gl = runBatch(*backends[1], water, batch);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const TestBody& body = testBodies()[batch[i].body];
      INFO(body.name);
      // Issue 7's tolerances: float texels and float partial sums against double sums.
      CHECK(relative(gl[i].submergedVolume, cpu[i].submergedVolume) <= 1e-5);
      CHECK((gl[i].buoyancyForce - cpu[i].buoyancyForce).norm() <= 1e-5 * cpu[i].buoyancyForce.norm());
      CHECK((gl[i].centerOfBuoyancy - cpu[i].centerOfBuoyancy).norm() <= 1e-4 * body.size);
      CHECK((gl[i].waterplaneCentroid - cpu[i].waterplaneCentroid).norm() <= 1e-4 * body.size);
      // Torque is force times a lever of the body's size: the centre tolerance carried over.
      CHECK((gl[i].torqueAboutCenterOfMass - cpu[i].torqueAboutCenterOfMass).norm() <
            1e-4 * body.size * cpu[i].buoyancyForce.norm());
      // Water-plane and wetted areas come from the waterline texels alone, weighted by float
      // fractions: 1e-4 relative.
      CHECK(relative(gl[i].waterplaneArea, cpu[i].waterplaneArea) <= 1e-4);
      CHECK(relative(gl[i].wettedArea, cpu[i].wettedArea) <= 1e-5);
      // Stiffness: the heave term is rho g A_wp; the rotational ones mix water-plane second
      // moments with V (y_B - h), each as above: 1e-4 of the largest entry.
      CHECK((gl[i].stiffness - cpu[i].stiffness).norm() <= 1e-4 * cpu[i].stiffness.norm());
    }
  }
}

TEST_CASE("every backend: mass properties against closed forms", "[backend][mass]") {
  // Uniform box 2 x 1 x 1.5 of 800 kg/m^3: the cone volumes sum to the exact volume (float
  // rounding: 1e-6), the centre is the origin, the inertia m (b^2 + c^2) / 12; the cone
  // covariance of a flat texel is exact, so 1e-5 relative holds.
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    TextureMassModel model;
    model.solidDensity = 800.0;
    MassProperties result;
    const BackendBodyId id = 0;
    REQUIRE(backend->massProperties({&id, 1}, {&model, 1}, {&result, 1}).ok());
    const double mass = 800.0 * 3.0;
    CHECK(relative(result.mass, mass) < 1e-6);
    CHECK(relative(result.volume, 3.0) < 1e-6);
    CHECK(result.centerOfMass.norm() < 1e-6);
    CHECK(relative(result.inertia(0, 0), mass * (1.0 + 2.25) / 12.0) < 1e-5);
    CHECK(relative(result.inertia(1, 1), mass * (4.0 + 2.25) / 12.0) < 1e-5);
    CHECK(relative(result.inertia(2, 2), mass * (4.0 + 1.0) / 12.0) < 1e-5);
    CHECK(std::abs(result.inertia(0, 1)) < 1e-6 * mass);
  }
}

TEST_CASE("GL backend mass properties match the CPU backend", "[backend][mass][parity]") {
  auto backends = allBackends();
  if (backends.size() < 2) return;
  for (auto& backend : backends) addBodies(*backend);
  // All bodies in one call: solid, shell, and a density map varying with the texel index.
  std::vector<BackendBodyId> ids;
  std::vector<TextureMassModel> models;
  for (BackendBodyId id = 0; id < testBodies().size(); ++id) {
    TextureMassModel model;
    model.solidDensity = 500.0 + 100.0 * id;
    model.shellDensity = id % 2 == 0 ? 0.0 : 12.0;
    if (id == 2) {
      const std::size_t count = testBodies()[id].geometry.textures.size();
      for (std::size_t i = 0; i < count; ++i) model.texelDensity.push_back(float(700.0 + 300.0 * std::sin(1e-3 * double(i))));
    }
    ids.push_back(id);
    models.push_back(model);
  }
  std::vector<MassProperties> cpu(ids.size()), gl(ids.size());
  REQUIRE(backends[0]->massProperties(ids, models, cpu).ok());
  REQUIRE(backends[1]->massProperties(ids, models, gl).ok());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const TestBody& body = testBodies()[i];
    INFO(body.name);
    CHECK(relative(gl[i].mass, cpu[i].mass) < 1e-5);
    CHECK(relative(gl[i].volume, cpu[i].volume) < 1e-5);
    CHECK((gl[i].centerOfMass - cpu[i].centerOfMass).norm() < 1e-4 * body.size);
    // Inertia is mass times size squared: the centre tolerance, relative, carried over.
    CHECK((gl[i].inertia - cpu[i].inertia).norm() < 1e-4 * cpu[i].inertia.norm());
  }
}

TEST_CASE("every backend: an open hull's shell leaves out its lid", "[backend][mass][open_hull]") {
  // The 2 x 0.5 x 1 m box without its deck, capped as an open hull: 60 kg/m^2 over the 5 m^2 of
  // walls, not over the 2 m^2 lid (exact lid moments subtracted from float texel sums: 1e-5).
  Mesh mesh = testing::openTopBox(Eigen::Vector3d(2.0, 0.5, 1.0), 4);
  RepairSettings repair;
  repair.openHull = true;
  REQUIRE(repairMesh(mesh, repair).ok());
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = 64;
  Expected<BodyGeometry> geometry = prepareBodyGeometry(std::move(mesh), settings);
  REQUIRE(geometry.ok());
  TextureMassModel model;
  model.solidDensity = 0.0;
  model.shellDensity = 60.0;
  std::vector<MassProperties> results;
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name());
    Expected<BackendBodyId> id = backend->addBody(geometry->bake, geometry->textures, Eigen::Vector3d::Zero());
    REQUIRE(id.ok());
    MassProperties result;
    REQUIRE(backend->massProperties({&*id, 1}, {&model, 1}, {&result, 1}).ok());
    CHECK(relative(result.mass, 300.0) < 1e-5);
    results.push_back(result);
  }
  // The GL backend's centre as the CPU's (the parity tolerance above, 1e-4 of the 2 m size).
  if (results.size() == 2) CHECK((results[1].centerOfMass - results[0].centerOfMass).norm() < 2e-4);
}

TEST_CASE("every backend: batching rules and bad input give errors, not crashes", "[backend]") {
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    CHECK(backend->bodyCount() == testBodies().size());
    FlatSurface water(0.0);
    std::vector<HydrostaticsResult> results(2);
    BackendHydrostaticsQuery q;
    q.body = 99;
    CHECK(!backend->hydrostatics(water, std::span(&q, 1), results).ok());
    q.body = 1;
    const std::vector<BackendHydrostaticsQuery> twice = {q, q};
    CHECK(!backend->hydrostatics(water, twice, results).ok());
    CHECK(!backend->hydrostatics(water, twice, std::span(results).first(1)).ok());
    q.query.gravity = -1.0;
    CHECK(!backend->hydrostatics(water, std::span(&q, 1), results).ok());
    FlatSurface bad(0.0, -5.0);
    q.query.gravity = 9.81;
    CHECK(!backend->hydrostatics(bad, std::span(&q, 1), results).ok());

    TextureMassModel model;
    model.texelDensity = {1.0f, 2.0f};  // wrong size
    MassProperties mass;
    const BackendBodyId id = 1;
    CHECK(!backend->massProperties({&id, 1}, {&model, 1}, {&mass, 1}).ok());
    model.texelDensity.assign(testBodies()[1].geometry.textures.size(), 900.0f);
    model.texelDensity[17] = -1.0f;
    CHECK(!backend->massProperties({&id, 1}, {&model, 1}, {&mass, 1}).ok());
    model.texelDensity[17] = NAN;
    CHECK(!backend->massProperties({&id, 1}, {&model, 1}, {&mass, 1}).ok());
    model.texelDensity.clear();
    model.solidDensity = -2.0;
    CHECK(!backend->massProperties({&id, 1}, {&model, 1}, {&mass, 1}).ok());

    SurfaceTextures wrong = testBodies()[0].geometry.textures;
    wrong.area.pop_back();
    CHECK(!backend->updateSurface(0, wrong).ok());
    CHECK(!backend->updateSurface(42, testBodies()[0].geometry.textures).ok());
    CHECK(!backend->addBody(testBodies()[0].geometry.bake, wrong, Eigen::Vector3d::Zero()).ok());
  }
}

TEST_CASE("every backend: a body asked alone answers as in a full batch", "[backend]") {
  // Bodies left out of a batch must not leak into the others' sums (the GL backend lifts them out
  // of the liquid): the same numbers to float-reduction order, 1e-12 relative.
  FlatSurface water(0.0);
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    const auto batch = poseBatches()[0];
    const auto full = runBatch(*backend, water, batch);
    const auto alone = runBatch(*backend, water, {batch[2]});
    CHECK(relative(alone[0].submergedVolume, full[2].submergedVolume) < 1e-12);
    CHECK((alone[0].centerOfBuoyancy - full[2].centerOfBuoyancy).norm() < 1e-12);
  }
}

TEST_CASE("every backend: an instance reads its model's texels and answers as the model does", "[backend][instance]") {
  // Bodies 4, 5, 7, 8 share the texels of 3, 1, 0 and 4 (addInstance: crates of a kind); 6 is a
  // copy of 0 registered between them, so that on the GL backend the instances' chunks and a new
  // body's interleave. With 64 KiB buffers every body spans several, and an instance's chunks
  // form runs of their own in its model's buffers; that backend also sums on the CPU, from the
  // model's block sums, which the host keeps once. Each instance, asked in a full batch at its own
  // pose (20 m beside its model's), under water, waves and air, answers as its model asked alone
  // at that pose: the same texels, chunk order and float partials, so 1e-12 relative (the final
  // double sums' order).
  gpu::GlBackendSettings small;
  small.segmentBytes = 64 * 1024;
  small.finalSum = gpu::FinalSum::Cpu;
  std::vector<std::unique_ptr<ComputeBackend>> backends = allBackends();
  if (backends.size() > 1) backends.push_back(std::move(allBackends(small).back()));
  const std::vector<std::pair<BackendBodyId, BackendBodyId>> sharing = {{4, 3}, {5, 1}, {6, 0}, {7, 0}, {8, 4}};
  const std::vector<BackendBodyId> modelOf = {0, 1, 2, 3, 3, 1, 0, 0, 3};  // the test body each one is
  const FlatSurface water(0.0);
  const GerstnerWaves waves({GerstnerWave{0.1, 5.0, Eigen::Vector2d(1.0, 0.5), 0.3, 0.7}});
  const UniformMedium air(1.225, 8400.0, 0.0);  // the medium's pressure reads the body's Sum p A^T and Sum A
  std::vector<MassProperties> referenceMass;  // the CPU backend's
  for (auto& backend : backends) {
    INFO("backend " << backend->name() << " on " << backend->renderer());
    addBodies(*backend);
    for (const auto& [id, of] : sharing) {
      Expected<BackendBodyId> added = id == 6 ? backend->addBody(testBodies()[0].geometry.bake, testBodies()[0].geometry.textures,
                                                                 testBodies()[0].centroid)
                                              : backend->addInstance(of);
      INFO((added ? std::string() : added.error().message));
      REQUIRE(added.ok());
      CHECK(*added == id);
    }
    const auto batches = poseBatches();
    for (const LiquidSurface* surface : {static_cast<const LiquidSurface*>(&water), static_cast<const LiquidSurface*>(&waves),
                                         static_cast<const LiquidSurface*>(&air)}) {
      for (std::size_t b = 0; b < batches.size(); ++b) {
        std::vector<BackendHydrostaticsQuery> batch = batches[b];
        for (BackendBodyId id = 4; id < modelOf.size(); ++id) {
          BackendHydrostaticsQuery q = batches[(b + id) % batches.size()][modelOf[id]];
          q.body = id;
          q.query.pose.translation.x() += 20.0;
          batch.push_back(q);
        }
        const auto full = runBatch(*backend, *surface, batch);
        for (std::size_t i = 4; i < batch.size(); ++i) {
          BackendHydrostaticsQuery alone = batch[i];
          alone.body = modelOf[alone.body];
          const HydrostaticsResult reference = runBatch(*backend, *surface, {alone})[0];
          const double size = testBodies()[alone.body].size;
          INFO("body " << batch[i].body << " (test body " << alone.body << "), batch " << b);
          CHECK(relative(full[i].submergedVolume, reference.submergedVolume) < 1e-12);
          CHECK((full[i].buoyancyForce - reference.buoyancyForce).norm() <= 1e-12 * reference.buoyancyForce.norm());
          CHECK((full[i].centerOfBuoyancy - reference.centerOfBuoyancy).norm() < 1e-12 * 30.0);  // |x| < 30 m
          CHECK((full[i].torqueAboutCenterOfMass - reference.torqueAboutCenterOfMass).norm() <=
                1e-12 * size * reference.buoyancyForce.norm() + 1e-12);
        }
      }
    }
    // Mass properties: an instance's are its model's, asked together in one batch, and the
    // model's are the CPU backend's (the first, the reference) within the GL parity bounds
    // (1e-5 on the mass, 1e-4 relative on the inertia: the mass parity case above).
    const std::vector<BackendBodyId> ids = {3, 4, 8, 0, 7};
    const std::vector<TextureMassModel> models(ids.size());
    std::vector<MassProperties> mass(ids.size());
    REQUIRE(backend->massProperties(ids, models, mass).ok());
    for (std::size_t i : {1, 2}) {
      CHECK(relative(mass[i].mass, mass[0].mass) < 1e-12);
      CHECK((mass[i].inertia - mass[0].inertia).norm() < 1e-12 * mass[0].inertia.norm());
    }
    CHECK(relative(mass[4].mass, mass[3].mass) < 1e-12);
    CHECK((mass[4].centerOfMass - mass[3].centerOfMass).norm() < 1e-12);
    if (referenceMass.empty()) referenceMass = mass;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      CHECK(relative(mass[i].mass, referenceMass[i].mass) < 1e-5);
      CHECK((mass[i].inertia - referenceMass[i].inertia).norm() < 1e-4 * referenceMass[i].inertia.norm());
    }
    // Shared texels are read-only: neither the model nor an instance takes new textures; a body
    // that shares nothing still does. An unknown model is refused.
    const TestBody& wigley = testBodies()[3];
    CHECK_FALSE(backend->updateSurface(3, wigley.geometry.textures).ok());
    CHECK_FALSE(backend->updateSurface(8, wigley.geometry.textures).ok());
    CHECK(backend->updateSurface(2, testBodies()[2].geometry.textures).ok());
    const Expected<BackendBodyId> unknown = backend->addInstance(99);
    REQUIRE_FALSE(unknown.ok());
    CHECK_THAT(unknown.error().message, Catch::Contains("99"));
    if (backend->name() == "gpu") {
      // On the GPU a density map and a deformation live beside the texels, which are shared.
      TextureMassModel mapped;
      mapped.texelDensity.assign(testBodies()[1].geometry.textures.size(), 700.0f);
      const BackendBodyId instance = 5;
      MassProperties out;
      const Status refused = backend->massProperties({&instance, 1}, {&mapped, 1}, {&out, 1});
      REQUIRE_FALSE(refused.ok());
      CHECK_THAT(refused.error().message, Catch::Contains("shares its texels"));
      CHECK_FALSE(gpu::enableGpuDeformation(*backend, 3, wigley.geometry.bake, wigley.geometry.mesh,
                                            wigley.geometry.atlas.layout).ok());
    }
  }
}

TEST_CASE("GL backend: a body that fits one buffer keeps to one, and its instances dispatch as one run", "[backend][gpu][instance]") {
  // Buffers of 2.5 boxes: two boxes fill most of the first; the third would straddle it and the
  // next, and starts the second instead. Its 20 instances read that buffer and follow each other,
  // so all 23 bodies asked together dispatch 2 runs (one per buffer); a straddling model would
  // give its instances one run per buffer each (42 runs more).
  const TestBody& box = testBodies()[0];
  gpu::GlBackendSettings settings;
  settings.segmentBytes = box.geometry.textures.size() * 52 * 5 / 2;  // 52 bytes a texel (HydroTexel)
  Expected<std::unique_ptr<gpu::EglContext>> context = gpu::EglContext::create();
  if (!context) {
    WARN("GL backend skipped, no headless EGL context: " << context.error().message);
    return;
  }
  Expected<std::unique_ptr<ComputeBackend>> made = gpu::makeGlBackend(std::move(context).value(), settings);
  REQUIRE(made.ok());
  ComputeBackend& gl = **made;
  for (int i = 0; i < 3; ++i) REQUIRE(gl.addBody(box.geometry.bake, box.geometry.textures, box.centroid).ok());
  for (int i = 0; i < 20; ++i) REQUIRE(gl.addInstance(2).ok());
  std::vector<BackendHydrostaticsQuery> batch(23);
  for (BackendBodyId id = 0; id < batch.size(); ++id) {
    batch[id].body = id;
    batch[id].query.pose.translation = Eigen::Vector3d(3.0 * id, 0.2, 0.0);
  }
  const auto results = runBatch(gl, FlatSurface(0.25), batch);
  const Expected<gpu::GlHydrostaticsStatistics> stats = gpu::lastHydrostaticsStatistics(gl);
  REQUIRE(stats.ok());
  CHECK(stats->runs == 2);
  // And every box answers the closed form (test "a box at rest"): V = 2 x 1.5 x 0.55.
  for (const HydrostaticsResult& r : results) CHECK(relative(r.submergedVolume, 2.0 * 1.5 * 0.55) < 1e-6);
}

TEST_CASE("every backend: a deforming body re-evaluated from its bake", "[backend]") {
  // The sphere scaled by 1.1 about its centre: the volume of a fully submerged body grows by
  // 1.1^3 exactly (texel sums are linear in the moved vertices' positions and area vectors).
  FlatSurface water(10.0);
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    const TestBody& sphere = testBodies()[1];
    Mesh grown = sphere.geometry.mesh;
    for (auto& vertex : grown.positions) vertex *= 1.1;
    const SurfaceTextures textures = evaluateSurface(sphere.geometry.bake, grown, sphere.geometry.atlas.layout);
    BackendHydrostaticsQuery q;
    q.body = 1;
    const double before = runBatch(*backend, water, {q})[0].submergedVolume;
    REQUIRE(backend->updateSurface(1, textures).ok());
    const double after = runBatch(*backend, water, {q})[0].submergedVolume;
    CHECK(relative(after, 1.331 * before) < 1e-5);
  }
}

TEST_CASE("GL backend: storage segments and the CPU final sum give the same answers", "[backend][gpu]") {
  // 64 KiB segments split every body across several buffers and dispatches; the final sum on the
  // CPU adds the same float partials in double in another order: 1e-12 relative.
  gpu::GlBackendSettings small;
  small.segmentBytes = 64 * 1024;
  small.finalSum = gpu::FinalSum::Cpu;
  Expected<std::unique_ptr<ComputeBackend>> reference = gpu::makeGlBackend();
  Expected<std::unique_ptr<ComputeBackend>> split = gpu::makeGlBackend(small);
  if (!reference || !split) {
    WARN("GL backend skipped, no headless EGL context: " << (reference ? split.error() : reference.error()).message);
    return;
  }
  addBodies(**reference);
  addBodies(**split);
  FlatSurface water(0.0);
  const auto batch = poseBatches()[1];
  const auto a = runBatch(**reference, water, batch);
  const auto b = runBatch(**split, water, batch);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    CHECK(relative(b[i].submergedVolume, a[i].submergedVolume) < 1e-12);
    CHECK((b[i].centerOfBuoyancy - a[i].centerOfBuoyancy).norm() < 1e-12 * testBodies()[i].size);
  }
  // Under waves too: the pressure-head partials take the same two routes.
  const GerstnerWaves waves({GerstnerWave{0.1, 5.0, Eigen::Vector2d(1.0, 0.5), 0.3, 0.7}});
  const auto wa = runBatch(**reference, waves, batch);
  const auto wb = runBatch(**split, waves, batch);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    CHECK(relative(wb[i].submergedVolume, wa[i].submergedVolume) < 1e-12);
    CHECK((wb[i].buoyancyForce - wa[i].buoyancyForce).norm() < 1e-12 * wa[i].buoyancyForce.norm());
  }
  TextureMassModel model;
  MassProperties ma, mb;
  const BackendBodyId id = 3;
  REQUIRE((*reference)->massProperties({&id, 1}, {&model, 1}, {&ma, 1}).ok());
  REQUIRE((*split)->massProperties({&id, 1}, {&model, 1}, {&mb, 1}).ok());
  CHECK(relative(mb.mass, ma.mass) < 1e-12);
  CHECK((mb.inertia - ma.inertia).norm() < 1e-12 * ma.inertia.norm());
}

namespace {

// Issue 7's parity (1e-5 relative on volume and force, 1e-4 of the body's size on centres) on two
// result sets of the same queries; the other quantities as in the flat parity case above.
void checkParity(const HydrostaticsResult& gl, const HydrostaticsResult& cpu, double size) {
  CHECK(relative(gl.submergedVolume, cpu.submergedVolume) <= 1e-5);
  CHECK((gl.buoyancyForce - cpu.buoyancyForce).norm() <= 1e-5 * cpu.buoyancyForce.norm());
  CHECK((gl.centerOfBuoyancy - cpu.centerOfBuoyancy).norm() <= 1e-4 * size);
  CHECK((gl.waterplaneCentroid - cpu.waterplaneCentroid).norm() <= 1e-4 * size);
  CHECK((gl.torqueAboutCenterOfMass - cpu.torqueAboutCenterOfMass).norm() <= 1e-4 * size * cpu.buoyancyForce.norm());
  CHECK(std::abs(gl.waterplaneArea - cpu.waterplaneArea) <= 1e-4 * std::max(cpu.waterplaneArea, size * size));
  CHECK(relative(gl.wettedArea, cpu.wettedArea) <= 1e-5);
  CHECK((gl.stiffness - cpu.stiffness).norm() <= 1e-4 * cpu.stiffness.norm());
}

// Three crossing waves, steep enough (sum Q k A = 0.28) that the rest-point search takes several
// Newton steps.
GerstnerWaves steepWaves() {
  return GerstnerWaves({GerstnerWave{0.15, 6.0, Eigen::Vector2d(1.0, 0.3), 0.4, 0.6},
                        GerstnerWave{0.08, 3.5, Eigen::Vector2d(-0.4, 1.0), 1.3, 0.8},
                        GerstnerWave{0.05, 2.2, Eigen::Vector2d(0.7, -0.7), 2.0, 0.5}},
                       0.05, 1025.0);
}

// The batches of poseBatches at `time` (s), moved by `shift` (m).
std::vector<std::vector<BackendHydrostaticsQuery>> shiftedBatches(double time, const Eigen::Vector3d& shift) {
  auto batches = poseBatches();
  for (auto& batch : batches)
    for (BackendHydrostaticsQuery& q : batch) {
      q.query.time = time;
      q.query.pose.translation += shift;
    }
  return batches;
}

}  // namespace

TEST_CASE("GL backend matches the CPU backend under Gerstner waves", "[backend][parity][surface]") {
  // The steep waves (steepWaves): near the origin at t = 3.7 s, then 400 m away at t = 1000 s,
  // where the phases k d . x - omega t reach thousands of radians (the GL backend reduces them
  // about each body's frame origin in double: its float search then works with the body's own
  // metres).
  auto backends = allBackends();
  if (backends.size() < 2) return;
  for (auto& backend : backends) addBodies(*backend);
  const GerstnerWaves waves = steepWaves();
  for (const auto& [time, shift] : {std::pair{3.7, Eigen::Vector3d(0.0, 0.0, 0.0)},
                                    std::pair{1000.0, Eigen::Vector3d(400.0, 0.0, -250.0)}}) {
    for (const auto& batch : shiftedBatches(time, shift)) {
      const auto cpu = runBatch(*backends[0], waves, batch);
      const auto gl = runBatch(*backends[1], waves, batch);
      for (std::size_t i = 0; i < batch.size(); ++i) {
        INFO(testBodies()[batch[i].body].name << " at t = " << time << " s");
        REQUIRE(cpu[i].submergedVolume > 0.0);
        checkParity(gl[i], cpu[i], testBodies()[batch[i].body].size);
      }
    }
  }
}

TEST_CASE("GL backend: chunks under waves take local surface models, within the per-texel answer", "[backend][gpu][surface]") {
  // Issue 19 item 1 on the GPU: a texel within the reach of its chunk's local model (the waves'
  // quadratic Taylor model about the centre of the chunk's box, its bound M3 rho^3 / 6 within
  // 1e-3 m, GlBackend.cpp) takes its height from the model instead of a search. Against the same
  // backend searching every texel (GlBackendSettings::surfaceModels = false), on the parity
  // case's three steep waves at both of its places and times: the submerged volume within 1e-5
  // of the body's volume (the CPU hierarchy's bound, TextureHydrostaticsSettings), the force
  // within 1e-5 rho g V, and every quantity within the two backends' parity (checkParity).
  // Measured on llvmpipe: at most 1.4e-6 V and 2.5e-6 rho g V (at 3e-3 m: 1.1e-5 rho g V). The
  // answers must differ somewhere (else the models never ran and this checks nothing).
  auto modeled = allBackends();
  if (modeled.size() < 2) return;
  gpu::GlBackendSettings perTexel;
  perTexel.surfaceModels = false;
  auto searched = allBackends(perTexel);
  REQUIRE(searched.size() == 2);
  addBodies(*modeled[1]);
  addBodies(*searched[1]);
  const GerstnerWaves waves = steepWaves();
  int differing = 0;
  double worstVolume = 0.0, worstForce = 0.0;
  for (const auto& [time, shift] : {std::pair{3.7, Eigen::Vector3d(0.0, 0.0, 0.0)},
                                    std::pair{1000.0, Eigen::Vector3d(400.0, 0.0, -250.0)}}) {
    for (const auto& batch : shiftedBatches(time, shift)) {
      const auto a = runBatch(*modeled[1], waves, batch);
      const auto b = runBatch(*searched[1], waves, batch);
      for (std::size_t i = 0; i < batch.size(); ++i) {
        const TestBody& body = testBodies()[batch[i].body];
        INFO(body.name << " at t = " << time << " s");
        REQUIRE(b[i].submergedVolume > 0.0);
        const double weight = 1025.0 * 9.81 * body.volume;
        const double volumeError = std::abs(a[i].submergedVolume - b[i].submergedVolume) / body.volume;
        const double forceError = (a[i].buoyancyForce - b[i].buoyancyForce).norm() / weight;
        worstVolume = std::max(worstVolume, volumeError);
        worstForce = std::max(worstForce, forceError);
        CHECK(volumeError <= 1e-5);
        CHECK(forceError <= 1e-5);
        CHECK((a[i].centerOfBuoyancy - b[i].centerOfBuoyancy).norm() <= 1e-4 * body.size);
        checkParity(a[i], b[i], body.size);  // and everything else as the two backends' parity
        if (a[i].submergedVolume != b[i].submergedVolume) ++differing;
      }
    }
  }
  INFO("worst volume " << worstVolume << " V, force " << worstForce << " rho g V");
  CHECK(differing > 0);
}

TEST_CASE("GL backend matches the CPU backend under a height grid", "[backend][parity][surface]") {
  // A smooth field sampled every 0.25 m over x in [-2, 8]: the Wigley hull (at x = 9) lies past
  // the grid's end, where HeightGrid holds the edge values (the shader's clamping), the others
  // inside; then the same field 1,000 m higher (the samples are uploaded about their mid-range and
  // the heights taken about each body's frame origin, so float still holds them).
  auto backends = allBackends();
  if (backends.size() < 2) return;
  for (auto& backend : backends) addBodies(*backend);
  HeightGrid grid(41, 25, 0.25, -2.0, -4.0, 0.0, 1025.0);
  for (int j = 0; j < grid.countZ(); ++j)
    for (int i = 0; i < grid.countX(); ++i) {
      const double x = -2.0 + 0.25 * i, z = -4.0 + 0.25 * j;
      grid.heights()[std::size_t(j * grid.countX() + i)] = 0.12 * std::sin(0.9 * x) * std::cos(0.6 * z) + 0.03 * z;
    }
  for (const auto& batch : poseBatches()) {
    const auto cpu = runBatch(*backends[0], grid, batch);
    const auto gl = runBatch(*backends[1], grid, batch);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      INFO(testBodies()[batch[i].body].name);
      REQUIRE(cpu[i].submergedVolume > 0.0);
      checkParity(gl[i], cpu[i], testBodies()[batch[i].body].size);
    }
  }
  // The same field lifted by 1,000 m with the bodies: the same answers but for the heights.
  HeightGrid lifted = grid;
  for (double& h : lifted.heights()) h += 1000.0;
  auto batch = shiftedBatches(0.0, Eigen::Vector3d(0.0, 1000.0, 0.0))[0];
  const auto cpu = runBatch(*backends[0], lifted, batch);
  const auto gl = runBatch(*backends[1], lifted, batch);
  for (std::size_t i = 0; i < batch.size(); ++i) checkParity(gl[i], cpu[i], testBodies()[batch[i].body].size);
}

TEST_CASE("every backend: level waves and a level grid answer as the flat surface", "[backend][surface]") {
  // Zero-amplitude waves and a grid of equal samples are the plane y = 0.2 reached through the
  // texel-by-texel pressure path: on the box (flat faces: the pressure, linear in the position, is
  // integrated exactly by the texel centres) volume, force and centre of buoyancy equal the flat
  // surface's Archimedes answer to float rounding of the texels and partial sums, 1e-6 relative
  // (1e-6 of the size on the centre); the water plane to the same. The pressure torque's lever
  // times pressure is quadratic in the position, which texel centres integrate to O(texel^2)
  // (1.3e-5 of size times force measured, the same on both backends): 1e-4.
  const FlatSurface flat(0.2, 1025.0);
  const GerstnerWaves level({GerstnerWave{0.0, 7.0, Eigen::Vector2d(1.0, 1.0), 0.5, 0.8}}, 0.2, 1025.0);
  HeightGrid grid(3, 3, 5.0, -5.0, -6.0, 0.2, 1025.0);
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    BackendHydrostaticsQuery q;
    q.query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(12.0, -25.0, 8.0), Eigen::Vector3d(0.5, 0.3, -1.0));
    const HydrostaticsResult reference = runBatch(*backend, flat, {q})[0];
    for (const LiquidSurface* surface : {static_cast<const LiquidSurface*>(&level), static_cast<const LiquidSurface*>(&grid)}) {
      const HydrostaticsResult r = runBatch(*backend, *surface, {q})[0];
      CHECK(relative(r.submergedVolume, reference.submergedVolume) < 1e-6);
      CHECK((r.buoyancyForce - reference.buoyancyForce).norm() < 1e-6 * reference.buoyancyForce.norm());
      CHECK((r.centerOfBuoyancy - reference.centerOfBuoyancy).norm() < 1e-6 * 2.0);
      CHECK(relative(r.waterplaneArea, reference.waterplaneArea) < 1e-6);
      CHECK((r.torqueAboutCenterOfMass - reference.torqueAboutCenterOfMass).norm() < 1e-4 * 2.0 * reference.buoyancyForce.norm());
    }
  }
}

TEST_CASE("every backend: a medium without a free surface", "[backend][surface]") {
  // A constant-density medium (water 5 m deep, no surface): every body is wholly submerged, the
  // force is rho g V upwards through the centroid. The pressure is integrated texel by texel at
  // the texel centres: volume and force (linear in the position) exact for the box's flat faces
  // up to the texels' float rounding (1e-6 relative), O(texel^2) on curved ones, where 2e-3 holds
  // at 128^2 as in the tilted-bodies case (measured 1e-4 on the torus); the centre's moments are
  // quadratic in the position, O(texel^2) on every face (2e-5 m measured on the box): 2e-3 of the
  // size. Then the GL backend against the CPU backend to issue 7's parity in that medium and in
  // air with a scale height.
  const UniformMedium water(1000.0, std::numeric_limits<double>::infinity(), 5.0);
  const UniformMedium air(1.225, 8400.0, 0.0);
  auto backends = allBackends();
  for (auto& backend : backends) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    for (const auto& batch : poseBatches()) {
      const auto results = runBatch(*backend, water, batch);
      for (std::size_t i = 0; i < batch.size(); ++i) {
        const TestBody& body = testBodies()[batch[i].body];
        INFO(body.name);
        const double tolerance = body.name == "box" ? 1e-6 : 2e-3;
        CHECK(relative(results[i].submergedVolume, body.volume) < tolerance);
        const Eigen::Vector3d expected(0.0, 1000.0 * 9.81 * body.volume, 0.0);
        CHECK((results[i].buoyancyForce - expected).norm() < tolerance * expected.norm());
        CHECK((results[i].centerOfBuoyancy - batch[i].query.pose.apply(body.centroid)).norm() < 2e-3 * body.size);
      }
    }
  }
  if (backends.size() < 2) return;
  for (const LiquidSurface* medium : {static_cast<const LiquidSurface*>(&water), static_cast<const LiquidSurface*>(&air)})
  for (const auto& batch : shiftedBatches(0.0, Eigen::Vector3d(0.0, 300.0, 0.0))) {
    const auto cpu = runBatch(*backends[0], *medium, batch);
    const auto gl = runBatch(*backends[1], *medium, batch);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const double size = testBodies()[batch[i].body].size;
      INFO(testBodies()[batch[i].body].name);
      CHECK(relative(gl[i].submergedVolume, cpu[i].submergedVolume) <= 1e-5);
      CHECK((gl[i].buoyancyForce - cpu[i].buoyancyForce).norm() <= 1e-5 * cpu[i].buoyancyForce.norm());
      CHECK((gl[i].centerOfBuoyancy - cpu[i].centerOfBuoyancy).norm() <= 1e-4 * size);
      CHECK((gl[i].torqueAboutCenterOfMass - cpu[i].torqueAboutCenterOfMass).norm() <=
            1e-4 * size * cpu[i].buoyancyForce.norm());
    }
  }
}

TEST_CASE("every backend: a wholly submerged body's volume and force are exact at any orientation",
          "[backend][moments]") {
  // No per-pose factor: the texels' sums with the moment corrections of texels of several pieces
  // are the pieces' own (Int x n^T dA = V I), so deep water and a medium give the mesh's volume
  // at every rotation, on every backend, and the GL backend the CPU's.
  auto backends = allBackends();
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<std::vector<BackendHydrostaticsQuery>> batches;
  for (int b = 0; b < 6; ++b) {
    std::vector<BackendHydrostaticsQuery> queries;
    for (BackendBodyId id = 0; id < testBodies().size(); ++id) {
      BackendHydrostaticsQuery q;
      q.body = id;
      q.query.pose = Pose::fromDegreesXYZ(180.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)),
                                          Eigen::Vector3d(3.0 * id, -4.0 + unit(rng), unit(rng)));
      q.query.centerOfMass = testBodies()[id].centroid;
      queries.push_back(q);
    }
    batches.push_back(queries);
  }
  const FlatSurface deep(0.0, 1000.0);
  const UniformMedium medium(1000.0, std::numeric_limits<double>::infinity(), 5.0);
  std::vector<std::vector<HydrostaticsResult>> reference;  // the CPU's, per surface and batch
  for (auto& backend : backends) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    double worstVolume = 0.0, worstForce = 0.0, worstParity = 0.0;
    std::size_t run = 0;
    for (const LiquidSurface* surface : {static_cast<const LiquidSurface*>(&deep), static_cast<const LiquidSurface*>(&medium)})
      for (const auto& batch : batches) {
        const auto results = runBatch(*backend, *surface, batch);
        if (backend == backends.front()) reference.push_back(results);
        for (std::size_t i = 0; i < batch.size(); ++i) {
          const TestBody& body = testBodies()[batch[i].body];
          worstVolume = std::max(worstVolume, relative(results[i].submergedVolume, body.volume));
          worstForce = std::max(worstForce, relative(results[i].buoyancyForce.y(), 1000.0 * 9.81 * body.volume));
          worstParity = std::max(worstParity, relative(results[i].submergedVolume, reference[run][i].submergedVolume));
        }
        ++run;
      }
    INFO("worst relative error of the volume " << worstVolume << ", force " << worstForce << ", against the CPU "
                                                << worstParity);
    // CPU: the mesh's volume to the float rounding of the stored texels and corrections; measured
    // 2.6e-7 on the volume, 5.4e-7 on the force (the medium's absolute pressure multiplies the
    // float rounding of Sum A): bound 2e-6. GL: float partial sums besides, measured 1.4e-6 on
    // both and 1.2e-6 against the CPU (llvmpipe): bound 5e-6, and issue 7's 1e-5 on the parity.
    const double tolerance = backend == backends.front() ? 2e-6 : 5e-6;
    CHECK(worstVolume < tolerance);
    CHECK(worstForce < tolerance);
    CHECK(worstParity <= 1e-5);
  }
}

TEST_CASE("GL backend: a liquid surface without a GPU form is refused, naming the CPU backend", "[backend][gpu]") {
  // A user's own LiquidSurface: its surfaceHeight is C++ the shaders cannot run.
  struct Tilted final : LiquidSurface {
    double surfaceHeight(double x, double, double) const override { return 0.1 * x; }
    double density() const override { return 1000.0; }
    Status validate() const override { return Ok{}; }
  };
  Expected<std::unique_ptr<ComputeBackend>> gl = gpu::makeGlBackend();
  if (!gl) {
    WARN("GL backend skipped, no headless EGL context: " << gl.error().message);
    return;
  }
  addBodies(**gl);
  BackendHydrostaticsQuery q;
  HydrostaticsResult result;
  const Status status = (*gl)->hydrostatics(Tilted{}, std::span(&q, 1), std::span(&result, 1));
  REQUIRE(!status.ok());
  CHECK(status.error().message.find("cpu backend") != std::string::npos);
  // A non-finite height at a body's centre of mass is an error, not a NaN result.
  HeightGrid broken(2, 2, 1.0, 0.0, 0.0);
  broken.heights()[0] = NAN;
  CHECK(!(*gl)->hydrostatics(broken, std::span(&q, 1), std::span(&result, 1)).ok());
}

TEST_CASE("GL backend: submerged chunks add their moments, only crossing chunks read texels", "[backend][gpu]") {
  // A sphere whose mesh frame origin lies far from it (25 m: the pre-summed moments are taken about
  // each chunk's centre, so float must still hold them), lowered from above the water to deep
  // under it. At each depth: the same answer as the CPU backend to issue 7's parity (1e-5
  // relative on volume, 1e-4 of the size on the centre of buoyancy), and the classification
  // counted: a floating sphere has chunks of all three kinds and reads fewer texels than it has,
  // a submerged one reads none.
  std::vector<std::unique_ptr<ComputeBackend>> backends = allBackends();
  if (backends.size() < 2) return;
  const Eigen::Vector3d away(25.0, -18.0, 9.0);
  Mesh mesh = prim::uvSphere(0.6, 32, 16);
  for (Eigen::Vector3d& vertex : mesh.positions) vertex += away;
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = kResolution;
  Expected<BodyGeometry> geometry = prepareBodyGeometry(std::move(mesh), settings);
  REQUIRE(geometry.ok());
  for (auto& backend : backends)
    REQUIRE(backend->addBody(geometry->bake, geometry->textures, away).ok());
  const FlatSurface water(0.0);
  for (double depth : {-1.1, -0.3, 0.0, 0.25, 0.55, 1.1, 3.0}) {
    INFO("sphere centre " << depth << " m under the surface");
    BackendHydrostaticsQuery q;
    q.query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d(20.0, -10.0, 35.0), Eigen::Vector3d(2.0, 0.0, 1.0));
    // Put the sphere's centre R away + t at height -depth.
    q.query.pose.translation.y() = -depth - (q.query.pose.rotation * away).y();
    q.query.centerOfMass = away;
    const HydrostaticsResult cpu = runBatch(*backends[0], water, {q})[0];
    const HydrostaticsResult gl = runBatch(*backends[1], water, {q})[0];
    CHECK(relative(gl.submergedVolume, cpu.submergedVolume) <= 1e-5);
    if (cpu.submergedVolume > 0.0) CHECK((gl.centerOfBuoyancy - cpu.centerOfBuoyancy).norm() <= 1e-4 * 1.2);
    const Expected<gpu::GlHydrostaticsStatistics> stats = gpu::lastHydrostaticsStatistics(*backends[1]);
    REQUIRE(stats.ok());
    CHECK(stats->dryChunks + stats->submergedChunks + stats->crossingChunks == stats->chunks);
    if (depth == 0.0) {
      CHECK(stats->dryChunks > 0);
      CHECK(stats->submergedChunks > 0);
      CHECK(stats->crossingChunks > 0);
      CHECK(stats->texelsRead < geometry->textures.size());
    }
    // Wholly under or over: the chunks' body-frame boxes, rotated, reach at most sqrt(3) 0.61 m.
    if (std::abs(depth) >= 1.1) CHECK(stats->texelsRead == 0);
  }
  CHECK(!gpu::lastHydrostaticsStatistics(*backends[0]).ok());
}

TEST_CASE("GL backend: a deforming mesh re-evaluated on the GPU matches evaluateSurface", "[backend][gpu][deform]") {
  // The torus's vertices moved by a smooth non-affine field (a twist and a bulge): PT, VAT, area
  // and edges from the GPU passes against core's evaluateSurface (double) on the same vertices,
  // to float rounding (positions 1e-5 of the size, vectors 1e-4 of the texel's area or edge
  // length, both well above the ~1e-7 relative float error of a few pieces' sums); then the
  // hydrostatics after the GPU update against the CPU backend updated with those textures, to
  // issue 7's parity (1e-5 relative volume, 1e-4 of the size on the centre of buoyancy).
  std::vector<std::unique_ptr<ComputeBackend>> backends = allBackends();
  if (backends.size() < 2) return;
  for (auto& backend : backends) addBodies(*backend);
  const TestBody& torus = testBodies()[2];
  ComputeBackend& gl = *backends[1];
  REQUIRE(gpu::enableGpuDeformation(gl, 2, torus.geometry.bake, torus.geometry.mesh, torus.geometry.atlas.layout).ok());
  FlatSurface water(0.0);
  for (int frame = 1; frame <= 3; ++frame) {
    INFO("frame " << frame);
    Mesh moved = torus.geometry.mesh;
    for (Eigen::Vector3d& v : moved.positions) {
      const double twist = 0.15 * frame * v.x();
      const double c = std::cos(twist), s = std::sin(twist);
      v = Eigen::Vector3d(v.x() * (1.0 + 0.05 * frame * v.z()), c * v.y() - s * v.z(), s * v.y() + c * v.z());
    }
    REQUIRE(gpu::updateVerticesOnGpu(gl, 2, moved.positions).ok());
    const SurfaceTextures reference = evaluateSurface(torus.geometry.bake, moved, torus.geometry.atlas.layout);
    const Expected<SurfaceTextures> onGpu = gpu::readGpuSurface(gl, 2);
    REQUIRE(onGpu.ok());
    REQUIRE(onGpu->size() == reference.size());
    double worstPosition = 0.0, worstArea = 0.0, worstEdge = 0.0;
    for (std::size_t i = 0; i < reference.size(); ++i) {
      const double scale = std::max<double>(reference.area[i], 1e-12);
      worstPosition = std::max<double>(worstPosition, (onGpu->position[i] - reference.position[i]).norm());
      worstArea = std::max<double>(worstArea, (onGpu->areaVector[i] - reference.areaVector[i]).norm() / scale);
      worstArea = std::max<double>(worstArea, std::abs(onGpu->area[i] - reference.area[i]) / scale);
      const double edge = std::max<double>(reference.edgeU[i].norm() + reference.edgeV[i].norm(), 1e-9);
      worstEdge = std::max<double>(worstEdge, ((onGpu->edgeU[i] - reference.edgeU[i]).norm() +
                                               (onGpu->edgeV[i] - reference.edgeV[i]).norm()) / edge);
    }
    CHECK(worstPosition <= 1e-5 * torus.size);
    CHECK(worstArea <= 1e-4);
    CHECK(worstEdge <= 1e-4);
    // The moment corrections (deform_texels.comp, SurfaceEvaluator's float formula): the same
    // texels, each entry to 1e-5 of size x its texel's area, as SurfaceEvaluator's own test bounds
    // its float differences c_k - p.
    CHECK(onGpu->momentTexel == reference.momentTexel);
    REQUIRE(onGpu->momentCorrection.size() == reference.momentCorrection.size());
    double worstMoment = 0.0;
    for (std::size_t c = 0; c < reference.momentCorrection.size(); ++c) {
      const double scale = torus.size * std::max<double>(reference.area[reference.momentTexel[c]], 1e-12);
      worstMoment = std::max<double>(worstMoment, (onGpu->momentCorrection[c] - reference.momentCorrection[c]).norm() / scale);
    }
    CHECK(worstMoment <= 1e-5);
    REQUIRE(backends[0]->updateSurface(2, reference).ok());
    for (const auto& batch : poseBatches()) {
      const BackendHydrostaticsQuery q = batch[2];
      const HydrostaticsResult cpu = runBatch(*backends[0], water, {q})[0];
      const HydrostaticsResult gpuResult = runBatch(gl, water, {q})[0];
      CHECK(relative(gpuResult.submergedVolume, cpu.submergedVolume) <= 1e-5);
      CHECK((gpuResult.centerOfBuoyancy - cpu.centerOfBuoyancy).norm() <= 1e-4 * torus.size);
    }
  }
  // Mass properties of the deformed torus from its GPU-side texels (deform_mass.comp: mass texels
  // and block sums evaluated from the moved triangles, nothing read back but 80 bytes per 256
  // texels) against the CPU backend's from evaluateSurface's textures of the same mesh (updated
  // above): issue 7's parity as in the mass parity case (1e-5 relative on mass and volume, 1e-4
  // of the size on the centre, 1e-4 relative on the inertia), for a solid, a solid with a shell
  // and a density map.
  const BackendBodyId id = 2;
  std::vector<TextureMassModel> models(3);
  models[0].solidDensity = 700.0;
  models[1].solidDensity = 500.0;
  models[1].shellDensity = 12.0;
  for (std::size_t i = 0; i < torus.geometry.textures.size(); ++i)
    models[2].texelDensity.push_back(float(700.0 + 300.0 * std::sin(1e-3 * double(i))));
  for (const TextureMassModel& model : models) {
    MassProperties cpu, onGpu;
    REQUIRE(backends[0]->massProperties({&id, 1}, {&model, 1}, {&cpu, 1}).ok());
    REQUIRE(gl.massProperties({&id, 1}, {&model, 1}, {&onGpu, 1}).ok());
    CHECK(relative(onGpu.mass, cpu.mass) < 1e-5);
    CHECK(relative(onGpu.volume, cpu.volume) < 1e-5);
    CHECK((onGpu.centerOfMass - cpu.centerOfMass).norm() < 1e-4 * torus.size);
    CHECK((onGpu.inertia - cpu.inertia).norm() < 1e-4 * cpu.inertia.norm());
  }
  // Errors for bad input, never a crash.
  TextureMassModel model;
  MassProperties mass;
  CHECK(!gpu::updateVerticesOnGpu(gl, 1, torus.geometry.mesh.positions).ok());  // not enabled
  CHECK(!gpu::updateVerticesOnGpu(gl, 2, {Eigen::Vector3d::Zero()}).ok());      // wrong count
  CHECK(!gpu::enableGpuDeformation(gl, 1, torus.geometry.bake, torus.geometry.mesh, torus.geometry.atlas.layout).ok());
  CHECK(!gpu::updateVerticesOnGpu(*backends[0], 2, torus.geometry.mesh.positions).ok());
  // Host textures again: the undeformed torus's mass, as the CPU backend gives it.
  REQUIRE(gl.updateSurface(2, torus.geometry.textures).ok());
  REQUIRE(backends[0]->updateSurface(2, torus.geometry.textures).ok());
  MassProperties cpuMass;
  REQUIRE(gl.massProperties({&id, 1}, {&model, 1}, {&mass, 1}).ok());
  REQUIRE(backends[0]->massProperties({&id, 1}, {&model, 1}, {&cpuMass, 1}).ok());
  CHECK(relative(mass.mass, cpuMass.mass) < 1e-5);
}

TEST_CASE("GL backend: GPU-deformed mass properties across storage segments and the CPU final sum", "[backend][gpu][deform]") {
  // 64 KiB segments put the torus's mass blocks in several buffers (one deform_mass dispatch per
  // segment run) and the final sum on the CPU reads the block geometry the host took from the GPU
  // block sums: the same answers as the default backend to float-partial order, 1e-6 relative
  // (the partials are the same floats; only double sums of them differ in order).
  gpu::GlBackendSettings small;
  small.segmentBytes = 64 * 1024;
  small.finalSum = gpu::FinalSum::Cpu;
  Expected<std::unique_ptr<ComputeBackend>> reference = gpu::makeGlBackend();
  Expected<std::unique_ptr<ComputeBackend>> split = gpu::makeGlBackend(small);
  if (!reference || !split) {
    WARN("GL backend skipped, no headless EGL context: " << (reference ? split.error() : reference.error()).message);
    return;
  }
  const TestBody& torus = testBodies()[2];
  Mesh moved = torus.geometry.mesh;
  for (Eigen::Vector3d& v : moved.positions) v = Eigen::Vector3d(1.2 * v.x(), v.y() + 0.1 * v.x() * v.x(), v.z());
  MassProperties results[2];
  int n = 0;
  for (ComputeBackend* backend : {reference->get(), split->get()}) {
    addBodies(*backend);
    REQUIRE(gpu::enableGpuDeformation(*backend, 2, torus.geometry.bake, torus.geometry.mesh, torus.geometry.atlas.layout).ok());
    REQUIRE(gpu::updateVerticesOnGpu(*backend, 2, moved.positions).ok());
    TextureMassModel model;
    model.shellDensity = 3.0;
    const BackendBodyId id = 2;
    REQUIRE(backend->massProperties({&id, 1}, {&model, 1}, {&results[n++], 1}).ok());
  }
  CHECK(relative(results[1].mass, results[0].mass) < 1e-6);
  CHECK((results[1].centerOfMass - results[0].centerOfMass).norm() < 1e-6 * torus.size);
  CHECK((results[1].inertia - results[0].inertia).norm() < 1e-6 * results[0].inertia.norm());
  // And the stretched torus's volume grew: 1.2 times (x scaled; the y shear keeps volume).
  CHECK(relative(results[0].volume, 1.2 * torus.volume) < 2e-3);
}

TEST_CASE("every backend runs the caller's work once per batch, while it is in flight", "[backend]") {
  // ComputeBackend::hydrostatics' `meanwhile`: the controller sums the drag there while a GPU's
  // passes run. It runs exactly once whatever the outcome, and does not change the answers.
  for (auto& backend : allBackends()) {
    INFO("backend " << backend->name());
    addBodies(*backend);
    FlatSurface water(0.0, 1000.0);
    const std::vector<BackendHydrostaticsQuery> queries = poseBatches()[0];
    const std::vector<HydrostaticsResult> plain = runBatch(*backend, water, queries);
    std::vector<HydrostaticsResult> overlapped(queries.size());
    int runs = 0;
    REQUIRE(backend->hydrostatics(water, queries, overlapped, [&] { ++runs; }).ok());
    CHECK(runs == 1);
    for (std::size_t i = 0; i < queries.size(); ++i) {
      CHECK(overlapped[i].submergedVolume == plain[i].submergedVolume);
      CHECK(overlapped[i].buoyancyForce == plain[i].buoyancyForce);
    }
    // A refused batch (a body asked twice) still runs it, once.
    std::vector<BackendHydrostaticsQuery> twice = {queries[0], queries[0]};
    runs = 0;
    CHECK_FALSE(backend->hydrostatics(water, twice, overlapped, [&] { ++runs; }).ok());
    CHECK(runs == 1);
  }
}
