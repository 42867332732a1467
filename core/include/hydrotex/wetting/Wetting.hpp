// SPDX-License-Identifier: Zlib
#pragma once
/// @file Wetting.hpp
/// One step of the liquid texture (paper section 4.2): absorption by Darcy's law (eq. 9) under the
/// liquid and from user sources (rain, a hose or splash), diffusion along the surface by Fick's law
/// on the texel graph (seams included), evaporation after Hall and Hoff (eq. 10) with a
/// constant-rate and a falling-rate stage. Stable at any time step, mass balance exact:
/// absorbed = held + evaporated, to float rounding.

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "hydrotex/wetting/DiffusionGroups.hpp"
#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/wetting/LiquidTexture.hpp"
#include "hydrotex/Pose.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/bake/TexelAdjacency.hpp"

namespace hydrotex {

/// Kinds of user liquid sources.
enum class LiquidSourceKind {
  Rain,    ///< falls along `direction` on every texel facing it (rate per horizontal area)
  Sphere,  ///< a hose or splash: every texel within `radius` of `centre` receives `rate`
};

/// Liquid supplied to the surface from outside (world frame). What a texel cannot absorb (it is
/// full) runs off and is not counted.
struct LiquidSource {
  LiquidSourceKind kind = LiquidSourceKind::Rain;  ///< rain or sphere
  double rate = 1e-6;  ///< supply (m/s of liquid depth): 1e-6 m/s = 3.6 mm/h of rain
  Eigen::Vector3d direction = Eigen::Vector3d(0.0, -1.0, 0.0);  ///< rain: direction of fall (world, normalised on use)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();             ///< sphere: centre (m, world)
  double radius = 0.1;                                          ///< sphere: radius (m)
  double pigment = 0.0;  ///< pigment volume fraction of the supplied liquid (0..1); kept when the texture has a pigment channel
};

/// Physics of the wetting step (the material is in LiquidTexture); defaults: water in air at 20 C.
struct WettingSettings {
  double diffusivity = 1e-6;        ///< D of liquid along the surface (m^2/s); fabrics 1e-7..1e-5
  double viscosity = 1e-3;          ///< mu of the liquid (Pa s); water 1e-3
  double capillaryPressure = 0.0;   ///< suction of the dry pores (Pa) added to the liquid's pressure under water
  double relativeHumidity = 0.5;    ///< ambient H (0..1); 1 stops evaporation
  double temperature = 293.15;      ///< ambient tau (K)
  double boundaryLayer = 0.005;     ///< thickness of the still air layer over the surface (m): dH/dx = (1 - H) / layer
  double criticalSaturation = 0.3;  ///< below this saturation evaporation falls (Hall and Hoff's second stage)
  double liquidDensity = 1000.0;    ///< rho_w (kg/m^3)
  double molarMass = 0.018015;      ///< M of the liquid (kg/mol); water 0.018015
  double vapourDiffusivity = 2.5e-5;  ///< D_w of the vapour in air (m^2/s); water vapour 2.5e-5
  int maxExplicitSubsteps = 4;      ///< above this many stable explicit sub-steps the step is implicit (backward Euler)
  /// Texels whose explicit stability bound A_i / (D sum_j g_ij) is below this fraction of the
  /// median texel's are merged, for diffusion only, with their most strongly coupled neighbour
  /// into one control volume (slivers at chart borders, the squeezed texels near a UV sphere's
  /// poles), until every such group meets the bound. Volume is conserved; 0 turns merging off.
  double mergeBelowFraction = 0.1;
  /// One-line reason when a value is out of range.
  Status validate() const;
  /// Hall and Hoff's constant-rate evaporation (m/s of liquid depth) for these settings.
  double evaporationRate() const;
};

/// What a step needs from the world.
struct WettingEnvironment {
  const LiquidSurface* liquid = nullptr;  ///< the liquid the body is in (may be null: in the open air)
  Pose pose;                              ///< body to world
  double time = 0.0;                      ///< s (for waves)
  double gravity = 9.81;                  ///< m/s^2
  std::vector<LiquidSource> sources;      ///< rain, hoses, splashes
};

/// Volumes moved by one step (m^3).
struct WettingStepReport {
  double absorbed = 0.0;    ///< taken in by absorption (Darcy) and from sources
  double evaporated = 0.0;  ///< lost to the air
  int diffusionSubsteps = 0;  ///< explicit sub-steps used; 0 when the implicit solve ran
  bool implicitDiffusion = false;  ///< true when backward Euler was used
  std::size_t submergedTexels = 0;  ///< texels under the liquid this step
};

/// Checks what a step is given (every backend's step calls it): `dt` finite and >= 0 (s), a
/// finite pose, positive gravity, a valid liquid surface, sources with finite non-negative rate
/// and radius and a pigment in 0..1. One-line error naming the value at fault.
Status checkWettingStep(const WettingEnvironment& environment, double dt);

/// The liquid's pressure (Pa, 0 in the air) at `count` texel centroids (m, body frame, one array
/// per coordinate) and whether each is under the liquid (1) or not (0): the per-texel pass a
/// step runs under any surface that is not flat (waves, a height grid, a medium), shared by the
/// CPU and the GPU backends so that both decide the waterline alike.
void liquidPressureAtTexels(const LiquidSurface& liquid, const WettingEnvironment& environment, const float* x,
                            const float* y, const float* z, std::size_t count, float* pressure, std::uint8_t* under);

/// Runs the liquid texture of one body. Holds the texel graph and the cached solver; per-step state
/// is the LiquidTexture the caller owns.
class Wetting {
 public:
  /// From the graph (buildTexelAdjacency) and the surface textures of the same bake (for the
  /// texels' normals). Errors: bad settings, sizes that do not match.
  static Expected<Wetting> create(TexelAdjacency adjacency, const SurfaceTextures& textures,
                                  const WettingSettings& settings);

