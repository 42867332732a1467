// SPDX-License-Identifier: Zlib
#pragma once
/// @file Advisor.hpp
/// What accuracy costs in time, measured on one mesh: the texture path (at a resolution, with the
/// tile hierarchy or by brute force) against the exact polyhedral path over a sample of depths and
/// orientations in a flat liquid, with the time per query. adviseHydrostatics() picks the cheapest
/// (method, resolution) under an error target (`hydrotex advise`); the pieces it is made of
/// (sampling, error measures, timing) serve the accuracy report (demos/report) as well.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex {

/// A way of answering a hydrostatics query.
enum class HydrostaticsMethod {
  Exact,              ///< polyhedralHydrostaticsUnchecked on the mesh (the reference)
  TextureHierarchy,   ///< TextureHydrostatics::query with TexelTraversal::Hierarchy
  TextureBruteForce,  ///< TextureHydrostatics::query with TexelTraversal::BruteForce
};

/// "exact", "texture-hierarchy" or "texture-brute-force".
std::string methodName(HydrostaticsMethod method);

/// Which poses of a body the measurements sample. The body sits in a flat surface at y = 0.
struct QuerySampling {
  /// Water levels per orientation, at (i + 1) / (depthCount + 1) of the rotated body's vertical
  /// extent (never wholly dry nor wholly submerged, where both paths are exact). At least 1.
  int depthCount = 5;
  /// Orientations: the first is the mesh as modelled, the others fixed tilts (see the .cpp). 1..8.
  int orientationCount = 4;
};

/// The sample of queries: for each orientation, each depth (depth varies fastest). The centre of
/// mass is the mesh's volume centroid (m, body frame). Empty for an empty mesh or bad sampling.
std::vector<HydrostaticsQuery> sampleHydrostaticsQueries(const Mesh& mesh, const QuerySampling& sampling);

/// Length of the diagonal of the mesh's axis-aligned bounding box (m): the "size" that centre
/// errors are relative to. 0 for an empty mesh.
double meshSize(const Mesh& mesh);

/// What errors are relative to.
struct ErrorScales {
  double totalVolume = 1.0;   ///< enclosed volume of the body (m^3)
  double size = 1.0;          ///< meshSize() (m)
  double density = 1000.0;    ///< liquid density (kg/m^3)
  double gravity = 9.81;      ///< m/s^2
};

/// Relative errors of one hydrostatics answer against a reference answer (dimensionless).
struct HydrostaticsErrors {
  double volume = 0.0;            ///< |V - V_ref| / total volume
  double centerOfBuoyancy = 0.0;  ///< |B - B_ref| / size
  double force = 0.0;             ///< |F - F_ref| / (rho g total volume)
  /// The larger of the volume and centre-of-buoyancy errors: what the advisor keeps under target.
  double worst() const { return volume > centerOfBuoyancy ? volume : centerOfBuoyancy; }
  /// Component-wise maximum with `other`.
  void keepMax(const HydrostaticsErrors& other);
};

/// Errors of `answer` against `reference` (see HydrostaticsErrors) with the given scales.
HydrostaticsErrors hydrostaticsErrors(const HydrostaticsResult& answer, const HydrostaticsResult& reference,
                                      const ErrorScales& scales);

/// Relative errors of mass properties against a reference (dimensionless).
struct MassErrors {
  double mass = 0.0;           ///< |m - m_ref| / m_ref
  double centerOfMass = 0.0;   ///< |c - c_ref| / size
  double inertia = 0.0;        ///< ||I - I_ref||_F / ||I_ref||_F (about the centre of mass)
};

/// Errors of `answer` against `reference`, centre of mass relative to `size` (m).
MassErrors massErrors(const MassProperties& answer, const MassProperties& reference, double size);

/// How times are taken.
struct TimingSettings {
  int runs = 5;                  ///< timed batches; the median is reported (>= 1)
  double batchSeconds = 0.02;    ///< wall time each batch aims at (s)
  /// Time nothing: each candidate's time is modeledMicrosecondsPerQuery's, so that a choice made
  /// from it is the same on every machine and every run (HydrostaticsMethod::Auto's).
  bool modeled = false;
};

