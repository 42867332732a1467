// SPDX-License-Identifier: Zlib
#pragma once
/// @file FloatingBodySettings.hpp
/// How one rigid body floats: its mesh, resolution, mass model and the effects it pays for
/// (docs/design.md "Effects on demand"). A settings struct with defaults and validate(), as Jolt's
/// XSettings.

#include <array>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/flooding/LiquidGraphBuilder.hpp"
#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/wetting/Wetting.hpp"
#include "hydrotex/bullet/ShapeMesh.hpp"

namespace hydrotex::bullet {

/// One effect of the liquid on a body. Each is off unless listed.
enum class Effect : std::uint32_t {
  Buoyancy = 1u << 0,      ///< hydrostatic pressure force and torque (implicit stiffness)
  Drag = 1u << 1,          ///< per-patch pressure and skin-friction drag, rotational damping
  AddedMass = 1u << 2,     ///< the liquid the body must accelerate with it
  VariableMass = 1u << 3,  ///< mass model followed every step (point-mass paths, run-time changes)
  Flooding = 1u << 4,      ///< liquid enters through permeable texels into a liquid graph (FloatingBodySettings::flooding)
  Deformation = 1u << 5,   ///< vertices moved every step (callback or scale keyframes); PT/VAT re-evaluated
  Wetting = 1u << 6,       ///< liquid texture: absorption, diffusion, evaporation (FloatingBodySettings::wetting)
};

/// A set of effects (bit flags).
class EffectSet {
 public:
  /// Empty set.
  constexpr EffectSet() = default;
  /// Set holding the listed effects.
  constexpr EffectSet(std::initializer_list<Effect> effects) {
    for (Effect e : effects) bits_ |= static_cast<std::uint32_t>(e);
  }
  /// True when `effect` is listed.
  constexpr bool has(Effect effect) const { return (bits_ & static_cast<std::uint32_t>(effect)) != 0; }
  /// Lists `effect`.
  constexpr void add(Effect effect) { bits_ |= static_cast<std::uint32_t>(effect); }
  /// True when nothing is listed.
  constexpr bool empty() const { return bits_ == 0; }
  /// The raw bits (for comparisons and logs).
  constexpr std::uint32_t bits() const { return bits_; }

