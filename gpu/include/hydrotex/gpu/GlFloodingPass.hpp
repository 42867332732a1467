// SPDX-License-Identifier: Zlib
#pragma once
/// @file GlFloodingPass.hpp
/// A flooding body's pass over its permeable texels on the GPU (flooding_texels.comp): the
/// per-node Darcy sums LiquidGraph::step needs under a flat surface, one work group per node,
/// in float as the CPU's loop. The texels are uploaded once; a step uploads the nodes' levels
/// and reads five floats per node back. The GL backend's ComputeBackend::makeFloodingPass.

#include <memory>

#include "hydrotex/Expected.hpp"
#include "hydrotex/flooding/LiquidGraph.hpp"
#include "hydrotex/gpu/EglContext.hpp"

namespace hydrotex::gpu {

/// The pass for `graph`'s permeable texels (copied) on `context`, which must outlive it. Errors:
/// more nodes than one dispatch takes (65,535), a shader that does not compile.
Expected<std::unique_ptr<FloodingTexelPass>> makeGlFloodingPass(const EglContext& context, const LiquidGraph& graph);

}  // namespace hydrotex::gpu