/// A model of the time of one query (us), for choices that must not depend on the machine or its
/// load, in flat water or (`waves`) under Gerstner waves, for a mesh of T triangles at R texels a
/// side whose waterline is `waterlineFactor` (f >= 1, waterlineFactor()) times a sphere's for its
/// surface. Both paths visit what the waterline crosses: the exact path (a PreparedPolyhedron,
/// what a body stepped by the controller runs) its triangles there, about f sqrt(T) of them, the
/// texture path's tile hierarchy its tiles, about f R. In flat water 0.01 + 0.05 f sqrt(T) and
/// 0.9 + 0.089 f R: fitted (least squares on relative error) at a body tilted 6 and 2 degrees,
/// floating at its centre of mass, median of batches (2-core reference machine, 2026-11-28, after
/// the flat walk's hierarchy halved across the height): exact 0.22 us (box), 0.92 (320-face hull),
/// 2.1 (1,280-face icosphere), 7.6 (Wigley hull, 4,222, f = 2.44), 5.2 (17,160-face sphere), 7.8
/// (20,480-face icosphere), 9.1 (32,256), 15.9 (81,920), within 25 % (mean 8 %); the hierarchy at
/// 64^2 / 128^2 / 256^2 6.0 / 11.5 / 21.0 (box), 8.3 / 13.3 / 23.6 (hull), 9.2 / 14.9 / 25.9
/// (icosphere), 18.9 / 33.9 / 58.5 (Wigley), 5.8 / 13.8 / 25.4 (17,160), 5.9 / 13.9 / 27.4
/// (32,256), 10.6 / 19.5 / 36.1 (3 m log, f = 1.75), within 29 % (mean 13 %). (The earlier 0.2 +
/// 0.13 sqrt(T) and 2 + 0.12 R, without f, put the Wigley hull's exact query at 8.6 against 7.6
/// and its texture one at 256^2 at 33 against 58.) Under waves 30 + 0.35 sqrt(T) for the exact
/// path (Auto prices it by its counted work instead, modeledExactMicroseconds) and 10 + 0.3 f R
/// for the hierarchy, fitted as above under bench_peers' three waves: exact 38 us (box), 34
/// (320-face hull), 33 (1,280-face icosphere), 144 (Wigley hull), 65 (17,160-face sphere), 90
/// (20,480-face icosphere), 98 (32,256), 119 (65,024); the hierarchy 22-38 us at 64^2, 27-52 at
/// 128^2, 48-92 at 256^2. The brute force, every texel: 10 + 0.0045 R^2, under waves 100 + 0.055
/// R^2 (the 1,280-face icosphere 31 / 339, 93 / 1,101, 298 / 3,689 us at 64^2, 128^2, 256^2).
/// A ranking, not a prediction of one machine's time.
double modeledMicrosecondsPerQuery(HydrostaticsMethod method, std::size_t triangles, int resolution, bool waves = false,
                                   double waterlineFactor = 1.0);

/// How much longer than a sphere's the waterline of `mesh` is for its surface area: the tile
/// hierarchy's tiles along the waterline number about R L / sqrt(A) (L the waterline's length, A
/// the area the atlas covers), sqrt(pi) R for a sphere, so the factor is L / sqrt(pi A), at least
/// 1, with L taken upright at the mid height of its bounds. A sphere 1, the 1 x 0.5 x 1 m box 1.13,
/// a 3 m log 1.75, the 4 m Wigley hull 2.44 (its texture path under waves: 252 us measured at
/// 256^2, modeledMicrosecondsPerQuery's figures above, where 10 + 0.3 R gave 87).
double waterlineFactor(const Mesh& mesh);

/// The modeled time (us) of an exact query on a prepared mesh that did `work` under waves: each
/// unit of work at its cost, 0.05 a node visited, 0.10 a local model, 0.045 a triangle clipped,
/// 0.31 a height asked of the surface itself, 0.19 a jet sampled and 0.05 a sampled piece (not
/// fitted: about 520 instructions a piece besides its jets in callgrind, half a model's). Fitted (least squares on
/// relative error) to 30 (mesh, sea) pairs: box, 162-vertex hull, Wigley hull, ship, log, buoys,
/// torus and spheres of data/meshes under bench_peers' swell, log_waves' and the tests' steep sea,
/// 100 poses each (2-core reference machine, 2026-11): within 14 % of the measured time on average,
/// 45 % at worst, where modeledMicrosecondsPerQuery's 30 + 0.35 sqrt(T) put the 192-triangle log at
/// 35 us against 267-416 and the ship under the steep sea at 58 against 6,700. A ranking, as that.
double modeledExactMicroseconds(const ExactWaveWork& work);

/// The modeled time (us) of an exact query on `body` under `surface`: under a surface that the
/// prepared path models (smoothness bounds: Gerstner waves) the mean over four queries of
/// modeledExactMicroseconds of their work, the body upright with the centre of its bounds at the
/// origin on the surface's mid height, at 0, 1, 2 and 3 s (deterministic: no timing); elsewhere
/// modeledMicrosecondsPerQuery's. Errors: those of the queries.
Expected<double> modeledExactMicroseconds(const PreparedPolyhedron& body, const LiquidSurface& surface);

/// Median over `settings.runs` batches of the mean wall time of one call of `work` (s), on the
/// calling thread, after one warm-up call. A batch holds as many calls as fit in batchSeconds
/// (at least one), so a slow `work` costs about runs + 2 calls.
double medianSecondsPerCall(const std::function<void()>& work, const TimingSettings& settings = {});

