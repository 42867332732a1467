// SPDX-License-Identifier: Zlib
/// @file GlBackend.cpp
/// The GL compute backend. Per body, the CPU's exact bake is uploaded once as packed texels
/// (HydroTexel for hydrostatics, MassTexel plus per-block geometry sums for mass); a call uploads
/// the poses (or densities), runs one chunk pass per storage run for all bodies at once, one
/// final double pass per body, and reads the per-body sums back once. The sums are those of
/// core's texture path (HydrostaticSums.hpp, TextureMassProperties.cpp) and are finished by the
/// same code (finishFlatHydrostatics; finishPressureHydrostatics under waves, grids and media) so
/// that the backends differ only by float rounding. Everything large in world units (a body's
/// position, the time, a wave's phase, a grid's origin) is reduced about each body's frame origin
/// in double on the host; the shaders' float sees metres of the body's own size.
/// Driver quirks handled here are marked "Quirk".

#include "hydrotex/gpu/GlBackend.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "GlObjects.hpp"
#include "hydrotex/gpu/EmbeddedShaders.hpp"
#include "hydrotex/gpu/GlFloodingPass.hpp"
#include "hydrotex/gpu/GlWetting.hpp"
#include "hydrotex/gpu/ShaderLayouts.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex::gpu {

namespace {

using detail::GlBuffer;
using detail::GlProgram;

// The largest error bound (m) of a local surface model under Gerstner waves (hydrostatics_surface.comp):
// a third of the CPU hierarchy's (kDefaultSurfaceModelTolerance), since a model here reaches as far
// as its bound allows in every direction from one side of a chunk, with no averaging over a
// symmetric footprint: at the CPU's 3e-3 m the parity case's torus and sphere were 1.1e-5 rho g V
// off the per-texel search (test_backend_parity), at 1e-3 m 2.5e-6.
constexpr double kGpuSurfaceModelTolerance = kDefaultSurfaceModelTolerance / 3.0;
constexpr std::uint32_t kHydroChunkTexels = 256;  // 64 invocations x 4 texels (hydrostatics_flat.comp)
// Hydrostatics chunks are whole bake tiles, merged while they stay under this many texels: the
// smaller the chunk, the tighter its bounds and the fewer texels the waterline chunks read, the
// more chunks to classify (bench_gpu, llvmpipe, 1,000 spheres at 256^2: one 16^2 tile per chunk
// reads 6.7 M texels, four tiles 16.7 M).
constexpr std::uint32_t kHydroChunkTarget = 256;
constexpr std::uint32_t kMassChunkTexels = 256;    // TextureMassIntegrator's block (mass_moments.comp)
constexpr GLuint kMaxGroupsX = 65535;              // GL's guaranteed minimum of GL_MAX_COMPUTE_WORK_GROUP_COUNT
constexpr GLuint kClassifyGroup = 64;              // invocations per group of hydrostatics_classify.comp
// A body not asked this step is lifted this far (m) above the surface, so that every chunk of it
// is culled by its bounds: one test per chunk instead of a second dispatch layout.
constexpr float kLifted = 1.0e30f;
constexpr double kTwoPi = 6.28318530717958647692;

// Append-only storage for one kind of texel, split into buffers, and the runs of global chunks
// that a pass dispatches: a run's chunks are consecutive and read one buffer.
// Quirk (llvmpipe): GL_MAX_SHADER_STORAGE_BLOCK_SIZE is 128 MiB (the spec's minimum), less than
// 1,000 bodies at 256^2 need; NVIDIA allows 2 GiB. Chunks never straddle buffers and each run
// gets its own dispatch. A body's own chunks go to the last buffer with room; an instance's
// (addInstance) read its model's texels where they lie, in runs of their own.
struct SegmentedStorage {
  struct Buffer {
    GlBuffer texels;
    GlBuffer densities;  // mass storage only: one float per texel
    std::size_t used = 0;
  };
  struct Run {
    std::uint32_t buffer = 0;
    std::uint32_t chunkBegin = 0, chunkEnd = 0;  // global chunk range
  };
  std::size_t elementBytes = 0;
  std::size_t capacity = 0;  // elements per buffer
  bool withDensities = false;
  std::vector<Buffer> buffers;
  std::vector<Run> runs;
  std::vector<std::uint32_t> chunkRun;  // per global chunk

  // Before a body's chunks are placed: a body of `count` elements that fits in one buffer starts a
  // new one rather than straddle two, so that its instances' chunks, which read its buffer, form
  // one run with each other instead of one per buffer each (two dispatches a run and step).
  void keepTogether(std::size_t count) {
    if (!buffers.empty() && buffers.back().used + count > capacity && count <= capacity) openBuffer();
  }
  // Places chunk `chunkIndex` of `count` elements; returns its first element in its buffer.
  std::uint32_t place(std::uint32_t chunkIndex, std::uint32_t count) {
    if (buffers.empty() || buffers.back().used + count > capacity) openBuffer();
    const auto begin = static_cast<std::uint32_t>(buffers.back().used);
    buffers.back().used += count;
    extendRuns(chunkIndex, static_cast<std::uint32_t>(buffers.size() - 1));
    return begin;
  }
  // Chunk `chunkIndex` reads the elements of the earlier chunk `of` (same buffer, same begin).
  void share(std::uint32_t chunkIndex, std::uint32_t of) { extendRuns(chunkIndex, runs[chunkRun[of]].buffer); }
  // The buffer chunk `chunk` reads.
  const Buffer& bufferOf(std::uint32_t chunk) const { return buffers[runs[chunkRun[chunk]].buffer]; }

 private:
  void openBuffer() {
    Buffer buffer;
    buffer.texels = GlBuffer(capacity * elementBytes);
    if (withDensities) buffer.densities = GlBuffer(capacity * sizeof(float));
    buffers.push_back(std::move(buffer));
  }
  // A run holds at most kMaxGroupsX chunks, so that its indirect dispatch (one group per crossing
  // chunk, x only) stays within GL's guaranteed group count.
  void extendRuns(std::uint32_t chunkIndex, std::uint32_t buffer) {
    if (runs.empty() || runs.back().buffer != buffer || runs.back().chunkEnd != chunkIndex ||
        runs.back().chunkEnd - runs.back().chunkBegin >= kMaxGroupsX)
      runs.push_back(Run{buffer, chunkIndex, chunkIndex});
    runs.back().chunkEnd = chunkIndex + 1;
    chunkRun.push_back(static_cast<std::uint32_t>(runs.size() - 1));
  }
};

// Texel covariance about its centre (TextureMassProperties.cpp, texelCovariance): a flat
// parallelogram of edges eu, ev has C = (eu eu^T + ev ev^T) / 12, scaled by the covered fraction.
Eigen::Matrix3d texelCovariance(const Eigen::Vector3d& edgeU, const Eigen::Vector3d& edgeV, double area) {
  const double spanned = edgeU.cross(edgeV).norm();
  const double fraction = spanned > 0.0 ? std::min(1.0, area / spanned) : 0.0;
  return fraction / 12.0 * (edgeU * edgeU.transpose() + edgeV * edgeV.transpose());
}

// Runs a caller's work exactly once: at the first run(), or when it goes out of scope.
class RunOnce {
 public:
  explicit RunOnce(const std::function<void()>& work) : work_(work) {}
  RunOnce(const RunOnce&) = delete;
  RunOnce& operator=(const RunOnce&) = delete;
  ~RunOnce() { run(); }
  void run() {
    if (!done_ && work_) work_();
    done_ = true;
  }

 private:
  const std::function<void()>& work_;
  bool done_ = false;
};

void dispatchGroups(std::uint32_t groups) {
  const GLuint x = std::min<GLuint>(groups, kMaxGroupsX);
  glDispatchCompute(x, (groups + x - 1) / x, 1);
}

// A body's liquid texture on the GPU (GlWetting) behind the backend's door: the liquid is
// uploaded at the first step and stays resident; it is copied back only when the texture is read
// (sync), not every step: the step's report already carries the volumes.
class GlBackendWetting final : public BackendWetting {
 public:
  explicit GlBackendWetting(std::unique_ptr<GlWetting> wetting) : wetting_(std::move(wetting)) {}
  Expected<WettingStepReport> step(LiquidTexture& texture, const WettingEnvironment& environment, double dt) override {
    if (!uploaded_) {
      if (Status s = wetting_->upload(texture); !s) return s.error();
      uploaded_ = true;
    }
    return wetting_->step(environment, dt);
  }
  Status sync(LiquidTexture& texture) override { return uploaded_ ? wetting_->download(texture) : Status(Ok{}); }
  bool threadSafe() const override { return false; }  // the GL context is driven from one thread

 private:
  std::unique_ptr<GlWetting> wetting_;
  bool uploaded_ = false;
};

class GlBackend final : public ComputeBackend {
 public:
  GlBackend(std::unique_ptr<EglContext> context, bool finalOnGpu, std::size_t segmentBytes, bool chunkModels)
      : context_(std::move(context)), finalOnGpu_(finalOnGpu), chunkModels_(chunkModels) {
    hydroStorage_.elementBytes = sizeof(layout::HydroTexel);
    hydroStorage_.capacity = std::max<std::size_t>(segmentBytes / sizeof(layout::HydroTexel), kHydroChunkTexels);
    massStorage_.elementBytes = sizeof(layout::MassTexel);
    massStorage_.capacity = std::max<std::size_t>(segmentBytes / sizeof(layout::MassTexel), kMassChunkTexels);
    massStorage_.withDensities = true;
  }

  ~GlBackend() override {
    // GL objects must go while the context is current; the context goes last.
    if (context_->makeCurrent()) {
      hydroStorage_.buffers.clear();
      massStorage_.buffers.clear();
      tables_ = Tables{};
      programs_ = Programs{};
    }
  }

