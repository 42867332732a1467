// SPDX-License-Identifier: Zlib
#pragma once
/// @file MassModel.hpp
/// A body's mass model that may change while it moves (docs/design.md "Mass model"; paper figure 13):
/// solid density, shell areal density, a per-texel density map (replaceable at run time) and
/// point masses (cargo, passengers) that may follow linear paths. Mass, centre of mass and the
/// full inertia tensor come from one TextureMassIntegrator pass plus the point masses, and are
/// recomputed only when something changed (revision counter). A deforming body that has told the
/// model its bake and layout (followTriangles) gets the solid, shell and map from a
/// TriangleMassIntegrator instead: O(triangles) per moved mesh, exact for uniform densities.
/// When the geometry changes (setGeometry) each part keeps what its setter asked for: no matter
/// appears because a mesh grows unless the user says it does (Conserved).

#include <cstdint>
#include <optional>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/mass/TriangleMassIntegrator.hpp"

namespace hydrotex {

/// One key of a point mass's path.
struct PathKeyframe {
  double time = 0.0;                                    ///< s (strictly increasing along a path)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();   ///< m, mesh frame
};

/// A concentrated mass (no inertia of its own): cargo, a passenger, a basket.
struct PointMass {
  double mass = 0.0;                                    ///< kg (>= 0)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();   ///< m, mesh frame (used when `path` is empty)
  /// Optional path: linear between keys, held at the first key before it and at the last after it.
  std::vector<PathKeyframe> path;
  /// One line naming the first unusable value (negative mass, NaN, unordered keys), or Ok.
  Status validate() const;
};

/// Position (m) on `path` at `time` (s): linear between keys, clamped at both ends. An empty
/// path gives the origin.
Eigen::Vector3d pathPosition(const std::vector<PathKeyframe>& path, double time);

/// What a uniform part (solid or shell) keeps when the geometry changes (MassModel::setGeometry).
enum class Conserved {
  /// The density (kg/m^3 or kg/m^2): the part's mass follows the volume or area, i.e. matter is
  /// added as the body grows (a body given by its density, a growing organism).
  Density,
  /// The mass (kg): the density follows the volume or area (a body given by its mass; a balloon's
  /// envelope stretching thinner).
  Mass,
};

/// Mass model of one body, over its current surface textures. Not thread-safe; cheap to query.
class MassModel {
 public:
  /// Prepares the texel pass for `textures` with cone apex `referencePoint` (m, mesh frame). The
  /// model starts as a uniform solid of 1000 kg/m^3 with no shell and no point masses.
  MassModel(const SurfaceTextures& textures, const Eigen::Vector3d& referencePoint);

