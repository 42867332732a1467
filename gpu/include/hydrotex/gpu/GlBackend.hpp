// SPDX-License-Identifier: Zlib
#pragma once
/// @file GlBackend.hpp
/// The OpenGL 4.3 compute backend (docs/design.md "Backends"): the CPU's exact bake uploaded once per
/// body, the per-step passes on the GPU. Hydrostatics under flat planes, Gerstner waves, height
/// grids and uniform media (the texture path's sums, TextureHydrostatics.cpp) and texture mass
/// properties, many bodies per dispatch, float per-texel work and per-workgroup float partials,
/// then a final pass in double (on the GPU when GL_ARB_gpu_shader_fp64 is there, else on the CPU
/// over the partials), results read back once per call.
///
/// Why the bake stays on the CPU, uploaded once (issue 7: "measure and choose"). bench_gpu, one
/// sphere, Mesa llvmpipe on a shared 2-core host (load 7), ms, median of three runs (range):
///
///   resolution | CPU bake + evaluate (once) | GL upload (once)  | GL step           | CPU step
///   256^2      |  17.6 (17 - 21)            |  11.6 (3.1 - 34)  | 0.37 (0.31 - 0.39) | 0.013
///   1024^2     | 152 (124 - 162)            | 148 (124 - 156)   | 4.1 (4.0 - 8.0)    | 0.066
///
/// The bake is paid once per body (a deforming mesh keeps its bake and is re-evaluated from it on
/// the GPU each step: enableGpuDeformation), so a GPU bake could only save a one-time cost, which
/// at 1024^2 the upload of its result already equals. A rasterized bake would also lose the exact
/// coverage (texel squares clipped against UV triangles: exact volumes to 1e-6, SurfaceBake.hpp)
/// unless it clipped polygons per texel in a shader; the per-step passes, where the time goes,
/// are on the GPU either way. Re-measure the step on a real GPU with scripts/bundle-gpu-bench.sh.

#include <memory>
#include <vector>

#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/gpu/EglContext.hpp"

namespace hydrotex::gpu {

/// Where the double-precision final sum over the float partials runs.
enum class FinalSum {
  Automatic,  ///< on the GPU when the context has GL_ARB_gpu_shader_fp64, else on the CPU
  Gpu,        ///< on the GPU (error at creation without GL_ARB_gpu_shader_fp64)
  Cpu,        ///< read the partials back and sum them on the CPU
};

/// Settings of the GL backend.
struct GlBackendSettings {
  FinalSum finalSum = FinalSum::Automatic;  ///< see FinalSum
  /// Bytes per storage buffer segment; 0: GL_MAX_SHADER_STORAGE_BLOCK_SIZE capped at 256 MiB.
  /// (Tests set it small to exercise bodies split across segments.)
  std::size_t segmentBytes = 0;
  /// Under Gerstner waves, each chunk (up to 256 texels) takes the surface's local quadratic
  /// model about the centre of its box, from one search and jet there, and its texels within the
  /// model's reach (where its error bound is within 1e-3 m) take their heights from it instead
  /// of a search each (issue 19 item 1 on the GPU); false: every texel searched (the per-texel
  /// answer).
  bool surfaceModels = true;
};

/// The GL backend on `context` (which it keeps and makes current on every call). Errors: shader
/// compilation or linking (the message holds the driver's log), FinalSum::Gpu without fp64.
/// hydrostatics() knows FlatSurface (any surface with a flatHeight), GerstnerWaves, HeightGrid and
/// UniformMedium; on any other LiquidSurface it answers an Error naming the CPU backend.
Expected<std::unique_ptr<ComputeBackend>> makeGlBackend(std::unique_ptr<EglContext> context,
                                                        const GlBackendSettings& settings = {});

/// What the last hydrostatics call of a GL backend did: its chunks (up to 1024 texels of one
/// body) classified against the surface by their bounds, as TextureHydrostatics classifies tiles.
struct GlHydrostaticsStatistics {
  std::size_t chunks = 0;           ///< chunks classified (those of the asked bodies' index window)
  std::size_t dryChunks = 0;        ///< wholly above the surface: nothing read
  std::size_t submergedChunks = 0;  ///< wholly under it: pre-summed moments added in O(1)
  std::size_t crossingChunks = 0;   ///< crossing it: texel by texel
  std::size_t texelsRead = 0;       ///< texels of the crossing chunks
  double bytesRead = 0.0;           ///< chunk headers and poses, moments and texels read (bytes)
  std::size_t runs = 0;             ///< storage runs dispatched (two dispatches each: classification, texels)
};

/// The statistics of `backend`'s last hydrostatics call (reads its counters back; not for the
/// per-step path). Error when `backend` is not a GL backend.
Expected<GlHydrostaticsStatistics> lastHydrostaticsStatistics(ComputeBackend& backend);

/// Deforming meshes re-evaluated on the GPU (issue 7): keeps `body`'s bake pieces, triangles and UV
/// maps on the GPU (uploaded once) so that a step uploads only the moved vertex positions
/// (updateVerticesOnGpu). `bake` must be the one the body was registered with, `mesh` gives the
/// topology (its triangles) and `layout` the UV layout of the bake. Errors: not a GL backend, an
/// unknown body, a bake or layout that does not match.
Status enableGpuDeformation(ComputeBackend& backend, BackendBodyId body, const SurfaceBake& bake, const Mesh& mesh,
                            const UvLayout& layout);

/// Uploads `positions` (m, body frame; the mesh's vertices, same topology) and re-evaluates the
/// body's PT, VAT, area and edges (SurfaceEvaluator's formulas, float), its moment corrections,
/// chunk bounds and pre-summed moments on the GPU, and its mass texels and per-block geometry sums
/// (deform_mass.comp); the next hydrostatics and massProperties calls use them (the texel fields
/// are never read back: only a hydrostatics chunk's header and moments, 172 bytes, and 80 bytes
/// per 256-texel mass block). Errors: no enableGpuDeformation, a vertex count that differs, a non-finite vertex.
Status updateVerticesOnGpu(ComputeBackend& backend, BackendBodyId body, const std::vector<Eigen::Vector3d>& positions);

/// Reads a body's texels and moment corrections as the GL backend holds them (bake order): for
/// tests of the GPU re-evaluation against evaluateSurface. Not for the per-step path.
Expected<SurfaceTextures> readGpuSurface(ComputeBackend& backend, BackendBodyId body);

/// Opens a headless context (EglContext::create) and makes the GL backend on it. Error when no
/// context can be opened: callers then use makeCpuBackend().
Expected<std::unique_ptr<ComputeBackend>> makeGlBackend(const GlBackendSettings& settings = {});

}  // namespace hydrotex::gpu
