// SPDX-License-Identifier: Zlib
/// @file GlWettingDiffusion.cpp
/// Wetting's explicit diffusion (core/src/wetting/Wetting.cpp, diffuseExplicit) as a gather over a CSR
/// neighbour list of the same diffusion groups (mergeStiffTexels), one dispatch per sub-step on
/// ping-pong buffers (wetting_diffuse.comp explains why the total is conserved without atomics),
/// between a pass that pools each merged group onto its holder and one that spreads it back
/// (wetting_groups.comp). The sub-step count and the stability bound are Wetting's:
/// n = ceil(dt / stable step of the groups), each of dt / n; beyond maxExplicitSubsteps, one
/// backward Euler step (solveImplicit, then one flux pass from its solution), as Wetting does.

#include "hydrotex/gpu/GlWettingDiffusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "GlObjects.hpp"
#include "hydrotex/wetting/DiffusionGroups.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"

namespace hydrotex::gpu {

using detail::GlBuffer;
using detail::GlProgram;

struct GlWettingDiffusion::Impl {
  GlProgram program, groupProgram;
  GlProgram implicitProgram, reduceProgram, implicitFluxProgram;
  GlBuffer liquid[2], pigment[2], graph, conductance, inverseArea, groupStart, members, area;
  GlBuffer solution, work, scalars;  // backward Euler's x, its r, z, p, Ap, and the solver's scalars (made on first use)
  int current = 0;  // which liquid (and pigment) buffer holds the state
  bool withPigment = false;
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
  // One buffer: the row starts, then the neighbours (the passes use few storage blocks).
  std::vector<std::uint32_t> graph(rowStart);
  graph.resize(n + 1 + 2 * pairs);
  std::uint32_t* neighbour = graph.data() + n + 1;
  std::vector<std::uint32_t> cursor(rowStart.begin(), rowStart.end() - 1);
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
  Impl& impl = *out->impl_;
  // Each program from its embedded shader after a prelude (the version, and any defines).
  auto compile = [](GlProgram& into, const char* file, std::string_view prelude) -> Status {
    Expected<GlProgram> program = GlProgram::compute(file, {prelude, embeddedShader(file)});
    if (!program) return Error{"gpu wetting diffusion: " + program.error().message};
    into = std::move(program).value();
    return Ok{};
  };
  constexpr std::string_view kVersion = "#version 430 core\n";
  for (const Status& compiled :
       {compile(impl.program, "wetting_diffuse.comp", kVersion), compile(impl.groupProgram, "wetting_groups.comp", kVersion),
        compile(impl.implicitProgram, "wetting_implicit.comp", kVersion),
        compile(impl.reduceProgram, "wetting_implicit_reduce.comp", kVersion),
        compile(impl.implicitFluxProgram, "wetting_diffuse.comp", "#version 430 core\n#define real double\n")})
    if (!compiled) return compiled.error();
  auto upload = [](const auto& items) {
    GlBuffer buffer(items.size() * sizeof(items[0]));
    buffer.write(0, items.data(), items.size() * sizeof(items[0]));
    return buffer;
  };
  impl.graph = upload(graph);
  impl.conductance = upload(conductance);
  impl.inverseArea = upload(inverseArea);
  impl.area = upload(area);
  impl.groupStart = upload(groups.start);
  impl.members = upload(groups.members);
  impl.groupCount = groups.groupCount();
  impl.liquid[0] = GlBuffer(n * sizeof(float));
  impl.liquid[1] = GlBuffer(n * sizeof(float));
  out->texelCount_ = n;
  out->stableStep_ = groups.stableTimeStep(settings.diffusivity);
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
  const int substeps = diffusionSubsteps(dt, stableStep_, maxSubsteps_);
  if (substeps == 0) return 0;
  if (Status s = context_.makeCurrent(); !s) return s.error();
  const bool implicit = substeps < 0;
  const int count = implicit ? 1 : substeps;
  Impl& impl = *impl_;
  impl.groups(false);
  // Backward Euler's solution is the potential of one flux pass; an explicit sub-step's is the
  // liquid itself.
  if (implicit) solveImplicit(dt);
  const GlProgram& program = implicit ? impl.implicitFluxProgram : impl.program;
  glUseProgram(program.id());
  impl.graph.bind(2);
  impl.conductance.bind(3);
  impl.inverseArea.bind(4);
  glUniform1ui(program.uniform("texelCount"), static_cast<GLuint>(texelCount_));
  glUniform1f(program.uniform("step"), static_cast<float>(dt / count));
  glUniform1i(program.uniform("withPigment"), impl.withPigment ? 1 : 0);
  for (int k = 0; k < count; ++k) {
    impl.liquid[impl.current].bind(0);
    impl.liquid[1 - impl.current].bind(1);
    // Without pigment the pigment bindings are never read; the liquid's stand in for them.
    (impl.withPigment ? impl.pigment[impl.current] : impl.liquid[impl.current]).bind(5);
    (impl.withPigment ? impl.pigment[1 - impl.current] : impl.liquid[1 - impl.current]).bind(6);
    (implicit ? impl.solution : impl.liquid[impl.current]).bind(7);
    Impl::dispatch(texelCount_);
    impl.current = 1 - impl.current;
  }
  impl.groups(true);
  if (const GLenum error = glGetError(); error != GL_NO_ERROR)
    return Error{"gpu wetting diffusion: OpenGL error " + std::to_string(error)};
  return implicit ? 0 : count;
}

void GlWettingDiffusion::solveImplicit(double dt) {
  // Preconditioned conjugate gradients in double, the scalars kept on the GPU
  // (wetting_implicit.comp and wetting_implicit_reduce.comp); the host reads the residual every
  // 16 iterations and stops at r.z / r0.z = 1e-20, the CPU's relative residual of 1e-10.
  Impl& impl = *impl_;
  const std::size_t n = texelCount_;
  const auto workGroups = static_cast<GLuint>((n + 63) / 64);
  const GLuint x = std::min<GLuint>(std::max<GLuint>(workGroups, 1u), 65535u);
  const GLuint partials = x * ((workGroups + x - 1) / x);  // one per dispatched work group
  constexpr std::size_t kScalars = 8;
  if (impl.solution.bytes() != n * sizeof(double)) {
    impl.solution = GlBuffer(n * sizeof(double));
    impl.work = GlBuffer(4 * n * sizeof(double));
    impl.scalars = GlBuffer((kScalars + partials) * sizeof(double));
  }
  enum : GLuint { kStart = 0, kApply = 1, kUpdate = 2, kDirection = 3 };
  auto pass = [&](GLuint mode) {
    glUseProgram(impl.implicitProgram.id());
    glUniform1ui(impl.implicitProgram.uniform("mode"), mode);
    Impl::dispatch(n);
  };
  auto reduce = [&](GLuint mode) {
    glUseProgram(impl.reduceProgram.id());
    glUniform1ui(impl.reduceProgram.uniform("mode"), mode);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  };
  impl.liquid[impl.current].bind(0);
  impl.solution.bind(1);
  impl.graph.bind(2);
  impl.conductance.bind(3);
  impl.inverseArea.bind(4);
  impl.work.bind(5);
  impl.scalars.bind(6);
  glUseProgram(impl.implicitProgram.id());
  glUniform1ui(impl.implicitProgram.uniform("texelCount"), static_cast<GLuint>(n));
  glUniform1f(impl.implicitProgram.uniform("dt"), static_cast<float>(dt));
  glUseProgram(impl.reduceProgram.id());
  glUniform1ui(impl.reduceProgram.uniform("partialCount"), partials);
  pass(kStart);
  reduce(0);
  double scalars[5];
  impl.scalars.read(0, scalars, sizeof scalars);
  const double start = scalars[4];
  if (!(start > 0.0)) return;  // already the solution (a uniform liquid)
  // Jacobi-preconditioned CG on this Laplacian needs about the square root of its condition
  // number, at most a few thousand iterations at 1024^2; the bound only stops a stagnating solve.
  const int most = 100 + static_cast<int>(10.0 * std::sqrt(static_cast<double>(n)));
  for (int iteration = 1; iteration <= most; ++iteration) {
    pass(kApply);
    reduce(1);
    pass(kUpdate);
    reduce(2);
    if (iteration % 16 == 0) {
      impl.scalars.read(0, scalars, sizeof scalars);
      if (!(scalars[0] > 1e-20 * start)) break;
    }
    pass(kDirection);
  }
}

void GlWettingDiffusion::bindLiquid(unsigned binding) const { impl_->liquid[impl_->current].bind(binding); }

void GlWettingDiffusion::bindArea(unsigned binding) const { impl_->area.bind(binding); }

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