  Status compile() {
    const std::string_view version = "#version 430 core\n";
    const std::string_view fp64 = "#extension GL_ARB_gpu_shader_fp64 : require\n";
    const std::string_view layouts = embeddedShader("layouts.glsl");
    const std::string_view waterline = embeddedShader("waterline.glsl");
    // `define` selects a variant of one shader file (hydrostatics_surface.comp's surface kinds).
    // `include` is a shared file some shaders need (deform_texel.glsl).
    auto build = [&](const char* name, bool needsFp64, GlProgram& out, std::string_view define = {},
                     std::string_view include = {}) -> Status {
      const std::string_view body = embeddedShader(name);
      if (body.empty() || layouts.empty() || waterline.empty())
        return Error{std::string("gpu backend: shader ") + name + " is not embedded"};
      std::vector<std::string_view> parts = {version};
      if (needsFp64) parts.push_back(fp64);
      if (!define.empty()) parts.push_back(define);
      parts.push_back(layouts);
      if (needsFp64) parts.push_back(embeddedShader("layouts_fp64.glsl"));
      parts.push_back(waterline);
      if (!include.empty()) parts.push_back(include);
      parts.push_back(body);
      Expected<GlProgram> program = GlProgram::compute(name, parts);
      if (!program) return Error{"gpu backend: " + program.error().message};
      out = std::move(program).value();
      return Ok{};
    };
    if (Status s = build("hydrostatics_classify.comp", false, programs_.classify); !s) return s;
    if (Status s = build("hydrostatics_flat.comp", false, programs_.hydrostatics); !s) return s;
    if (Status s = build("hydrostatics_surface.comp", false, programs_.gerstner, "#define SURFACE_GERSTNER\n"); !s) return s;
    if (Status s = build("hydrostatics_surface.comp", false, programs_.grid, "#define SURFACE_GRID\n"); !s) return s;
    if (Status s = build("hydrostatics_surface.comp", false, programs_.medium, "#define SURFACE_MEDIUM\n"); !s) return s;
    if (Status s = build("mass_moments.comp", false, programs_.mass); !s) return s;
    if (Status s = build("deform_triangles.comp", false, programs_.deformTriangles); !s) return s;
    const std::string_view deformTexel = embeddedShader("deform_texel.glsl");
    if (deformTexel.empty()) return Error{"gpu backend: shader deform_texel.glsl is not embedded"};
    if (Status s = build("deform_texels.comp", false, programs_.deformTexels, {}, deformTexel); !s) return s;
    if (Status s = build("deform_mass.comp", false, programs_.deformMass, {}, deformTexel); !s) return s;
    if (finalOnGpu_)
      if (Status s = build("reduce_partials.comp", true, programs_.reduce); !s) return s;
    return Ok{};
  }

  std::string name() const override { return "gpu"; }

  Expected<std::unique_ptr<BackendWetting>> makeWetting(TexelAdjacency adjacency, const SurfaceTextures& textures,
                                                        const WettingSettings& settings) override {
    Expected<std::unique_ptr<GlWetting>> wetting = GlWetting::create(*context_, adjacency, textures, settings);
    if (!wetting) return Error{"gpu wetting: " + wetting.error().message};
    return std::unique_ptr<BackendWetting>(std::make_unique<GlBackendWetting>(std::move(wetting).value()));
  }

  Expected<std::unique_ptr<FloodingTexelPass>> makeFloodingPass(const LiquidGraph& graph) override {
    return makeGlFloodingPass(*context_, graph);
  }
  std::string renderer() const override { return context_->renderer(); }
  std::size_t bodyCount() const override { return bodies_.size(); }

  Expected<BackendBodyId> addBody(const SurfaceBake& bake, const SurfaceTextures& textures,
                                  const Eigen::Vector3d& referencePoint) override {
    const std::size_t count = bake.coveredCount();
    if (Status s = checkTextures(textures, count); !s) return s.error();
    if (count == 0) return Error{"gpu backend: the bake covers no texel"};
    if (!referencePoint.allFinite()) return Error{"gpu backend: mass reference point is not finite"};
    if (count > std::numeric_limits<std::uint32_t>::max() / 2) return Error{"gpu backend: body has too many texels"};
    if (Status s = context_->makeCurrent(); !s) return s.error();

    Body body;
    body.texelCount = count;
    body.referencePoint = referencePoint;
    const auto id = static_cast<std::uint32_t>(bodies_.size());
    body.source = id;
    body.hydroChunkBegin = static_cast<std::uint32_t>(hydroChunks_.size());
    body.momentBegin = hydroMoments_.size();
    body.blockBegin = blocks_.size();
    body.correctionBegin = hydroCorrections_.size();
    hydroStorage_.keepTogether(count);
    massStorage_.keepTogether(count);
    std::size_t corrected = 0;  // the textures' moment corrections placed so far (ascending texels)
    for (const auto& [first, chunkCount] : hydroChunkRuns(bake)) {
      layout::Chunk chunk{};
      chunk.body = id;
      chunk.count = chunkCount;
      chunk.table = static_cast<std::uint32_t>(hydroMoments_.size());
      chunk.begin = hydroStorage_.place(static_cast<std::uint32_t>(hydroChunks_.size()), chunk.count);
      // The chunk's texels of several pieces: their corrections, in one range (values: uploadSurface).
      chunk.correctionBegin = static_cast<std::uint32_t>(hydroCorrections_.size());
      while (corrected < textures.momentTexel.size() && textures.momentTexel[corrected] < first + chunkCount) {
        hydroCorrections_.push_back(layout::TexelCorrection{textures.momentTexel[corrected] - first, {}, 0.0f});
        ++corrected;
      }
      chunk.correctionCount = static_cast<std::uint32_t>(hydroCorrections_.size()) - chunk.correctionBegin;
      hydroChunks_.push_back(chunk);
      hydroChunkFirst_.push_back(first);
      hydroMoments_.push_back(layout::ChunkMoments{});
    }
    body.hydroChunkEnd = static_cast<std::uint32_t>(hydroChunks_.size());
    body.correctionEnd = hydroCorrections_.size();
    body.massChunkBegin = static_cast<std::uint32_t>(massChunks_.size());
    for (std::size_t first = 0; first < count; first += kMassChunkTexels) {
      layout::Chunk chunk{};
      chunk.body = id;
      chunk.count = static_cast<std::uint32_t>(std::min<std::size_t>(kMassChunkTexels, count - first));
      chunk.begin = massStorage_.place(static_cast<std::uint32_t>(massChunks_.size()), chunk.count);
      chunk.table = static_cast<std::uint32_t>(blocks_.size());
      massChunks_.push_back(chunk);
      blocks_.push_back(layout::BlockGeometry{});
    }
    body.massChunkEnd = static_cast<std::uint32_t>(massChunks_.size());
    bodies_.push_back(std::move(body));
    uploadSurface(bodies_.back(), textures);
    tablesDirty_ = true;
    return id;
  }

  // The instance gets chunk records of its own (its body index, its poses and sums) that read the
  // model's texels, corrections, bounds, chunk moments and block sums where they lie (Chunk::table):
  // what an instance adds is its chunk records and partial slots.
  Expected<BackendBodyId> addInstance(BackendBodyId of) override {
    if (of >= bodies_.size()) return Error{"gpu backend: unknown body " + std::to_string(of)};
    if (bodies_[of].deformation)
      return Error{"gpu backend: body " + std::to_string(of) + " deforms on the GPU; a deforming body's texels are not shared"};
    const Body& model = bodies_[of];
    const auto id = static_cast<std::uint32_t>(bodies_.size());
    Body body;  // its texel sums are its source's (sourceOf), not copied
    body.shared = true;
    body.source = model.source;
    body.hydroChunkBegin = static_cast<std::uint32_t>(hydroChunks_.size());
    for (std::uint32_t c = model.hydroChunkBegin; c < model.hydroChunkEnd; ++c) {
      layout::Chunk chunk = hydroChunks_[c];
      chunk.body = id;
      const std::uint32_t first = hydroChunkFirst_[c];
      hydroStorage_.share(static_cast<std::uint32_t>(hydroChunks_.size()), c);
      hydroChunks_.push_back(chunk);
      hydroChunkFirst_.push_back(first);
    }
    body.hydroChunkEnd = static_cast<std::uint32_t>(hydroChunks_.size());
    body.massChunkBegin = static_cast<std::uint32_t>(massChunks_.size());
    for (std::uint32_t c = model.massChunkBegin; c < model.massChunkEnd; ++c) {
      layout::Chunk chunk = massChunks_[c];
      chunk.body = id;
      massStorage_.share(static_cast<std::uint32_t>(massChunks_.size()), c);
      massChunks_.push_back(chunk);
    }
    body.massChunkEnd = static_cast<std::uint32_t>(massChunks_.size());
    bodies_[of].shared = true;
    bodies_.push_back(std::move(body));
    tablesDirty_ = true;
    return id;
  }

  Status updateSurface(BackendBodyId id, const SurfaceTextures& textures) override {
    if (id >= bodies_.size()) return Error{"gpu backend: unknown body " + std::to_string(id)};
    if (bodies_[id].shared)
      return Error{"gpu backend: body " + std::to_string(id) + " shares its texels with another (addInstance); a deforming body needs its own"};
    if (Status s = checkTextures(textures, bodies_[id].texelCount); !s) return s;
    // The same bake names the same texels of several pieces (SurfaceTextures::momentTexel).
    if (textures.momentCorrection.size() != bodies_[id].correctionEnd - bodies_[id].correctionBegin)
      return Error{"gpu backend: surface textures hold " + std::to_string(textures.momentCorrection.size()) +
                   " moment corrections, body " + std::to_string(id) + " has " +
                   std::to_string(bodies_[id].correctionEnd - bodies_[id].correctionBegin)};
    if (Status s = context_->makeCurrent(); !s) return s;
    uploadSurface(bodies_[id], textures);
    bodies_[id].gpuDeformed = false;  // the host's textures are the body's again
    bodies_[id].momentsPending = bodies_[id].massPending = false;
    tablesDirty_ = true;
    return Ok{};
  }

