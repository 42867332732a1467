// SPDX-License-Identifier: Zlib
// MassModelsStep, the mass phase of a step: every due texel mass pass goes to the backend in one
// batch, read back once, and each model finishes with the backend's answer. Checked against the
// independent path, each MassModel evaluating itself (properties()): the CPU backend holds an
// equal TextureMassIntegrator (same textures, same cone apex), so the bits must be equal.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <optional>
#include <vector>

#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/step/MassModelsStep.hpp"

using namespace hydrotex;
namespace prim = hydrotex::primitives;

namespace {

BodyGeometry geometryOf(const Mesh& mesh, int resolution) {
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = resolution;
  Expected<BodyGeometry> geometry = prepareBodyGeometry(mesh, settings);
  REQUIRE(geometry.ok());
  return std::move(geometry).value();
}

bool sameBits(const MassProperties& a, const MassProperties& b) {
  return std::memcmp(&a.mass, &b.mass, sizeof(double)) == 0 && std::memcmp(&a.volume, &b.volume, sizeof(double)) == 0 &&
         std::memcmp(a.centerOfMass.data(), b.centerOfMass.data(), 3 * sizeof(double)) == 0 &&
         std::memcmp(a.inertia.data(), b.inertia.data(), 9 * sizeof(double)) == 0;
}

/// Three bodies, each registered with the backend and given two equal models: one the step
/// finishes, one that evaluates itself (the reference).
struct Bodies {
  std::vector<BodyGeometry> geometry;
  std::vector<MassModel> stepped, reference;
  std::vector<BackendBodyId> ids;
};

Bodies makeBodies(ComputeBackend& backend) {
  Bodies bodies;
  bodies.geometry.push_back(geometryOf(prim::box({2.0, 1.0, 1.5}), 48));
  bodies.geometry.push_back(geometryOf(prim::uvSphere(0.7, 32, 16), 48));
  bodies.geometry.push_back(geometryOf(prim::box({0.5, 0.8, 3.0}), 32));
  for (const BodyGeometry& g : bodies.geometry) {
    const Eigen::Vector3d apex(0.05, -0.02, 0.01);  // not the centre: the apex must be the registered one
    Expected<BackendBodyId> id = backend.addBody(g.bake, g.textures, apex);
    REQUIRE(id.ok());
    bodies.ids.push_back(*id);
    for (auto* models : {&bodies.stepped, &bodies.reference}) {
      models->emplace_back(g.textures, apex);
      REQUIRE(models->back().setSolidDensity(600.0).ok());
      REQUIRE(models->back().setShellDensity(15.0).ok());
      REQUIRE(models->back().addPointMass(PointMass{30.0, Eigen::Vector3d(0.2, 0.1, 0.0), {}}).ok());
    }
  }
  return bodies;
}

}  // namespace

TEST_CASE("mass phase: one backend batch, the same bits as each model's own pass", "[step][mass]") {
  std::unique_ptr<ComputeBackend> backend = makeCpuBackend();
  Bodies bodies = makeBodies(*backend);
  MassModelsStep step;
  std::vector<MassModelTask> tasks(bodies.ids.size());
  std::vector<std::optional<Expected<MassProperties>>> results(tasks.size());
  for (std::size_t i = 0; i < tasks.size(); ++i) tasks[i] = MassModelTask{&bodies.stepped[i], bodies.ids[i]};

  // First evaluation: every model's texel pass is due, all three in one batch.
  REQUIRE(bodies.stepped[0].needsTexelPass());
  MassModelsStepStatistics statistics = step.run(*backend, tasks, results);
  CHECK(statistics.massBatches == 1);
  CHECK(statistics.massBatchBodies == 3);
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    CAPTURE(i);
    REQUIRE(results[i].has_value());
    REQUIRE(results[i]->ok());
    const Expected<MassProperties> own = bodies.reference[i].properties();
    REQUIRE(own.ok());
    CHECK(sameBits(**results[i], *own));
    CHECK(bodies.stepped[i].texelPasses() == 1);  // the backend's pass, counted by the model that took it
    CHECK_FALSE(bodies.stepped[i].needsTexelPass());
  }

  // Only a point mass moved: nothing is due, no batch; the models combine again.
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    REQUIRE(bodies.stepped[i].setPointMassPosition(0, Eigen::Vector3d(-0.1, 0.0, 0.2)).ok());
    REQUIRE(bodies.reference[i].setPointMassPosition(0, Eigen::Vector3d(-0.1, 0.0, 0.2)).ok());
  }
  statistics = step.run(*backend, tasks, results);
  CHECK(statistics.massBatches == 0);
  CHECK(statistics.massBatchBodies == 0);
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    REQUIRE(results[i]->ok());
    CHECK(sameBits(**results[i], *bodies.reference[i].properties()));
    CHECK(bodies.stepped[i].texelPasses() == 1);
  }

  // A new density map on the second body only: one batch of one body; a task with no model
  // (nothing changed) gets no result.
  std::vector<float> map(bodies.stepped[1].texelCount());
  for (std::size_t t = 0; t < map.size(); ++t) map[t] = float(400.0 + 300.0 * std::sin(0.01 * double(t)));
  REQUIRE(bodies.stepped[1].setTexelDensity(map).ok());
  REQUIRE(bodies.reference[1].setTexelDensity(map).ok());
  tasks[0].model = nullptr;
  statistics = step.run(*backend, tasks, results);
  CHECK(statistics.massBatches == 1);
  CHECK(statistics.massBatchBodies == 1);
  CHECK_FALSE(results[0].has_value());
  REQUIRE(results[1]->ok());
  CHECK(sameBits(**results[1], *bodies.reference[1].properties()));
  CHECK(bodies.stepped[1].texelPasses() == 2);
  CHECK(bodies.stepped[1].texelModel().texelDensity == map);  // the map lent to the batch came back
  CHECK(bodies.stepped[2].texelPasses() == 1);
}

