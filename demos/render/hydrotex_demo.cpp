// SPDX-License-Identifier: Zlib
// hydrotex_demo: runs one of the paper's scenes headless and renders it.
//   hydrotex_demo NAME_OR_FILE --out DIR [--frames N] [--size WxH] [--no-video] [--smoke] [--window [--window-check]]
//   hydrotex_demo --list
// NAME is a demo in data/scenes (demo_NAME.json), e.g. "ship"; FILE any demo file. --window also
// shows the frames in a GLFW window as they are drawn, when the build found GLFW.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "DemoRunner.hpp"
#ifdef HYDROTEX_DEMO_WITH_WINDOW
#include <cmath>
#include <memory>

#include "PreviewWindow.hpp"
#endif

namespace {

std::vector<std::filesystem::path> bundledDemos() {
  std::vector<std::filesystem::path> demos;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(HYDROTEX_SCENES_DIR, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("demo_", 0) == 0 && entry.path().extension() == ".json") demos.push_back(entry.path());
  }
  std::sort(demos.begin(), demos.end());
  return demos;
}

#ifdef HYDROTEX_DEMO_WITH_WINDOW
/// Largest difference of one channel of one pixel (0..255); 256 when the sizes differ.
int maxChannelDifference(const hydrotex::render::RgbImage& a, const hydrotex::render::RgbImage& b) {
  if (a.width != b.width || a.height != b.height || a.pixels.size() != b.pixels.size()) return 256;
  int largest = 0;
  for (std::size_t k = 0; k < a.pixels.size(); ++k) largest = std::max(largest, std::abs(int(a.pixels[k]) - int(b.pixels[k])));
  return largest;
}

