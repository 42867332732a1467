// SPDX-License-Identifier: Zlib
#include "GlRenderer.hpp"

#include <epoxy/gl.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "RenderMesh.hpp"
#include "RenderShaders.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"

namespace hydrotex::render {
namespace {

// A renderer shader with its `#include "NAME"` lines replaced by the library's embedded shader of
// that name (gpu/shaders, e.g. wet_shading.glsl): the demos draw with the very code users get.
Expected<std::string> shaderText(std::string_view name) {
  const std::string_view text = renderShader(name);
  if (text.empty()) return Error{"renderer: shader " + std::string(name) + " is not embedded"};
  std::string out;
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(at, end - at);
    constexpr std::string_view directive = "#include \"";
    if (line.rfind(directive, 0) == 0 && line.size() > directive.size() + 1 && line.back() == '"') {
      const std::string_view included = line.substr(directive.size(), line.size() - directive.size() - 1);
      const std::string_view body = gpu::embeddedShader(included);
      if (body.empty()) return Error{"renderer: " + std::string(name) + " includes " + std::string(included) + ", which is not embedded"};
      out += body;
    } else {
      out += line;
    }
    out += '\n';
    at = end + 1;
  }
  return out;
}

Expected<GLuint> compileProgram(std::string_view vertexName, std::string_view fragmentName) {
  const GLuint program = glCreateProgram();
  for (const auto& [name, kind] : {std::pair{vertexName, GLenum(GL_VERTEX_SHADER)}, std::pair{fragmentName, GLenum(GL_FRAGMENT_SHADER)}}) {
    Expected<std::string> resolved = shaderText(name);
    if (!resolved) return resolved.error();
    const std::string& text = *resolved;
    const GLuint shader = glCreateShader(kind);
    const GLchar* source = text.data();
    const GLint length = static_cast<GLint>(text.size());
    glShaderSource(shader, 1, &source, &length);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[2048] = {};
      glGetShaderInfoLog(shader, sizeof log, nullptr, log);
      return Error{"renderer: " + std::string(name) + " does not compile: " + log};
    }
    glAttachShader(program, shader);
    glDeleteShader(shader);
  }
  glLinkProgram(program);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    return Error{"renderer: " + std::string(vertexName) + " + " + std::string(fragmentName) + " do not link: " + log};
  }
  return program;
}

// Colour images are sRGB encoded; data maps (overlays) are linear levels.
GLuint makeTexture(const RgbImage& image, bool srgb) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // Row 0 of the image is the top (v = 1): upload bottom-up so that GL's t matches v.
  std::vector<std::uint8_t> flipped(image.pixels.size());
  const std::size_t row = static_cast<std::size_t>(image.width) * 3;
  for (int y = 0; y < image.height; ++y)
    std::copy_n(image.pixels.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(image.height - 1 - y)), row,
                flipped.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y)));
  glTexImage2D(GL_TEXTURE_2D, 0, srgb ? GL_SRGB8 : GL_RGB8, image.width, image.height, 0, GL_RGB, GL_UNSIGNED_BYTE, flipped.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return texture;
}

RgbImage solid(std::uint8_t r, std::uint8_t g, std::uint8_t b) { return {1, 1, {r, g, b}}; }

void setMatrix(GLuint program, const char* name, const Eigen::Matrix4f& m) {
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, m.data());
}
void setVector(GLuint program, const char* name, const Eigen::Vector3d& v) {
  glUniform3f(glGetUniformLocation(program, name), float(v.x()), float(v.y()), float(v.z()));
}

}  // namespace