  /// Uniform solid density (kg/m^3) filling the current enclosed volume, used where no density map
  /// is set (0: hollow). `conserved` says what a later change of geometry keeps: the density
  /// (default), or the solid's mass density * volume() of now, the density then following the
  /// volume. Error for a negative or non-finite value.
  Status setSolidDensity(double density, Conserved conserved = Conserved::Density);
  /// Areal density of the current surface (kg/m^2): hulls, buoys, balloon envelopes. `conserved`
  /// says what a later change of geometry keeps: the shell's mass density * area() of now (default:
  /// an envelope that stretches gets thinner), or the areal density. Error when < 0 or NaN.
  Status setShellDensity(double density, Conserved conserved = Conserved::Mass);
  /// Replaces the density map: one density (kg/m^3) per covered texel (SurfaceTextures order),
  /// each filling the cone from the reference point to its texel. Empty: back to the uniform
  /// solid. Error when the size is not the texel count; a negative or non-finite density makes
  /// the next properties() an error (checked inside the texel pass, which costs nothing extra).
  Status setTexelDensity(std::vector<float> density);
  /// As setTexelDensity, without allocating: the new map is swapped in and `density` receives
  /// the previous one (empty when there was none), for animations that refill two buffers. On
  /// error nothing is swapped.
  Status swapTexelDensity(std::vector<float>& density);
  /// Adds a point mass; returns its index. Error from PointMass::validate().
  Expected<std::size_t> addPointMass(PointMass pointMass);
  /// Moves point mass `index` to `position` (m, mesh frame) and drops its path.
  Status setPointMassPosition(std::size_t index, const Eigen::Vector3d& position);
  /// Changes the mass (kg) of point mass `index`.
  Status setPointMassMass(std::size_t index, double mass);
  /// Moves every point mass that has a path to its position at `time` (s). Changes nothing (no
  /// new revision) when none moved.
  void advanceTo(double time);
  /// The surface moved (a deforming body): prepares the texel pass again for `textures`, which
  /// must have as many texels as before when a density map is set. The solid and the shell keep
  /// what their setters asked for (Conserved); a density map keeps its densities. Error once the
  /// model follows triangles (it then takes the moved Mesh, below).
  Status setGeometry(const SurfaceTextures& textures);
  /// For a deforming body: from now on the solid, shell and density map are summed per triangle
  /// (TriangleMassIntegrator) over `mesh` (the mesh `bake` was made of, vertices possibly moved)
  /// with `layout` (the UV layout of the bake), cones from the model's reference point. Each moved
  /// mesh (setGeometry(Mesh)) then costs O(triangles) instead of a pass over the texels, and a
  /// uniform solid or shell is exact (polyhedral). The texel pass's arrays are released. Error,
  /// changing nothing, when the bake and layout do not fit together or a density map set has
  /// another texel count; or from setGeometry(mesh).
  Status followTriangles(const SurfaceBake& bake, const UvLayout& layout, const Mesh& mesh);
  /// The mesh moved (a deforming body that follows triangles): same topology as the bake's mesh.
  /// The solid and the shell keep what their setters asked for (Conserved), as setGeometry(textures).
  /// O(triangles), allocation-free. Error when the model does not follow triangles, or from
  /// TriangleMassIntegrator::update (triangle count, an index out of range, a non-finite vertex);
  /// properties() is then an error until a valid mesh is given.
  Status setGeometry(const Mesh& mesh);
  /// True once followTriangles succeeded.
  bool followsTriangles() const { return triangles_.has_value(); }

  /// Mass properties (mesh frame) of everything together. Runs the texel pass only when the
  /// solid, shell, map or geometry changed since the last call, and combines the point masses
  /// (parallel-axis theorem) only when anything changed; otherwise returns the cached answer.
  /// Error when the total mass is not positive.
  Expected<MassProperties> properties();

  /// True when the next properties() would run a texel pass (TextureMassIntegrator::evaluate of
  /// texelModel() over this model's texels): the solid, shell, map or geometry changed since the
  /// last evaluation, and the model does not follow triangles (whose per-triangle sums are no
  /// pass over texels: properties() evaluates them, O(1) after setGeometry(Mesh)). A caller that
  /// batches the passes of many bodies (a ComputeBackend holding the same texels, core's
  /// MassModelsStep) runs it elsewhere and hands the answer to finish().
  bool needsTexelPass() const { return !triangles_ && evaluatedDistributed_ != distributedRevision_; }
  /// What the texel pass integrates: solid and shell density, the density map (kg/m^3 per texel,
  /// SurfaceTextures order; empty: the uniform solid) and the cones' apex (m, mesh frame).
  const TextureMassModel& texelModel() const { return distributed_; }
  /// Lends texelModel() to a batch that needs many models side by side (a ComputeBackend's
  /// span, core's MassModelsStep) without copying the map: `batch` receives the densities and the
  /// reference point, and the map is swapped into it (`batch`'s own map, any, comes in its place).
  /// Give it back with takeBackTexelModel(batch) before any other call on this model.
  void lendTexelModel(TextureMassModel& batch);
  /// Takes back the map lendTexelModel() swapped into `batch` (swapped out again: `batch` gets
  /// back what it held). Nothing else changes: no new revision.
  void takeBackTexelModel(TextureMassModel& batch);
  /// properties() with the texel pass run elsewhere: `texelPart` is TextureMassIntegrator::evaluate
  /// of texelModel() over the same texels and reference point (an equal integrator gives equal
  /// bits). Counted in texelPasses(); the point masses are combined as properties() does. Error
  /// (nothing stored) when no texel pass is due (needsTexelPass() false), `texelPart` is not
  /// finite, or the total mass is not positive.
  Expected<MassProperties> finish(const MassProperties& texelPart);

