// SPDX-License-Identifier: Zlib
#pragma once
// Per-body state of the controller: what was baked at registration (read-only afterwards) and the
// pieces of Bullet it changed (compound shape, frames). Private to the plugin.

#include <btBulletDynamicsCommon.h>

#include <memory>
#include <optional>
#include <vector>

#include "hydrotex/flooding/LiquidGraph.hpp"
#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/bake/SurfaceEvaluator.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/step/MassModelsStep.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"
#include "hydrotex/wetting/Wetting.hpp"
#include "DeformedCollision.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"

namespace hydrotex::bullet {

/// What a deforming body keeps to re-evaluate its surface every step (only for Effect::Deformation).
struct DeformationState {
  Mesh rest;                            ///< the mesh as registered (mesh frame, m)
  std::shared_ptr<Mesh> current;        ///< moved vertices, same topology (FloatingBody::mesh points here)
  SurfaceBake bake;                     ///< exact texel pieces, kept from registration (no re-rasterizing)
  UvLayout layout;                      ///< the physics atlas the bake was made with
  SurfaceTextures textures;             ///< PT/VAT of the current vertices
  SurfaceEvaluator evaluator;           ///< the bake arranged for the per-step re-evaluation
  std::vector<Eigen::Vector3d> positions;  ///< scratch for the deformation function
  DeformedCollision collision;          ///< the collision shape a deformation function moves (BodyDeformation.cpp)
};

/// The liquid texture of a body (only for Effect::Wetting).
struct WettingState {
  std::unique_ptr<BackendWetting> solver;  ///< texel graph and solve, on the controller's backend
  LiquidTexture texture; ///< liquid per texel (m)
  WettingEnvironment environment; ///< sources set at registration; pose, time and gravity per step
};

/// The liquid graph of a body and the point masses that carry its liquid (only for Effect::Flooding).
struct FloodingState {
  LiquidGraph graph;                      ///< nodes, edges, permeable texels, liquid held
  std::vector<std::size_t> pointMasses;   ///< per node: its liquid's point mass in FloatingBody::massModel
  std::vector<double> appliedMass;        ///< per node: kg last handed to the mass model
  std::vector<Eigen::Vector3d> appliedCentroid;  ///< per node: m, mesh frame, last handed to the mass model
  std::unique_ptr<FloodingTexelPass> texelPass;  ///< the backend's pass over the permeable texels (null: the graph's own)
  /// This step's flow (inflow, outflow) and the mass before it, kept from the read phase's graph
  /// step to the mass phase's velocity correction (floodingVelocityCorrection).
  FloodingStepResult stepped;
  double massBefore = 0.0;                ///< kg
};

/// What bodies of one mesh and the same bake and drag settings share, read-only (MuJoCo's
/// model/data split): made by the first such body, reused by the next ones (BuoyancyController::
/// addBody), so that a second crate of a kind bakes nothing and holds no texel of its own.
struct SharedBodyModel {
  std::shared_ptr<const Mesh> mesh;                          ///< keeps the key's mesh alive
  MassProperties unitDensity;                                ///< exact mass properties at density 1
  std::optional<BackendBodyId> backendBody;                  ///< the first body's texels, to instance
  std::size_t backendTexels = 0;                             ///< covered texels there
  std::shared_ptr<const std::vector<DragPatch>> dragPatches; ///< when drag is listed
  std::shared_ptr<const DragPatchSet> dragPatchSet;          ///< prepareDragPatches(*dragPatches)
  double totalDragPatchArea = 0.0;                           ///< m^2
  DragDamping dragDamping = DragDamping::Secant;             ///< how the drag's patches are linearized
  std::shared_ptr<const PreparedPolyhedron> exactPrepared;   ///< the exact path's prepared mesh, when it runs
};

/// One registered body.
struct FloatingBody {
  btRigidBody* body = nullptr;                  ///< not owned
  FloatingBodySettings settings;                ///< as registered (validated)
  std::shared_ptr<const Mesh> mesh;             ///< closed mesh, mesh frame (m)
  std::optional<BackendBodyId> backendBody;     ///< its id in the controller's backend (HydrostaticsMethod::Texture)
  std::size_t backendTexels = 0;                ///< covered texels registered there
  std::shared_ptr<const std::vector<DragPatch>> dragPatches;  ///< only when Effect::Drag is listed (shared by a model)
  std::shared_ptr<const DragPatchSet> dragPatchSet;           ///< prepareDragPatches(*dragPatches), for the drag sum
  std::shared_ptr<const SharedBodyModel> model; ///< what it shares with bodies of its mesh and settings, or null
  /// The exact path's mesh prepared once (HydrostaticsMethod::Polyhedral with buoyancy or added
  /// mass, a mesh that does not deform; shared by a model), else null: the mesh itself is clipped.
  std::shared_ptr<const PreparedPolyhedron> exactPrepared;
  /// A true sphere of this radius (m) about the mesh frame's origin (a btSphereShape given no
  /// mesh): its mass properties and flat-water hydrostatics in closed form.
  std::optional<double> sphereRadius;
  /// A btBoxShape given no mesh, on the exact path: its half extents (m, with Bullet's margin, as
  /// its mesh), for core's rule on its faces under waves.
  std::optional<Eigen::Vector3d> boxHalfExtents;
  double totalDragPatchArea = 0.0;              ///< m^2, sum of patch areas
  /// Linearized for a rigid body's mesh patches, Secant for a deforming body's dense texel patches.
  DragDamping dragDamping = DragDamping::Secant;
  btCollisionShape* originalShape = nullptr;    ///< the user's shape (mesh frame), not owned
  std::unique_ptr<btCompoundShape> compound;    ///< wraps originalShape at the centre-of-mass offset
  btTransform bodyToMesh = btTransform::getIdentity();                     ///< body (COM, principal) frame in the mesh frame
  Eigen::Vector3d boundsCenter = Eigen::Vector3d::Zero();  ///< m, mesh frame
  double boundsRadius = 0.0;                    ///< m, sphere around boundsCenter holding the mesh
  double referenceLength = 1.0;                 ///< m, largest extent (Reynolds number, debug arrows)
  FloatingBodyReport report;                    ///< last step
  /// Its drag model as core's step reads it (patches, coefficients), when Effect::Drag is listed:
  /// refreshed from the fields above at each step's read phase (a deformation re-merges the patches).
  DragBody dragBody;
  /// This body's work in the step in progress, added to the controller's statistics at the write phase.
  ControllerStatistics stepCounters;
  std::optional<MassModel> massModel;           ///< only with a shell, map, point masses, variable mass or deformation
  std::uint64_t appliedMassRevision = 0;        ///< massModel revision last handed to Bullet
  /// Where the mass model's texel pass runs (variable mass, not deforming): its id in the
  /// controller's backend, registered with the model's textures and reference point (backendBody
  /// itself for a texture-path body; a registration for the mass alone otherwise), or empty:
  /// inside the model (core's MassModelsStep).
  std::optional<BackendBodyId> massBackendBody;
  /// massModel->geometryRevision() when massBackendBody was registered: a user's setGeometry
  /// afterwards moves the model's texels away from the backend's, and the model evaluates itself.
  std::uint64_t massBackendGeometry = 0;
  std::uint64_t massPassesBefore = 0;           ///< massModel->texelPasses() before this step's mass phase
  std::unique_ptr<DeformationState> deformation; ///< only with Effect::Deformation
  std::unique_ptr<FloodingState> flooding;      ///< only with Effect::Flooding
  std::unique_ptr<WettingState> wetting;        ///< only with Effect::Wetting
  // The controller integrates gravity itself (see BuoyancyController::addBody): these restore it.
  bool usesWorldGravity = true;                 ///< the body followed the world's gravity before
  btVector3 ownGravity{0, 0, 0};                ///< m/s^2, its own gravity when it did not
  int originalFlags = 0;                        ///< btRigidBody flags before registration
};

/// Gives `floating` its drag model from `patches` (mesh frame): the patches, their prepared layout
/// for the drag sum (prepareDragPatches), their total area and how the implicit update linearizes
/// them (`damping`), the derived state made in one place (registration and each deformation's
/// re-merge).
inline void setDragPatches(FloatingBody& floating, std::vector<DragPatch> patches, DragDamping damping) {
  floating.dragDamping = damping;
  double area = 0.0;
  for (const DragPatch& patch : patches) area += patch.area;
  floating.totalDragPatchArea = area;
  floating.dragPatchSet = std::make_shared<const DragPatchSet>(prepareDragPatches(patches));
  floating.dragPatches = std::make_shared<const std::vector<DragPatch>>(std::move(patches));
}

}  // namespace hydrotex::bullet
