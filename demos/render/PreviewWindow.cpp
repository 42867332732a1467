// SPDX-License-Identifier: Zlib
#include "PreviewWindow.hpp"

// epoxy's gl.h must come first: GLFW_INCLUDE_NONE keeps GLFW from including the system GL headers,
// which would clash with it.
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace hydrotex::render {
namespace {

std::string& lastGlfwError() {
  static std::string error;
  return error;
}

void recordGlfwError(int /*code*/, const char* description) { lastGlfwError() = description != nullptr ? description : "unknown error"; }

void closeOnEscape(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(window, GLFW_TRUE);
}

bool hasDisplay() {
  for (const char* variable : {"DISPLAY", "WAYLAND_DISPLAY"})
    if (const char* value = std::getenv(variable); value != nullptr && *value != '\0') return true;
  return false;
}

}  // namespace

Expected<std::unique_ptr<PreviewWindow>> PreviewWindow::open(const PreviewWindowSettings& settings) {
  // Checked first: GLFW's own message for this case depends on its version and platform.
  if (!hasDisplay()) return Error{"no display: neither DISPLAY nor WAYLAND_DISPLAY is set (drop --window, or run under xvfb-run)"};
  if (settings.width <= 0 || settings.height <= 0) return Error{"window size must be positive"};
  glfwSetErrorCallback(recordGlfwError);
  if (glfwInit() != GLFW_TRUE) return Error{"glfwInit failed: " + lastGlfwError()};
  std::unique_ptr<PreviewWindow> preview(new PreviewWindow());  // from here the destructor cleans up
  preview->readBack_ = settings.readBack;
  // GL 3.3 core: the picture is shown with glBlitFramebuffer, no shaders needed.
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  preview->window_ = glfwCreateWindow(settings.width, settings.height, settings.title.c_str(), nullptr, nullptr);
  if (preview->window_ == nullptr) return Error{"no window with an OpenGL 3.3 core context: " + lastGlfwError()};
  glfwSetKeyCallback(preview->window_, closeOnEscape);
  glfwMakeContextCurrent(preview->window_);
  glfwSwapInterval(0);  // never wait for the display: the demo's pace is the simulation's
  glGenTextures(1, &preview->texture_);
  glBindTexture(GL_TEXTURE_2D, preview->texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glGenFramebuffers(1, &preview->framebuffer_);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glfwSwapBuffers(preview->window_);
  glfwMakeContextCurrent(nullptr);
  glfwPollEvents();
  return preview;
}

PreviewWindow::~PreviewWindow() {
  // Destroying the window destroys its context and with it the texture and framebuffer.
  if (window_ != nullptr) glfwDestroyWindow(window_);
  glfwTerminate();
  glfwSetErrorCallback(nullptr);
}

Expected<bool> PreviewWindow::show(const RgbImage& picture, const std::string& title) {
  glfwMakeContextCurrent(window_);
  if (glfwGetCurrentContext() != window_) return Error{"window: its GL context cannot be made current: " + lastGlfwError()};
  glfwSetWindowTitle(window_, title.c_str());
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);  // pixels; differs from the window's on HiDPI screens
  glBindTexture(GL_TEXTURE_2D, texture_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // rows of 3 * width bytes, not padded to 4
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, picture.width, picture.height, 0, GL_RGB, GL_UNSIGNED_BYTE, picture.pixels.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  // The picture's row 0 (its top) went in as the texture's row 0, which GL puts at the bottom:
  // the destination's y range is given top to bottom to turn it right side up.
  const bool sameSize = width == picture.width && height == picture.height;
  glBlitFramebuffer(0, 0, picture.width, picture.height, 0, height, width, 0, GL_COLOR_BUFFER_BIT, sameSize ? GL_NEAREST : GL_LINEAR);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  if (readBack_) {
    drawn_ = RgbImage{width, height, std::vector<std::uint8_t>(std::size_t(width) * std::size_t(height) * 3)};
    std::vector<std::uint8_t> upsideDown(drawn_.pixels.size());
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, upsideDown.data());
    const std::size_t row = std::size_t(width) * 3;
    for (int y = 0; y < height; ++y)
      std::copy_n(upsideDown.begin() + std::ptrdiff_t(row * std::size_t(height - 1 - y)), row,
                  drawn_.pixels.begin() + std::ptrdiff_t(row * std::size_t(y)));
  }
  const GLenum glError = glGetError();
  glfwSwapBuffers(window_);
  glfwMakeContextCurrent(nullptr);
  glfwPollEvents();
  if (glError != GL_NO_ERROR) {
    char text[64];
    std::snprintf(text, sizeof text, "window: drawing the picture failed (GL error 0x%04x)", unsigned(glError));
    return Error{text};
  }
  return glfwWindowShouldClose(window_) == GLFW_FALSE;
}

}  // namespace hydrotex::render