  // See enableGpuDeformation (GlBackend.hpp).
  Status enableDeformation(BackendBodyId id, const SurfaceBake& bake, const Mesh& mesh, const UvLayout& uvLayout) {
    if (id >= bodies_.size()) return Error{"gpu deformation: unknown body " + std::to_string(id)};
    Body& body = bodies_[id];
    if (body.shared)
      return Error{"gpu deformation: body " + std::to_string(id) + " shares its texels with another (addInstance); a deforming body needs its own"};
    if (bake.coveredCount() != body.texelCount || bake.pieceStart.size() != body.texelCount + 1)
      return Error{"gpu deformation: the bake has " + std::to_string(bake.coveredCount()) + " texels, body " +
                   std::to_string(id) + " has " + std::to_string(body.texelCount)};
    const auto runs = hydroChunkRuns(bake);
    if (runs.size() != body.hydroChunkEnd - body.hydroChunkBegin)
      return Error{"gpu deformation: the bake is not the one body " + std::to_string(id) + " was registered with"};
    if (uvLayout.uvTriangles.size() != mesh.triangles.size())
      return Error{"gpu deformation: the UV layout has " + std::to_string(uvLayout.uvTriangles.size()) +
                   " triangles, the mesh " + std::to_string(mesh.triangles.size())};
    if (Status s = context_->makeCurrent(); !s) return s;
    // The per-triangle UV maps and per-piece UV shares, as SurfaceEvaluator's constructor makes them.
    const double texelU = 1.0 / bake.width, texelV = 1.0 / bake.height;
    const std::size_t triangleCount = mesh.triangles.size();
    std::vector<layout::DeformTriangle> triangles(triangleCount);
    std::vector<double> uvArea(triangleCount, 0.0);
    const int uvCount = static_cast<int>(uvLayout.uvs.size());
    const auto none = std::numeric_limits<std::uint32_t>::max();
    for (std::size_t t = 0; t < triangleCount; ++t) {
      const Eigen::Vector3i& tri = mesh.triangles[t];
      layout::DeformTriangle& out = triangles[t];
      out = {none, none, none, 0.0f, 0.0f, 0.0f, 0.0f};
      if ((tri.array() >= 0).all()) out = {std::uint32_t(tri[0]), std::uint32_t(tri[1]), std::uint32_t(tri[2]), 0.0f, 0.0f, 0.0f, 0.0f};
      const Eigen::Vector3i& uvTri = uvLayout.uvTriangles[t];
      if ((uvTri.array() < 0).any() || (uvTri.array() >= uvCount).any()) continue;
      const Eigen::Vector2d d1 = uvLayout.uvs[uvTri[1]] - uvLayout.uvs[uvTri[0]];
      const Eigen::Vector2d d2 = uvLayout.uvs[uvTri[2]] - uvLayout.uvs[uvTri[0]];
      const double det = d1.x() * d2.y() - d2.x() * d1.y();
      if (det == 0.0 || !std::isfinite(det)) continue;
      uvArea[t] = 0.5 * std::abs(det);
      out.cu1 = float(d2.y() / det * texelU);
      out.cu2 = float(-d1.y() / det * texelU);
      out.cv1 = float(-d2.x() / det * texelV);
      out.cv2 = float(d1.x() / det * texelV);
    }
    std::vector<layout::DeformPiece> pieces(bake.pieces.size());
    for (std::size_t i = 0; i < body.texelCount; ++i) {
      const std::uint32_t begin = bake.pieceStart[i];
      const std::uint32_t end = std::min<std::uint32_t>(bake.pieceStart[i + 1], std::uint32_t(pieces.size()));
      double texelUv = 0.0;
      for (std::uint32_t k = begin; k < end; ++k)
        if (bake.pieces[k].triangle < triangleCount) texelUv += bake.pieces[k].areaFraction * uvArea[bake.pieces[k].triangle];
      for (std::uint32_t k = begin; k < end; ++k) {
        const TexelPiece& piece = bake.pieces[k];
        const double share = texelUv > 0.0 && piece.triangle < triangleCount
                                 ? piece.areaFraction * uvArea[piece.triangle] / texelUv : 0.0;
        pieces[k] = {piece.triangle, piece.areaFraction, piece.centroidBary1, piece.centroidBary2, float(share)};
      }
    }
    std::vector<std::uint32_t> chunkFirst;
    for (const auto& run : runs) chunkFirst.push_back(run.first);
    auto upload = [](const auto& items) {
      GlBuffer buffer(items.size() * sizeof(items[0]));
      buffer.write(0, items.data(), items.size() * sizeof(items[0]));
      return buffer;
    };
    auto deform = std::make_unique<Deformation>();
    deform->triangles = upload(triangles);
    deform->pieceStart = upload(bake.pieceStart);
    deform->pieces = upload(pieces);
    deform->chunkFirst = upload(chunkFirst);
    deform->frames = GlBuffer(triangleCount * sizeof(layout::TriangleFrame));
    deform->massBlocks = GlBuffer((body.massChunkEnd - body.massChunkBegin) * sizeof(layout::MassBlock));
    deform->vertices = GlBuffer(mesh.positions.size() * 3 * sizeof(float));
    deform->triangleCount = std::uint32_t(triangleCount);
    deform->vertexCount = std::uint32_t(mesh.positions.size());
    deform->pieceCount = std::uint32_t(pieces.size());
    body.deformation = std::move(deform);
    return Ok{};
  }

  // See updateVerticesOnGpu (GlBackend.hpp).
  Status updateVertices(BackendBodyId id, const std::vector<Eigen::Vector3d>& positions) {
    if (id >= bodies_.size()) return Error{"gpu deformation: unknown body " + std::to_string(id)};
    Body& body = bodies_[id];
    if (!body.deformation) return Error{"gpu deformation: body " + std::to_string(id) + " has no enableGpuDeformation"};
    if (positions.size() != body.deformation->vertexCount)
      return Error{"gpu deformation: " + std::to_string(positions.size()) + " vertices, the mesh had " +
                   std::to_string(body.deformation->vertexCount)};
    std::vector<float>& packed = vertexScratch_;
    packed.resize(positions.size() * 3);
    for (std::size_t v = 0; v < positions.size(); ++v) {
      if (!positions[v].allFinite()) return Error{"gpu deformation: vertex " + std::to_string(v) + " is not finite"};
      for (int c = 0; c < 3; ++c) packed[3 * v + std::size_t(c)] = float(positions[v][c]);
    }
    if (Status s = context_->makeCurrent(); !s) return s;
    body.deformation->vertices.write(0, packed.data(), packed.size() * sizeof(float));
    body.gpuDeformed = true;
    body.momentsPending = true;
    body.massPending = true;
    if (!tablesDirty_) runDeformation(body);  // else ensureTables runs it on the fresh tables
    if (const GLenum error = glGetError(); error != GL_NO_ERROR)
      return Error{"gpu deformation: OpenGL error " + std::to_string(error)};
    return Ok{};
  }

  // See readGpuSurface (GlBackend.hpp).
  Expected<SurfaceTextures> readSurface(BackendBodyId id) {
    if (id >= bodies_.size()) return Error{"gpu backend: unknown body " + std::to_string(id)};
    if (Status s = context_->makeCurrent(); !s) return s.error();
    ensureTables();
    const Body& body = bodies_[id];       // its chunks
    const Body& source = sourceOf(id);    // its texel count and corrections
    SurfaceTextures out;
    out.position.resize(source.texelCount);
    out.areaVector.resize(source.texelCount);
    out.area.resize(source.texelCount);
    out.edgeU.resize(source.texelCount);
    out.edgeV.resize(source.texelCount);
    std::vector<layout::HydroTexel> texels;
    for (std::uint32_t c = body.hydroChunkBegin; c < body.hydroChunkEnd; ++c) {
      const layout::Chunk& chunk = hydroChunks_[c];
      texels.resize(chunk.count);
      hydroStorage_.bufferOf(c).texels.read(
          std::size_t(chunk.begin) * sizeof(layout::HydroTexel), texels.data(), texels.size() * sizeof(layout::HydroTexel));
      for (std::uint32_t k = 0; k < chunk.count; ++k) {
        const layout::HydroTexel& t = texels[k];
        const std::size_t i = hydroChunkFirst_[c] + k;
        out.position[i] = Eigen::Vector3f(t.px, t.py, t.pz);
        out.areaVector[i] = Eigen::Vector3f(t.ax, t.ay, t.az);
        out.area[i] = t.area;
        out.edgeU[i] = Eigen::Vector3f(t.ux, t.uy, t.uz);
        out.edgeV[i] = Eigen::Vector3f(t.vx, t.vy, t.vz);
      }
    }
    std::vector<layout::TexelCorrection> corrections(source.correctionEnd - source.correctionBegin);
    if (!corrections.empty())
      tables_.corrections.read(source.correctionBegin * sizeof(layout::TexelCorrection), corrections.data(),
                               corrections.size() * sizeof(layout::TexelCorrection));
    for (std::uint32_t c = body.hydroChunkBegin; c < body.hydroChunkEnd; ++c) {
      const layout::Chunk& chunk = hydroChunks_[c];
      for (std::uint32_t k = 0; k < chunk.correctionCount; ++k) {
        const layout::TexelCorrection& correction = corrections[chunk.correctionBegin - source.correctionBegin + k];
        out.momentTexel.push_back(hydroChunkFirst_[c] + correction.texel);
        out.momentCorrection.push_back(Eigen::Map<const Eigen::Matrix<float, 3, 3, Eigen::RowMajor>>(correction.moment));
        out.momentReach.push_back(correction.reach);
      }
    }
    return out;
  }

  using ComputeBackend::hydrostatics;
  Status hydrostatics(const LiquidSurface& surface, std::span<const BackendHydrostaticsQuery> queries,
                      std::span<HydrostaticsResult> results, const std::function<void()>& meanwhile) override {
    // The caller's work runs once, whatever the outcome: while the passes are in flight when they
    // were submitted (finalSums), else when this returns.
    RunOnce runMeanwhile(meanwhile);
    if (results.size() < queries.size())
      return Error{"gpu backend: " + std::to_string(queries.size()) + " queries, room for " +
                   std::to_string(results.size()) + " results"};
    const Expected<SurfaceKind> kind = surfaceKind(surface);
    if (!kind) return kind.error();
    ++batch_;
    for (const BackendHydrostaticsQuery& q : queries) {
      if (q.body >= bodies_.size()) return Error{"gpu backend: unknown body " + std::to_string(q.body)};
      if (bodies_[q.body].batch == batch_) return Error{"gpu backend: body " + std::to_string(q.body) + " asked twice in one batch"};
      bodies_[q.body].batch = batch_;
      if (Status valid = validateHydrostaticsQuery(surface, q.query); !valid)
        return Error{"gpu backend: body " + std::to_string(q.body) + ": " + valid.error().message};
    }
    // Each body's frame origin o, as TextureHydrostatics::query picks it: (t_x, h, t_z) with h the
    // plane's height, or the surface's height above the centre of mass; t for a medium.
    origins_.resize(queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const HydrostaticsQuery& q = queries[i].query;
      const Eigen::Vector3d& t = q.pose.translation;
      if (*kind == SurfaceKind::Medium) {
        origins_[i] = t;
        continue;
      }
      double height = 0.0;
      if (*kind == SurfaceKind::Flat) {
        height = *surface.flatHeight();
      } else {
        const Eigen::Vector3d centerOfMass = q.pose.apply(q.centerOfMass);
        height = surface.surfaceHeight(centerOfMass.x(), centerOfMass.z(), q.time);
        if (!std::isfinite(height))
          return Error{"gpu backend: body " + std::to_string(queries[i].body) + ": the liquid surface height is not finite"};
      }
      origins_[i] = Eigen::Vector3d(t.x(), height, t.z());
    }
    if (queries.empty()) return Ok{};
    if (Status s = context_->makeCurrent(); !s) return s;
    ensureTables();
    if (*kind != SurfaceKind::Flat && !partialHeads_) {  // the first surface that is not flat
      partialHeads_ = true;
      tables_.partials = GlBuffer(partialCount() * sizeof(layout::Partial));
    }
    for (const BackendHydrostaticsQuery& q : queries)
      if (bodies_[q.body].momentsPending) readMoments(bodies_[q.body]);

    layout::BodyPose lifted{};
    lifted.row0[0] = lifted.row1[1] = lifted.row2[2] = 1.0f;
    lifted.row1[3] = kLifted;
    std::fill(poses_.begin(), poses_.end(), lifted);
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const BackendHydrostaticsQuery& q = queries[i];
      const Eigen::Matrix3d& r = q.query.pose.rotation;
      // x' = R p + (t - o): only the vertical offset is not zero.
      const double offset[3] = {0.0, q.query.pose.translation.y() - origins_[i].y(), 0.0};
      float* rows[3] = {poses_[q.body].row0, poses_[q.body].row1, poses_[q.body].row2};
      for (int row = 0; row < 3; ++row) {
        for (int j = 0; j < 3; ++j) rows[row][j] = static_cast<float>(r(row, j));
        rows[row][3] = static_cast<float>(offset[row]);
      }
    }
    tables_.poses.write(0, poses_.data(), poses_.size() * sizeof(layout::BodyPose));
    if (*kind != SurfaceKind::Flat) uploadSurfaceFrames(surface, *kind, queries);