  /// One step of `dt` seconds: absorption, sources and evaporation in one pass over the texels
  /// (a texel in the air takes its sources' liquid, then dries), then diffusion. Errors (texture size, non-finite dt or
  /// pose, invalid liquid surface) leave `texture` untouched.
  Expected<WettingStepReport> step(LiquidTexture& texture, const WettingEnvironment& environment, double dt);

  /// Absorption alone (m^3 absorbed): Darcy's law under the liquid, exact for a constant head
  /// (the back-pressure grows with saturation: dphi/dt = k P (1 - S) / (mu L)); sources up to
  /// capacity. Counts submerged texels in `submerged` and marks them in submergedMask().
  double absorb(LiquidTexture& texture, const WettingEnvironment& environment, double dt, std::size_t& submerged);
  /// Diffusion alone (conserves the held volume); returns the explicit sub-steps used (0: implicit).
  int diffuse(LiquidTexture& texture, double dt);
  /// Evaporation alone (m^3 evaporated) from texels not marked submerged by the last absorb().
  double evaporate(LiquidTexture& texture, double dt);

  /// The texel graph.
  const TexelAdjacency& adjacency() const { return adjacency_; }
  /// The settings.
  const WettingSettings& settings() const { return settings_; }
  /// Texels under the liquid at the last absorb() (1) or not (0).
  const std::vector<std::uint8_t>& submergedMask() const { return submerged_; }
  /// Largest stable explicit step (s) of the diffusion (after merging stiff texels).
  double stableTimeStep() const { return groups_.stableTimeStep(settings_.diffusivity); }
  /// Number of merged diffusion groups (of two or more texels).
  std::size_t mergedGroupCount() const { return groups_.groupCount(); }
  /// Number of texels in merged diffusion groups.
  std::size_t mergedTexelCount() const { return groups_.members.size(); }
  /// The diffusion's control volumes (merged stiff texels) and the pairs between them.
  const DiffusionGroups& diffusionGroups() const { return groups_; }

  /// Moves the solver (the cached implicit system is kept).
  Wetting(Wetting&&) noexcept;
  /// Moves the solver.
  Wetting& operator=(Wetting&&) noexcept;
  ~Wetting();