/// One measured (method, resolution) on one mesh.
struct MethodMeasurement {
  HydrostaticsMethod method = HydrostaticsMethod::Exact;
  int resolution = 0;                 ///< texels per side; 0 for the exact path
  HydrostaticsErrors maxErrors;       ///< worst over the sampled queries
  double microsecondsPerQuery = 0.0;  ///< median (see medianSecondsPerCall), mean over the sample
  std::size_t bytes = 0;              ///< data the query reads: packed texels and tiles, or the mesh
};

/// Answers one query (any method); the measuring code times and compares through it.
using HydrostaticsAnswer = std::function<Expected<HydrostaticsResult>(const HydrostaticsQuery&)>;

/// Runs `answer` over `queries`, compares each with `references` (same order) and times a pass
/// over the whole sample. Error when the sizes differ or the sample is empty, or the first failing
/// answer's message.
Expected<MethodMeasurement> measureMethod(const HydrostaticsAnswer& answer, const std::vector<HydrostaticsQuery>& queries,
                                          const std::vector<HydrostaticsResult>& references,
                                          const ErrorScales& scales, const TimingSettings& timing);

/// Bytes a texture query reads: packed texels, moment corrections, tiles and groups (lower bound
/// on what is held).
std::size_t textureHydrostaticsBytes(const TextureHydrostatics& texture);
/// Bytes of the mesh the exact path reads: positions and triangles.
std::size_t meshBytes(const Mesh& mesh);

/// What the advisor sweeps.
struct AdvisorSettings {
  std::vector<int> resolutions = {32, 64, 128, 256, 512, 1024, 2048};  ///< texels per side, tried in increasing order
  QuerySampling sampling;                    ///< depths and orientations
  TimingSettings timing;                     ///< per candidate
  bool includeBruteForce = false;            ///< also try TexelTraversal::BruteForce (same errors, never faster on a flat surface)
  double density = 1000.0;                   ///< liquid density (kg/m^3)
};

/// The advisor's answer: the cheapest candidate under the target and all that were measured.
struct Advice {
  MethodMeasurement best;                    ///< lowest time among those whose worst() <= target
  std::vector<MethodMeasurement> candidates; ///< exact first, then the texture ones in sweep order
  double targetError = 0.0;                  ///< as asked
};

/// Measures the exact path and the texture path at increasing resolutions on `mesh` over the sampled
/// queries, and returns the cheapest (method, resolution) whose relative volume and centre-of-
/// buoyancy errors stay under `targetError` at every sampled query. The exact path always meets it,
/// so there is always an answer. The sweep stops at the first texture resolution that meets the
/// target, or once the texture path is slower than the exact one (time grows with resolution).
/// Errors: a target that is not positive and finite, an open or empty mesh, a resolution out of
/// range, an invalid sampling.
Expected<Advice> adviseHydrostatics(const Mesh& mesh, double targetError, const AdvisorSettings& settings = {});

/// An upper bound of |d2 h / ds2| (1/m) of `surface`'s height over every point and direction: 0
/// for a flat surface or a medium, sum A k^2 / (1 - sum Q k A)^2 for Gerstner waves (the
/// trochoid's curvature at its crests, where the horizontal squeeze 1 - Q k A is smallest);
/// empty when unknown (height grids and other surfaces: their kinks have no bound).
std::optional<double> surfaceCurvatureBound(const LiquidSurface& surface);

/// Relative volume error (of the body's volume) that the exact path's linearization of `surface`
/// between the mesh's vertices may make: M2 e^2 / 8 (the largest height error of the linear
/// interpolant over an edge of length e, M2 = surfaceCurvatureBound), plus kExactWaveHeightError
/// (the vertices' heights may be interpolated), times the body's largest
/// bounding-box face (a bound of its water-plane area), over its volume. 0 under a flat surface
/// or a medium; +infinity when the curvature is unknown.
double exactLinearizationError(const Mesh& mesh, double volume, const LiquidSurface& surface);

/// Relative error (of the body's volume), beyond its flat-water exactness, of the exact path on a
/// prepared mesh (PreparedPolyhedron: what the controller runs) under `surface` at `time` (s): 0
/// under a flat surface or a medium, and under a surface with smoothness bounds (Gerstner waves),
/// where it takes the surface from local models as the texture path does (their error, which both
/// paths carry and neither bound counts, is measured by test_polyhedral_hydrostatics_waves: within
/// 4.4e-5 V of the per-texel answer, and by test_texture_hydrostatics_waves for the texture path);
/// else exactLinearizationError (height grids: +infinity).
double preparedExactSurfaceError(const Mesh& mesh, double volume, const LiquidSurface& surface, double time = 0.0);

}  // namespace hydrotex
