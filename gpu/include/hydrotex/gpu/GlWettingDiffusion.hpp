// SPDX-License-Identifier: Zlib
#pragma once
/// @file GlWettingDiffusion.hpp
/// The diffusion of core's Wetting (Fick's law on the texel graph, explicit sub-steps under the
/// computed stability bound) on the GPU, same results as Wetting::diffuse to float rounding: the
/// same merged groups of stiff texels (mergeStiffTexels) and the pigment channel carried upwind.
/// The graph is uploaded once; the liquid stays on the GPU between steps (upload / download when
/// the host needs it). GlWetting adds the absorption, sources and evaporation pass for a whole
/// step. A step that needs more than maxExplicitSubsteps explicit sub-steps is solved by backward
/// Euler, as on the CPU, with conjugate gradients on the GPU (float vectors, double scalars).

#include <memory>

#include "hydrotex/Expected.hpp"
#include "hydrotex/wetting/LiquidTexture.hpp"
#include "hydrotex/bake/TexelAdjacency.hpp"
#include "hydrotex/wetting/Wetting.hpp"
#include "hydrotex/gpu/EglContext.hpp"

namespace hydrotex::gpu {

/// Liquid diffusion of one body on the GPU.
class GlWettingDiffusion {
 public:
  /// Merges the stiff texels as Wetting does (settings.mergeBelowFraction) and uploads the
  /// groups and the graph between them (a CSR neighbour list: per holding texel its pairs' other
  /// holder and D g_ij, and 1 / group area). `context` must outlive the object and is made
  /// current on every call. Errors: bad settings, a graph naming a texel out of range, a shader
  /// that does not compile.
  static Expected<std::unique_ptr<GlWettingDiffusion>> create(const EglContext& context, const TexelAdjacency& adjacency,
                                                              const WettingSettings& settings);
  ~GlWettingDiffusion();
  GlWettingDiffusion(const GlWettingDiffusion&) = delete;
  GlWettingDiffusion& operator=(const GlWettingDiffusion&) = delete;

  /// Copies the liquid (m per texel), and the pigment channel when the texture has one, to the
  /// GPU. Error when a size is not the texel count.
  Status upload(const LiquidTexture& texture);
  /// Diffuses the resident liquid for `dt` seconds as Wetting::diffuse: in ceil(dt /
  /// stableTimeStep()) explicit sub-steps, or by backward Euler when that is more than
  /// maxExplicitSubsteps; returns the sub-steps (0 for the implicit step, dt <= 0 or no pairs).
  /// Error, with nothing done, when dt is not finite.
  Expected<int> diffuse(double dt);
  /// Copies the resident liquid (and pigment) back into `texture` (waits for the GPU). Error on a
  /// size mismatch or a texture whose pigment channel differs from the uploaded one's.
  Status download(LiquidTexture& texture) const;
  /// Binds the resident liquid (m per texel) to shader storage binding `binding` of the current
  /// context, for passes that change it between diffusion steps (GlWetting's absorption and
  /// evaporation). The context must be current.
  void bindLiquid(unsigned binding) const;
  /// Binds the texels' areas (float m^2, the values of TexelAdjacency::area) to storage binding
  /// `binding` of the current context.
  void bindArea(unsigned binding) const;
  /// Binds the resident pigment (m of pigment per texel) to storage binding `binding` and returns
  /// true; without a pigment channel binds the liquid there (not to be read) and returns false.
  bool bindPigment(unsigned binding) const;
  /// Largest stable explicit step (s) of the merged groups: DiffusionGroups::stableTimeStep.
  double stableTimeStep() const { return stableStep_; }
  /// Number of texels.
  std::size_t texelCount() const { return texelCount_; }

 private:
  struct Impl;
  explicit GlWettingDiffusion(const EglContext& context);
  void solveImplicit(double dt);
  const EglContext& context_;
  std::unique_ptr<Impl> impl_;
  std::size_t texelCount_ = 0;
  double stableStep_ = 0.0;
  int maxSubsteps_ = 0;
};

}  // namespace hydrotex::gpu