    const auto [low, high] = bodyWindow(queries);
    runHydrostaticsPasses(bodies_[low].hydroChunkBegin, bodies_[high - 1].hydroChunkEnd, *kind);
    if (Status s = finalSums(false, low, high, *kind != SurfaceKind::Flat, &runMeanwhile); !s) return s;

    for (std::size_t i = 0; i < queries.size(); ++i) {
      const Body& body = sourceOf(queries[i].body);  // its Sum p A^T and Sum A
      const HydrostaticsQuery& q = queries[i].query;
      const double* v = sums_[queries[i].body].value;
      const FlatWettedSums wetted{v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10]};
      if (*kind == SurfaceKind::Flat) {
        results[i] = finishFlatHydrostatics(wetted, origins_[i].y(), surface.density(), q);
        continue;
      }
      const double* head = headSums_[queries[i].body].value;
      const Eigen::Vector3d headForce(head[0], head[1], head[2]), headTorque(head[3], head[4], head[5]);
      const double rhoG = surface.density() * q.gravity;
      PressureSums pressure;
      if (*kind == SurfaceKind::Medium) {
        // p = rho0 g c (base + e), e the head the GPU summed (hydrostatics_surface.comp): the
        // constant part's sums, base Sum A' and base Sum x' x A' (x' = R p here), in double from
        // the body's moments, so that they cancel as on the CPU.
        const auto& medium = static_cast<const UniformMedium&>(surface);
        const double ty = q.pose.translation.y();
        const bool constant = std::isinf(medium.scaleHeight());
        const double c = constant ? 1.0 : std::exp(-(ty - medium.referenceHeight()) / medium.scaleHeight());
        const double base = constant ? medium.referenceHeight() - ty : medium.scaleHeight();
        const Eigen::Matrix3d& pa = body.sumPA;
        const Eigen::Vector3d cross(pa(1, 2) - pa(2, 1), pa(2, 0) - pa(0, 2), pa(0, 1) - pa(1, 0));
        pressure.force = -rhoG * c * (base * (q.pose.rotation * body.sumA) + headForce);
        pressure.torque = -rhoG * c * (base * (q.pose.rotation * cross) + headTorque);
      } else {
        pressure.force = -rhoG * headForce;  // p = rho g D
        pressure.torque = -rhoG * headTorque;
      }
      results[i] = finishPressureHydrostatics(wetted, pressure, origins_[i], surface.density(), q,
                                              *kind != SurfaceKind::Medium);
    }
    return Ok{};
  }

  Status massProperties(std::span<const BackendBodyId> ids, std::span<const TextureMassModel> models,
                        std::span<MassProperties> results) override {
    if (ids.size() != models.size() || results.size() < ids.size())
      return Error{"gpu backend: " + std::to_string(ids.size()) + " bodies, " + std::to_string(models.size()) +
                   " models and room for " + std::to_string(results.size()) + " results"};
    ++batch_;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (ids[i] >= bodies_.size()) return Error{"gpu backend: unknown body " + std::to_string(ids[i])};
      if (bodies_[ids[i]].batch == batch_) return Error{"gpu backend: body " + std::to_string(ids[i]) + " asked twice in one batch"};
      bodies_[ids[i]].batch = batch_;
      const TextureMassModel& model = models[i];
      // The density map lies beside the mass texels, which an instance shares with its model.
      if (!model.texelDensity.empty() && bodies_[ids[i]].shared)
        return Error{"gpu backend: body " + std::to_string(ids[i]) +
                     " shares its texels with another (addInstance); a density map needs a body of its own"};
      if (!model.texelDensity.empty() && model.texelDensity.size() != sourceOf(ids[i]).texelCount)
        return Error{"density map has " + std::to_string(model.texelDensity.size()) + " texels, the bake has " +
                     std::to_string(sourceOf(ids[i]).texelCount)};
      if (!std::isfinite(model.solidDensity) || model.solidDensity < 0.0)
        return Error{"solid density " + std::to_string(model.solidDensity) + " kg/m^3 is negative or not finite"};
      if (!std::isfinite(model.shellDensity) || model.shellDensity < 0.0)
        return Error{"shell density " + std::to_string(model.shellDensity) + " kg/m^2 is negative or not finite"};
    }
    if (ids.empty()) return Ok{};
    if (Status s = context_->makeCurrent(); !s) return s;
    ensureTables();
    for (BackendBodyId id : ids)
      if (bodies_[id].massPending) readMassBlocks(bodies_[id]);

    for (layout::BodyRange& range : massRanges_) range.mode = 2;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const Body& body = bodies_[ids[i]];
      const TextureMassModel& model = models[i];
      layout::BodyRange& range = massRanges_[ids[i]];
      range.mode = model.texelDensity.empty() ? 0u : 1u;
      range.uniformDensity = static_cast<float>(model.solidDensity);
      if (range.mode == 1) uploadDensities(body, model.texelDensity);
    }
    tables_.massRanges.write(0, massRanges_.data(), massRanges_.size() * sizeof(layout::BodyRange));

    glUseProgram(programs_.mass.id());
    tables_.massChunks.bind(1);
    tables_.massRanges.bind(2);
    tables_.partials.bind(3);
    const auto [low, high] = std::minmax_element(ids.begin(), ids.end());
    runSegments(massStorage_, programs_.mass, true, bodies_[*low].massChunkBegin, bodies_[*high].massChunkEnd);
    if (Status s = finalSums(true, *low, *high + 1); !s) return s;

    for (std::size_t i = 0; i < ids.size(); ++i) {
      const Body& body = sourceOf(ids[i]);  // its shell sums, volume and reference point
      const TextureMassModel& model = models[i];
      const double* v = sums_[ids[i]].value;
      if (!model.texelDensity.empty() && (!(v[10] >= 0.0) || !std::isfinite(v[0])))
        return Error{"density map has a negative or non-finite density"};
      double mass = v[0] + model.shellDensity * body.shellArea;
      Eigen::Vector3d first = Eigen::Vector3d(v[1], v[2], v[3]) + model.shellDensity * body.shellFirst;
      Eigen::Matrix3d second;
      second << v[4], v[7], v[8], v[7], v[5], v[9], v[8], v[9], v[6];
      second += model.shellDensity * body.shellSecond;
      // TextureMassIntegrator::finish: centre from the first moment, inertia from the central
      // second moment S as trace(S) Id - S.
      MassProperties out;
      out.mass = mass;
      out.volume = body.totalVolume;
      out.centerOfMass = body.referencePoint;
      if (mass > 0.0) {
        const Eigen::Vector3d offset = first / mass;
        out.centerOfMass = body.referencePoint + offset;
        const Eigen::Matrix3d central = second - mass * offset * offset.transpose();
        out.inertia = central.trace() * Eigen::Matrix3d::Identity() - central;
      }
      results[i] = out;
    }
    return Ok{};
  }

 private:
  // A body's GPU re-evaluation data (enableGpuDeformation): uploaded once, but the vertices.
  struct Deformation {
    GlBuffer vertices, triangles, frames, pieceStart, pieces, chunkFirst;
    GlBuffer massBlocks;  // per mass block: MassBlock (deform_mass.comp)
    std::uint32_t triangleCount = 0, vertexCount = 0, pieceCount = 0;
  };
  struct Body {
    std::size_t texelCount = 0;
    std::uint32_t hydroChunkBegin = 0, hydroChunkEnd = 0, massChunkBegin = 0, massChunkEnd = 0;
    Eigen::Vector3d referencePoint = Eigen::Vector3d::Zero();
    double totalVolume = 0.0;
    double shellArea = 0.0;
    Eigen::Vector3d shellFirst = Eigen::Vector3d::Zero();
    Eigen::Matrix3d shellSecond = Eigen::Matrix3d::Zero();
    // Lids over openings (Mesh.hpp), about the reference point: left out of the shell sums.
    OpeningMoments lids;
    // Sum p A^T plus the moment corrections (m^3, body frame, double): V I for a closed surface up
    // to float rounding; a medium's absolute pressure multiplies its antisymmetric part (as on
    // the CPU, which sums the same terms texel by texel).
    Eigen::Matrix3d sumPA = Eigen::Matrix3d::Zero();
    std::size_t correctionBegin = 0, correctionEnd = 0;  // its entries of hydroCorrections_
    // Sum A (m^2, body frame, double): zero for a closed surface up to the texels' rounding, which
    // a medium's absolute pressure multiplies (as on the CPU). Zero for a GPU-deformed body.
    Eigen::Vector3d sumA = Eigen::Vector3d::Zero();
    std::uint64_t batch = 0;
    std::unique_ptr<Deformation> deformation;
    bool gpuDeformed = false;        // its texels on the GPU come from updateVertices, not the host
    bool momentsPending = false;     // its chunk moments (for sumPA) wait on the GPU
    bool massPending = false;        // its mass block sums wait on the GPU
    bool shared = false;             // its texels serve several bodies (addInstance): read-only
    // The body whose texels, texel sums (above: texelCount to sumA), moments and block sums it
    // reads: itself, or its model's source. An instance keeps only its chunks and its batch.
    std::uint32_t source = 0;
    std::size_t momentBegin = 0, blockBegin = 0;  // its entries of hydroMoments_ and blocks_ (a source's only)
  };
  struct Tables {
    GlBuffer hydroChunks, massChunks, poses, hydroRanges, massRanges, blocks, results;
    // Per chunk: its float Partial at the chunk's index, then (from headBase(), per hydro chunk)
    // the pressure-head sums of hydrostatics_surface.comp; one buffer, so that the texel passes
    // stay within GL 4.3's guaranteed 8 storage blocks per shader (bindings 0..7).
    GlBuffer partials;
    GlBuffer chunkMoments;  // per hydro chunk
    GlBuffer corrections;   // TexelCorrection, each hydro chunk's range (Chunk::correctionBegin)
    GlBuffer crossing;      // per hydro chunk: the crossing lists, one region per run
    GlBuffer counters;      // per hydro run: SegmentCounters
    GlBuffer headResults;   // per body: their double sums
    GlBuffer dryLevels;     // per body: the surface's highest point in its frame (non-flat surfaces)
    GlBuffer surfaceData;   // binding 5 of hydrostatics_surface.comp (waves or grid samples), grown on demand
    GlBuffer bodySurface;   // binding 7 of hydrostatics_surface.comp (per-body phases or grid frames), grown on demand
  };
  struct Programs {
    GlProgram classify, hydrostatics, mass, reduce, deformTriangles, deformTexels;
    GlProgram gerstner, grid, medium;  // hydrostatics_surface.comp's variants
    GlProgram deformMass;
  };

  // The body whose texels and texel sums `id` reads (itself unless an instance).
  const Body& sourceOf(BackendBodyId id) const { return bodies_[bodies_[id].source]; }

  static Status checkTextures(const SurfaceTextures& textures, std::size_t count) {
    if (textures.size() != count || textures.areaVector.size() != count || textures.area.size() != count ||
        textures.edgeU.size() != count || textures.edgeV.size() != count)
      return Error{"gpu backend: surface textures hold " + std::to_string(textures.size()) + " texels, the body has " +
                   std::to_string(count)};
    for (std::size_t i = 0; i < count; ++i)
      if (!textures.position[i].allFinite() || !textures.areaVector[i].allFinite() || !textures.edgeU[i].allFinite() ||
          !textures.edgeV[i].allFinite() || !std::isfinite(textures.area[i]))
        return Error{"gpu backend: texel " + std::to_string(i) + " has a non-finite value"};
    if (textures.momentCorrection.size() != textures.momentTexel.size() ||
        textures.momentReach.size() != textures.momentTexel.size())
      return Error{"gpu backend: " + std::to_string(textures.momentTexel.size()) + " corrected texels, " +
                   std::to_string(textures.momentCorrection.size()) + " moment corrections"};
    for (std::size_t c = 0; c < textures.momentTexel.size(); ++c) {
      if (textures.momentTexel[c] >= count || (c > 0 && textures.momentTexel[c] <= textures.momentTexel[c - 1]))
        return Error{"gpu backend: moment correction " + std::to_string(c) + " names texel " +
                     std::to_string(textures.momentTexel[c]) + " (out of range or out of order)"};
      if (!textures.momentCorrection[c].allFinite() || !(textures.momentReach[c] >= 0.0f) ||
          !std::isfinite(textures.momentReach[c]))
        return Error{"gpu backend: moment correction " + std::to_string(c) + " has a non-finite value"};
    }
    return Ok{};
  }

  // Packs and writes a body's texels, chunk bounds, mass blocks and shell sums.
  void uploadSurface(Body& body, const SurfaceTextures& textures) {
    std::vector<layout::HydroTexel> hydro(body.texelCount);
    std::vector<layout::MassTexel> mass(body.texelCount);
    body.totalVolume = body.shellArea = 0.0;
    body.sumPA.setZero();
    body.sumA.setZero();
    body.shellFirst.setZero();
    body.shellSecond.setZero();
    for (std::size_t i = 0; i < body.texelCount; ++i) {
      const Eigen::Vector3f& p = textures.position[i];
      const Eigen::Vector3f& a = textures.areaVector[i];
      const Eigen::Vector3f& u = textures.edgeU[i];
      const Eigen::Vector3f& v = textures.edgeV[i];
      hydro[i] = {p.x(), p.y(), p.z(), a.x(), a.y(), a.z(), textures.area[i], u.x(), u.y(), u.z(), v.x(), v.y(), v.z()};
      // The cone of texel i from the reference point (TextureMassIntegrator's constructor).
      const Eigen::Vector3d d = p.cast<double>() - body.referencePoint;
      const double volume = d.dot(a.cast<double>()) / 3.0;
      const double area = textures.area[i];
      mass[i] = {{float(d.x()), float(d.y()), float(d.z()), float(volume)}};
      const Eigen::Matrix3d covariance = texelCovariance(u.cast<double>(), v.cast<double>(), area);
      layout::BlockGeometry& block = blocks_[body.blockBegin + i / kMassChunkTexels];
      if (i % kMassChunkTexels == 0) block = layout::BlockGeometry{};
      const Eigen::Matrix3d cone = 0.6 * volume * covariance;
      const double terms[6] = {cone(0, 0), cone(1, 1), cone(2, 2), cone(0, 1), cone(0, 2), cone(1, 2)};
      for (int k = 0; k < 6; ++k) block.covariance[k] += terms[k];
      block.absVolume += std::abs(volume);
      body.totalVolume += volume;
      body.sumA += a.cast<double>();
      body.sumPA += p.cast<double>() * a.cast<double>().transpose();
      body.shellArea += area;
      body.shellFirst += area * d;
      body.shellSecond += area * (d * d.transpose() + covariance);
    }
    // A lid over an opening is no material (Mesh.hpp): its exact moments leave the shell, as on the CPU.
    body.lids = textures.openings.about(body.referencePoint);
    body.shellArea -= body.lids.area;
    body.shellFirst -= body.lids.first;
    body.shellSecond -= body.lids.second;
    for (std::size_t c = 0; c < body.correctionEnd - body.correctionBegin; ++c) {
      const Eigen::Matrix3f& m = textures.momentCorrection[c];
      layout::TexelCorrection& out = hydroCorrections_[body.correctionBegin + c];
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) out.moment[3 * i + k] = m(i, k);
      out.reach = textures.momentReach[c];
      body.sumPA += m.cast<double>();
    }
    for (std::uint32_t c = body.hydroChunkBegin; c < body.hydroChunkEnd; ++c) {
      layout::Chunk& chunk = hydroChunks_[c];
      const std::size_t first = hydroChunkFirst_[c];
      Eigen::Vector3d low = Eigen::Vector3d::Constant(INFINITY), high = Eigen::Vector3d::Constant(-INFINITY);
      for (std::size_t i = first; i < first + chunk.count; ++i) {
        // The patch p + s eU + t eV lies within p +- (|eU| + |eV|) / 2 per axis.
        const Eigen::Vector3d p = textures.position[i].cast<double>();
        const Eigen::Vector3d reach =
            0.5 * (textures.edgeU[i].cast<double>().cwiseAbs() + textures.edgeV[i].cast<double>().cwiseAbs());
        low = low.cwiseMin(p - reach);
        high = high.cwiseMax(p + reach);
      }
      // A corrected texel's pieces lie within its reach of p (beyond its patch where they are far apart).
      for (std::uint32_t k = 0; k < chunk.correctionCount; ++k) {
        const layout::TexelCorrection& correction = hydroCorrections_[chunk.correctionBegin + k];
        const Eigen::Vector3d p = textures.position[first + correction.texel].cast<double>();
        low = low.cwiseMin(p - Eigen::Vector3d::Constant(correction.reach));
        high = high.cwiseMax(p + Eigen::Vector3d::Constant(correction.reach));
      }
      const Eigen::Vector3d center = 0.5 * (low + high);
      // Widened by float rounding of the centre and of the shader's dot products, so that the
      // culling never drops a texel the per-texel test would keep.
      const Eigen::Vector3d half = 0.5 * (high - low) * (1.0 + 1e-5) + Eigen::Vector3d::Constant(1e-5 * center.norm() + 1e-9);
      chunk.centerX = float(center.x());
      chunk.centerY = float(center.y());
      chunk.centerZ = float(center.z());
      chunk.halfX = float(half.x());
      chunk.halfY = float(half.y());
      chunk.halfZ = float(half.z());
      hydroMoments_[body.momentBegin + (c - body.hydroChunkBegin)] =
          chunkMoments(textures, first, chunk, hydroCorrections_.data() + chunk.correctionBegin,
                       Eigen::Vector3d(chunk.centerX, chunk.centerY, chunk.centerZ));
      hydroStorage_.bufferOf(c).texels.write(
          std::size_t(chunk.begin) * sizeof(layout::HydroTexel), hydro.data() + first, chunk.count * sizeof(layout::HydroTexel));
    }
    for (std::uint32_t c = body.massChunkBegin; c < body.massChunkEnd; ++c) {
      const layout::Chunk& chunk = massChunks_[c];
      const std::size_t first = std::size_t(c - body.massChunkBegin) * kMassChunkTexels;
      massStorage_.bufferOf(c).texels.write(
          std::size_t(chunk.begin) * sizeof(layout::MassTexel), mass.data() + first, chunk.count * sizeof(layout::MassTexel));
    }
  }

  // Writes a density map beside the body's mass texels, one write per run of chunks that are
  // consecutive in one run.
  void uploadDensities(const Body& body, const std::vector<float>& densities) {
    std::uint32_t c = body.massChunkBegin;
    while (c < body.massChunkEnd) {
      std::uint32_t end = c + 1;
      while (end < body.massChunkEnd && massStorage_.chunkRun[end] == massStorage_.chunkRun[c]) ++end;
      const std::size_t first = std::size_t(c - body.massChunkBegin) * kMassChunkTexels;
      const std::size_t last = std::min(body.texelCount, std::size_t(end - body.massChunkBegin) * kMassChunkTexels);
      massStorage_.bufferOf(c).densities.write(
          std::size_t(massChunks_[c].begin) * sizeof(float), densities.data() + first, (last - first) * sizeof(float));
      c = end;
    }
  }

  // Runs a deforming body's two passes on its current vertices: triangle frames, then per chunk
  // the texels, bounds, moment corrections and moments (deform_*.comp), one dispatch per run.
  void runDeformation(const Body& body) {
    const Deformation& d = *body.deformation;
    glUseProgram(programs_.deformTriangles.id());
    d.vertices.bind(0);
    d.triangles.bind(1);
    d.frames.bind(2);
    glUniform1ui(programs_.deformTriangles.uniform("triangleCount"), d.triangleCount);
    glUniform1ui(programs_.deformTriangles.uniform("vertexCount"), d.vertexCount);
    dispatchGroups((d.triangleCount + kClassifyGroup - 1) / kClassifyGroup);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    const GlProgram& program = programs_.deformTexels;
    glUseProgram(program.id());
    tables_.hydroChunks.bind(1);
    d.frames.bind(2);
    d.pieceStart.bind(3);
    d.pieces.bind(4);
    tables_.chunkMoments.bind(5);
    d.chunkFirst.bind(6);
    tables_.corrections.bind(7);
    glUniform1ui(program.uniform("bodyChunkBegin"), body.hydroChunkBegin);
    glUniform1ui(program.uniform("triangleCount"), d.triangleCount);
    glUniform1ui(program.uniform("pieceCount"), d.pieceCount);
    // One dispatch per run of the body's chunks that read one texel buffer (binding 0).
    const auto dispatchPerSegment = [](const GlProgram& shader, const auto& storage, std::uint32_t begin,
                                       std::uint32_t endChunk) {
      for (std::uint32_t c = begin; c < endChunk;) {
        std::uint32_t end = c + 1;
        while (end < endChunk && storage.chunkRun[end] == storage.chunkRun[c]) ++end;
        storage.bufferOf(c).texels.bind(0);
        glUniform1ui(shader.uniform("chunkBase"), c - begin);
        glUniform1ui(shader.uniform("chunkCount"), end - c);
        dispatchGroups(end - c);
        c = end;
      }
    };
    dispatchPerSegment(program, hydroStorage_, body.hydroChunkBegin, body.hydroChunkEnd);
    // The mass texels and block sums from the same frames (deform_mass.comp), one dispatch per
    // run of mass chunks the body's blocks lie in.
    const GlProgram& mass = programs_.deformMass;
    glUseProgram(mass.id());
    tables_.massChunks.bind(1);
    d.massBlocks.bind(5);
    glUniform1ui(mass.uniform("bodyChunkBegin"), body.massChunkBegin);
    glUniform1ui(mass.uniform("triangleCount"), d.triangleCount);
    glUniform1ui(mass.uniform("pieceCount"), d.pieceCount);
    glUniform3f(mass.uniform("referencePoint"), float(body.referencePoint.x()), float(body.referencePoint.y()),
                float(body.referencePoint.z()));
    dispatchPerSegment(mass, massStorage_, body.massChunkBegin, body.massChunkEnd);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  }

  // A GPU-deformed body's block geometry and shell sums from its GPU mass blocks (float per
  // 256-texel block, double over blocks; 80 bytes per block are read, never the texels), into the
  // host's tables as uploadSurface would have made them from host textures.
  void readMassBlocks(Body& body) {
    std::vector<layout::MassBlock> sums(body.massChunkEnd - body.massChunkBegin);
    body.deformation->massBlocks.read(0, sums.data(), sums.size() * sizeof(layout::MassBlock));
    body.totalVolume = body.shellArea = 0.0;
    body.shellFirst.setZero();
    body.shellSecond.setZero();
    static constexpr int kPair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};  // MassBlock's order
    for (std::size_t b = 0; b < sums.size(); ++b) {
      const float* v = sums[b].value;
      layout::BlockGeometry& block = blocks_[body.blockBegin + b];
      block = layout::BlockGeometry{};
      for (int k = 0; k < 6; ++k) block.covariance[k] = v[k];
      block.absVolume = v[6];
      body.totalVolume += v[7];
      body.shellArea += v[8];
      for (int k = 0; k < 3; ++k) body.shellFirst[k] += v[9 + k];
      for (int k = 0; k < 6; ++k) {
        body.shellSecond(kPair[k][0], kPair[k][1]) += v[12 + k];
        if (kPair[k][0] != kPair[k][1]) body.shellSecond(kPair[k][1], kPair[k][0]) += v[12 + k];
      }
    }
    // A deformed body keeps the lids of its rest mesh (SurfaceBake.hpp).
    body.shellArea -= body.lids.area;
    body.shellFirst -= body.lids.first;
    body.shellSecond -= body.lids.second;
    tables_.blocks.write(body.blockBegin * sizeof(layout::BlockGeometry), blocks_.data() + body.blockBegin,
                         sums.size() * sizeof(layout::BlockGeometry));
    body.massPending = false;
  }

  // A GPU-deformed body's Sum p A^T with its corrections, from the chunk moments and centres the
  // deformation pass wrote (float per chunk, double over chunks): Sum q A^T + c Sum A^T per chunk.
  void readMoments(Body& body) {
    const std::size_t count = body.hydroChunkEnd - body.hydroChunkBegin;
    std::vector<layout::ChunkMoments> moments(count);
    std::vector<layout::Chunk> chunks(count);
    tables_.chunkMoments.read(body.momentBegin * sizeof(layout::ChunkMoments), moments.data(),
                              count * sizeof(layout::ChunkMoments));
    tables_.hydroChunks.read(body.hydroChunkBegin * sizeof(layout::Chunk), chunks.data(), count * sizeof(layout::Chunk));
    body.sumPA.setZero();
    for (std::size_t c = 0; c < count; ++c) {
      const float* m = moments[c].value;
      const Eigen::Vector3d center(chunks[c].centerX, chunks[c].centerY, chunks[c].centerZ);
      const Eigen::Vector3d sumA(m[1], m[2], m[3]);
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) body.sumPA(i, k) += double(m[4 + 3 * i + k]) + center[i] * sumA[k];
    }
    body.sumA.setZero();
    body.momentsPending = false;
  }

  // The hydrostatics chunks of a bake as (first texel, count): its tiles (contiguous texel ranges)
  // merged in order while under kHydroChunkTarget texels, a tile larger than kHydroChunkTexels
  // split. A bake without a consistent tile table is cut into runs of kHydroChunkTarget.
  static std::vector<std::pair<std::uint32_t, std::uint32_t>> hydroChunkRuns(const SurfaceBake& bake) {
    const auto count = static_cast<std::uint32_t>(bake.coveredCount());
    std::vector<std::pair<std::uint32_t, std::uint32_t>> runs;
    const bool tiled = bake.tileStart.size() >= 2 && bake.tileStart.front() == 0 && bake.tileStart.back() == count &&
                       std::is_sorted(bake.tileStart.begin(), bake.tileStart.end());
    if (!tiled) {
      for (std::uint32_t first = 0; first < count; first += kHydroChunkTarget)
        runs.emplace_back(first, std::min(kHydroChunkTarget, count - first));
      return runs;
    }
    std::uint32_t first = 0, size = 0;
    for (std::size_t t = 0; t + 1 < bake.tileStart.size(); ++t) {
      std::uint32_t begin = bake.tileStart[t];
      const std::uint32_t end = bake.tileStart[t + 1];
      if (begin == end) continue;
      if (size > 0 && size + (end - begin) > kHydroChunkTarget) {
        runs.emplace_back(first, size);
        size = 0;
      }
      for (; end - begin > kHydroChunkTexels; begin += kHydroChunkTexels) runs.emplace_back(begin, kHydroChunkTexels);
      if (size == 0) first = begin;
      size += end - begin;
    }
    if (size > 0) runs.emplace_back(first, size);
    return runs;
  }

  // The moments of the chunk's texels (from `first`) and their moment corrections (chunk's
  // correctionCount from `corrections`) about `center` (double, then float): the sums
  // TextureHydrostatics keeps per tile, taken about the chunk's centre so that float holds them
  // to its rounding whatever the body frame's origin.
  static layout::ChunkMoments chunkMoments(const SurfaceTextures& textures, std::size_t first, const layout::Chunk& chunk,
                                           const layout::TexelCorrection* corrections, const Eigen::Vector3d& center) {
    double m[32] = {};
    for (std::size_t i = first; i < first + chunk.count; ++i) {
      const Eigen::Vector3d q = textures.position[i].cast<double>() - center;
      const Eigen::Vector3d a = textures.areaVector[i].cast<double>();
      const double pairs[6] = {q.x() * q.x(), q.x() * q.y(), q.x() * q.z(), q.y() * q.y(), q.y() * q.z(), q.z() * q.z()};
      m[0] += textures.area[i];
      for (int k = 0; k < 3; ++k) {
        m[1 + k] += a[k];
        for (int row = 0; row < 3; ++row) m[4 + 3 * row + k] += q[row] * a[k];
        for (int pair = 0; pair < 6; ++pair) m[13 + 3 * pair + k] += pairs[pair] * a[k];
      }
    }
    // As core's tiles add them: q A^T gains dM, q_i q_j A_k gains q_i dM_jk + dM_ik q_j.
    static constexpr int kPairs[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (std::uint32_t c = 0; c < chunk.correctionCount; ++c) {
      const layout::TexelCorrection& correction = corrections[c];
      const Eigen::Vector3d q = textures.position[first + correction.texel].cast<double>() - center;
      for (int k = 0; k < 3; ++k) {
        for (int row = 0; row < 3; ++row) m[4 + 3 * row + k] += correction.moment[3 * row + k];
        for (int pair = 0; pair < 6; ++pair) {
          const int i = kPairs[pair][0], j = kPairs[pair][1];
          m[13 + 3 * pair + k] += q[i] * correction.moment[3 * j + k] + correction.moment[3 * i + k] * q[j];
        }
      }
    }
    layout::ChunkMoments out{};
    for (int k = 0; k < 32; ++k) out.value[k] = float(m[k]);
    return out;
  }

  // The liquids the GPU passes know (hydrostatics_flat.comp, hydrostatics_surface.comp's
  // variants); any other LiquidSurface has no shader form of its surfaceHeight or pressure.
  enum class SurfaceKind { Flat, Gerstner, Grid, Medium };

  static Expected<SurfaceKind> surfaceKind(const LiquidSurface& surface) {
    if (!surface.hasFreeSurface()) {
      if (dynamic_cast<const UniformMedium*>(&surface) != nullptr) return SurfaceKind::Medium;
    } else if (surface.flatHeight()) {
      return SurfaceKind::Flat;
    } else if (dynamic_cast<const GerstnerWaves*>(&surface) != nullptr) {
      return SurfaceKind::Gerstner;
    } else if (dynamic_cast<const HeightGrid*>(&surface) != nullptr) {
      return SurfaceKind::Grid;
    }
    return Error{"gpu backend: this liquid surface has no GPU form (flat planes, Gerstner waves, height grids and "
                 "uniform media have); use the cpu backend for it"};
  }

  // A height (m, frame) above which every point is dry, in float and never below `level`: a few
  // ulps of slack, so that float rounding never skips a wet texel.
  static float dryLevel(double level) { return float(level + 1e-6 * std::abs(level) + 1e-9); }

  // Writes what hydrostatics_surface.comp and the classification need besides the poses: per
  // asked body its dry level, and its wave phases or grid frame; the waves or grid samples. Every
  // number that is large in world units (positions, times, phases) is reduced about the body's
  // frame origin here, in double, so that the shader's float works with small ones.
  void uploadSurfaceFrames(const LiquidSurface& surface, SurfaceKind kind, std::span<const BackendHydrostaticsQuery> queries) {
    const double time = queries.empty() ? 0.0 : queries[0].query.time;
    // Bodies not asked are lifted 1e30 m (kLifted): dry under any level below that. A medium
    // wets all of an asked body.
    dryLevels_.assign(bodies_.size(), 0.0f);
    if (kind == SurfaceKind::Medium)
      for (const BackendHydrostaticsQuery& q : queries) dryLevels_[q.body] = 3.0e38f;
    std::vector<float>& data = surfaceScratch_;  // grid samples
    std::vector<float>& perBody = bodyScratch_;
    std::vector<layout::GerstnerComponent>& packedWaves = waveScratch_;
    data.clear();
    perBody.clear();
    packedWaves.clear();
    if (kind == SurfaceKind::Gerstner) {
      const auto& waves = static_cast<const GerstnerWaves&>(surface);
      const auto& components = waves.components();
      const std::size_t stride = components.size() + 2;  // hydrostatics_surface.comp's bodyWaves
      perBody.assign(bodies_.size() * stride, 0.0f);
      for (const GerstnerWaves::Component& c : components)
        packedWaves.push_back({float(c.waveNumber), float(c.dirX), float(c.dirZ), float(c.amplitude),
                               float(c.steepness * c.amplitude)});
      for (std::size_t i = 0; i < queries.size(); ++i) {
        const Eigen::Vector3d& o = origins_[i];
        const double highest = surface.heightRange(queries[i].query.time).second;
        dryLevels_[queries[i].body] = dryLevel(highest - o.y());
        float* out = perBody.data() + queries[i].body * stride;
        out[0] = float(waves.meanLevel() - o.y());
        out[1] = dryLevels_[queries[i].body];
        for (std::size_t w = 0; w < components.size(); ++w) {
          const GerstnerWaves::Component& c = components[w];
          const double theta = c.waveNumber * (c.dirX * o.x() + c.dirZ * o.z()) - c.omega * queries[i].query.time + c.phase;
          out[2 + w] = float(theta - kTwoPi * std::floor(theta / kTwoPi));
        }
      }
    } else if (kind == SurfaceKind::Grid) {
      const auto& grid = static_cast<const HeightGrid&>(surface);
      const auto [lowest, highest] = grid.heightRange(time);
      const double reference = 0.5 * (lowest + highest);
      for (double h : grid.heights()) data.push_back(float(h - reference));
      perBody.assign(bodies_.size() * sizeof(layout::GridFrame) / sizeof(float), 0.0f);
      for (std::size_t i = 0; i < queries.size(); ++i) {
        const Eigen::Vector3d& o = origins_[i];
        dryLevels_[queries[i].body] = dryLevel(highest - o.y());
        // o's grid coordinate as a whole cell and a part; a body beyond 2^30 cells is clamped to
        // the edge by the shader whatever its part.
        auto split = [&](double coordinate, int& cell, float& part) {
          const double g = std::floor(coordinate);
          const double limit = double(1 << 30);
          cell = int(std::clamp(g, -limit, limit));
          part = std::abs(g) < limit ? float(coordinate - g) : 0.0f;
        };
        layout::GridFrame frame{};
        split((o.x() - grid.originX()) / grid.spacing(), frame.cellX, frame.fracX);
        split((o.z() - grid.originZ()) / grid.spacing(), frame.cellZ, frame.fracZ);
        frame.heightOffset = float(reference - o.y());
        frame.dryLevel = dryLevels_[queries[i].body];
        std::memcpy(perBody.data() + queries[i].body * sizeof(layout::GridFrame) / sizeof(float), &frame, sizeof(frame));
      }
    }
    tables_.dryLevels.write(0, dryLevels_.data(), dryLevels_.size() * sizeof(float));
    auto fill = [](GlBuffer& buffer, const auto& values) {
      const std::size_t bytes = values.size() * sizeof(values[0]);
      if (buffer.bytes() < std::max<std::size_t>(bytes, 4)) buffer = GlBuffer(std::max<std::size_t>(bytes, 4));
      buffer.write(0, values.data(), bytes);
    };
    if (kind == SurfaceKind::Gerstner) fill(tables_.surfaceData, packedWaves);
    else fill(tables_.surfaceData, data);
    fill(tables_.bodySurface, perBody);
    // The variant's uniforms.
    if (kind == SurfaceKind::Gerstner) {
      const auto& waves = static_cast<const GerstnerWaves&>(surface);
      double horizontal = 0.0;
      for (const GerstnerWaves::Component& c : waves.components()) horizontal += std::abs(c.steepness * c.amplitude);
      glUseProgram(programs_.gerstner.id());
      glUniform1ui(programs_.gerstner.uniform("waveCount"), GLuint(waves.components().size()));
      glUniform1f(programs_.gerstner.uniform("horizontalSum"), float(horizontal));
      // Local models (hydrostatics_surface.comp) reach as far as their Taylor bound M3 rho^3 / 6
      // stays within kGpuSurfaceModelTolerance; without smoothness bounds (crests that may loop)
      // every texel is searched.
      const std::optional<SurfaceSmoothness> smooth = surface.smoothness(time);
      const bool modeled = chunkModels_ && smooth && std::isfinite(smooth->third) && smooth->third >= 0.0;
      const double reach = modeled && smooth->third > 0.0 ? std::cbrt(6.0 * kGpuSurfaceModelTolerance / smooth->third) : 1e15;
      glUniform1f(programs_.gerstner.uniform("modelReachSquared"), modeled ? float(reach * reach) : -1.0f);
    } else if (kind == SurfaceKind::Grid) {
      const auto& grid = static_cast<const HeightGrid&>(surface);
      glUseProgram(programs_.grid.id());
      glUniform1i(programs_.grid.uniform("countX"), grid.countX());
      glUniform1i(programs_.grid.uniform("countZ"), grid.countZ());
      glUniform1f(programs_.grid.uniform("inverseSpacing"), float(1.0 / grid.spacing()));
    } else {
      const auto& medium = static_cast<const UniformMedium&>(surface);
      glUseProgram(programs_.medium.id());
      glUniform1f(programs_.medium.uniform("inverseScaleHeight"),
                  std::isinf(medium.scaleHeight()) ? 0.0f : float(1.0 / medium.scaleHeight()));
    }
  }

  // The hydrostatics passes over global chunks [first, last) (the asked bodies' window), per
  // run: classification (zero, pre-summed moments, or onto the crossing list), then the texel
  // pass over the crossing list through an indirect dispatch, so that a step reads texels of
  // waterline chunks only (under a surface that is not flat: every chunk not wholly above it, through
  // the surface kind's variant of hydrostatics_surface.comp).
  void runHydrostaticsPasses(std::uint32_t first, std::uint32_t last, SurfaceKind kind) {
    for (layout::SegmentCounters& counter : counters_) counter = {0u, 1u, 1u, 0u};
    tables_.counters.write(0, counters_.data(), counters_.size() * sizeof(layout::SegmentCounters));
    tables_.hydroChunks.bind(1);
    tables_.poses.bind(2);
    tables_.partials.bind(3);
    tables_.chunkMoments.bind(5);
    tables_.crossing.bind(6);
    tables_.counters.bind(7);
    tables_.dryLevels.bind(0);
    tables_.corrections.bind(4);
    glUseProgram(programs_.classify.id());
    glUniform1i(programs_.classify.uniform("surfaceMode"), kind == SurfaceKind::Flat ? 0 : 1);
    glUniform1ui(programs_.classify.uniform("headBase"), headBase());
    const GLint base = programs_.classify.uniform("chunkBase"), count = programs_.classify.uniform("chunkCount");
    const GLint runUniform = programs_.classify.uniform("runIndex"), listUniform = programs_.classify.uniform("listBase");
    for (std::size_t s = 0; s < hydroStorage_.runs.size(); ++s) {
      const SegmentedStorage::Run& run = hydroStorage_.runs[s];
      const std::uint32_t begin = std::max(first, run.chunkBegin), end = std::min(last, run.chunkEnd);
      if (begin >= end) continue;
      glUniform1ui(base, begin);
      glUniform1ui(count, end - begin);
      glUniform1ui(runUniform, static_cast<GLuint>(s));
      glUniform1ui(listUniform, run.chunkBegin);
      dispatchGroups((end - begin + kClassifyGroup - 1) / kClassifyGroup);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    const GlProgram& texelPass = kind == SurfaceKind::Flat       ? programs_.hydrostatics
                                 : kind == SurfaceKind::Gerstner ? programs_.gerstner
                                 : kind == SurfaceKind::Grid     ? programs_.grid
                                                                 : programs_.medium;
    glUseProgram(texelPass.id());
    if (kind != SurfaceKind::Flat) {
      tables_.surfaceData.bind(5);
      tables_.bodySurface.bind(7);
    }
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, tables_.counters.id());
    const GLint listBase = texelPass.uniform("listBase");
    if (kind != SurfaceKind::Flat) glUniform1ui(texelPass.uniform("headBase"), headBase());
    for (std::size_t s = 0; s < hydroStorage_.runs.size(); ++s) {
      const SegmentedStorage::Run& run = hydroStorage_.runs[s];
      if (std::max(first, run.chunkBegin) >= std::min(last, run.chunkEnd)) continue;
      hydroStorage_.buffers[run.buffer].texels.bind(0);
      glUniform1ui(listBase, run.chunkBegin);
      glDispatchComputeIndirect(static_cast<GLintptr>(s * sizeof(layout::SegmentCounters)));
    }
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    lastWindow_ = {first, last};
  }

 public:
  // What the last hydrostatics call did (reads the counters and crossing lists back).
  GlHydrostaticsStatistics lastStatistics() {
    GlHydrostaticsStatistics out;
    if (!context_->makeCurrent() || counters_.empty()) return out;
    const auto [first, last] = lastWindow_;
    out.chunks = last - first;
    for (const SegmentedStorage::Run& run : hydroStorage_.runs)
      if (std::max(first, run.chunkBegin) < std::min(last, run.chunkEnd)) ++out.runs;
    tables_.counters.read(0, counters_.data(), counters_.size() * sizeof(layout::SegmentCounters));
    std::vector<std::uint32_t> list;
    for (std::size_t s = 0; s < counters_.size(); ++s) {
      out.crossingChunks += counters_[s].crossingGroups;
      out.submergedChunks += counters_[s].submergedChunks;
      list.resize(counters_[s].crossingGroups);
      tables_.crossing.read(std::size_t(hydroStorage_.runs[s].chunkBegin) * sizeof(std::uint32_t), list.data(),
                            list.size() * sizeof(std::uint32_t));
      for (std::uint32_t c : list) out.texelsRead += c < hydroChunks_.size() ? hydroChunks_[c].count : 0u;
    }
    out.dryChunks = out.chunks - out.crossingChunks - out.submergedChunks;
    // Classification reads every chunk's header and its body's pose; submerged chunks read their
    // moments; crossing chunks their texels.
    out.bytesRead = double(out.chunks) * double(sizeof(layout::Chunk) + sizeof(layout::BodyPose)) +
                    double(out.submergedChunks) * double(sizeof(layout::ChunkMoments)) +
                    double(out.texelsRead) * double(sizeof(layout::HydroTexel));
    return out;
  }

 private:
  // (Re)creates the small per-chunk and per-body tables after bodies were added or changed.
  void ensureTables() {
    if (!tablesDirty_) return;
    const std::size_t bodies = bodies_.size();
    poses_.assign(bodies, layout::BodyPose{});
    sums_.assign(bodies, layout::BodySums{});
    headSums_.assign(bodies, layout::BodySums{});
    hydroRanges_.resize(bodies);
    massRanges_.resize(bodies);
    for (std::size_t b = 0; b < bodies; ++b) {
      hydroRanges_[b] = {bodies_[b].hydroChunkBegin, bodies_[b].hydroChunkEnd, 0u, 0.0f};
      massRanges_[b] = {bodies_[b].massChunkBegin, bodies_[b].massChunkEnd, 2u, 0.0f};
    }
    auto upload = [](const auto& items) {
      GlBuffer buffer(items.size() * sizeof(items[0]));
      buffer.write(0, items.data(), items.size() * sizeof(items[0]));
      return buffer;
    };
    tables_.hydroChunks = upload(hydroChunks_);
    tables_.massChunks = upload(massChunks_);
    tables_.hydroRanges = upload(hydroRanges_);
    tables_.massRanges = upload(massRanges_);
    // Per chunk of a body with texels of its own: an instance's chunks read their model's entries
    // (Chunk::table).
    tables_.blocks = upload(blocks_);
    tables_.chunkMoments = upload(hydroMoments_);
    // Never an empty buffer (a body whose texels each lie on one triangle has no correction).
    if (hydroCorrections_.empty()) tables_.corrections = GlBuffer(sizeof(layout::TexelCorrection));
    else tables_.corrections = upload(hydroCorrections_);
    tables_.crossing = GlBuffer(hydroChunks_.size() * sizeof(std::uint32_t));
    tables_.counters = GlBuffer(hydroStorage_.runs.size() * sizeof(layout::SegmentCounters));
    counters_.assign(hydroStorage_.runs.size(), layout::SegmentCounters{});
    tablesDirty_ = false;
    // The fresh tables hold the host's chunk bounds and moments: bodies deformed on the GPU
    // evaluate theirs again from their kept vertices.
    for (const Body& body : bodies_)
      if (body.gpuDeformed) runDeformation(body);
    tables_.poses = GlBuffer(bodies * sizeof(layout::BodyPose));
    tables_.partials = GlBuffer(partialCount() * sizeof(layout::Partial));
    tables_.dryLevels = GlBuffer(bodies * sizeof(float));
    tables_.results = GlBuffer(bodies * sizeof(layout::BodySums));
    tables_.headResults = GlBuffer(bodies * sizeof(layout::BodySums));
    // The host reads the chunk partials back only to sum them itself (48 bytes a chunk).
    if (!finalOnGpu_) partials_.resize(std::max(hydroChunks_.size(), massChunks_.size()));
  }

  // One dispatch per run over its chunks inside [first, last) (binding 0: its buffer's texels; 4:
  // its densities). The window spans the asked bodies only.
  // Quirk (llvmpipe): an empty workgroup still costs microseconds, so a call about one body must
  // not dispatch the chunks of the 1,000 others.
  static void runSegments(const SegmentedStorage& storage, const GlProgram& program, bool withDensities,
                          std::uint32_t first, std::uint32_t last) {
    const GLint base = program.uniform("chunkBase"), count = program.uniform("chunkCount");
    for (const SegmentedStorage::Run& run : storage.runs) {
      const std::uint32_t begin = std::max(first, run.chunkBegin), end = std::min(last, run.chunkEnd);
      if (begin >= end) continue;
      const SegmentedStorage::Buffer& buffer = storage.buffers[run.buffer];
      buffer.texels.bind(0);
      if (withDensities) buffer.densities.bind(4);
      glUniform1ui(base, begin);
      glUniform1ui(count, end - begin);
      dispatchGroups(end - begin);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  }

  // Where the pressure-head partials start in tables_.partials (after every chunk's own partial).
  std::uint32_t headBase() const { return std::uint32_t(std::max(hydroChunks_.size(), massChunks_.size())); }
  // Partials in tables_.partials: every chunk's, and the pressure heads' once a surface that is not
  // flat asked for them (partialHeads_): flat water does not pay 48 bytes a hydro chunk for them.
  std::size_t partialCount() const { return headBase() + (partialHeads_ ? hydroChunks_.size() : 0); }

  // The smallest range of bodies [low, high) holding every queried one.
  static std::pair<std::uint32_t, std::uint32_t> bodyWindow(std::span<const BackendHydrostaticsQuery> queries) {
    std::uint32_t low = queries[0].body, high = queries[0].body;
    for (const BackendHydrostaticsQuery& q : queries) {
      low = std::min(low, q.body);
      high = std::max(high, q.body);
    }
    return {low, high + 1};
  }

  // Per-body double sums of the chunk partials of bodies [low, high) into sums_ and, with
  // `withHeads` (surfaces that are not flat), of the pressure-head partials into headSums_: on the
  // GPU (both reductions dispatched, then both read back after one wait) or on the CPU.
  // Sums each body's partials [low, high) and reads them back; `beforeReading` runs after the
  // passes were flushed to the GPU and before the (blocking) read, on this thread.
  Status finalSums(bool massMode, std::uint32_t low, std::uint32_t high, bool withHeads = false,
                   RunOnce* beforeReading = nullptr) {
    const std::vector<layout::BodyRange>& ranges = massMode ? massRanges_ : hydroRanges_;
    if (finalOnGpu_) {
      glUseProgram(programs_.reduce.id());
      (massMode ? tables_.massRanges : tables_.hydroRanges).bind(1);
      tables_.blocks.bind(2);
      tables_.massChunks.bind(4);  // the mass chunks' block entries (Chunk::table)
      glUniform1ui(programs_.reduce.uniform("bodyBase"), low);
      glUniform1ui(programs_.reduce.uniform("bodyCount"), high - low);
      glUniform1i(programs_.reduce.uniform("massMode"), massMode ? 1 : 0);
      tables_.partials.bind(0);
      tables_.results.bind(3);
      const GLint partialBase = programs_.reduce.uniform("partialBase");
      glUniform1ui(partialBase, 0u);
      dispatchGroups(high - low);
      if (withHeads) {
        glUniform1ui(partialBase, headBase());
        tables_.headResults.bind(3);
        dispatchGroups(high - low);
      }
      glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
      glFlush();
      if (beforeReading != nullptr) beforeReading->run();
      const std::size_t offset = low * sizeof(layout::BodySums), bytes = (high - low) * sizeof(layout::BodySums);
      tables_.results.read(offset, sums_.data() + low, bytes);
      if (withHeads) tables_.headResults.read(offset, headSums_.data() + low, bytes);
    } else {
      glFlush();
      if (beforeReading != nullptr) beforeReading->run();
      const std::uint32_t first = ranges[low].chunkBegin, last = ranges[high - 1].chunkEnd;
      auto sumOnHost = [&](std::size_t base, std::vector<layout::BodySums>& out) {
        tables_.partials.read((base + first) * sizeof(layout::Partial), partials_.data() + first,
                              (last - first) * sizeof(layout::Partial));
        for (std::size_t b = low; b < high; ++b) {
          if (massMode && ranges[b].mode == 2) continue;
          double s[12] = {};
          if (massMode) s[10] = 3.0e38;
          for (std::uint32_t c = ranges[b].chunkBegin; c < ranges[b].chunkEnd; ++c) {
            const float* v = partials_[c].value;
            if (!massMode) {
              for (int k = 0; k < 11; ++k) s[k] += v[k];
              continue;
            }
            // Same as reduce_partials.comp.
            const layout::BlockGeometry& block = blocks_[bodies_[bodies_[b].source].blockBegin + (c - ranges[b].chunkBegin)];
            const double meanDensity = ranges[b].mode == 1 ? (block.absVolume > 0.0 ? v[10] / block.absVolume : 0.0)
                                                           : double(ranges[b].uniformDensity);
            s[0] += v[0];
            for (int k = 1; k < 4; ++k) s[k] += 0.75 * v[k];
            for (int k = 4; k < 10; ++k) s[k] += 0.6 * v[k] + meanDensity * block.covariance[k - 4];
            if (!(double(v[11]) >= s[10])) s[10] = v[11];
          }
          std::copy(std::begin(s), std::end(s), out[b].value);
        }
      };
      sumOnHost(0, sums_);
      if (withHeads) sumOnHost(headBase(), headSums_);
    }
    if (const GLenum error = glGetError(); error != GL_NO_ERROR)
      return Error{"gpu backend: OpenGL error " + std::to_string(error) + " in a compute pass"};
    return Ok{};
  }

  std::unique_ptr<EglContext> context_;
  bool finalOnGpu_;
  bool chunkModels_;  // GlBackendSettings::surfaceModels
  Programs programs_;
  SegmentedStorage hydroStorage_, massStorage_;
  std::vector<layout::Chunk> hydroChunks_, massChunks_;
  std::vector<layout::BlockGeometry> blocks_;       // per mass chunk of a body with texels of its own (Body::blockBegin)
  std::vector<layout::ChunkMoments> hydroMoments_;  // per hydro chunk of such a body (Body::momentBegin)
  std::vector<layout::TexelCorrection> hydroCorrections_;  // per texel of several pieces, by hydro chunk
  std::vector<std::uint32_t> hydroChunkFirst_;      // per hydro chunk: its first texel in its body
  std::vector<layout::SegmentCounters> counters_;   // per hydro run
  std::pair<std::uint32_t, std::uint32_t> lastWindow_{0, 0};
  std::vector<float> vertexScratch_;
  std::vector<Body> bodies_;
  std::vector<layout::BodyRange> hydroRanges_, massRanges_;
  std::vector<layout::BodyPose> poses_;
  std::vector<layout::BodySums> sums_;
  std::vector<layout::BodySums> headSums_;  // per body: the pressure-head sums (surfaces that are not flat)
  std::vector<Eigen::Vector3d> origins_;     // per query of the current call: the frame origin o (m, world)
  std::vector<float> dryLevels_, surfaceScratch_, bodyScratch_;
  std::vector<layout::GerstnerComponent> waveScratch_;
  std::vector<layout::Partial> partials_;  // per chunk, with the final sum on the CPU only
  Tables tables_;
  bool tablesDirty_ = true;
  bool partialHeads_ = false;  // tables_.partials holds the pressure-head region (partialCount)
  std::uint64_t batch_ = 0;
};

}  // namespace