struct GlRenderer::Impl {
  struct Body {
    GLuint vertexArray = 0, buffer = 0, albedo = 0, overlay = 0, wetness = 0;
    int wetnessWidth = 0, wetnessHeight = 0;
    Eigen::Vector3f pigmentTransmittance = Eigen::Vector3f::Ones();
    GLsizei vertexCount = 0;
    Palette palette = Palette::Heat;
  };
  GLuint skyProgram = 0, bodyProgram = 0, shadowProgram = 0, waterProgram = 0, lineProgram = 0;
  GLuint emptyVertexArray = 0;
  GLuint msFramebuffer = 0, msColour = 0, msDepth = 0;
  GLuint resolveFramebuffer = 0, resolveColour = 0;
  GLuint shadowFramebuffer = 0, shadowDepth = 0;
  GLuint waterVertexArray = 0, waterBuffer = 0, waterIndices = 0;
  GLsizei waterIndexCount = 0;
  GLuint lineVertexArray = 0, lineBuffer = 0;
  std::vector<Body> bodies;

  ~Impl() {
    for (Body& b : bodies) {
      glDeleteVertexArrays(1, &b.vertexArray);
      glDeleteBuffers(1, &b.buffer);
      glDeleteTextures(1, &b.albedo);
      if (b.overlay) glDeleteTextures(1, &b.overlay);
      if (b.wetness) glDeleteTextures(1, &b.wetness);
    }
    for (GLuint p : {skyProgram, bodyProgram, shadowProgram, waterProgram, lineProgram}) glDeleteProgram(p);
    glDeleteVertexArrays(1, &emptyVertexArray);
    glDeleteVertexArrays(1, &waterVertexArray);
    glDeleteVertexArrays(1, &lineVertexArray);
    for (GLuint b : {waterBuffer, waterIndices, lineBuffer}) glDeleteBuffers(1, &b);
    for (GLuint f : {msFramebuffer, resolveFramebuffer, shadowFramebuffer}) glDeleteFramebuffers(1, &f);
    for (GLuint r : {msColour, msDepth, resolveColour}) glDeleteRenderbuffers(1, &r);
    glDeleteTextures(1, &shadowDepth);
  }
};

GlRenderer::GlRenderer(const RendererSettings& settings) : settings_(settings), impl_(std::make_unique<Impl>()) {}
GlRenderer::~GlRenderer() = default;

