// SPDX-License-Identifier: Zlib
/// @file GlFloodingPass.cpp
/// The permeable-texel pass of flooding on the GPU (GlFloodingPass.hpp).

#include "hydrotex/gpu/GlFloodingPass.hpp"

#include <string>
#include <vector>

#include "GlObjects.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"

namespace hydrotex::gpu {
namespace {

using detail::GlBuffer;
using detail::GlProgram;

constexpr std::size_t kMaxNodes = 65535;  // one work group per node, x only
constexpr int kSums = 5;                  // FloodingNodeSums' fields, in order

class GlFloodingPass final : public FloodingTexelPass {
 public:
  explicit GlFloodingPass(const EglContext& context) : context_(context) {}
  ~GlFloodingPass() override { (void)context_.makeCurrent(); }  // GL objects die with the context current
  GlFloodingPass(const GlFloodingPass&) = delete;
  GlFloodingPass& operator=(const GlFloodingPass&) = delete;

  Status upload(const LiquidGraph& graph) {
    const std::vector<PermeableTexel>& texels = graph.permeableTexels();
    nodeCount_ = graph.nodes().size();
    if (nodeCount_ > kMaxNodes)
      return Error{"gpu flooding: " + std::to_string(nodeCount_) + " nodes, at most " + std::to_string(kMaxNodes)};
    std::vector<float> packed;
    packed.reserve(4 * texels.size());
    std::vector<std::uint32_t> start(nodeCount_ + 1, 0);
    for (const PermeableTexel& t : texels) {  // grouped by node (LiquidGraph::permeableTexels)
      packed.insert(packed.end(), {t.position.x(), t.position.y(), t.position.z(), t.transmissibility});
      ++start[t.node + 1];
    }
    for (std::size_t i = 0; i < nodeCount_; ++i) start[i + 1] += start[i];
    if (Status s = context_.makeCurrent(); !s) return s;
    Expected<GlProgram> program = GlProgram::compute("flooding_texels.comp", {"#version 430 core\n", embeddedShader("flooding_texels.comp")});
    if (!program) return Error{"gpu flooding: " + program.error().message};
    program_ = std::move(program).value();
    texels_ = GlBuffer(packed.size() * sizeof(float));
    texels_.write(0, packed.data(), packed.size() * sizeof(float));
    starts_ = GlBuffer(start.size() * sizeof(std::uint32_t));
    starts_.write(0, start.data(), start.size() * sizeof(std::uint32_t));
    levels_ = GlBuffer(2 * nodeCount_ * sizeof(float));
    sums_ = GlBuffer(kSums * nodeCount_ * sizeof(float));
    levelScratch_.resize(2 * nodeCount_);
    sumScratch_.resize(kSums * nodeCount_);
    return Ok{};
  }

  Status sums(const FloodingTexelLevels& levels, std::span<FloodingNodeSums> out) override {
    if (levels.insideLevel.size() != nodeCount_ || levels.wetLevel.size() != nodeCount_ || out.size() != nodeCount_)
      return Error{"gpu flooding: levels or sums for " + std::to_string(out.size()) + " nodes, the graph has " +
                   std::to_string(nodeCount_)};
    if (nodeCount_ == 0) return Ok{};
    if (Status s = context_.makeCurrent(); !s) return s;
    for (std::size_t i = 0; i < nodeCount_; ++i) {
      levelScratch_[2 * i] = levels.insideLevel[i];
      levelScratch_[2 * i + 1] = levels.wetLevel[i];
    }
    levels_.write(0, levelScratch_.data(), levelScratch_.size() * sizeof(float));
    glUseProgram(program_.id());
    glUniform3f(program_.uniform("up"), levels.up.x(), levels.up.y(), levels.up.z());
    glUniform1f(program_.uniform("outsideLevel"), levels.outsideLevel);
    texels_.bind(0);
    starts_.bind(1);
    levels_.bind(2);
    sums_.bind(3);
    glDispatchCompute(static_cast<GLuint>(nodeCount_), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    sums_.read(0, sumScratch_.data(), sumScratch_.size() * sizeof(float));
    if (const GLenum error = glGetError(); error != GL_NO_ERROR)
      return Error{"gpu flooding: OpenGL error " + std::to_string(error)};
    for (std::size_t i = 0; i < nodeCount_; ++i) {
      const float* s = sumScratch_.data() + kSums * i;
      out[i] = FloodingNodeSums{double(s[0]), double(s[1]), double(s[2]), double(s[3]), double(s[4])};
    }
    return Ok{};
  }

 private:
  const EglContext& context_;
  std::size_t nodeCount_ = 0;
  GlProgram program_;
  GlBuffer texels_, starts_, levels_, sums_;
  std::vector<float> levelScratch_, sumScratch_;
};

}  // namespace

Expected<std::unique_ptr<FloodingTexelPass>> makeGlFloodingPass(const EglContext& context, const LiquidGraph& graph) {
  auto pass = std::make_unique<GlFloodingPass>(context);
  if (Status s = pass->upload(graph); !s) return s.error();
  return std::unique_ptr<FloodingTexelPass>(std::move(pass));
}

}  // namespace hydrotex::gpu
