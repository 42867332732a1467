// SPDX-License-Identifier: Zlib
#pragma once
/// @file ComputeBackend.hpp
/// One interface for the per-step texel passes (docs/design.md "Backends"): a CPU implementation here in
/// core and a GL compute implementation in hydrotex::gpu, with the same inputs and the same
/// outputs, so that every backend runs the same test bodies. Bodies are registered once (their
/// baked surface); each step asks for many bodies at once (batched) and gets every answer back
/// together.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/bake/TexelAdjacency.hpp"
#include "hydrotex/flooding/LiquidGraph.hpp"
#include "hydrotex/wetting/LiquidTexture.hpp"
#include "hydrotex/wetting/Wetting.hpp"

namespace hydrotex {

/// Index of a body registered with a backend (0, 1, 2, ... in the order of addBody).
using BackendBodyId = std::uint32_t;

/// One body's hydrostatics question inside a batch.
struct BackendHydrostaticsQuery {
  BackendBodyId body = 0;        ///< as returned by ComputeBackend::addBody
  HydrostaticsQuery query;       ///< pose, gravity, centre of mass, time, mass
};

/// One body's liquid texture stepped by a backend (ComputeBackend::makeWetting): core's Wetting
/// on the CPU, the GL compute one (GlWetting) on the GPU, with the same equations.
class BackendWetting {
 public:
  virtual ~BackendWetting() = default;
  /// One step of `dt` seconds, as Wetting::step, of the liquid in `texture` (a GPU uploads it at
  /// the first step and keeps it resident after: `texture` is current again after sync()).
  virtual Expected<WettingStepReport> step(LiquidTexture& texture, const WettingEnvironment& environment, double dt) = 0;
  /// Brings `texture` up to date with the liquid the steps left (a GPU copies it back; the CPU's
  /// texture is always current). Called only when someone reads the texture, not every step.
  virtual Status sync(LiquidTexture& texture) = 0;
  /// Whether step() may run on any thread, beside other bodies' steps (the CPU's); false for a
  /// backend that must be driven from the thread that owns its context (the GL one).
  virtual bool threadSafe() const = 0;
};

/// A compute backend: holds the baked texels of many bodies and answers batched per-step passes.
/// Not thread-safe: one thread drives a backend (the GL one owns a GL context).
class ComputeBackend {
 public:
  virtual ~ComputeBackend() = default;

  /// Short name: "cpu" or "gpu".
  virtual std::string name() const = 0;
  /// What runs the passes: "CPU" for the CPU backend, the GL_RENDERER string for the GL one
  /// (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)", "NVIDIA H100 80GB HBM3/PCIe/SSE2").
  virtual std::string renderer() const = 0;

  /// Registers a body from its exact bake and surface textures (body frame). The cone apex of the
  /// mass pass is `massReferencePoint` (m, body frame; the body's centroid keeps float rounding
  /// lowest). Errors: textures that do not match the bake, non-finite texels, an empty bake.
  virtual Expected<BackendBodyId> addBody(const SurfaceBake& bake, const SurfaceTextures& textures,
                                          const Eigen::Vector3d& massReferencePoint) = 0;

  /// Replaces a body's surface textures (a deforming mesh re-evaluated with evaluateSurface from
  /// the same bake). Errors: unknown body, texel count differs from the registered one.
  virtual Status updateSurface(BackendBodyId body, const SurfaceTextures& textures) = 0;

  /// Number of registered bodies.
  virtual std::size_t bodyCount() const = 0;

  /// Registers a body that shares the texels of registered body `of` (the same bake, surface and
  /// mass reference point; a crate of a kind), read-only: its own id, no copy of the texels.
  /// updateSurface on either is then refused (and, on the GL backend, GPU deformation and density
  /// maps, which live beside the shared texels). Errors: unknown body; a backend that does not
  /// share (the default) says so, and the caller registers the body with addBody instead.
  virtual Expected<BackendBodyId> addInstance(BackendBodyId of) {
    (void)of;
    return Error{name() + " backend: does not share bodies' texels (addInstance); register the body with addBody"};
  }

  /// Frees what a body holds, when its owner no longer asks for it (a controller's removeBody).
  /// Its id stays taken, and asking for it afterwards is an error of the pass that asks. The
  /// default keeps everything (the GL backend packs all bodies in shared buffers and keeps their
  /// slots until it is destroyed).
  virtual void releaseBody(BackendBodyId body) { (void)body; }

  /// Hydrostatics of every queried body in `surface`, one result per query (same order).
  /// `meanwhile` (may be empty) runs exactly once on the calling thread, whatever the outcome, while
  /// the batch is in flight: a GPU backend calls it after submitting its passes and before reading
  /// the results back, so that the caller's CPU work (the drag) overlaps them; the CPU backend
  /// after its batch. Errors (nothing is written then): `results` shorter than `queries`, an
  /// unknown body, a body asked twice in one batch, an invalid query or surface
  /// (validateHydrostaticsQuery).
  virtual Status hydrostatics(const LiquidSurface& surface, std::span<const BackendHydrostaticsQuery> queries,
                              std::span<HydrostaticsResult> results, const std::function<void()>& meanwhile) = 0;
  /// The same with nothing to run meanwhile.
  Status hydrostatics(const LiquidSurface& surface, std::span<const BackendHydrostaticsQuery> queries,
                      std::span<HydrostaticsResult> results) {
    return hydrostatics(surface, queries, results, {});
  }