 private:
  Wetting();
  // Per-step values of the absorption / evaporation pass (float, the precision of the contents).
  struct ExchangeConstants {
    bool absorbing = false, withLiquid = false;
    float heightRow[4] = {0, 0, 0, 0};  // second row of the pose, offset by the flat surface's height
    float pressurePerDepth = 0.0f;      // rho g (Pa/m)
    float capillary = 0.0f;             // Pa
    float darcyFactor = 0.0f;           // dt / (mu L)
    float evaporationDepth = 0.0f;      // constant-rate evaporation over the step (m)
    float criticalSaturation = 0.0f;
    bool wide = false;                  // eight lanes (AVX2) instead of four
  };
  struct ExchangeTotals {
    double absorbed = 0.0, evaporated = 0.0;
    std::size_t submerged = 0;
  };
  void buildDiffusionGroups();
  template <bool Flat>
  void exchange(LiquidTexture& texture, const WettingEnvironment& environment, double dt, bool absorbing,
                bool evaporating, WettingStepReport& report);
  template <bool Flat>
  ExchangeConstants prepareExchange(const LiquidTexture& texture, const WettingEnvironment& environment, double dt,
                                    bool absorbing, bool evaporating);
  int explicitSubsteps(double dt) const;  // 0: no diffusion, -1: implicit
  template <bool Flat>
  void fusedStep(LiquidTexture& texture, const WettingEnvironment& environment, double dt, int substeps,
                 WettingStepReport& report);
  template <bool Flat>
  void exchangeRange(LiquidTexture& texture, const ExchangeConstants& constants, std::size_t begin, std::size_t end,
                     ExchangeTotals& totals);
  void poolGroups(LiquidTexture& texture) const;
  void poolGroup(LiquidTexture& texture, std::size_t group) const;
  void spreadGroups(LiquidTexture& texture) const;
  void diffuseExplicit(LiquidTexture& texture, double dt);
  template <bool WithPigment, class Ahead>
  void sweep(LiquidTexture& texture, float step, Ahead&& ahead);
  void diffuseImplicit(LiquidTexture& texture, double dt);
  void applyPairFluxes(LiquidTexture& texture);

  struct ImplicitSystem;
  TexelAdjacency adjacency_;
  WettingSettings settings_;
  // Texel centroids and unit normals (body frame), one array per coordinate so that the per-texel
  // pass streams them; normals are zero where the area vector vanishes.
  std::vector<float> px_, py_, pz_, nx_, ny_, nz_;
  std::vector<float> area_;                  // texel areas in float for the per-texel pass (m^2)
  std::vector<float> pressure_;              // scratch: liquid pressure per texel under a non-flat surface (Pa)
  std::vector<std::uint8_t> submerged_;
  // Diffusion runs on groups of texels (DiffusionGroups): most are alone; a merged group's liquid
  // is pooled into its first texel, diffused there with the group's area, and copied back.
  DiffusionGroups groups_;
  std::vector<float> inverseNodeArea_;       // 1 / groups_.nodeArea, 0 where that is 0 (1/m^2)
  std::vector<float> nextConductance_;       // D g of the pair (i, i + 1), 0 without one (m^2/s)
  std::vector<float> otherConductance_;      // D g of one other pair (i, i + otherOffset_), 0 without one (m^2/s)
  std::vector<std::uint32_t> otherOffset_;   // its index offset (0 without one)
  std::vector<std::uint32_t> extraFirst_, extraSecond_;  // any further pairs (seams), by lower texel
  std::vector<float> extraConductance_;      // their D g (m^2/s)
  std::vector<float> ring_, pigmentRing_;    // scratch: fluxes sent ahead in a sweep (m^3), power-of-two size
  struct BodySource;
  std::vector<BodySource> bodySources_;      // scratch: this step's sources in the body frame
  std::unique_ptr<ImplicitSystem> implicit_;
};

}  // namespace hydrotex
