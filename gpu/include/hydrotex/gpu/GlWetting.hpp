// SPDX-License-Identifier: Zlib
#pragma once
/// @file GlWetting.hpp
/// A whole liquid texture step of core's Wetting on the GPU: absorption by Darcy's law (paper
/// eq. 9) under the liquid, rain and sphere sources, evaporation after Hall and Hoff
/// (paper eq. 10) in one pass (wetting_exchange.comp, the float equations of Wetting.cpp), then
/// the diffusion sub-steps of GlWettingDiffusion. The liquid stays on the GPU between steps; the
/// volumes moved come back per work group and are summed in double, so the balance
/// absorbed = held + evaporated holds to float rounding as on the CPU. The pigment channel and
/// merged stiff texels are carried as on the CPU, and so is the implicit (backward Euler)
/// diffusion of long steps. Under a flat surface the pressure is formed on the GPU; under any
/// other (waves, a height grid, a medium) the host evaluates it per texel with the CPU's
/// liquidPressureAtTexels and uploads it (a float per texel per step). Limit (an Error, never a
/// crash): up to kMaxSources sources.

#include <memory>

#include "hydrotex/Expected.hpp"
#include "hydrotex/wetting/LiquidTexture.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/bake/TexelAdjacency.hpp"
#include "hydrotex/wetting/Wetting.hpp"
#include "hydrotex/gpu/EglContext.hpp"

namespace hydrotex::gpu {

/// The liquid texture of one body, stepped on the GPU.
class GlWetting {
 public:
  /// Most liquid sources one step takes (the shader's uniform arrays).
  static constexpr int kMaxSources = 8;

  /// Uploads the graph (GlWettingDiffusion::create), the texels' centroids, unit normals and
  /// areas. `context` must outlive the object. Errors: those of GlWettingDiffusion::create, sizes
  /// of `textures` and `adjacency` that differ, a shader that does not compile.
  static Expected<std::unique_ptr<GlWetting>> create(const EglContext& context, const TexelAdjacency& adjacency,
                                                     const SurfaceTextures& textures, const WettingSettings& settings);
  ~GlWetting();
  GlWetting(const GlWetting&) = delete;
  GlWetting& operator=(const GlWetting&) = delete;

  /// Copies the texture's liquid (m), capacity (m), permeability (m^2) and pigment (when it has
  /// that channel) per texel and its layer thickness (m) to the GPU. Errors: a size that is not
  /// the texel count, a layer thickness that is not positive.
  Status upload(const LiquidTexture& texture);
  /// One step of `dt` seconds, as Wetting::step: absorption, sources and evaporation, then
  /// diffusion. The report's volumes are m^3. Errors (nothing done): those of Wetting::step,
  /// more than kMaxSources sources, nothing uploaded.
  Expected<WettingStepReport> step(const WettingEnvironment& environment, double dt);
  /// Copies the resident liquid (m per texel) and pigment back into `texture`. Error on a size
  /// mismatch or a pigment channel that differs from the uploaded texture's.
  Status download(LiquidTexture& texture) const;
  /// Largest stable explicit diffusion step (s).
  double stableTimeStep() const;
  /// Number of texels.
  std::size_t texelCount() const { return texelCount_; }

 private:
  struct Impl;
  explicit GlWetting(const EglContext& context);
  const EglContext& context_;
  std::unique_ptr<Impl> impl_;
  std::size_t texelCount_ = 0;
  WettingSettings settings_;
  double layerThickness_ = 0.0;
  bool uploaded_ = false;
};

}  // namespace hydrotex::gpu
