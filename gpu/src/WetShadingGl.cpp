// SPDX-License-Identifier: Zlib
// GPU evaluation of gpu/shaders/wet_shading.glsl through gpu/shaders/wet_shading_eval.comp: two
// vec4 in and two vec4 out per sample (std430 arrays of vec4 have a 16-byte stride, so plain float
// arrays map onto them).
#include "hydrotex/gpu/WetShadingGl.hpp"

#include <cmath>
#include <string>

#include "GlObjects.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"

namespace hydrotex::gpu {

Expected<std::vector<WetShadingResult>> evaluateWetShading(const EglContext& context,
                                                           const std::vector<WetShadingSample>& samples) {
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const WetShadingSample& s = samples[i];
    if (!(s.refractiveIndex > 1.0f && std::isfinite(s.refractiveIndex)) || !s.dryRgb.allFinite() ||
        !std::isfinite(s.saturation) || !s.filmTransmittance.allFinite())
      return Error{"wet shading sample " + std::to_string(i) + ": refractive index " + std::to_string(s.refractiveIndex) +
                   " is not above 1, or a value is NaN"};
  }
  if (Status s = context.makeCurrent(); !s) return s.error();
  const std::string_view model = embeddedShader("wet_shading.glsl");
  const std::string_view kernel = embeddedShader("wet_shading_eval.comp");
  if (model.empty() || kernel.empty()) return Error{"wet shading: wet_shading.glsl is not embedded"};
  Expected<detail::GlProgram> program =
      detail::GlProgram::compute("wet_shading.glsl", {"#version 430 core\n", model, "\n", kernel});
  if (!program) return program.error();
  std::vector<WetShadingResult> results(samples.size());
  if (samples.empty()) return results;

  std::vector<float> input(8 * samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const WetShadingSample& s = samples[i];
    float* in = &input[8 * i];
    in[0] = s.dryRgb.x(), in[1] = s.dryRgb.y(), in[2] = s.dryRgb.z(), in[3] = s.saturation;
    in[4] = s.filmTransmittance.x(), in[5] = s.filmTransmittance.y(), in[6] = s.filmTransmittance.z();
    in[7] = s.refractiveIndex;
  }
  const detail::GlBuffer inputBuffer(input.size() * sizeof(float));
  const detail::GlBuffer outputBuffer(input.size() * sizeof(float));
  inputBuffer.write(0, input.data(), input.size() * sizeof(float));
  inputBuffer.bind(0);
  outputBuffer.bind(1);
  glUseProgram(program->id());
  glUniform1ui(program->uniform("sampleCount"), static_cast<GLuint>(samples.size()));
  glDispatchCompute(static_cast<GLuint>((samples.size() + 63) / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<float> output(input.size());
  outputBuffer.read(0, output.data(), output.size() * sizeof(float));
  glUseProgram(0);
  if (const GLenum error = glGetError(); error != GL_NO_ERROR)
    return Error{"wet shading: GL error " + std::to_string(error) + " while evaluating the shader"};
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const float* out = &output[8 * i];
    WetShadingResult& r = results[i];
    r.surfaceRgb = Eigen::Vector3f(out[0], out[1], out[2]);
    r.internalReflection = out[3];
    r.averageInternalReflectance = out[4];
    r.filmReflectance = out[5];
    r.redDiffuse = out[6];
    r.redTotal = out[7];
  }
  return results;
}

}  // namespace hydrotex::gpu