Expected<std::unique_ptr<ComputeBackend>> makeGlBackend(std::unique_ptr<EglContext> context,
                                                        const GlBackendSettings& settings) {
  if (!context) return Error{"gpu backend: no context given"};
  if (Status s = context->makeCurrent(); !s) return s.error();
  if (settings.finalSum == FinalSum::Gpu && !context->hasShaderFp64())
    return Error{"gpu backend: " + context->renderer() + " lacks GL_ARB_gpu_shader_fp64 for the final sum on the GPU"};
  const bool finalOnGpu = settings.finalSum == FinalSum::Gpu ||
                          (settings.finalSum == FinalSum::Automatic && context->hasShaderFp64());
  GLint maxBlock = 0;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
  std::size_t segmentBytes = std::min<std::size_t>(std::size_t(maxBlock > 0 ? maxBlock : (1 << 27)), std::size_t(1) << 28);
  if (settings.segmentBytes > 0) segmentBytes = std::min(segmentBytes, settings.segmentBytes);
  auto backend = std::make_unique<GlBackend>(std::move(context), finalOnGpu, segmentBytes, settings.surfaceModels);
  if (Status s = backend->compile(); !s) return s.error();
  return std::unique_ptr<ComputeBackend>(std::move(backend));
}

Expected<GlHydrostaticsStatistics> lastHydrostaticsStatistics(ComputeBackend& backend) {
  auto* gl = dynamic_cast<GlBackend*>(&backend);
  if (gl == nullptr) return Error{"hydrostatics statistics: backend '" + backend.name() + "' is not the GL backend"};
  return gl->lastStatistics();
}

