// SPDX-License-Identifier: Zlib
#pragma once
/// @file GlObjects.hpp
/// Private to hydrotex::gpu: owning handles for GL buffers and compute programs. They must be
/// destroyed while their context is current (GlBackend keeps it so).

#include <epoxy/gl.h>

#include <string>
#include <string_view>
#include <vector>

#include "hydrotex/Expected.hpp"

namespace hydrotex::gpu::detail {

/// A GL buffer object of a fixed size (bytes), storage for compute passes.
class GlBuffer {
 public:
  GlBuffer() = default;
  /// Allocates `bytes` (GL_DYNAMIC_DRAW; contents undefined).
  explicit GlBuffer(std::size_t bytes) : bytes_(bytes) {
    glGenBuffers(1, &id_);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
    glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(bytes > 0 ? bytes : 4), nullptr, GL_DYNAMIC_DRAW);
  }
  ~GlBuffer() {
    if (id_ != 0) glDeleteBuffers(1, &id_);
  }
  GlBuffer(GlBuffer&& other) noexcept : id_(other.id_), bytes_(other.bytes_) { other.id_ = 0; }
  GlBuffer& operator=(GlBuffer&& other) noexcept {
    if (this != &other) {
      if (id_ != 0) glDeleteBuffers(1, &id_);
      id_ = other.id_;
      bytes_ = other.bytes_;
      other.id_ = 0;
    }
    return *this;
  }
  GlBuffer(const GlBuffer&) = delete;
  GlBuffer& operator=(const GlBuffer&) = delete;

  /// Copies `bytes` from `data` to byte `offset`.
  void write(std::size_t offset, const void* data, std::size_t bytes) const {
    if (bytes == 0) return;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
  }
  /// Copies `bytes` from byte `offset` to `data` (waits for the GPU).
  void read(std::size_t offset, void* data, std::size_t bytes) const {
    if (bytes == 0) return;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
  }
  /// Binds the whole buffer to storage binding `index`.
  void bind(GLuint index) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, index, id_); }
  /// Size in bytes.
  std::size_t bytes() const { return bytes_; }
  /// GL name (0 when empty).
  GLuint id() const { return id_; }

 private:
  GLuint id_ = 0;
  std::size_t bytes_ = 0;
};

/// A linked compute program.
class GlProgram {
 public:
  GlProgram() = default;
  ~GlProgram() {
    if (id_ != 0) glDeleteProgram(id_);
  }
  GlProgram(GlProgram&& other) noexcept : id_(other.id_) { other.id_ = 0; }
  GlProgram& operator=(GlProgram&& other) noexcept {
    if (this != &other) {
      if (id_ != 0) glDeleteProgram(id_);
      id_ = other.id_;
      other.id_ = 0;
    }
    return *this;
  }
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;

  /// Compiles and links one compute shader from the concatenated `parts`; the error holds `name`
  /// and the driver's log.
  static Expected<GlProgram> compute(std::string_view name, const std::vector<std::string_view>& parts) {
    std::vector<const GLchar*> texts;
    std::vector<GLint> lengths;
    for (std::string_view part : parts) {
      texts.push_back(part.data());
      lengths.push_back(static_cast<GLint>(part.size()));
    }
    const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(shader, static_cast<GLsizei>(texts.size()), texts.data(), lengths.data());
    glCompileShader(shader);
    GLint compiled = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
    if (!compiled) {
      const std::string log = shaderLog(shader, false);
      glDeleteShader(shader);
      return Error{std::string(name) + ": does not compile: " + log};
    }
    GlProgram program;
    program.id_ = glCreateProgram();
    glAttachShader(program.id_, shader);
    glLinkProgram(program.id_);
    glDeleteShader(shader);
    GLint linked = 0;
    glGetProgramiv(program.id_, GL_LINK_STATUS, &linked);
    if (!linked) return Error{std::string(name) + ": does not link: " + shaderLog(program.id_, true)};
    return program;
  }

  /// GL name.
  GLuint id() const { return id_; }
  /// Location of a uniform (-1 when the compiler dropped it).
  GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }

 private:
  static std::string shaderLog(GLuint object, bool isProgram) {
    GLint length = 0;
    if (isProgram)
      glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
    else
      glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
    if (isProgram)
      glGetProgramInfoLog(object, length, nullptr, log.data());
    else
      glGetShaderInfoLog(object, length, nullptr, log.data());
    for (char& c : log)
      if (c == '\n') c = ' ';
    while (!log.empty() && (log.back() == '\0' || log.back() == ' ')) log.pop_back();
    return log;
  }

  GLuint id_ = 0;
};

}  // namespace hydrotex::gpu::detail
