// SPDX-License-Identifier: Zlib
/// @file MakeBackend.cpp
/// Backend selection by name.

#include "hydrotex/gpu/MakeBackend.hpp"

#include <string>

#include "hydrotex/gpu/EglContext.hpp"
#include "hydrotex/gpu/GlBackend.hpp"

namespace hydrotex::gpu {

bool isSoftwareRenderer(std::string_view renderer) {
  for (std::string_view software : {"llvmpipe", "softpipe", "swrast", "SwiftShader"})
    if (renderer.find(software) != std::string_view::npos) return true;
  return false;
}

Expected<std::unique_ptr<ComputeBackend>> makeBackend(std::string_view name) {
  if (name == "cpu") return makeCpuBackend();
  if (name == "gpu" || name == "gl") return makeGlBackend();
  if (name == "auto") {
    Expected<std::unique_ptr<ComputeBackend>> gl = makeGlBackend();
    if (gl) return gl;
    return makeCpuBackend();
  }
  return Error{"backend '" + std::string(name) + "' is unknown (cpu, gpu or auto)"};
}

Expected<std::shared_ptr<ComputeBackend>> makeControllerBackend(std::string_view name) {
  if (name == "cpu") return std::shared_ptr<ComputeBackend>();
  if (name != "gpu" && name != "gl" && name != "auto") return Error{"backend '" + std::string(name) + "' is unknown (cpu, gpu or auto)"};
  Expected<std::unique_ptr<EglContext>> context = EglContext::create();
  if (!context) {
    if (name == "auto") return std::shared_ptr<ComputeBackend>();
    return Error{"gpu backend: " + context.error().message};
  }
  // "auto" wants a GPU: a software rasterizer (Mesa's llvmpipe, softpipe) runs the same passes
  // on the CPU, slower than the CPU backend, so it is passed over before any shader is compiled
  // (asked for by name, it is used).
  if (name == "auto" && isSoftwareRenderer((*context)->renderer())) return std::shared_ptr<ComputeBackend>();
  Expected<std::unique_ptr<ComputeBackend>> gl = makeGlBackend(std::move(context).value());
  if (!gl) {
    if (name == "auto") return std::shared_ptr<ComputeBackend>();
    return gl.error();
  }
  return std::shared_ptr<ComputeBackend>(std::move(gl).value());
}

}  // namespace hydrotex::gpu
