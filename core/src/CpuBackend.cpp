// SPDX-License-Identifier: Zlib
/// @file CpuBackend.cpp
/// The CPU compute backend: each body keeps its TextureHydrostatics (tile hierarchy) and its
/// TextureMassIntegrator; a batch is a loop over the bodies. The reference every other backend
/// is compared with (tests/gpu/test_backend_parity.cpp).

#include <optional>
#include <string>
#include <vector>

#include "hydrotex/ComputeBackend.hpp"
#include "hydrotex/TextureHydrostatics.hpp"

namespace hydrotex {

namespace {

class CpuBackend final : public ComputeBackend {
 public:
  std::string name() const override { return "cpu"; }
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
    bodies_.push_back(Body{std::move(layout), std::move(hydrostatics).value(),
                           TextureMassIntegrator(textures, massReferencePoint), massReferencePoint});
    seen_.push_back(0);
    return BackendBodyId(bodies_.size() - 1);
  }

  Status updateSurface(BackendBodyId id, const SurfaceTextures& textures) override {
    if (id >= bodies_.size()) return Error{"cpu backend: unknown body " + std::to_string(id)};
    Body& body = bodies_[id];
    if (textures.size() != body.hydrostatics.texelCount())
      return Error{"cpu backend: body " + std::to_string(id) + " has " + std::to_string(body.hydrostatics.texelCount()) +
                   " texels, the new textures " + std::to_string(textures.size())};
    Expected<TextureHydrostatics> hydrostatics = TextureHydrostatics::build(body.bake, textures);
    if (!hydrostatics) return Error{"cpu backend: " + hydrostatics.error().message};
    body.hydrostatics = std::move(hydrostatics).value();
    body.integrator = TextureMassIntegrator(textures, body.referencePoint);
    return Ok{};
  }

  std::size_t bodyCount() const override { return bodies_.size(); }

  Status hydrostatics(const LiquidSurface& surface, std::span<const BackendHydrostaticsQuery> queries,
                      std::span<HydrostaticsResult> results) override {
    if (Status valid = checkBatch(queries, results.size()); !valid) return valid;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      Expected<HydrostaticsResult> result = bodies_[queries[i].body].hydrostatics.query(surface, queries[i].query);
      if (!result) return Error{"cpu backend: body " + std::to_string(queries[i].body) + ": " + result.error().message};
      results[i] = *result;
    }
    return Ok{};
  }

  Status massProperties(std::span<const BackendBodyId> ids, std::span<const TextureMassModel> models,
                        std::span<MassProperties> results) override {
    if (ids.size() != models.size() || results.size() < ids.size())
      return Error{"cpu backend: " + std::to_string(ids.size()) + " bodies, " + std::to_string(models.size()) +
                   " models and room for " + std::to_string(results.size()) + " results"};
    for (BackendBodyId id : ids)
      if (id >= bodies_.size()) return Error{"cpu backend: unknown body " + std::to_string(id)};
    for (std::size_t i = 0; i < ids.size(); ++i) {
      Expected<MassProperties> result = bodies_[ids[i]].integrator.evaluate(models[i]);
      if (!result) return Error{"cpu backend: body " + std::to_string(ids[i]) + ": " + result.error().message};
      results[i] = *result;
    }
    return Ok{};
  }

 private:
  struct Body {
    SurfaceBake bake;  // texel layout only (no pieces), to rebuild the tiles when the surface deforms
    TextureHydrostatics hydrostatics;
    TextureMassIntegrator integrator;
    Eigen::Vector3d referencePoint;
  };

  // Same batch rules as every backend: known bodies, each at most once.
  Status checkBatch(std::span<const BackendHydrostaticsQuery> queries, std::size_t room) {
    if (room < queries.size())
      return Error{"cpu backend: " + std::to_string(queries.size()) + " queries, room for " + std::to_string(room) +
                   " results"};
    ++batch_;
    for (const BackendHydrostaticsQuery& q : queries) {
      if (q.body >= bodies_.size()) return Error{"cpu backend: unknown body " + std::to_string(q.body)};
      if (seen_[q.body] == batch_) return Error{"cpu backend: body " + std::to_string(q.body) + " asked twice in one batch"};
      seen_[q.body] = batch_;
    }
    return Ok{};
  }

  std::vector<Body> bodies_;
  std::vector<std::uint64_t> seen_;  // batch stamp per body
  std::uint64_t batch_ = 0;
};

}  // namespace

std::unique_ptr<ComputeBackend> makeCpuBackend() { return std::make_unique<CpuBackend>(); }

}  // namespace hydrotex
