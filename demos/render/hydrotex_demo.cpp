// hydrotex_demo: runs one of the paper's scenes headless and renders it.
//   hydrotex_demo NAME_OR_FILE --out DIR [--frames N] [--size WxH] [--no-video] [--smoke] [--window]
//   hydrotex_demo --list
// NAME is a demo in data/scenes (demo_NAME.json), e.g. "ship"; FILE any demo file.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "DemoRunner.hpp"

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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hydrotex_demo: the paper's scenes, simulated and rendered headless (EGL)"};
  std::string demoName, outDir, size;
  std::optional<int> frames;
  bool smoke = false, noVideo = false, list = false, window = false;
  app.add_option("demo", demoName, "demo name (e.g. ship; see --list) or a demo JSON file");
  app.add_option("--out", outDir, "output directory (default: demo-output/NAME)");
  app.add_option("--frames", frames, "frames to render (default: the scene's duration at the demo's fps)");
  app.add_option("--size", size, "picture size WxH (default: the demo's, 640x360)");
  app.add_flag("--no-video", noVideo, "skip the MP4");
  app.add_flag("--smoke", smoke, "CI check: 4 small frames, no video, fail on a blank picture");
  app.add_flag("--window", window, "show the frames in a window as they are drawn (not in this build: it renders headless only)");
  app.add_flag("--list", list, "list the bundled demos and whether each can run in this build");
  CLI11_PARSE(app, argc, argv);
  if (window) {
    // The renderer draws into an offscreen EGL framebuffer; no windowing library (GLFW) is wired in.
    std::fprintf(stderr, "hydrotex_demo: --window: this build renders headless only (no GLFW window%s); drop --window and open the "
                         "frames, video and contact sheet it writes under --out\n",
                 std::getenv("DISPLAY") == nullptr && std::getenv("WAYLAND_DISPLAY") == nullptr ? ", and no display is set" : "");
    return 2;
  }

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
  return hydrotex::render::runDemo(*demo, options);
}