Expected<std::unique_ptr<GlRenderer>> GlRenderer::create(const RendererSettings& settings) {
  if (settings.width < 16 || settings.height < 16 || settings.width > 8192 || settings.height > 8192)
    return Error{"renderer: picture size " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                 " is outside 16..8192"};
  if (settings.waterGridCells < 2 || settings.waterGridCells > 2048 || !(settings.waterHalfExtent > 0.0))
    return Error{"renderer: water grid needs 2..2048 cells and a positive extent"};
  std::unique_ptr<GlRenderer> renderer(new GlRenderer(settings));
  Impl& gl = *renderer->impl_;
  const std::pair<const char*, const char*> programs[] = {
      {"sky.vert", "sky.frag"}, {"body.vert", "body.frag"}, {"shadow.vert", "shadow.frag"}, {"water.vert", "water.frag"}, {"line.vert", "line.frag"}};
  GLuint* slots[] = {&gl.skyProgram, &gl.bodyProgram, &gl.shadowProgram, &gl.waterProgram, &gl.lineProgram};
  for (int i = 0; i < 5; ++i) {
    Expected<GLuint> program = compileProgram(programs[i].first, programs[i].second);
    if (!program) return program.error();
    *slots[i] = *program;
  }
  glGenVertexArrays(1, &gl.emptyVertexArray);

  // Multisampled scene target, resolved into a plain one for reading back.
  GLint maxSamples = 0;
  glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
  const GLsizei samples = std::clamp(settings.samples, 0, maxSamples);
  glGenFramebuffers(1, &gl.msFramebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl.msFramebuffer);
  glGenRenderbuffers(1, &gl.msColour);
  glBindRenderbuffer(GL_RENDERBUFFER, gl.msColour);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_SRGB8_ALPHA8, settings.width, settings.height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, gl.msColour);
  glGenRenderbuffers(1, &gl.msDepth);
  glBindRenderbuffer(GL_RENDERBUFFER, gl.msDepth);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, settings.width, settings.height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, gl.msDepth);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return Error{"renderer: scene framebuffer incomplete"};
  glGenFramebuffers(1, &gl.resolveFramebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl.resolveFramebuffer);
  glGenRenderbuffers(1, &gl.resolveColour);
  glBindRenderbuffer(GL_RENDERBUFFER, gl.resolveColour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_SRGB8_ALPHA8, settings.width, settings.height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, gl.resolveColour);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return Error{"renderer: resolve framebuffer incomplete"};

  // Shadow map: a depth texture compared in the shader (sampler2DShadow).
  glGenTextures(1, &gl.shadowDepth);
  glBindTexture(GL_TEXTURE_2D, gl.shadowDepth);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, settings.shadowMapSize, settings.shadowMapSize, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glGenFramebuffers(1, &gl.shadowFramebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl.shadowFramebuffer);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, gl.shadowDepth, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) return Error{"renderer: shadow framebuffer incomplete"};

  // Water grid: positions and normals rewritten every frame, indices fixed.
  const int n = settings.waterGridCells;
  std::vector<GLuint> indices;
  indices.reserve(static_cast<std::size_t>(n) * n * 6);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const GLuint a = GLuint(j * (n + 1) + i), b = a + 1, c = a + GLuint(n + 1), d = c + 1;
      indices.insert(indices.end(), {a, c, b, b, c, d});
    }
  gl.waterIndexCount = static_cast<GLsizei>(indices.size());
  glGenVertexArrays(1, &gl.waterVertexArray);
  glBindVertexArray(gl.waterVertexArray);
  glGenBuffers(1, &gl.waterBuffer);
  glBindBuffer(GL_ARRAY_BUFFER, gl.waterBuffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(sizeof(float) * 6 * std::size_t(n + 1) * std::size_t(n + 1)), nullptr, GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  glGenBuffers(1, &gl.waterIndices);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gl.waterIndices);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(GLuint)), indices.data(), GL_STATIC_DRAW);

  glGenVertexArrays(1, &gl.lineVertexArray);
  glBindVertexArray(gl.lineVertexArray);
  glGenBuffers(1, &gl.lineBuffer);
  glBindBuffer(GL_ARRAY_BUFFER, gl.lineBuffer);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  glBindVertexArray(0);
  if (const GLenum error = glGetError(); error != GL_NO_ERROR) return Error{"renderer: GL error " + std::to_string(error) + " while setting up"};
  return renderer;
}

Expected<int> GlRenderer::addBody(const Mesh& mesh, const RgbImage* albedo, const RgbImage* overlay, Palette palette,
                                  const UvLayout* physicsLayout) {
  const std::vector<RenderVertex> vertices = unrollMesh(mesh, 40.0, physicsLayout);
  if (vertices.empty()) return Error{"renderer: mesh " + mesh.sourceName + " has no triangles"};
  Impl::Body body;
  body.vertexCount = static_cast<GLsizei>(vertices.size());
  body.palette = palette;
  glGenVertexArrays(1, &body.vertexArray);
  glBindVertexArray(body.vertexArray);
  glGenBuffers(1, &body.buffer);
  glBindBuffer(GL_ARRAY_BUFFER, body.buffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(RenderVertex)), vertices.data(), GL_STATIC_DRAW);
  // position, normal, uv, physicsUv
  constexpr GLint sizes[] = {3, 3, 2, 2};
  constexpr std::size_t offsets[] = {0, 3, 6, 8};
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, sizes[a], GL_FLOAT, GL_FALSE, sizeof(RenderVertex), reinterpret_cast<void*>(offsets[a] * sizeof(float)));
  }
  glBindVertexArray(0);
  body.albedo = makeTexture(albedo != nullptr && !albedo->pixels.empty() ? *albedo : solid(200, 200, 200), true);
  if (overlay != nullptr && !overlay->pixels.empty()) {
    body.overlay = makeTexture(*overlay, false);
  }
  impl_->bodies.push_back(body);
  return static_cast<int>(impl_->bodies.size()) - 1;
}

