// SPDX-License-Identifier: Zlib
/// @file EglContext.cpp
/// Headless EGL: EGL_EXT_platform_device first, EGL_MESA_platform_surfaceless second, GL core
/// context without a surface. Driver quirks handled here are marked "Quirk".

#include "hydrotex/gpu/EglContext.hpp"

#include <epoxy/egl.h>
#include <dlfcn.h>
#include <epoxy/gl.h>

#include <cstdio>
#include <cstring>
#include <optional>
#include <vector>

namespace hydrotex::gpu {

namespace {

std::string eglErrorName(EGLint code) {
  char text[32];
  std::snprintf(text, sizeof text, "EGL error 0x%04X", static_cast<unsigned>(code));
  return text;
}

bool hasExtension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t length = std::strlen(name);
  for (const char* at = std::strstr(list, name); at != nullptr; at = std::strstr(at + 1, name))
    if ((at == list || at[-1] == ' ') && (at[length] == ' ' || at[length] == '\0')) return true;
  return false;
}

struct Attempt {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
};

// Initializes `display` and makes a core context of the asked version current without a surface.
Expected<Attempt> openContext(EGLDisplay display, const EglContextSettings& settings) {
  if (display == EGL_NO_DISPLAY) return Error{"no display (" + eglErrorName(eglGetError()) + ")"};
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return Error{"eglInitialize failed (" + eglErrorName(eglGetError()) + ")"};
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  if (!hasExtension(extensions, "EGL_KHR_surfaceless_context"))
    return Error{"display lacks EGL_KHR_surfaceless_context"};
  if (!eglBindAPI(EGL_OPENGL_API)) return Error{"eglBindAPI(EGL_OPENGL_API) failed"};
  // A context needs no config when EGL_KHR_no_config_context is there (Mesa, NVIDIA); otherwise
  // any config that renders OpenGL will do, since nothing is ever drawn to a surface.
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!hasExtension(extensions, "EGL_KHR_no_config_context")) {
    const EGLint wanted[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_DONT_CARE, EGL_NONE};
    EGLint found = 0;
    if (!eglChooseConfig(display, wanted, &config, 1, &found) || found < 1)
      return Error{"no EGL config renders OpenGL"};
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, settings.majorVersion, EGL_CONTEXT_MINOR_VERSION,
                               settings.minorVersion, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT)
    return Error{"no OpenGL " + std::to_string(settings.majorVersion) + "." + std::to_string(settings.minorVersion) +
                 " core context (" + eglErrorName(eglGetError()) + ")"};
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    return Error{"eglMakeCurrent without a surface failed (" + eglErrorName(eglGetError()) + ")"};
  }
  return Attempt{display, context};
}

}  // namespace

Expected<std::unique_ptr<EglContext>> EglContext::create(const EglContextSettings& settings) {
  if (settings.majorVersion * 10 + settings.minorVersion < 43)
    return Error{"EGL context: OpenGL 4.3 or newer is needed for compute shaders"};
  // Quirk (libepoxy): epoxy dlopens libEGL on the first EGL call and abort()s when it is not
  // there; probing it first turns a machine without EGL into an Error instead of a crash.
  if (void* egl = dlopen("libEGL.so.1", RTLD_LAZY | RTLD_LOCAL); egl == nullptr)
    return Error{"EGL context: libEGL.so.1 cannot be loaded (no EGL installed)"};
  // Quirk (libepoxy 1.5): EGL 1.5 entry points such as eglGetPlatformDisplay cannot be resolved
  // before a display exists (epoxy learns the EGL version from a display), so the EXT client
  // extensions eglGetPlatformDisplayEXT and eglQueryDevicesEXT are used. A libEGL without any
  // vendor gives a null client extension string: that is the "no EGL" error.
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (client == nullptr) return Error{"EGL context: libEGL offers no client extensions (no EGL driver installed?)"};
  if (!hasExtension(client, "EGL_EXT_platform_base"))
    return Error{"EGL context: libEGL lacks EGL_EXT_platform_base (headless platforms need it)"};

  std::string tried;
  auto note = [&](const std::string& what, const std::string& why) {
    tried += (tried.empty() ? "" : "; ") + what + ": " + why;
  };
  std::optional<Attempt> opened;
  std::string platform;

  if (settings.tryDevicePlatform && hasExtension(client, "EGL_EXT_platform_device") &&
      hasExtension(client, "EGL_EXT_device_enumeration")) {
    EGLint count = 0;
    eglQueryDevicesEXT(0, nullptr, &count);
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count > 0 ? count : 0));
    if (count > 0) eglQueryDevicesEXT(count, devices.data(), &count);
    for (std::size_t i = 0; i < devices.size() && !opened; ++i) {
      Expected<Attempt> attempt =
          openContext(eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr), settings);
      if (attempt) {
        opened = *attempt;
        platform = "device";
      } else {
        note("device " + std::to_string(i), attempt.error().message);
      }
    }
    if (devices.empty()) note("device platform", "no EGL device");
  }
  if (!opened && settings.trySurfacelessPlatform && hasExtension(client, "EGL_MESA_platform_surfaceless")) {
    Expected<Attempt> attempt =
        openContext(eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr), settings);
    if (attempt) {
      opened = *attempt;
      platform = "surfaceless";
    } else {
      note("surfaceless", attempt.error().message);
    }
  }
  if (!opened) return Error{"EGL context: no headless OpenGL context (" + (tried.empty() ? std::string("no platform tried") : tried) + ")"};

  std::unique_ptr<EglContext> out(new EglContext());
  out->display_ = opened->display;
  out->context_ = opened->context;
  out->platform_ = platform;
  const auto text = [](GLenum name) {
    const GLubyte* value = glGetString(name);
    return value ? std::string(reinterpret_cast<const char*>(value)) : std::string();
  };
  out->renderer_ = text(GL_RENDERER);
  out->version_ = text(GL_VERSION);
  out->hasShaderFp64_ = epoxy_has_gl_extension("GL_ARB_gpu_shader_fp64");
  return out;
}

EglContext::~EglContext() {
  if (context_ == nullptr) return;
  auto display = static_cast<EGLDisplay>(display_);
  if (eglGetCurrentContext() == static_cast<EGLContext>(context_))
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display, static_cast<EGLContext>(context_));
  // Quirk: an EGLDisplay is one per platform and device for the whole process, shared by every
  // EglContext; eglTerminate would pull it from under the others (two backends in one test), so
  // it is left initialized and released at process exit.
}

Status EglContext::makeCurrent() const {
  auto display = static_cast<EGLDisplay>(display_);
  auto context = static_cast<EGLContext>(context_);
  if (eglGetCurrentContext() == context) return Ok{};
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
    return Error{"EGL context: eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")"};
  return Ok{};
}

Status EglContext::release() const {
  auto display = static_cast<EGLDisplay>(display_);
  if (eglGetCurrentContext() != static_cast<EGLContext>(context_)) return Ok{};
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT))
    return Error{"EGL context: releasing it failed (" + eglErrorName(eglGetError()) + ")"};
  return Ok{};
}

}  // namespace hydrotex::gpu
