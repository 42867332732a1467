/// @file GlWettingDiffusion.cpp
/// Wetting's explicit diffusion (core/src/Wetting.cpp, diffuseExplicit) as a gather over a CSR
/// neighbour list, one dispatch per sub-step on ping-pong buffers (wetting_diffuse.comp explains
/// why the total is conserved without atomics). The sub-step count and the stability bound are
/// Wetting's: n = ceil(dt / min_i A_i / (D sum_j g_ij)), each of dt / n.

#include "hydrotex/gpu/GlWettingDiffusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "GlObjects.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"

namespace hydrotex::gpu {

using detail::GlBuffer;
using detail::GlProgram;

struct GlWettingDiffusion::Impl {
  GlProgram program;
  GlBuffer liquid[2], rowStart, neighbour, conductance, inverseArea;
  int current = 0;  // which liquid buffer holds the state
  bool hasPairs = false;
};

GlWettingDiffusion::GlWettingDiffusion(const EglContext& context) : context_(context), impl_(std::make_unique<Impl>()) {}

GlWettingDiffusion::~GlWettingDiffusion() {
  if (!context_.makeCurrent()) (void)impl_.release();  // no context: leak the names rather than touch another one
}

Expected<std::unique_ptr<GlWettingDiffusion>> GlWettingDiffusion::create(const EglContext& context,
                                                                         const TexelAdjacency& adjacency,
                                                                         const WettingSettings& settings) {
  if (Status s = settings.validate(); !s) return s.error();
  if (settings.mergeBelowFraction > 0.0)
    return Error{"gpu wetting diffusion: merged texels are not on the GPU yet; set mergeBelowFraction to 0"};
  const std::size_t n = adjacency.area.size();
  const std::size_t pairs = adjacency.pairCount();
  if (adjacency.second.size() != pairs || adjacency.conductance.size() != pairs)
    return Error{"gpu wetting diffusion: the graph's pair arrays differ in size"};
  if (n >= std::numeric_limits<std::uint32_t>::max() || pairs >= std::numeric_limits<std::uint32_t>::max() / 2)
    return Error{"gpu wetting diffusion: graph too large"};
  // CSR: every pair appears in both of its texels' rows.
  std::vector<std::uint32_t> rowStart(n + 1, 0);
  for (std::size_t p = 0; p < pairs; ++p) {
    const std::uint32_t i = adjacency.first[p], j = adjacency.second[p];
    if (i >= n || j >= n || i == j)
      return Error{"gpu wetting diffusion: pair " + std::to_string(p) + " names texel " + std::to_string(std::max(i, j)) +
                   " of " + std::to_string(n) + " or itself"};
    ++rowStart[i + 1];
    ++rowStart[j + 1];
  }
  for (std::size_t i = 0; i < n; ++i) rowStart[i + 1] += rowStart[i];
  std::vector<std::uint32_t> cursor(rowStart.begin(), rowStart.end() - 1), neighbour(2 * pairs);
  std::vector<float> conductance(2 * pairs);
  std::vector<double> conductanceSum(n, 0.0);
  for (std::size_t p = 0; p < pairs; ++p) {
    const std::uint32_t i = adjacency.first[p], j = adjacency.second[p];
    // The same float D g_ij as Wetting's pairConductance_, on both sides.
    const float c = static_cast<float>(settings.diffusivity * adjacency.conductance[p]);
    neighbour[cursor[i]] = j;
    conductance[cursor[i]++] = c;
    neighbour[cursor[j]] = i;
    conductance[cursor[j]++] = c;
    conductanceSum[i] += adjacency.conductance[p];
    conductanceSum[j] += adjacency.conductance[p];
  }
  std::vector<float> inverseArea(n);
  double stable = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    inverseArea[i] = adjacency.area[i] > 0.0 ? static_cast<float>(1.0 / adjacency.area[i]) : 0.0f;
    if (settings.diffusivity > 0.0 && conductanceSum[i] > 0.0)
      stable = std::min(stable, adjacency.area[i] / (settings.diffusivity * conductanceSum[i]));
  }