  /// Texture mass properties of `bodies[i]` made of `models[i]` (TextureMassIntegrator's
  /// formulas; the models' referencePoint is ignored: the registered one is used). Errors: spans
  /// of different sizes or `results` too short, an unknown body, a density map of the wrong size
  /// or with negative or non-finite densities, negative or non-finite densities.
  virtual Status massProperties(std::span<const BackendBodyId> bodies, std::span<const TextureMassModel> models,
                                std::span<MassProperties> results) = 0;

  /// A liquid texture solver for one body on this backend, from the texel graph and the surface
  /// textures of its wetting bake (buildTexelAdjacency, evaluateSurface) and `settings`. Errors:
  /// those of Wetting::create (bad settings, sizes that do not match), and the backend's own.
  virtual Expected<std::unique_ptr<BackendWetting>> makeWetting(TexelAdjacency adjacency,
                                                                const SurfaceTextures& textures,
                                                                const WettingSettings& settings) = 0;

  /// The pass over `graph`'s permeable texels a flooding body's steps hand to LiquidGraph::step on
  /// this backend: null for the CPU (the graph's own vectorized loop), the GL compute one on the
  /// GPU (under a flat surface; the graph's loop under others). `graph`'s texels are copied.
  virtual Expected<std::unique_ptr<FloodingTexelPass>> makeFloodingPass(const LiquidGraph& graph) = 0;
};

/// Core's Wetting as a BackendWetting (thread-safe): the CPU backend's makeWetting.
Expected<std::unique_ptr<BackendWetting>> makeCpuWetting(TexelAdjacency adjacency, const SurfaceTextures& textures,
                                                         const WettingSettings& settings);

/// Runs work(i) once for every i in [0, count), on as many threads as it likes, and returns when
/// all calls have returned (a controller hands the CPU backend its own threads this way).
using ParallelFor = std::function<void(std::size_t count, const std::function<void(std::size_t)>& work)>;

/// The CPU backend: TextureHydrostatics (tile hierarchy) and TextureMassIntegrator per body. The
/// bodies of one batch are computed through `parallelFor` (empty: one after the other); each
/// body's answer depends only on its own data, so the results are the same for every thread count.
std::unique_ptr<ComputeBackend> makeCpuBackend(ParallelFor parallelFor = {});

/// The wetted-surface sums of one body under a flat surface at height h, in the world frame
/// translated to o = (t_x, h, t_z) (t the body's translation), accumulated over texels or
/// triangles exactly as core's texture path does (HydrostaticSums.hpp, derivation there). Lets a
/// backend that accumulates them elsewhere (a GPU) finish with the same code as the CPU.
struct FlatWettedSums {
  double sumDAy = 0.0;     ///< Sum D A_y (m^3); the submerged volume is its negative
  double sumDXAy = 0.0;    ///< Sum D x' A_y (m^4)
  double sumDZAy = 0.0;    ///< Sum D z' A_y (m^4)
  double sumYB = 0.0;      ///< Sum (Q / 2) A_y (m^4), Q the mean squared depth term
  double sumAy = 0.0;      ///< Sum frac A_y (m^2)
  double sumXAy = 0.0;     ///< Sum frac x' A_y (m^3)
  double sumZAy = 0.0;     ///< Sum frac z' A_y (m^3)
  double sumXXAy = 0.0;    ///< Sum frac x'^2 A_y (m^4)
  double sumXZAy = 0.0;    ///< Sum frac x' z' A_y (m^4)
  double sumZZAy = 0.0;    ///< Sum frac z'^2 A_y (m^4)
  double wettedArea = 0.0; ///< Sum frac |A| (m^2)
};

/// The HydrostaticsResult of a body under a flat surface at `surfaceHeight` (m) of `density`
/// (kg/m^3) from its wetted sums: Archimedes force, centre of buoyancy, torques, water plane and
/// stiffness, exactly as TextureHydrostatics::query assembles them. `query` must be valid.
HydrostaticsResult finishFlatHydrostatics(const FlatWettedSums& sums, double surfaceHeight, double density,
                                          const HydrostaticsQuery& query);

/// The pressure sums of one body under a surface that is not a flat plane (waves, a height grid,
/// a medium), in the world frame translated to the frame origin o: core's texture path integrates
/// the pressure texel by texel there (TextureHydrostatics.cpp) instead of using Archimedes' force.
struct PressureSums {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< -Sum p A (N)
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< -Sum x' x p A (N m) about o
};

/// The HydrostaticsResult of a body from its wetted sums under waves, a height grid
/// (`hasWaterplane` true; `sums.sumYB` then holds Sum (Q/2 - h' D) A_y, h' the local surface
/// height above o_y) or a medium without a free surface (`hasWaterplane` false, o = the body's
/// translation), exactly as TextureHydrostatics::query assembles them. `origin` is o (m, world),
/// `density` the surface's nominal density (kg/m^3); `query` must be valid.
HydrostaticsResult finishPressureHydrostatics(const FlatWettedSums& sums, const PressureSums& pressure,
                                              const Eigen::Vector3d& origin, double density,
                                              const HydrostaticsQuery& query, bool hasWaterplane);

}  // namespace hydrotex
