#pragma once
/// @file GlWettingDiffusion.hpp
/// The diffusion of core's Wetting (Fick's law on the texel graph, explicit sub-steps under the
/// computed stability bound) on the GPU, same results as Wetting::diffuse to float rounding. The
/// graph is uploaded once; the liquid stays on the GPU between steps (upload / download when the
/// host needs it). GlWetting adds the absorption, sources and evaporation pass for a whole step.
/// Not on the GPU: merged stiff texels (WettingSettings::mergeBelowFraction must be 0), the
/// implicit fallback (a step that needs more than maxExplicitSubsteps answers an Error), and the
/// pigment channel.

#include <memory>

#include "hydrotex/Expected.hpp"
#include "hydrotex/LiquidTexture.hpp"
#include "hydrotex/TexelAdjacency.hpp"
#include "hydrotex/Wetting.hpp"
#include "hydrotex/gpu/EglContext.hpp"

namespace hydrotex::gpu {

/// Liquid diffusion of one body on the GPU.
class GlWettingDiffusion {
 public:
  /// Uploads the graph (a CSR neighbour list: per texel its pairs' other texel and D g_ij) and
  /// 1 / area per texel. `context` must outlive the object and is made current on every call.
  /// Errors: bad settings, merging asked for (mergeBelowFraction > 0), a graph naming a texel out
  /// of range, a shader that does not compile.
  static Expected<std::unique_ptr<GlWettingDiffusion>> create(const EglContext& context, const TexelAdjacency& adjacency,
                                                              const WettingSettings& settings);
  ~GlWettingDiffusion();
  GlWettingDiffusion(const GlWettingDiffusion&) = delete;
  GlWettingDiffusion& operator=(const GlWettingDiffusion&) = delete;

  /// Copies the liquid (m per texel) to the GPU. Error when its size is not the texel count.
  Status upload(const LiquidTexture& texture);
  /// Diffuses the resident liquid for `dt` seconds in ceil(dt / stableTimeStep()) explicit
  /// sub-steps, as Wetting::diffuse; returns the sub-steps (0 for dt <= 0 or no pairs). Error,
  /// with nothing done, when more than maxExplicitSubsteps are needed (the CPU then solves
  /// implicitly) or dt is not finite.
  Expected<int> diffuse(double dt);
  /// Copies the resident liquid back into `texture` (waits for the GPU). Error on a size mismatch.
  Status download(LiquidTexture& texture) const;
  /// Binds the resident liquid (m per texel) to shader storage binding `binding` of the current
  /// context, for passes that change it between diffusion steps (GlWetting's absorption and
  /// evaporation). The context must be current.
  void bindLiquid(unsigned binding) const;
  /// Largest stable explicit step (s): TexelAdjacency::stableTimeStep of the diffusivity.
  double stableTimeStep() const { return stableStep_; }
  /// Number of texels.
  std::size_t texelCount() const { return texelCount_; }

 private:
  struct Impl;
  explicit GlWettingDiffusion(const EglContext& context);
  const EglContext& context_;
  std::unique_ptr<Impl> impl_;
  std::size_t texelCount_ = 0;
  double stableStep_ = 0.0;
  double diffusivity_ = 0.0;
  int maxSubsteps_ = 0;
};

}  // namespace hydrotex::gpu
