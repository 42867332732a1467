// SPDX-License-Identifier: Zlib
#pragma once
/// @file MakeBackend.hpp
/// A compute backend by name, for command lines (`--backend cpu|gpu`) and scene files.

#include <memory>
#include <string_view>

#include "hydrotex/ComputeBackend.hpp"

namespace hydrotex::gpu {

/// "cpu": makeCpuBackend(); "gpu" (or "gl"): the GL compute backend on a headless EGL context.
/// Errors: an unknown name, or no GL context for "gpu" (the message says why; no fallback is
/// taken silently, so that a figure labelled gpu was measured on one).
Expected<std::unique_ptr<ComputeBackend>> makeBackend(std::string_view name);

}  // namespace hydrotex::gpu
