// SPDX-License-Identifier: Zlib
/// @file GlWetting.cpp
/// The liquid texture step on the GPU: wetting_exchange.comp for absorption, sources and
/// evaporation (the per-step constants are those Wetting::prepareExchange forms, in float), then
/// GlWettingDiffusion's sub-steps on the same resident liquid.

#include "hydrotex/gpu/GlWetting.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "GlObjects.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"
#include "hydrotex/gpu/GlWettingDiffusion.hpp"

namespace hydrotex::gpu {

using detail::GlBuffer;
using detail::GlProgram;

namespace {
constexpr std::size_t kGroupSize = 64;  // wetting_exchange.comp's local_size_x
}

struct GlWetting::Impl {
  std::unique_ptr<GlWettingDiffusion> diffusion;
  GlProgram program;
  GlBuffer material, pressure, geometry, submerged, partials;
  std::vector<float> partialsHost;  // per work group: absorbed, evaporated (m^3), submerged texels
  // Under a surface that is not flat the host evaluates the pressure per texel, as the CPU does:
  // the centroids as Wetting keeps them, one array per coordinate, and scratch for the pass.
  std::vector<float> px, py, pz, pressureHost;
  std::vector<std::uint8_t> underHost;
};

GlWetting::GlWetting(const EglContext& context) : context_(context), impl_(std::make_unique<Impl>()) {}

GlWetting::~GlWetting() {
  if (!context_.makeCurrent()) (void)impl_.release();  // no context: leak the names rather than touch another one
}

Expected<std::unique_ptr<GlWetting>> GlWetting::create(const EglContext& context, const TexelAdjacency& adjacency,
                                                       const SurfaceTextures& textures, const WettingSettings& settings) {
  const std::size_t n = adjacency.area.size();
  if (textures.size() != n || adjacency.centroid.size() != n)
    return Error{"gpu wetting: texel graph has " + std::to_string(n) + " texels, surface textures " +
                 std::to_string(textures.size())};
  auto diffusion = GlWettingDiffusion::create(context, adjacency, settings);
  if (!diffusion) return diffusion.error();
  if (Status s = context.makeCurrent(); !s) return s.error();
  std::unique_ptr<GlWetting> out(new GlWetting(context));
  Impl& impl = *out->impl_;
  impl.diffusion = std::move(diffusion).value();
  Expected<GlProgram> program = GlProgram::compute(
      "wetting_exchange.comp", {"#version 430 core\n", embeddedShader("wetting_exchange.comp")});
  if (!program) return Error{"gpu wetting: " + program.error().message};
  impl.program = std::move(program).value();
  // The same float centroids and unit normals as Wetting::create (the areas are the diffusion's),
  // centroid and normal of a texel side by side in one buffer (the pass uses eight storage
  // blocks, GL 4.3's minimum).
  std::vector<float> geometry(6 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const float norm = textures.areaVector[i].norm();
    const Eigen::Vector3f unit = norm > 0.0f ? Eigen::Vector3f(textures.areaVector[i] / norm) : Eigen::Vector3f::Zero();
    for (int k = 0; k < 3; ++k) {
      geometry[6 * i + k] = static_cast<float>(adjacency.centroid[i][k]);
      geometry[6 * i + 3 + k] = unit[k];
    }
  }
  auto upload = [](const std::vector<float>& items) {
    GlBuffer buffer(items.size() * sizeof(float));
    buffer.write(0, items.data(), items.size() * sizeof(float));
    return buffer;
  };
  impl.geometry = upload(geometry);
  impl.px.resize(n);
  impl.py.resize(n);
  impl.pz.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    impl.px[i] = geometry[6 * i];
    impl.py[i] = geometry[6 * i + 1];
    impl.pz[i] = geometry[6 * i + 2];
  }
  impl.material = GlBuffer(2 * n * sizeof(float));
  impl.pressure = GlBuffer(n * sizeof(float));
  impl.submerged = GlBuffer(n * sizeof(std::uint32_t));
  const std::vector<std::uint32_t> dry(n, 0u);
  impl.submerged.write(0, dry.data(), n * sizeof(std::uint32_t));
  const std::size_t groups = (n + kGroupSize - 1) / kGroupSize;
  impl.partials = GlBuffer(3 * groups * sizeof(float));
  impl.partialsHost.resize(3 * groups);
  out->texelCount_ = n;
  out->settings_ = settings;
  return out;
}

