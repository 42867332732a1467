// SPDX-License-Identifier: Zlib
#pragma once
/// @file PreviewWindow.hpp
/// A GLFW window that shows a demo's frames as they are drawn (hydrotex_demo --window). It has its
/// own GL context (GLX on X11) and only copies finished pictures onto the screen: all drawing stays
/// in the headless EGL context, so the frames written are the same with or without a window.

#include <memory>
#include <string>

#include "GlRenderer.hpp"
#include "hydrotex/Expected.hpp"

struct GLFWwindow;

namespace hydrotex::render {

/// How the window is opened.
struct PreviewWindowSettings {
  int width = 640;                      ///< pixels: the picture's width; the window is made this wide
  int height = 360;                     ///< pixels: the picture's height
  std::string title = "hydrotex_demo";  ///< title until the first show()
  bool readBack = false;                ///< keep what each show() drew (drawnPicture()), for tests
};

/// One window on the display, with GLFW initialized for its lifetime (one at a time).
class PreviewWindow {
 public:
  /// Opens the window (shown, not resizable). Error saying why not: no display set, glfwInit
  /// failed, no window with a GL 3.3 core context; GLFW's own description is included.
  static Expected<std::unique_ptr<PreviewWindow>> open(const PreviewWindowSettings& settings);
  ~PreviewWindow();
  PreviewWindow(const PreviewWindow&) = delete;
  PreviewWindow& operator=(const PreviewWindow&) = delete;

  /// Shows `picture` (row 0 at the top) stretched over the window, sets the title and handles
  /// pending events. Call it with no GL context current (libglvnd does not let a GLX context be
  /// made current over an EGL one); it leaves none current either. Returns true while the window
  /// stays open, false once the user has closed it or pressed Esc (the caller then stops); error
  /// when the context cannot be made current or GL reports an error.
  Expected<bool> show(const RgbImage& picture, const std::string& title);

  /// What the last show() drew into the window, read back before the swap (row 0 at the top, the
  /// framebuffer's size); empty unless PreviewWindowSettings::readBack.
  const RgbImage& drawnPicture() const { return drawn_; }

 private:
  PreviewWindow() = default;
  GLFWwindow* window_ = nullptr;
  unsigned texture_ = 0;      // GLuint: the picture
  unsigned framebuffer_ = 0;  // GLuint: reads the picture for the blit
  bool readBack_ = false;
  RgbImage drawn_;
};

}  // namespace hydrotex::render
