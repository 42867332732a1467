// SPDX-License-Identifier: Zlib
#pragma once
/// @file DemoRunner.hpp
/// Runs a demo: simulates its scene headless, renders every frame (EGL, no display), writes the
/// PNG frames, an MP4 and a contact sheet, prints a progress bar and, at the end, the figures a
/// viewer wants (time simulated and taken, sink time, list angle, liquid held).

#include <functional>
#include <optional>
#include <string>

#include "DemoDescription.hpp"
#include "GlRenderer.hpp"

namespace hydrotex::render {

/// Exit status of a demo whose effect this build lacks (CTest's SKIP_RETURN_CODE).
inline constexpr int kDemoWaitingExitCode = 77;

/// Command-line choices.
struct DemoOptions {
  std::string outputDirectory;      ///< frames/, NAME.mp4, NAME_contact.png, NAME_figures.txt go here
  std::optional<int> frames;        ///< frames to render (default: fps * scene duration)
  bool smoke = false;               ///< CI check: 4 frames at 160x90, no video, the contact sheet checked not blank
  bool video = true;                ///< make the MP4 (needs ffmpeg)
  std::optional<int> width;         ///< pixels, overrides the demo's size
  std::optional<int> height;        ///< pixels
  std::optional<int> threads;       ///< overrides the scene's `threads` (ControllerSettings::threads, 0: all cores)
  std::optional<std::string> backend; ///< overrides the scene's `backend` ("cpu", "gpu" or "auto")
  /// Called with each frame once it is written (row 0 at the top) and the simulated time (s), with
  /// no GL context current; returns false to stop the run early (e.g. its window was closed): the
  /// frames so far are kept and the video, contact sheet and figures are made from them. Empty: none.
  std::function<bool(const RgbImage& picture, double time)> showFrame;
};

/// A picture's size in pixels.
struct PictureSize {
  int width = 0;   ///< pixels
  int height = 0;  ///< pixels
};

/// The size the frames of `demo` are drawn at: --size, else 160x90 for --smoke, else the demo's.
PictureSize pictureSize(const DemoDescription& demo, const DemoOptions& options);

/// Why a demo cannot run in this build (an effect it needs is missing), or empty when it can.
std::optional<std::string> missingRequirement(const DemoDescription& demo);

/// Runs the demo; returns the process exit status (0 done, 1 error, kDemoWaitingExitCode waiting
/// for an effect), after printing what went wrong.
int runDemo(const DemoDescription& demo, const DemoOptions& options);

}  // namespace hydrotex::render
