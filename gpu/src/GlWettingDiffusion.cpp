/// @file GlWettingDiffusion.cpp
/// Wetting's explicit diffusion (core/src/Wetting.cpp, diffuseExplicit) as a gather over a CSR
/// neighbour list of the same diffusion groups (mergeStiffTexels), one dispatch per sub-step on
/// ping-pong buffers (wetting_diffuse.comp explains why the total is conserved without atomics),
/// between a pass that pools each merged group onto its holder and one that spreads it back
/// (wetting_groups.comp). The sub-step count and the stability bound are Wetting's:
/// n = ceil(dt / stable step of the groups), each of dt / n.

#include "hydrotex/gpu/GlWettingDiffusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "GlObjects.hpp"
#include "hydrotex/DiffusionGroups.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"

namespace hydrotex::gpu {

using detail::GlBuffer;
using detail::GlProgram;

struct GlWettingDiffusion::Impl {
  GlProgram program, groupProgram;
  GlBuffer liquid[2], pigment[2], rowStart, neighbour, conductance, inverseArea, groupStart, members, area;
  int current = 0;  // which liquid (and pigment) buffer holds the state
  bool hasPairs = false, withPigment = false;
  std::size_t groupCount = 0;

  // Pools (spreading false) or spreads every merged group of the current buffers.
  void groups(bool spreading) {
    if (groupCount == 0) return;
    glUseProgram(groupProgram.id());
    liquid[current].bind(0);
    (withPigment ? pigment[current] : liquid[1 - current]).bind(1);
    groupStart.bind(2);
    members.bind(3);
    area.bind(4);
    inverseArea.bind(5);
    glUniform1ui(groupProgram.uniform("groupCount"), static_cast<GLuint>(groupCount));
    glUniform1i(groupProgram.uniform("spreading"), spreading ? 1 : 0);
    glUniform1i(groupProgram.uniform("withPigment"), withPigment ? 1 : 0);
    dispatch(groupCount);
  }
  static void dispatch(std::size_t items) {
    const auto workGroups = static_cast<GLuint>((items + 63) / 64);
    const GLuint x = std::min<GLuint>(std::max<GLuint>(workGroups, 1u), 65535u);
    glDispatchCompute(x, (workGroups + x - 1) / x, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  }
};

GlWettingDiffusion::GlWettingDiffusion(const EglContext& context) : context_(context), impl_(std::make_unique<Impl>()) {}

GlWettingDiffusion::~GlWettingDiffusion() {
  if (!context_.makeCurrent()) (void)impl_.release();  // no context: leak the names rather than touch another one
}

Expected<std::unique_ptr<GlWettingDiffusion>> GlWettingDiffusion::create(const EglContext& context,
                                                                         const TexelAdjacency& adjacency,
                                                                         const WettingSettings& settings) {
  if (Status s = settings.validate(); !s) return s.error();
  const std::size_t n = adjacency.area.size();
  const std::size_t texelPairs = adjacency.pairCount();
  if (adjacency.second.size() != texelPairs || adjacency.conductance.size() != texelPairs ||
      adjacency.conductanceSum.size() != n)
    return Error{"gpu wetting diffusion: the graph's pair arrays differ in size"};
  if (n >= std::numeric_limits<std::uint32_t>::max() || texelPairs >= std::numeric_limits<std::uint32_t>::max() / 2)
    return Error{"gpu wetting diffusion: graph too large"};
  for (std::size_t p = 0; p < texelPairs; ++p) {
    const std::uint32_t i = adjacency.first[p], j = adjacency.second[p];
    if (i >= n || j >= n || i == j)
      return Error{"gpu wetting diffusion: pair " + std::to_string(p) + " names texel " + std::to_string(std::max(i, j)) +
                   " of " + std::to_string(n) + " or itself"};
  }
  // The CPU's groups, so that both diffuse between the same control volumes.
  const DiffusionGroups groups = mergeStiffTexels(adjacency, settings.mergeBelowFraction);
  const std::size_t pairs = groups.pairFirst.size();
  // CSR: every pair appears in both of its holding texels' rows.
  std::vector<std::uint32_t> rowStart(n + 1, 0);
  for (std::size_t p = 0; p < pairs; ++p) {
    ++rowStart[groups.pairFirst[p] + 1];
    ++rowStart[groups.pairSecond[p] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) rowStart[i + 1] += rowStart[i];
  std::vector<std::uint32_t> cursor(rowStart.begin(), rowStart.end() - 1), neighbour(2 * pairs);
  std::vector<float> conductance(2 * pairs);
  for (std::size_t p = 0; p < pairs; ++p) {
    const std::uint32_t i = groups.pairFirst[p], j = groups.pairSecond[p];
    // The same float D g_ij as Wetting's sweep, on both sides.
    const float c = static_cast<float>(settings.diffusivity * groups.pairGeometric[p]);
    neighbour[cursor[i]] = j;
    conductance[cursor[i]++] = c;
    neighbour[cursor[j]] = i;
    conductance[cursor[j]++] = c;
  }
  std::vector<float> inverseArea(n), area(n);
  for (std::size_t i = 0; i < n; ++i) {
    inverseArea[i] = groups.nodeArea[i] > 0.0 ? static_cast<float>(1.0 / groups.nodeArea[i]) : 0.0f;
    area[i] = static_cast<float>(adjacency.area[i]);
  }

  if (Status s = context.makeCurrent(); !s) return s.error();
  std::unique_ptr<GlWettingDiffusion> out(new GlWettingDiffusion(context));
  Expected<GlProgram> program = GlProgram::compute(
      "wetting_diffuse.comp", {"#version 430 core\n", embeddedShader("wetting_diffuse.comp")});
  if (!program) return Error{"gpu wetting diffusion: " + program.error().message};
  Expected<GlProgram> groupProgram = GlProgram::compute(
      "wetting_groups.comp", {"#version 430 core\n", embeddedShader("wetting_groups.comp")});
  if (!groupProgram) return Error{"gpu wetting diffusion: " + groupProgram.error().message};
  Impl& impl = *out->impl_;
  impl.program = std::move(program).value();
  impl.groupProgram = std::move(groupProgram).value();
  auto upload = [](const auto& items) {
    GlBuffer buffer(items.size() * sizeof(items[0]));
    buffer.write(0, items.data(), items.size() * sizeof(items[0]));
    return buffer;
  };
  impl.rowStart = upload(rowStart);
  impl.neighbour = upload(neighbour);
  impl.conductance = upload(conductance);
  impl.inverseArea = upload(inverseArea);
  impl.area = upload(area);
  impl.groupStart = upload(groups.start);
  impl.members = upload(groups.members);
  impl.groupCount = groups.groupCount();
  impl.liquid[0] = GlBuffer(n * sizeof(float));
  impl.liquid[1] = GlBuffer(n * sizeof(float));
  impl.hasPairs = pairs > 0;
  out->texelCount_ = n;
  out->stableStep_ = groups.stableTimeStep(settings.diffusivity);
  out->diffusivity_ = settings.diffusivity;
  out->maxSubsteps_ = settings.maxExplicitSubsteps;
  return out;
}

Status GlWettingDiffusion::upload(const LiquidTexture& texture) {
  if (texture.liquid.size() != texelCount_)
    return Error{"gpu wetting diffusion: liquid texture has " + std::to_string(texture.liquid.size()) + " texels, the graph " +
                 std::to_string(texelCount_)};
  if (!texture.pigment.empty() && texture.pigment.size() != texelCount_)
    return Error{"gpu wetting diffusion: pigment channel has " + std::to_string(texture.pigment.size()) +
                 " texels, the graph " + std::to_string(texelCount_)};
  if (Status s = context_.makeCurrent(); !s) return s;
  Impl& impl = *impl_;
  impl.current = 0;
  impl.liquid[0].write(0, texture.liquid.data(), texelCount_ * sizeof(float));
  impl.withPigment = !texture.pigment.empty();
  if (impl.withPigment) {
    for (GlBuffer& buffer : impl.pigment)
      if (buffer.bytes() != texelCount_ * sizeof(float)) buffer = GlBuffer(texelCount_ * sizeof(float));
    impl.pigment[0].write(0, texture.pigment.data(), texelCount_ * sizeof(float));
  }
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
  impl.groups(false);
  glUseProgram(impl.program.id());
  impl.rowStart.bind(2);
  impl.neighbour.bind(3);
  impl.conductance.bind(4);
  impl.inverseArea.bind(5);
  glUniform1ui(impl.program.uniform("texelCount"), static_cast<GLuint>(texelCount_));
  glUniform1f(impl.program.uniform("step"), static_cast<float>(dt / count));
  glUniform1i(impl.program.uniform("withPigment"), impl.withPigment ? 1 : 0);
  for (int k = 0; k < count; ++k) {
    impl.liquid[impl.current].bind(0);
    impl.liquid[1 - impl.current].bind(1);
    // Without pigment the pigment bindings are never read; the liquid's stand in for them.
    (impl.withPigment ? impl.pigment[impl.current] : impl.liquid[impl.current]).bind(6);
    (impl.withPigment ? impl.pigment[1 - impl.current] : impl.liquid[1 - impl.current]).bind(7);
    Impl::dispatch(texelCount_);
    impl.current = 1 - impl.current;
  }
  impl.groups(true);
  if (const GLenum error = glGetError(); error != GL_NO_ERROR)
    return Error{"gpu wetting diffusion: OpenGL error " + std::to_string(error)};
  return count;
}

void GlWettingDiffusion::bindLiquid(unsigned binding) const { impl_->liquid[impl_->current].bind(binding); }

bool GlWettingDiffusion::bindPigment(unsigned binding) const {
  // Without a pigment channel the liquid stands in for the binding (never read).
  (impl_->withPigment ? impl_->pigment[impl_->current] : impl_->liquid[impl_->current]).bind(binding);
  return impl_->withPigment;
}

Status GlWettingDiffusion::download(LiquidTexture& texture) const {
  if (texture.liquid.size() != texelCount_)
    return Error{"gpu wetting diffusion: liquid texture has " + std::to_string(texture.liquid.size()) + " texels, the graph " +
                 std::to_string(texelCount_)};
  if (impl_->withPigment != !texture.pigment.empty() || (impl_->withPigment && texture.pigment.size() != texelCount_))
    return Error{std::string("gpu wetting diffusion: the texture ") + (texture.pigment.empty() ? "has no" : "has a") +
                 " pigment channel, the GPU's liquid " + (impl_->withPigment ? "has one" : "has none")};
  if (Status s = context_.makeCurrent(); !s) return s;
  impl_->liquid[impl_->current].read(0, texture.liquid.data(), texelCount_ * sizeof(float));
  if (impl_->withPigment) impl_->pigment[impl_->current].read(0, texture.pigment.data(), texelCount_ * sizeof(float));
  return Ok{};
}

}  // namespace hydrotex::gpu
