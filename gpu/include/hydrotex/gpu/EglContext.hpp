// SPDX-License-Identifier: Zlib
#pragma once
/// @file EglContext.hpp
/// A headless OpenGL 4.3+ core context through EGL, with no window and no surface
/// (EGL_KHR_surfaceless_context). Context creation is apart from the GL backend (docs/design.md
/// "Magnum / Filament"): the backend takes a context that exists.

#include <memory>
#include <string>

#include "hydrotex/Expected.hpp"

namespace hydrotex::gpu {

/// Which EGL platforms to try, in order.
struct EglContextSettings {
  bool tryDevicePlatform = true;       ///< EGL_EXT_platform_device: a real GPU, no display server
  bool trySurfacelessPlatform = true;  ///< EGL_MESA_platform_surfaceless: Mesa (llvmpipe on CI)
  int majorVersion = 4;                ///< at least 4.3: compute shaders and storage buffers
  int minorVersion = 3;                ///< see majorVersion
};

/// An EGL display and GL context owned together; current on the thread that created it.
class EglContext {
 public:
  /// Opens a context: every EGL device first, then Mesa's surfaceless platform. Error (never a
  /// crash) naming what each attempt said when none gives a GL 4.3 core context, e.g. when libEGL
  /// has no usable driver; callers then use the CPU backend.
  static Expected<std::unique_ptr<EglContext>> create(const EglContextSettings& settings = {});

  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  /// Makes the context current on the calling thread. Error when EGL refuses.
  Status makeCurrent() const;
  /// Leaves the calling thread with no EGL context current (no-op when this one is not current),
  /// so that another window system's context (GLX, e.g. a GLFW window) can be made current:
  /// libglvnd refuses a context of a second API while one of the first is still current.
  Status release() const;
  /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  const std::string& renderer() const { return renderer_; }
  /// GL_VERSION, e.g. "4.5 (Core Profile) Mesa 22.3.6".
  const std::string& version() const { return version_; }
  /// "device" or "surfaceless": the EGL platform that gave the context.
  const std::string& platform() const { return platform_; }
  /// True when GL_ARB_gpu_shader_fp64 is there (the final reduction then runs on the GPU).
  bool hasShaderFp64() const { return hasShaderFp64_; }

 private:
  EglContext() = default;
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  std::string renderer_, version_, platform_;
  bool hasShaderFp64_ = false;
};

}  // namespace hydrotex::gpu