/// Shows one frame in `preview`, titled with the demo's name and the simulated time; with `check`,
/// compares what the window drew with the frame and sets `failed` when they differ. False: stop.
bool showInWindow(hydrotex::render::PreviewWindow& preview, const std::string& demoName, const hydrotex::render::RgbImage& picture,
                  double time, bool check, bool& failed) {
  char title[160];
  std::snprintf(title, sizeof title, "hydrotex_demo: %s   t = %.2f s", demoName.c_str(), time);
  hydrotex::Expected<bool> open = preview.show(picture, title);
  if (!open) {
    std::fprintf(stderr, "\nhydrotex_demo: --window: %s\n", open.error().message.c_str());
    failed = true;
    return false;
  }
  if (check) {
    // A copy at the same size: exact but for a display whose channels are not 8 bits.
    const int difference = maxChannelDifference(preview.drawnPicture(), picture);
    if (difference > 2) {
      std::fprintf(stderr, "\nhydrotex_demo: --window-check: the window shows a %dx%d picture that differs from the %dx%d frame by up to %d levels\n",
                   preview.drawnPicture().width, preview.drawnPicture().height, picture.width, picture.height, difference);
      failed = true;
      return false;
    }
  }
  return *open;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hydrotex_demo: the paper's scenes, simulated and rendered headless (EGL)"};
  std::string demoName, outDir, size;
  std::optional<int> frames, threads;
  bool smoke = false, noVideo = false, list = false, window = false, windowCheck = false;
  app.add_option("demo", demoName, "demo name (e.g. ship; see --list) or a demo JSON file");
  app.add_option("--out", outDir, "output directory (default: demo-output/NAME)");
  app.add_option("--frames", frames, "frames to render (default: the scene's duration at the demo's fps)");
  app.add_option("--size", size, "picture size WxH (default: the demo's, 640x360)");
  app.add_option("--threads", threads, "threads for the bodies' loads (0: all cores; default: the scene's)");
  std::optional<std::string> backend;
  app.add_option("--backend", backend, "backend of the controller's texture hydrostatics: cpu, gpu or auto (default: the scene's)")
      ->check(CLI::IsMember({"cpu", "gpu", "auto"}));
  app.add_flag("--no-video", noVideo, "skip the MP4");
  app.add_flag("--smoke", smoke, "CI check: 4 small frames, no video, fail on a blank picture");
#ifdef HYDROTEX_DEMO_WITH_WINDOW
  app.add_flag("--window", window, "also show the frames in a window as they are drawn (needs a display; Esc or closing it stops the run)");
#else
  app.add_flag("--window", window, "show the frames in a window as they are drawn (not in this build: it renders headless only)");
#endif
  app.add_flag("--window-check", windowCheck, "--window, and exit 1 unless the window shows each frame as written (a test of the window)");
  app.add_flag("--list", list, "list the bundled demos and whether each can run in this build");
  CLI11_PARSE(app, argc, argv);
  if (threads && *threads < 0) {
    std::fprintf(stderr, "hydrotex_demo: --threads %d: expected a whole number >= 0 (0: all cores)\n", *threads);
    return 2;
  }
  window = window || windowCheck;
#ifndef HYDROTEX_DEMO_WITH_WINDOW
  if (window) {
    // The renderer draws into an offscreen EGL framebuffer; GLFW was not found when this was built.
    std::fprintf(stderr, "hydrotex_demo: --window: this build renders headless only (no GLFW window%s); drop --window and open the "
                         "frames, video and contact sheet it writes under --out\n",
                 std::getenv("DISPLAY") == nullptr && std::getenv("WAYLAND_DISPLAY") == nullptr ? ", and no display is set" : "");
    return 2;
  }
#endif

  if (list || demoName.empty()) {
    for (const auto& path : bundledDemos()) {
      auto demo = hydrotex::render::loadDemoDescription(path.string());
      if (!demo) {
        std::printf("  %-16s (unreadable: %s)\n", path.stem().string().c_str(), demo.error().message.c_str());
        continue;
      }
      const auto missing = hydrotex::render::missingRequirement(*demo);
      std::printf("  %-16s %s%s%s\n", demo->name.c_str(), demo->title.c_str(), missing ? "  [waiting: " : "",
                  missing ? (*missing + "]").c_str() : "");
    }
    return demoName.empty() && !list ? 2 : 0;
  }
  std::filesystem::path path(demoName);
  if (path.extension() != ".json") path = std::filesystem::path(HYDROTEX_SCENES_DIR) / ("demo_" + demoName + ".json");
  auto demo = hydrotex::render::loadDemoDescription(path.string());
  if (!demo) {
    std::fprintf(stderr, "hydrotex_demo: %s (hydrotex_demo --list shows the demos)\n", demo.error().message.c_str());
    return 1;
  }
  hydrotex::render::DemoOptions options;
  options.outputDirectory = outDir.empty() ? "demo-output/" + demo->name : outDir;
  options.frames = frames;
  options.threads = threads;
  options.backend = backend;
  options.smoke = smoke;
  options.video = !noVideo;
  if (!size.empty()) {
    int w = 0, h = 0;
    if (std::sscanf(size.c_str(), "%dx%d", &w, &h) != 2) {
      std::fprintf(stderr, "hydrotex_demo: --size %s: expected WxH, e.g. 640x360\n", size.c_str());
      return 2;
    }
    options.width = w;
    options.height = h;
  }
#ifdef HYDROTEX_DEMO_WITH_WINDOW
  // Opened before anything is run or written, so that a missing display changes nothing on disk.
  std::unique_ptr<hydrotex::render::PreviewWindow> preview;
  bool windowFailed = false;
  if (window && !hydrotex::render::missingRequirement(*demo)) {
    const hydrotex::render::PictureSize pictureSize = hydrotex::render::pictureSize(*demo, options);
    auto opened = hydrotex::render::PreviewWindow::open({pictureSize.width, pictureSize.height, "hydrotex_demo: " + demo->name, windowCheck});
    if (!opened) {
      std::fprintf(stderr, "hydrotex_demo: --window: %s\n", opened.error().message.c_str());
      return 2;
    }
    preview = std::move(*opened);
    options.showFrame = [&](const hydrotex::render::RgbImage& picture, double time) {
      return showInWindow(*preview, demo->name, picture, time, windowCheck, windowFailed);
    };
  }
  const int status = hydrotex::render::runDemo(*demo, options);
  return status == 0 && windowFailed ? 1 : status;
#else
  return hydrotex::render::runDemo(*demo, options);
#endif
}