  if (Status s = context.makeCurrent(); !s) return s.error();
  std::unique_ptr<GlWettingDiffusion> out(new GlWettingDiffusion(context));
  Expected<GlProgram> program = GlProgram::compute(
      "wetting_diffuse.comp", {"#version 430 core\n", embeddedShader("wetting_diffuse.comp")});
  if (!program) return Error{"gpu wetting diffusion: " + program.error().message};
  Impl& impl = *out->impl_;
  impl.program = std::move(program).value();
  auto upload = [](const auto& items) {
    GlBuffer buffer(items.size() * sizeof(items[0]));
    buffer.write(0, items.data(), items.size() * sizeof(items[0]));
    return buffer;
  };
  impl.rowStart = upload(rowStart);
  impl.neighbour = upload(neighbour);
  impl.conductance = upload(conductance);
  impl.inverseArea = upload(inverseArea);
  impl.liquid[0] = GlBuffer(n * sizeof(float));
  impl.liquid[1] = GlBuffer(n * sizeof(float));
  impl.hasPairs = pairs > 0;
  out->texelCount_ = n;
  out->stableStep_ = stable;
  out->diffusivity_ = settings.diffusivity;
  out->maxSubsteps_ = settings.maxExplicitSubsteps;
  return out;
}

Status GlWettingDiffusion::upload(const LiquidTexture& texture) {
  if (texture.liquid.size() != texelCount_)
    return Error{"gpu wetting diffusion: liquid texture has " + std::to_string(texture.liquid.size()) + " texels, the graph " +
                 std::to_string(texelCount_)};
  if (Status s = context_.makeCurrent(); !s) return s;
  impl_->current = 0;
  impl_->liquid[0].write(0, texture.liquid.data(), texelCount_ * sizeof(float));
  return Ok{};
}

Expected<int> GlWettingDiffusion::diffuse(double dt) {
  if (!std::isfinite(dt)) return Error{"gpu wetting diffusion: time step " + std::to_string(dt) + " s is not finite"};
  if (!(dt > 0.0) || !impl_->hasPairs || !(diffusivity_ > 0.0)) return 0;
  const double substeps = std::ceil(dt / stableStep_);
  if (substeps > maxSubsteps_)
    return Error{"gpu wetting diffusion: " + std::to_string(dt) + " s needs " + std::to_string(substeps) +
                 " explicit sub-steps, more than " + std::to_string(maxSubsteps_) + " (the implicit solve is CPU only)"};
  if (Status s = context_.makeCurrent(); !s) return s.error();
  const int count = std::max(1, static_cast<int>(substeps));
  Impl& impl = *impl_;
  glUseProgram(impl.program.id());
  impl.rowStart.bind(2);
  impl.neighbour.bind(3);
  impl.conductance.bind(4);
  impl.inverseArea.bind(5);
  glUniform1ui(impl.program.uniform("texelCount"), static_cast<GLuint>(texelCount_));
  glUniform1f(impl.program.uniform("step"), static_cast<float>(dt / count));
  const auto groups = static_cast<GLuint>((texelCount_ + 63) / 64);
  const GLuint x = std::min<GLuint>(groups, 65535u);
  for (int k = 0; k < count; ++k) {
    impl.liquid[impl.current].bind(0);
    impl.liquid[1 - impl.current].bind(1);
    glDispatchCompute(x, (groups + x - 1) / x, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    impl.current = 1 - impl.current;
  }
  if (const GLenum error = glGetError(); error != GL_NO_ERROR)
    return Error{"gpu wetting diffusion: OpenGL error " + std::to_string(error)};
  return count;
}

void GlWettingDiffusion::bindLiquid(unsigned binding) const { impl_->liquid[impl_->current].bind(binding); }

Status GlWettingDiffusion::download(LiquidTexture& texture) const {
  if (texture.liquid.size() != texelCount_)
    return Error{"gpu wetting diffusion: liquid texture has " + std::to_string(texture.liquid.size()) + " texels, the graph " +
                 std::to_string(texelCount_)};
  if (Status s = context_.makeCurrent(); !s) return s;
  impl_->liquid[impl_->current].read(0, texture.liquid.data(), texelCount_ * sizeof(float));
  return Ok{};
}

}  // namespace hydrotex::gpu