Status enableGpuDeformation(ComputeBackend& backend, BackendBodyId body, const SurfaceBake& bake, const Mesh& mesh,
                            const UvLayout& layout) {
  auto* gl = dynamic_cast<GlBackend*>(&backend);
  if (gl == nullptr) return Error{"gpu deformation: backend '" + backend.name() + "' is not the GL backend"};
  return gl->enableDeformation(body, bake, mesh, layout);
}

Status updateVerticesOnGpu(ComputeBackend& backend, BackendBodyId body, const std::vector<Eigen::Vector3d>& positions) {
  auto* gl = dynamic_cast<GlBackend*>(&backend);
  if (gl == nullptr) return Error{"gpu deformation: backend '" + backend.name() + "' is not the GL backend"};
  return gl->updateVertices(body, positions);
}

Expected<SurfaceTextures> readGpuSurface(ComputeBackend& backend, BackendBodyId body) {
  auto* gl = dynamic_cast<GlBackend*>(&backend);
  if (gl == nullptr) return Error{"gpu backend: backend '" + backend.name() + "' is not the GL backend"};
  return gl->readSurface(body);
}

Expected<std::unique_ptr<ComputeBackend>> makeGlBackend(const GlBackendSettings& settings) {
  Expected<std::unique_ptr<EglContext>> context = EglContext::create();
  if (!context) return Error{"gpu backend: " + context.error().message};
  return makeGlBackend(std::move(context).value(), settings);
}

}  // namespace hydrotex::gpu