Status GlRenderer::setBodyMesh(int body, const Mesh& mesh) {
  if (body < 0 || body >= static_cast<int>(impl_->bodies.size())) return Error{"renderer: no body " + std::to_string(body)};
  const std::vector<RenderVertex> vertices = unrollMesh(mesh, 40.0);
  if (vertices.empty()) return Error{"renderer: mesh " + mesh.sourceName + " has no triangles"};
  Impl::Body& b = impl_->bodies[static_cast<std::size_t>(body)];
  glBindBuffer(GL_ARRAY_BUFFER, b.buffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(RenderVertex)), vertices.data(), GL_DYNAMIC_DRAW);
  b.vertexCount = static_cast<GLsizei>(vertices.size());
  return Ok{};
}

Status GlRenderer::setAlbedo(int body, const RgbImage& albedo) {
  if (body < 0 || body >= static_cast<int>(impl_->bodies.size())) return Error{"renderer: no body " + std::to_string(body)};
  glDeleteTextures(1, &impl_->bodies[static_cast<std::size_t>(body)].albedo);
  impl_->bodies[static_cast<std::size_t>(body)].albedo = makeTexture(albedo, true);
  return Ok{};
}

Status GlRenderer::setWetness(int body, int width, int height, const std::vector<float>& wetness,
                              const Eigen::Vector3f& pigmentTransmittance) {
  if (body < 0 || body >= static_cast<int>(impl_->bodies.size())) return Error{"renderer: no body " + std::to_string(body)};
  if (width < 1 || height < 1 || wetness.size() != 2 * std::size_t(width) * std::size_t(height))
    return Error{"renderer: wetness of body " + std::to_string(body) + " has " + std::to_string(wetness.size()) + " values for 2 x " +
                 std::to_string(width) + "x" + std::to_string(height)};
  Impl::Body& b = impl_->bodies[static_cast<std::size_t>(body)];
  if (b.wetness == 0 || b.wetnessWidth != width || b.wetnessHeight != height) {
    if (b.wetness) glDeleteTextures(1, &b.wetness);
    glGenTextures(1, &b.wetness);
    glBindTexture(GL_TEXTURE_2D, b.wetness);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RG16F, width, height, 0, GL_RG, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    b.wetnessWidth = width;
    b.wetnessHeight = height;
  }
  // Bake row 0 is v = 1, GL's first row is t = 0: upload bottom-up.
  b.pigmentTransmittance = pigmentTransmittance;
  std::vector<float> flipped(wetness.size());
  const std::size_t row = 2 * std::size_t(width);
  for (int y = 0; y < height; ++y)
    std::copy_n(wetness.begin() + static_cast<std::ptrdiff_t>(row * std::size_t(height - 1 - y)), row,
                flipped.begin() + static_cast<std::ptrdiff_t>(row * std::size_t(y)));
  glBindTexture(GL_TEXTURE_2D, b.wetness);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RG, GL_FLOAT, flipped.data());
  return Ok{};
}