 private:
  std::uint32_t bits_ = 0;
};

/// The effect named `name` ("buoyancy", "drag", "added_mass", "variable_mass", "flooding",
/// "deformation", "wetting"); empty for an unknown name.
std::optional<Effect> effectFromName(std::string_view name);
/// The scene-file name of `effect`.
std::string_view effectName(Effect effect);

/// One key of a scale animation (scene key `deform: {type: "scale", keyframes: [[t, sx, sy, sz], ...]}`).
struct ScaleKeyframe {
  double time = 0.0;                               ///< s (strictly increasing)
  Eigen::Vector3d scale = Eigen::Vector3d::Ones(); ///< per-axis factor (> 0) about the mesh origin
};

/// Scale (per axis) of a keyframed animation at `time` (s): linear between keys, held outside.
/// Ones for no keys.
Eigen::Vector3d scaleAt(const std::vector<ScaleKeyframe>& keyframes, double time);

/// Moves a deforming body's vertices: given the simulated time (s) and the rest mesh (mesh frame,
/// m), writes the current positions (same count and order as rest.positions) into `positions`.
using DeformationFunction =
    std::function<void(double time, const Mesh& rest, std::vector<Eigen::Vector3d>& positions)>;

/// The liquid texture of a body that lists Effect::Wetting (paper section 4).
struct WettingBodySettings {
  /// Texels per side of the liquid texture (16..4096); 0 takes the body's resolution.
  int resolution = 0;
  /// Absorbent layer: porosity, thickness (m), permeability (m^2).
  WettingMaterial material;
  /// Diffusivity (m^2/s), ambient humidity and temperature (K), evaporation and Darcy constants.
  WettingSettings physics;
  /// Rain, hoses, splashes (world frame).
  std::vector<LiquidSource> sources;
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// How a body that lists Effect::Flooding takes on liquid (paper section 3).
struct FloodingBodySettings {
  /// Permeability map (PMT; gray levels 0..1 at the texel centres of the physics atlas): black is
  /// watertight, white lets liquid through with graph.permeability. Null: the whole surface is white,
  /// except for an open hull, whose walls are then black: liquid enters through its openings
  /// (lids, graph.openingConductance), pouring in once they go under.
  std::shared_ptr<const ImageMap> permeabilityMap;
  /// Darcy permeability of white (m^2), wall thickness (m), porosity, permeability inside, cells.
  LiquidGraphBuildSettings graph;
  /// Automatic graph: number of nodes (0: defaultLiquidGraphNodeCount of the mesh).
  int nodeCount = 0;
  /// A manual graph (mesh frame) instead of the automatic one; null: automatic.
  std::shared_ptr<const ManualLiquidGraph> manualGraph;
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// What a deformation callback (FloatingBodySettings::deformation) does to the body's collision
/// shape. Scale keyframes always scale the user's shape (setLocalScaling) instead.
enum class DeformedCollisionShape {
  /// The user's shape follows the moved vertices every step, AABBs refreshed: a
  /// btConvexHullShape whose points all sit on mesh vertices (its points are moved; it is the
  /// user's object, and keeps the last shape after removeBody), or a btGImpactMeshShape or
  /// btBvhTriangleMeshShape over a one-part vertex array holding the mesh's vertices in order
  /// (the array is rewritten and the tree refitted). These are changed in place: a shape (or
  /// array) shared with other bodies moves for them too, so give each deforming body its own.
  /// Any other shape (a primitive, a compound, a hull of other points, a scaled shape) cannot
  /// follow: addBody returns an Error naming it.
  Follow,
  /// The body collides as a convex hull of all its moved vertices, made and owned by the
  /// controller (margin: the user's shape's); the user's shape is kept aside and given back by
  /// removeBody. For primitives, and for concave bodies when a hull is good enough.
  ConvexHull,
  /// The user's shape is left as registered: it will not match the deformed mesh (as before
  /// this option existed). For a shape that is deliberately a fixed proxy.
  Keep,
};

/// Which hydrostatics path a body uses.
enum class HydrostaticsMethod {
  Texture,     ///< texel sums (any surface: flat, waves, grids, gases)
  Polyhedral,  ///< exact clipping of the triangle mesh (any surface; waves and grids linearized between vertices)
  /// Resolved at addBody to Texture or Polyhedral (the report's `method` says which), the same way
  /// on every machine and run: by core's cost model (modeledMicrosecondsPerQuery: in flat water
  /// the exact path 0.01 + 0.05 f sqrt(triangles) us, the texture path 0.9 + 0.089 f us a texel
  /// of side, f the mesh's waterline factor; under waves the exact path's counted work at a
  /// standard pose and 10 + 0.3 f a texel of side), the exact path when
  /// it is the cheaper and within `autoMethodError`, without measuring anything; otherwise core's
  /// advisor measures the texture path at the body's `resolution` against the exact path over 20
  /// poses in flat water (a bake), and the texture path is taken when its volume and
  /// centre-of-buoyancy errors stay under `autoMethodError`; else the exact path. Under waves the
  /// exact path linearizes the surface between vertices: when that error's bound (surface
  /// curvature x longest edge^2 / 8 x the largest face of the bounding box, over the volume)
  /// exceeds the target, the texture path is taken if it meets the target or errs less; under
  /// height grids (no curvature bound) likewise. A deforming body always takes Texture.
  Auto,
};

/// Everything the controller needs to float one rigid body.
struct FloatingBodySettings {
  /// The body's closed mesh in its own frame (m). This, `meshPath`, or neither: then the mesh is
  /// made from the body's own collision shape (meshFromCollisionShape, tessellated as `shape` says).
  std::shared_ptr<const Mesh> mesh;
  /// A mesh file any assimp format (used when `mesh` is empty).
  std::string meshPath;
  /// With neither mesh nor meshPath: how the body's collision shape becomes its mesh (volume
  /// error bound of round shapes, overlapping compound children).
  ShapeTessellation shape;
  /// How `meshPath` is read: up axis, scale and repairs (on by default; a defect left unrepaired
  /// is refused by addBody with one line). Not applied to `mesh`, which is used as given.
  MeshLoadSettings load;
  /// Texels per side of the bake (16..4096); 256 is a good default for game objects.
  int resolution = 256;
  /// Hydrostatics path: Auto by default (resolved once at addBody, the same on every machine; the
  /// report's `method` says which path runs); Texture or Polyhedral to choose one.
  HydrostaticsMethod method = HydrostaticsMethod::Auto;
  /// With HydrostaticsMethod::Auto: the largest error allowed of the texture path, relative to the
  /// body's volume (submerged volume) and to its bounding-box diagonal (centre of buoyancy);
  /// 1e-4 by default (> 0).
  double autoMethodError = 1e-4;
  /// Uniform solid density (kg/m^3). Exactly one of density and mass may be given; with neither,
  /// the rigid body's own mass is kept and spread uniformly. What is given is what a deforming
  /// body keeps (matter does not appear because a mesh grows): a body given by its density keeps
  /// the density, its mass following the volume.
  std::optional<double> density;
  /// Total mass (kg) of a uniform solid. A deforming body given by its mass (or by the rigid
  /// body's own mass) keeps that mass: its density follows the volume.
  std::optional<double> mass;
  /// Shell areal density (kg/m^2) over the whole surface at registration: hulls, buoys, balloon
  /// envelopes. Lids over the openings of an open hull (MeshLoadSettings::repair.openHull,
  /// Mesh::openingTriangles) have none: an open hull's mass is its shell's (and its loads'). With a shell or a density map and neither density nor mass, the body is hollow (no
  /// solid part). A deforming body's shell keeps its mass as its area stretches (a balloon's
  /// envelope gets thinner) unless the mass model is changed (MassModel::setShellDensity with
  /// Conserved::Density). A density map keeps its densities.
  double shellDensity = 0.0;
  /// Optional density map (gray levels 0..1, sampled at texel centres of the physics atlas):
  /// density densityRange[0] + level (densityRange[1] - densityRange[0]) kg/m^3 fills the cone
  /// from the centre of the mesh's bounding box to each texel, replacing `density`.
  std::shared_ptr<const ImageMap> densityMap;
  /// kg/m^3 for black and white in densityMap (both >= 0).
  std::array<double, 2> densityRange{0.0, 0.0};
  /// Concentrated masses (cargo, passengers, a basket), mesh frame; paths need Effect::VariableMass.
  std::vector<PointMass> pointMasses;
  /// With Effect::Deformation: moves the vertices every step (or use scaleKeyframes). The
  /// collision shape follows as deformedCollision says.
  DeformationFunction deformation;
  /// With a deformation function: how the collision shape follows the moved vertices.
  DeformedCollisionShape deformedCollision = DeformedCollisionShape::Follow;
  /// With Effect::Deformation: scales the mesh about its origin; the collision shape is scaled too.
  std::vector<ScaleKeyframe> scaleKeyframes;
  /// The effects this body pays for.
  EffectSet effects{Effect::Buoyancy, Effect::Drag};
  /// Drag law coefficients (used with Effect::Drag).
  DragCoefficients drag;
  /// Rotational damping (1/s): torque -this * submerged fraction * I omega, with Effect::Drag.
  /// Catches the spin of round bodies, which the pressure law does not see. Typical 0.1..1.
  double rotationalDamping = 0.3;
  /// Added-mass coefficient: m_a = this * rho * V_submerged (0.5 for a sphere), with Effect::AddedMass.
  double addedMassCoefficient = 0.5;
  /// With Effect::Wetting: the liquid texture.
  WettingBodySettings wetting;
  /// With Effect::Flooding: permeability map, Darcy constants and the liquid graph.
  FloodingBodySettings flooding;
  /// Triangle-piece (a rigid body) or texel (a deforming body) normals within this cosine are
  /// merged into one drag patch (0..1).
  double dragPatchNormalCosine = 0.9;
  /// Drag patches reach at most this fraction of the body's largest extent: a rigid body's
  /// triangle pieces are merged in grid cells at most twice this wide (meshDragPatches, no bake);
  /// a deforming body's texels from their first texel (mergeTexelsIntoDragPatches, per tile).
  /// Merging loses spin damping as this squared: 4 % of a spinning cube's drag torque at 0.2, 1 %
  /// at 0.1.
  double dragPatchRadiusFraction = 0.2;

  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

}  // namespace hydrotex::bullet