Status GlWetting::upload(const LiquidTexture& texture) {
  const std::size_t n = texelCount_;
  if (texture.liquid.size() != n || texture.capacity.size() != n || texture.permeability.size() != n)
    return Error{"gpu wetting: liquid texture has " + std::to_string(texture.liquid.size()) + " texels, the graph " +
                 std::to_string(n)};
  if (!(texture.layerThickness > 0.0 && std::isfinite(texture.layerThickness)))
    return Error{"gpu wetting: layer thickness " + std::to_string(texture.layerThickness) + " m is not positive"};
  if (Status s = impl_->diffusion->upload(texture); !s) return s;
  // Capacity and permeability side by side (the pass uses eight storage blocks, GL 4.3's minimum).
  std::vector<float> material(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    material[2 * i] = texture.capacity[i];
    material[2 * i + 1] = texture.permeability[i];
  }
  impl_->material.write(0, material.data(), material.size() * sizeof(float));
  layerThickness_ = texture.layerThickness;
  uploaded_ = true;
  return Ok{};
}

Expected<WettingStepReport> GlWetting::step(const WettingEnvironment& environment, double dt) {
  if (Status s = checkWettingStep(environment, dt); !s) return s.error();
  if (!uploaded_) return Error{"gpu wetting: no liquid texture uploaded"};
  const auto* flat = dynamic_cast<const FlatSurface*>(environment.liquid);
  std::vector<const LiquidSource*> sources;
  for (const LiquidSource& source : environment.sources)
    if (source.rate > 0.0) sources.push_back(&source);
  if (sources.size() > static_cast<std::size_t>(kMaxSources))
    return Error{"gpu wetting: " + std::to_string(sources.size()) + " liquid sources, at most " +
                 std::to_string(kMaxSources) + " on the GPU"};
  if (Status s = context_.makeCurrent(); !s) return s.error();

  Impl& impl = *impl_;
  const bool hostPressure = environment.liquid && !flat;
  if (hostPressure) {
    // Waves, a height grid or a medium: the CPU's per-texel pass, uploaded as the pressure under
    // the liquid and -1 in the air.
    const std::size_t n = texelCount_;
    impl.pressureHost.resize(n);
    impl.underHost.resize(n);
    liquidPressureAtTexels(*environment.liquid, environment, impl.px.data(), impl.py.data(), impl.pz.data(), n,
                           impl.pressureHost.data(), impl.underHost.data());
    for (std::size_t i = 0; i < n; ++i)
      if (!impl.underHost[i]) impl.pressureHost[i] = -1.0f;
    impl.pressure.write(0, impl.pressureHost.data(), n * sizeof(float));
  }
  const Eigen::Matrix3d& rotation = environment.pose.rotation;
  const Eigen::Vector3d& translation = environment.pose.translation;
  const GLuint id = impl.program.id();
  glUseProgram(id);
  impl.diffusion->bindLiquid(0);
  impl.material.bind(1);
  impl.pressure.bind(2);
  impl.diffusion->bindArea(3);
  impl.geometry.bind(4);
  const bool withPigment = impl.diffusion->bindPigment(5);
  impl.submerged.bind(6);
  impl.partials.bind(7);
  glUniform1ui(impl.program.uniform("texelCount"), static_cast<GLuint>(texelCount_));
  glUniform1i(impl.program.uniform("absorbing"), 1);
  glUniform1i(impl.program.uniform("withLiquid"), environment.liquid ? 1 : 0);
  glUniform1i(impl.program.uniform("hostPressure"), hostPressure ? 1 : 0);
  glUniform4f(impl.program.uniform("heightRow"), static_cast<float>(rotation(1, 0)), static_cast<float>(rotation(1, 1)),
              static_cast<float>(rotation(1, 2)), static_cast<float>(translation.y() - (flat ? flat->height() : 0.0)));
  glUniform1f(impl.program.uniform("pressurePerDepth"), flat ? static_cast<float>(flat->density() * environment.gravity) : 0.0f);
  glUniform1f(impl.program.uniform("capillary"), static_cast<float>(settings_.capillaryPressure));
  glUniform1f(impl.program.uniform("darcyFactor"), static_cast<float>(dt / (settings_.viscosity * layerThickness_)));
  const double rate = dt > 0.0 ? settings_.evaporationRate() : 0.0;
  glUniform1f(impl.program.uniform("evaporationDepth"), static_cast<float>(rate * dt));
  glUniform1f(impl.program.uniform("criticalSaturation"), static_cast<float>(settings_.criticalSaturation));
  glUniform1i(impl.program.uniform("sourceCount"), static_cast<GLint>(sources.size()));
  glUniform1i(impl.program.uniform("withPigment"), withPigment ? 1 : 0);
  for (std::size_t s = 0; s < sources.size(); ++s) {
    const LiquidSource& source = *sources[s];
    auto location = [&](const char* array) {
      std::string name(array);
      name += '[';
      name += std::to_string(s);
      name += ']';
      return impl.program.uniform(name.c_str());
    };
    // Body frame, as Wetting::prepareExchange: rain as the unit vector against its fall, a
    // sphere by its centre.
    const Eigen::Vector3d fall = source.direction.norm() > 0.0 ? source.direction.normalized() : Eigen::Vector3d(0.0, -1.0, 0.0);
    const bool rain = source.kind == LiquidSourceKind::Rain;
    const Eigen::Vector3f vector =
        (rain ? Eigen::Vector3d(-(rotation.transpose() * fall)) : Eigen::Vector3d(rotation.transpose() * (source.centre - translation)))
            .cast<float>();
    glUniform1i(location("sourceRain"), rain ? 1 : 0);
    glUniform3f(location("sourceVector"), vector.x(), vector.y(), vector.z());
    glUniform1f(location("sourceRadiusSquared"), static_cast<float>(source.radius * source.radius));
    glUniform1f(location("sourceDepth"), static_cast<float>(source.rate * dt));
    glUniform1f(location("sourcePigment"), static_cast<float>(source.pigment));
  }
  const auto groups = static_cast<GLuint>((texelCount_ + kGroupSize - 1) / kGroupSize);
  const GLuint x = std::min<GLuint>(std::max<GLuint>(groups, 1u), 65535u);
  glDispatchCompute(x, (groups + x - 1) / x, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);

  WettingStepReport report;
  Expected<int> diffused = impl.diffusion->diffuse(dt);
  if (!diffused) return diffused.error();
  report.diffusionSubsteps = *diffused;
  report.implicitDiffusion = diffusionSubsteps(dt, impl.diffusion->stableTimeStep(), settings_.maxExplicitSubsteps) < 0;
  impl.partials.read(0, impl.partialsHost.data(), impl.partialsHost.size() * sizeof(float));
  double submerged = 0.0;
  for (std::size_t g = 0; g < groups; ++g) {
    report.absorbed += impl.partialsHost[3 * g];
    report.evaporated += impl.partialsHost[3 * g + 1];
    submerged += impl.partialsHost[3 * g + 2];
  }
  report.submergedTexels = static_cast<std::size_t>(std::llround(submerged));
  if (const GLenum error = glGetError(); error != GL_NO_ERROR)
    return Error{"gpu wetting: OpenGL error " + std::to_string(error)};
  return report;
}

Status GlWetting::download(LiquidTexture& texture) const { return impl_->diffusion->download(texture); }

double GlWetting::stableTimeStep() const { return impl_->diffusion->stableTimeStep(); }

}  // namespace hydrotex::gpu