Expected<RgbImage> GlRenderer::render(const FrameInput& frame) {
  Impl& gl = *impl_;
  const int width = settings_.width, height = settings_.height;
  const Eigen::Matrix4f viewProjection = frame.camera.projection(double(width) / height) * frame.camera.view();
  const Eigen::Matrix4f light = lightViewProjection(frame.sunDirection, frame.shadowCentre, frame.shadowRadius);
  for (const BodyInstance& instance : frame.bodies)
    if (instance.body < 0 || instance.body >= static_cast<int>(gl.bodies.size()))
      return Error{"renderer: frame names unknown body " + std::to_string(instance.body)};

  // 1. Shadow map.
  glBindFramebuffer(GL_FRAMEBUFFER, gl.shadowFramebuffer);
  glViewport(0, 0, settings_.shadowMapSize, settings_.shadowMapSize);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glClear(GL_DEPTH_BUFFER_BIT);
  glUseProgram(gl.shadowProgram);
  setMatrix(gl.shadowProgram, "lightViewProjection", light);
  for (const BodyInstance& instance : frame.bodies) {
    const Impl::Body& body = gl.bodies[static_cast<std::size_t>(instance.body)];
    setMatrix(gl.shadowProgram, "model", instance.model);
    glBindVertexArray(body.vertexArray);
    glDrawArrays(GL_TRIANGLES, 0, body.vertexCount);
  }

  // 2. Sky (and the deep water below the horizon).
  glBindFramebuffer(GL_FRAMEBUFFER, gl.msFramebuffer);
  glViewport(0, 0, width, height);
  glEnable(GL_FRAMEBUFFER_SRGB);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glDisable(GL_DEPTH_TEST);
  glUseProgram(gl.skyProgram);
  setMatrix(gl.skyProgram, "inverseViewProjection", viewProjection.inverse());
  setVector(gl.skyProgram, "sunDirection", frame.sunDirection);
  glBindVertexArray(gl.emptyVertexArray);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  // 3. Bodies.
  glEnable(GL_DEPTH_TEST);
  glUseProgram(gl.bodyProgram);
  setMatrix(gl.bodyProgram, "viewProjection", viewProjection);
  setMatrix(gl.bodyProgram, "lightViewProjection", light);
  setVector(gl.bodyProgram, "sunDirection", frame.sunDirection);
  setVector(gl.bodyProgram, "eye", frame.camera.eye);
  glUniform1i(glGetUniformLocation(gl.bodyProgram, "albedoMap"), 0);
  glUniform1i(glGetUniformLocation(gl.bodyProgram, "overlayMap"), 1);
  glUniform1i(glGetUniformLocation(gl.bodyProgram, "shadowMap"), 2);
  glUniform1i(glGetUniformLocation(gl.bodyProgram, "wetnessMap"), 3);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, gl.shadowDepth);
  for (const BodyInstance& instance : frame.bodies) {
    const Impl::Body& body = gl.bodies[static_cast<std::size_t>(instance.body)];
    setMatrix(gl.bodyProgram, "model", instance.model);
    const Eigen::Matrix3f normalMatrix = instance.model.topLeftCorner<3, 3>().inverse().transpose();
    glUniformMatrix3fv(glGetUniformLocation(gl.bodyProgram, "normalMatrix"), 1, GL_FALSE, normalMatrix.data());
    glUniform1f(glGetUniformLocation(gl.bodyProgram, "overlayOpacity"), body.overlay ? instance.overlayOpacity : 0.0f);
    glUniform1i(glGetUniformLocation(gl.bodyProgram, "palette"), static_cast<int>(body.palette));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, body.albedo);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, body.overlay ? body.overlay : body.albedo);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, body.wetness ? body.wetness : body.albedo);
    glUniform1i(glGetUniformLocation(gl.bodyProgram, "hasWetness"), body.wetness ? 1 : 0);
    glUniform3f(glGetUniformLocation(gl.bodyProgram, "pigmentTransmittance"), body.pigmentTransmittance.x(), body.pigmentTransmittance.y(),
                body.pigmentTransmittance.z());
    glUniform1f(glGetUniformLocation(gl.bodyProgram, "wetnessViewOpacity"), body.wetness ? instance.wetnessViewOpacity : 0.0f);
    glBindVertexArray(body.vertexArray);
    glDrawArrays(GL_TRIANGLES, 0, body.vertexCount);
  }

  // 4. Water: heights and normals from the surface itself (the same query the physics uses).
  if (frame.surface != nullptr && frame.surface->hasFreeSurface()) {
    const int n = settings_.waterGridCells;
    const double half = settings_.waterHalfExtent, spacing = 2.0 * half / n;
    const double cx = frame.camera.target.x(), cz = frame.camera.target.z();
    std::vector<double> heights(std::size_t(n + 1) * std::size_t(n + 1));
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        heights[std::size_t(j) * std::size_t(n + 1) + std::size_t(i)] =
            frame.surface->surfaceHeight(cx - half + i * spacing, cz - half + j * spacing, frame.time);
    std::vector<float> vertices;
    vertices.reserve(heights.size() * 6);
    auto h = [&](int i, int j) {
      return heights[std::size_t(std::clamp(j, 0, n)) * std::size_t(n + 1) + std::size_t(std::clamp(i, 0, n))];
    };
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const Eigen::Vector3d normal = Eigen::Vector3d(h(i - 1, j) - h(i + 1, j), 2.0 * spacing, h(i, j - 1) - h(i, j + 1)).normalized();
        vertices.insert(vertices.end(), {float(cx - half + i * spacing), float(h(i, j)), float(cz - half + j * spacing),
                                         float(normal.x()), float(normal.y()), float(normal.z())});
      }
    glBindBuffer(GL_ARRAY_BUFFER, gl.waterBuffer);
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data());
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(gl.waterProgram);
    setMatrix(gl.waterProgram, "viewProjection", viewProjection);
    setVector(gl.waterProgram, "eye", frame.camera.eye);
    setVector(gl.waterProgram, "sunDirection", frame.sunDirection);
    glUniform1f(glGetUniformLocation(gl.waterProgram, "fadeDistance"), float(half));
    glBindVertexArray(gl.waterVertexArray);
    glDrawElements(GL_TRIANGLES, gl.waterIndexCount, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_BLEND);
  }

  // 5. Overlay lines as camera-facing ribbons, on top of everything (forces inside a hull show).
  if (!frame.lines.empty()) {
    std::vector<float> vertices;
    vertices.reserve(frame.lines.size() * 36);
    const Eigen::Vector3f eye = frame.camera.eye.cast<float>();
    const float pixelAngle = float(frame.camera.verticalFovDegrees * 3.14159265358979 / 180.0 / height);
    for (const DebugLine& line : frame.lines) {
      const Eigen::Vector3f mid = 0.5f * (line.from + line.to), along = line.to - line.from;
      Eigen::Vector3f side = along.cross(eye - mid);
      if (side.norm() < 1e-9f) continue;
      side = side.normalized() * (1.5f * pixelAngle * (eye - mid).norm());  // about 3 pixels wide
      const Eigen::Vector3f corners[6] = {line.from - side, line.from + side, line.to + side,
                                          line.from - side, line.to + side, line.to - side};
      for (const Eigen::Vector3f& c : corners) vertices.insert(vertices.end(), {c.x(), c.y(), c.z(), line.colour.x(), line.colour.y(), line.colour.z()});
    }
    glDisable(GL_DEPTH_TEST);
    glUseProgram(gl.lineProgram);
    setMatrix(gl.lineProgram, "viewProjection", viewProjection);
    glBindVertexArray(gl.lineVertexArray);
    glBindBuffer(GL_ARRAY_BUFFER, gl.lineBuffer);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data(), GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size() / 6));
    glEnable(GL_DEPTH_TEST);
  }
  glBindVertexArray(0);

  // 6. Resolve and read back (GL's rows are bottom-up).
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl.msFramebuffer);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, gl.resolveFramebuffer);
  glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, gl.resolveFramebuffer);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  std::vector<std::uint8_t> upsideDown(std::size_t(width) * std::size_t(height) * 3);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, upsideDown.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (const GLenum error = glGetError(); error != GL_NO_ERROR) return Error{"renderer: GL error " + std::to_string(error) + " while drawing"};
  RgbImage image{width, height, std::vector<std::uint8_t>(upsideDown.size())};
  const std::size_t row = std::size_t(width) * 3;
  for (int y = 0; y < height; ++y)
    std::copy_n(upsideDown.begin() + static_cast<std::ptrdiff_t>(row * std::size_t(height - 1 - y)), row,
                image.pixels.begin() + static_cast<std::ptrdiff_t>(row * std::size_t(y)));
  return image;
}

}  // namespace hydrotex::render