TEST_CASE("mass phase: a bad density map fails its own body, not the batch", "[step][mass]") {
  std::unique_ptr<ComputeBackend> backend = makeCpuBackend();
  Bodies bodies = makeBodies(*backend);
  MassModelsStep step;
  std::vector<MassModelTask> tasks(bodies.ids.size());
  std::vector<std::optional<Expected<MassProperties>>> results(tasks.size());
  for (std::size_t i = 0; i < tasks.size(); ++i) tasks[i] = MassModelTask{&bodies.stepped[i], bodies.ids[i]};
  // A negative density is found inside the pass (MassModel::setTexelDensity leaves it to the pass).
  REQUIRE(bodies.stepped[2].setTexelDensity(std::vector<float>(bodies.stepped[2].texelCount(), -5.0f)).ok());
  const MassModelsStepStatistics statistics = step.run(*backend, tasks, results);
  // The batch failed whole, then each body was asked alone: 1 + 3 batches.
  CHECK(statistics.massBatches == 4);
  REQUIRE(results[0]->ok());
  REQUIRE(results[1]->ok());
  CHECK(sameBits(**results[0], *bodies.reference[0].properties()));
  CHECK(sameBits(**results[1], *bodies.reference[1].properties()));
  REQUIRE_FALSE(results[2]->ok());
  CHECK(results[2]->error().message.find("densit") != std::string::npos);
  CHECK(bodies.stepped[2].needsTexelPass());  // still due: nothing was stored
  CHECK(bodies.stepped[2].texelModel().texelDensity.size() == bodies.stepped[2].texelCount());  // its map came back
}

TEST_CASE("mass phase: models without a backend body or following triangles evaluate themselves", "[step][mass]") {
  std::unique_ptr<ComputeBackend> backend = makeCpuBackend();
  const BodyGeometry g = geometryOf(prim::box({1.0, 1.0, 1.0}), 32);
  MassModel alone(g.textures, Eigen::Vector3d::Zero());
  MassModel triangles(g.textures, Eigen::Vector3d::Zero());
  REQUIRE(triangles.followTriangles(g.bake, g.atlas.layout, g.mesh).ok());
  CHECK_FALSE(triangles.needsTexelPass());  // per-triangle sums: no pass over texels
  Expected<BackendBodyId> id = backend->addBody(g.bake, g.textures, Eigen::Vector3d::Zero());
  REQUIRE(id.ok());
  MassModelsStep step;
  std::vector<MassModelTask> tasks = {{&alone, std::nullopt}, {&triangles, *id}};
  std::vector<std::optional<Expected<MassProperties>>> results(2);
  const MassModelsStepStatistics statistics = step.run(*backend, tasks, results);
  CHECK(statistics.massBatches == 0);
  // A uniform 1000 kg/m^3 unit cube: 1000 kg, the texel sums to float rounding (1e-6), the
  // triangle sums exact (1e-12).
  REQUIRE(results[0]->ok());
  REQUIRE(results[1]->ok());
  CHECK((*results[0])->mass == Approx(1000.0).epsilon(1e-6));
  CHECK((*results[1])->mass == Approx(1000.0).epsilon(1e-12));
  CHECK(alone.texelPasses() == 1);
  CHECK(triangles.texelPasses() == 0);
  // finish() refuses an answer nothing asked for.
  CHECK_FALSE(alone.finish(**results[0]).ok());
}
