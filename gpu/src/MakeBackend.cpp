// SPDX-License-Identifier: Zlib
/// @file MakeBackend.cpp
/// Backend selection by name.

#include "hydrotex/gpu/MakeBackend.hpp"

#include <string>

#include "hydrotex/gpu/GlBackend.hpp"

namespace hydrotex::gpu {

Expected<std::unique_ptr<ComputeBackend>> makeBackend(std::string_view name) {
  if (name == "cpu") return makeCpuBackend();
  if (name == "gpu" || name == "gl") return makeGlBackend();
  return Error{"backend '" + std::string(name) + "' is unknown (cpu or gpu)"};
}

}  // namespace hydrotex::gpu
