// SPDX-License-Identifier: Zlib
// The headless context and backend selection: creation failures are Error values (never a crash),
// and on a machine with EGL (CI: Mesa llvmpipe through the surfaceless platform) a GL 4.3+ core
// context opens and names its renderer.
#include <catch2/catch.hpp>

#include <string>

#include "hydrotex/gpu/EglContext.hpp"
#include "hydrotex/gpu/GlBackend.hpp"
#include "hydrotex/gpu/MakeBackend.hpp"

using namespace hydrotex;

TEST_CASE("no platform to try gives an error, not a crash", "[egl]") {
  gpu::EglContextSettings settings;
  settings.tryDevicePlatform = false;
  settings.trySurfacelessPlatform = false;
  const auto context = gpu::EglContext::create(settings);
  REQUIRE(!context.ok());
  CHECK(context.error().message.find("EGL context") != std::string::npos);
}

TEST_CASE("an OpenGL version without compute shaders is refused", "[egl]") {
  gpu::EglContextSettings settings;
  settings.majorVersion = 3;
  settings.minorVersion = 3;
  const auto context = gpu::EglContext::create(settings);
  REQUIRE(!context.ok());
  CHECK(context.error().message.find("4.3") != std::string::npos);
}

TEST_CASE("an unknown backend name is an error; cpu always works", "[egl]") {
  const auto unknown = gpu::makeBackend("vulkan");
  REQUIRE(!unknown.ok());
  CHECK(unknown.error().message.find("vulkan") != std::string::npos);
  const auto cpu = gpu::makeBackend("cpu");
  REQUIRE(cpu.ok());
  CHECK((*cpu)->name() == "cpu");
  CHECK((*cpu)->renderer() == "CPU");
  CHECK(!gpu::makeGlBackend(std::unique_ptr<gpu::EglContext>{}).ok());
}

TEST_CASE("a headless context opens and reports its renderer", "[egl]") {
  const auto context = gpu::EglContext::create();
  if (!context) {
    WARN("no headless EGL context on this machine: " << context.error().message);
    return;
  }
  const gpu::EglContext& c = **context;
  CHECK(!c.renderer().empty());
  CHECK((c.platform() == "device" || c.platform() == "surfaceless"));
  CHECK(c.makeCurrent().ok());
  // "4.5 (Core Profile) Mesa 22.3.6" or "4.6.0 NVIDIA 550.54": major.minor first.
  const int version = (c.version()[0] - '0') * 10 + (c.version()[2] - '0');
  CHECK(version >= 43);
  // release() (before a window's GLX context is made current) and back; twice is harmless.
  CHECK(c.release().ok());
  CHECK(c.release().ok());
  CHECK(c.makeCurrent().ok());
  WARN("EGL platform " << c.platform() << ", renderer " << c.renderer() << ", GL " << c.version()
                       << (c.hasShaderFp64() ? ", fp64" : ", no fp64"));

  // Two contexts (and two backends) live side by side and are destroyed in any order.
  auto first = gpu::makeBackend("gpu");
  auto second = gpu::makeBackend("gpu");
  REQUIRE(first.ok());
  REQUIRE(second.ok());
  CHECK((*first)->renderer() == c.renderer());
  first->reset();
  CHECK((*second)->bodyCount() == 0);
}