  /// Increases by one with every change that alters the mass properties.
  std::uint64_t revision() const { return revision_; }
  /// Texel passes run so far (the expensive part): the texel path's evaluation (here, or handed
  /// to finish()), or, following triangles, a new density map's pass over the texel pieces.
  std::uint64_t texelPasses() const { return texelPasses_; }
  /// Evaluations of the solid, shell and map from the per-triangle sums (following triangles;
  /// O(1) after setGeometry(Mesh)'s O(triangles) pass).
  std::uint64_t trianglePasses() const { return trianglePasses_; }
  /// Times properties() combined the parts (any change), cheap compared to a texel pass.
  std::uint64_t combinations() const { return combinations_; }
  /// Point masses, in the order they were added.
  const std::vector<PointMass>& pointMasses() const { return pointMasses_; }
  /// Uniform solid density (kg/m^3) of the current geometry.
  double solidDensity() const { return distributed_.solidDensity; }
  /// Shell areal density (kg/m^2) of the current geometry.
  double shellDensity() const { return distributed_.shellDensity; }
  /// What the solid keeps when the geometry changes.
  Conserved solidConserved() const { return solidConserved_; }
  /// What the shell keeps when the geometry changes.
  Conserved shellConserved() const { return shellConserved_; }
  /// Enclosed volume (m^3) of the current geometry.
  double volume() const { return triangles_ ? triangles_->volume() : integrator_.volume(); }
  /// Surface area (m^2) of the current geometry that carries the shell (lids over openings excluded).
  double area() const { return triangles_ ? triangles_->area() : integrator_.area(); }
  /// Increases with every setGeometry(textures) (the texels the texel pass integrates moved): a
  /// caller that registered this model's texels elsewhere (a ComputeBackend) knows when its copy
  /// no longer fits.
  std::uint64_t geometryRevision() const { return geometryRevision_; }
  /// Number of covered texels (the size a density map must have).
  std::size_t texelCount() const { return triangles_ ? triangles_->texelCount() : integrator_.size(); }

 private:
  /// The solid, shell and map part from the triangle path (a new map first costs a piece pass).
  Expected<MassProperties> evaluateTriangles();
  /// The geometry changed: the densities of the parts that keep their mass follow it.
  void conserveMasses();
  /// The solid, shell and map part (distributedProperties_) and the point masses together.
  Expected<MassProperties> combine();

  TextureMassIntegrator integrator_;
  std::optional<TriangleMassIntegrator> triangles_;  // set by followTriangles
  bool mapPending_ = false;  // the map changed since it was handed to triangles_
  Eigen::Vector3d referencePoint_;
  TextureMassModel distributed_;
  std::vector<PointMass> pointMasses_;
  Conserved solidConserved_ = Conserved::Density;
  Conserved shellConserved_ = Conserved::Mass;
  double solidMass_ = 0.0;  // kg, kept when solidConserved_ is Mass
  double shellMass_ = 0.0;  // kg, kept when shellConserved_ is Mass
  MassProperties distributedProperties_;
  MassProperties combined_;
  std::uint64_t revision_ = 1;
  std::uint64_t distributedRevision_ = 1;  // revision of the last change to the texel part
  std::uint64_t evaluatedDistributed_ = 0; // revision at which distributedProperties_ was computed
  std::uint64_t evaluatedCombined_ = 0;    // revision at which combined_ was computed
  std::uint64_t texelPasses_ = 0;
  std::uint64_t trianglePasses_ = 0;
  std::uint64_t combinations_ = 0;
  std::uint64_t geometryRevision_ = 0;
};

}  // namespace hydrotex
