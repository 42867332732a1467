// SPDX-License-Identifier: Zlib
/// @file CpuBackend.cpp
/// The CPU compute backend: each body keeps its TextureHydrostatics (tile hierarchy) and its
/// TextureMassIntegrator; a batch is a loop over the bodies. The reference every other backend
/// is compared with (tests/gpu/test_backend_parity.cpp).

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex {

namespace {

/// Core's Wetting behind the backend's door.
class CpuWetting final : public BackendWetting {
 public:
  explicit CpuWetting(Wetting solver) : solver_(std::move(solver)) {}
  Expected<WettingStepReport> step(LiquidTexture& texture, const WettingEnvironment& environment, double dt) override {
    return solver_.step(texture, environment, dt);
  }
  Status sync(LiquidTexture&) override { return Ok{}; }  // stepped in place
  bool threadSafe() const override { return true; }

 private:
  Wetting solver_;
};

class CpuBackend final : public ComputeBackend {
 public:
  explicit CpuBackend(ParallelFor parallelFor) : parallelFor_(std::move(parallelFor)) {}

  std::string name() const override { return "cpu"; }

  Expected<std::unique_ptr<BackendWetting>> makeWetting(TexelAdjacency adjacency, const SurfaceTextures& textures,
                                                        const WettingSettings& settings) override {
    return makeCpuWetting(std::move(adjacency), textures, settings);
  }

  Expected<std::unique_ptr<FloodingTexelPass>> makeFloodingPass(const LiquidGraph&) override {
    return std::unique_ptr<FloodingTexelPass>();  // the graph's own loop
  }
  std::string renderer() const override { return "CPU"; }

  Expected<BackendBodyId> addBody(const SurfaceBake& bake, const SurfaceTextures& textures,
                                  const Eigen::Vector3d& massReferencePoint) override {
    if (!massReferencePoint.allFinite()) return Error{"cpu backend: mass reference point is not finite"};
    Expected<TextureHydrostatics> hydrostatics = TextureHydrostatics::build(bake, textures);
    if (!hydrostatics) return Error{"cpu backend: " + hydrostatics.error().message};
    // Only the texel layout is kept to rebuild the tiles later, not the pieces (the bulk of a
    // bake: 1,000 bodies at 256^2 would hold gigabytes of them).
    SurfaceBake layout;
    layout.width = bake.width;
    layout.height = bake.height;
    layout.tileSize = bake.tileSize;
    layout.texelIndex = bake.texelIndex;
    layout.tileStart = bake.tileStart;
    bodies_.push_back(std::make_shared<Body>(Body{std::move(layout), std::move(hydrostatics).value(),
                                                  TextureMassIntegrator(textures, massReferencePoint), massReferencePoint}));
    seen_.push_back(0);
    return BackendBodyId(bodies_.size() - 1);
  }

  Status updateSurface(BackendBodyId id, const SurfaceTextures& textures) override {
    if (id >= bodies_.size() || !bodies_[id]) return Error{"cpu backend: unknown body " + std::to_string(id)};
    if (bodies_[id].use_count() > 1)
      return Error{"cpu backend: body " + std::to_string(id) + " shares its texels with another (addInstance); a deforming body needs its own"};
    Body& body = *bodies_[id];
    if (textures.size() != body.hydrostatics.texelCount())
      return Error{"cpu backend: body " + std::to_string(id) + " has " + std::to_string(body.hydrostatics.texelCount()) +
                   " texels, the new textures " + std::to_string(textures.size())};
    // In place: the tiles' moments and bounds from the moved texels, no re-packing.
    if (Status s = body.hydrostatics.update(textures); !s) return Error{"cpu backend: " + s.error().message};
    body.integrator = TextureMassIntegrator(textures, body.referencePoint);
    return Ok{};
  }

  std::size_t bodyCount() const override { return bodies_.size(); }

  Expected<BackendBodyId> addInstance(BackendBodyId of) override {
    if (of >= bodies_.size() || !bodies_[of]) return Error{"cpu backend: unknown body " + std::to_string(of)};
    bodies_.push_back(bodies_[of]);  // the same read-only texels, tiles and integrator
    seen_.push_back(0);
    return BackendBodyId(bodies_.size() - 1);
  }

  void releaseBody(BackendBodyId id) override {
    // Its texels, tiles and mass integrator freed; the id stays taken (checkBatch refuses it).
    if (id < bodies_.size()) bodies_[id].reset();
  }

  using ComputeBackend::hydrostatics;
  Status hydrostatics(const LiquidSurface& surface, std::span<const BackendHydrostaticsQuery> queries,
                      std::span<HydrostaticsResult> results, const std::function<void()>& meanwhile) override {
    // On the CPU nothing is in flight: the caller's work runs after the batch, on the same threads.
    const Status answered = answerBatch(surface, queries, results);
    if (meanwhile) meanwhile();
    return answered;
  }

 private:
  Status answerBatch(const LiquidSurface& surface, std::span<const BackendHydrostaticsQuery> queries,
                     std::span<HydrostaticsResult> results) {
    if (Status valid = checkBatch(queries, results.size()); !valid) return valid;
    // Each query reads only its own body (const) and writes only its own answer: the bodies run
    // in parallel when a ParallelFor was given. Nothing is written to `results` unless all succeed.
    answers_.resize(queries.size());
    failures_.assign(queries.size(), std::nullopt);
    // Two pointers captured: std::function keeps them without allocating (the per-step path
    // allocates nothing, test_controller.cpp).
    const struct {
      const LiquidSurface& surface;
      std::span<const BackendHydrostaticsQuery> queries;
    } batch{surface, queries};
    auto answer = [this, &batch](std::size_t i) {
      const BackendHydrostaticsQuery& q = batch.queries[i];
      Expected<HydrostaticsResult> result = bodies_[q.body]->hydrostatics.query(batch.surface, q.query);
      if (result) {
        answers_[i] = *result;
      } else {
        failures_[i] = result.error();
      }
    };
    forEachBody(queries.size(), answer);
    for (std::size_t i = 0; i < queries.size(); ++i)
      if (failures_[i]) return Error{"cpu backend: body " + std::to_string(queries[i].body) + ": " + failures_[i]->message};
    std::copy(answers_.begin(), answers_.end(), results.begin());
    return Ok{};
  }

 public:
  Status massProperties(std::span<const BackendBodyId> ids, std::span<const TextureMassModel> models,
                        std::span<MassProperties> results) override {
    if (ids.size() != models.size() || results.size() < ids.size())
      return Error{"cpu backend: " + std::to_string(ids.size()) + " bodies, " + std::to_string(models.size()) +
                   " models and room for " + std::to_string(results.size()) + " results"};
    for (BackendBodyId id : ids)
      if (id >= bodies_.size() || !bodies_[id]) return Error{"cpu backend: unknown body " + std::to_string(id)};
    // Each body reads only its own integrator and writes only its own answer: in parallel when a
    // ParallelFor was given (the same bits for any thread count). Nothing is written to `results`
    // unless all succeed.
    massAnswers_.resize(ids.size());
    failures_.assign(ids.size(), std::nullopt);
    const struct {
      std::span<const BackendBodyId> ids;
      std::span<const TextureMassModel> models;
    } batch{ids, models};
    auto answer = [this, &batch](std::size_t i) {
      Expected<MassProperties> result = bodies_[batch.ids[i]]->integrator.evaluate(batch.models[i]);
      if (result) {
        massAnswers_[i] = *result;
      } else {
        failures_[i] = result.error();
      }
    };
    forEachBody(ids.size(), answer);
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (failures_[i]) return Error{"cpu backend: body " + std::to_string(ids[i]) + ": " + failures_[i]->message};
    std::copy(massAnswers_.begin(), massAnswers_.end(), results.begin());
    return Ok{};
  }

 private:
  struct Body {
    SurfaceBake bake;  // texel layout only (no pieces), to rebuild the tiles when the surface deforms
    TextureHydrostatics hydrostatics;
    TextureMassIntegrator integrator;
    Eigen::Vector3d referencePoint;
  };

  // Calls answer(i) for every i in [0, count): through parallelFor_ when one was given and there
  // is more than one, else in order. Each answer reads only its own body and writes only its own
  // slot, so the results are the same for every thread count.
  void forEachBody(std::size_t count, const std::function<void(std::size_t)>& answer) {
    if (parallelFor_ && count > 1) {
      parallelFor_(count, answer);
      return;
    }
    for (std::size_t i = 0; i < count; ++i) answer(i);
  }

  // Same batch rules as every backend: known bodies, each at most once.
  Status checkBatch(std::span<const BackendHydrostaticsQuery> queries, std::size_t room) {
    if (room < queries.size())
      return Error{"cpu backend: " + std::to_string(queries.size()) + " queries, room for " + std::to_string(room) +
                   " results"};
    ++batch_;
    for (const BackendHydrostaticsQuery& q : queries) {
      if (q.body >= bodies_.size() || !bodies_[q.body]) return Error{"cpu backend: unknown body " + std::to_string(q.body)};
      if (seen_[q.body] == batch_) return Error{"cpu backend: body " + std::to_string(q.body) + " asked twice in one batch"};
      seen_[q.body] = batch_;
    }
    return Ok{};
  }

  ParallelFor parallelFor_;  // empty: one body after the other
  std::vector<std::shared_ptr<Body>> bodies_;  // null once released; shared by instances
  std::vector<HydrostaticsResult> answers_;  // per query of the batch in progress
  std::vector<MassProperties> massAnswers_;  // per body of the mass batch in progress
  std::vector<std::optional<Error>> failures_;  // ... and its error, if any
  std::vector<std::uint64_t> seen_;  // batch stamp per body
  std::uint64_t batch_ = 0;
};

}  // namespace

std::unique_ptr<ComputeBackend> makeCpuBackend(ParallelFor parallelFor) {
  return std::make_unique<CpuBackend>(std::move(parallelFor));
}

Expected<std::unique_ptr<BackendWetting>> makeCpuWetting(TexelAdjacency adjacency, const SurfaceTextures& textures,
                                                         const WettingSettings& settings) {
  Expected<Wetting> solver = Wetting::create(std::move(adjacency), textures, settings);
  if (!solver) return solver.error();
  return std::unique_ptr<BackendWetting>(std::make_unique<CpuWetting>(std::move(solver).value()));
}

}  // namespace hydrotex
