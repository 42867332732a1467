// SPDX-License-Identifier: Zlib
#pragma once
/// @file MakeBackend.hpp
/// A compute backend by name, for command lines (`--backend cpu|gpu`) and scene files.

#include <memory>
#include <string_view>

#include "hydrotex/backend/ComputeBackend.hpp"

namespace hydrotex::gpu {

/// "cpu": makeCpuBackend(); "gpu" (or "gl"): the GL compute backend on a headless EGL
/// context; "auto": the GL one when an EGL device with GL 4.3 opens, else the CPU one (the only
/// silent choice: name() says which was made). Errors: an unknown name, or no GL context for
/// "gpu" (the message says why; no fallback is taken, so that a figure labelled gpu was measured
/// on one).
Expected<std::unique_ptr<ComputeBackend>> makeBackend(std::string_view name);

/// True for a GL_RENDERER string of a software rasterizer (Mesa's llvmpipe, softpipe, swrast;
/// SwiftShader): GL that runs on the CPU.
bool isSoftwareRenderer(std::string_view renderer);

/// A BuoyancyController's backend by name (ControllerSettings::backend, scene key `backend`):
/// "gpu" the GL one (or its error; llvmpipe included); "auto" the GL one when an EGL device opens
/// that is a GPU (not isSoftwareRenderer); "cpu", and "auto" otherwise, null: the controller then
/// makes its own CPU backend on its threads. Errors as makeBackend's.
Expected<std::shared_ptr<ComputeBackend>> makeControllerBackend(std::string_view name);

}  // namespace hydrotex::gpu
