// SPDX-License-Identifier: Zlib
#include "hydrotex/bullet/BuoyancyController.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <span>

#include "BodyThreads.hpp"
#include "BulletEigen.hpp"
#include "FloatingBody.hpp"
#include "MeshInterning.hpp"
#include "MethodChoice.hpp"
#include "ShapeKey.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/hydrostatics/MeshDragPatches.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/mass/PrimitiveMassProperties.hpp"
#include "hydrotex/step/RigidBodiesStep.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"

namespace hydrotex::bullet {
namespace {

/// Principal frame of an inertia tensor: rotation whose columns are the principal axes (right
/// handed) and the principal moments.
struct PrincipalFrame {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d moments = Eigen::Vector3d::Zero();
};

Expected<PrincipalFrame> principalFrame(const Eigen::Matrix3d& inertia) {
  if (!inertia.allFinite()) return Error{"inertia: not finite"};
  if ((inertia - inertia.transpose()).norm() > 1e-9 * std::max(1.0, inertia.norm())) {
    return Error{"inertia: not symmetric"};
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(inertia);
  if (solver.info() != Eigen::Success || !(solver.eigenvalues().minCoeff() > 0.0)) {
    return Error{"inertia: not positive definite"};
  }
  PrincipalFrame frame;
  frame.axes = solver.eigenvectors();
  if (frame.axes.determinant() < 0.0) frame.axes.col(2) = -frame.axes.col(2);
  frame.moments = solver.eigenvalues();
  return frame;
}

/// Removes a body's cached contact pairs before its shape type changes: Bullet picks a pair's
/// collision algorithm by shape type once, so a stale pair would run the wrong algorithm.
void forgetPairs(btDynamicsWorld& world, btRigidBody* body) {
  if (body->getBroadphaseHandle() == nullptr) return;
  world.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(body->getBroadphaseHandle(),
                                                                         world.getDispatcher());
}

/// Places body origin at the centre of mass with principal axes, mass and inertia set, the
/// compound child offset moved so that the shape stays put, and the motion state told.
void applyBodyFrame(btDynamicsWorld& world, FloatingBody& floating, const btTransform& meshWorld) {
  btRigidBody* body = floating.body;
  const btTransform meshToBody = floating.bodyToMesh.inverse();
  floating.compound->updateChildTransform(0, meshToBody, true);
  const btTransform bodyWorld = meshWorld * floating.bodyToMesh;
  body->setCenterOfMassTransform(bodyWorld);
  if (auto* motionState = dynamic_cast<btDefaultMotionState*>(body->getMotionState())) {
    motionState->m_centerOfMassOffset = meshToBody;
    motionState->setWorldTransform(bodyWorld);
  }
  floating.report.meshToBody = meshToBody;
  if (body->getBroadphaseHandle() != nullptr) world.updateSingleAabb(body);
}

/// Adds one body's counters of a step to the controller's.
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

void addCounters(ControllerStatistics& into, const ControllerStatistics& from) {
  // Every counter is a std::uint64_t: a new one that is not added here fails this check.
  static_assert(sizeof(ControllerStatistics) == 19 * sizeof(std::uint64_t), "add the new counter below");
  into.steps += from.steps;
  into.hydrostaticsQueries += from.hydrostaticsQueries;
  into.dragPasses += from.dragPasses;
  into.dragPatchesVisited += from.dragPatchesVisited;
  into.addedMassUpdates += from.addedMassUpdates;
  into.skippedOutOfLiquid += from.skippedOutOfLiquid;
  into.skippedAsleep += from.skippedAsleep;
  into.failedQueries += from.failedQueries;
  into.massUpdates += from.massUpdates;
  into.massTexelPasses += from.massTexelPasses;
  into.deformations += from.deformations;
  into.floodingSteps += from.floodingSteps;
  into.permeableTexelsVisited += from.permeableTexelsVisited;
  into.wettingSteps += from.wettingSteps;
  into.backendBatches += from.backendBatches;
  into.autoMethodChoices += from.autoMethodChoices;
  into.exactPreparations += from.exactPreparations;
  into.massBatches += from.massBatches;
  into.massBatchBodies += from.massBatchBodies;
}

}  // namespace

Status LiquidSettings::validate() const {
  if (!surface) return Error{"liquid.surface: no surface given"};
  if (Status s = surface->validate(); !s) return Error{"liquid.surface: " + s.error().message};
  if (!(std::isfinite(viscosity) && viscosity >= 0.0)) return Error{"liquid.viscosity: must be >= 0 and finite"};
  if (!(std::isfinite(current.x()) && std::isfinite(current.y()) && std::isfinite(current.z()))) {
    return Error{"liquid.current: not finite"};
  }
  return Ok{};
}

Status ControllerSettings::validate() const {
  auto bad = [](double v) { return !(std::isfinite(v) && v >= 0.0); };
  if (bad(restForceFraction)) return Error{"restForceFraction: must be >= 0 and finite"};
  if (bad(restLinearSpeed)) return Error{"restLinearSpeed: must be >= 0 and finite"};
  if (bad(restAngularSpeed)) return Error{"restAngularSpeed: must be >= 0 and finite"};
  if (bad(debugMetersPerNewton)) return Error{"debugMetersPerNewton: must be >= 0 and finite"};
  if (threads < 0) return Error{"threads: " + std::to_string(threads) + ": must be >= 0 (0: all cores)"};
  return Ok{};
}

BuoyancyController::BuoyancyController(btDynamicsWorld& world, LiquidSettings liquid, ControllerSettings settings)
    : world_(world),
      liquid_(std::move(liquid)),
      settings_(settings),
      threads_(std::make_unique<BodyThreads>(std::max(settings.threads, 0))),
      backend_(settings.backend),
      meshes_(std::make_unique<InternedMeshes>()) {
  BodyThreads* threads = threads_.get();
  parallelFor_ = [threads](std::size_t count, const std::function<void(std::size_t)>& work) {
    threads->forEach(count, work);
  };
  // The default backend computes its batch on the controller's own threads.
  if (!backend_) backend_ = makeCpuBackend(parallelFor_);
}

BuoyancyController::~BuoyancyController() {
  while (!bodies_.empty()) removeBody(bodies_.back()->body);
}

int BuoyancyController::threads() const { return threads_->threads(); }

Status BuoyancyController::setLiquid(LiquidSettings liquid) {
  if (Status s = liquid.validate(); !s) return s;
  liquid_ = std::move(liquid);
  autoChoices_.clear();  // made against the old surface (whose address a new one may take)
  // A body asleep in the old liquid is skipped as unchanged: wake it to meet the new one.
  for (const auto& floating : bodies_) floating->body->activate(true);
  return Ok{};
}

FloatingBody* BuoyancyController::find(const btRigidBody* body) const {
  for (const auto& floating : bodies_) {
    if (floating->body == body) return floating.get();
  }
  return nullptr;
}

Status BuoyancyController::addBody(btRigidBody* body, const FloatingBodySettings& settings) {
  if (Status s = liquid_.validate(); !s) return s;
  if (Status s = settings_.validate(); !s) return s;
  if (body == nullptr) return Error{"body: null"};
  if (body->isStaticOrKinematicObject() && body->getInvMass() == btScalar(0) && !settings.density && !settings.mass) {
    return Error{"body: static or kinematic with no density or mass given"};
  }
  if (find(body) != nullptr) return Error{"body: already registered"};
  if (body->getCollisionShape() == nullptr) return Error{"body: has no collision shape"};
  if (Status s = settings.validate(); !s) return s;

  auto floating = std::make_unique<FloatingBody>();
  floating->body = body;
  floating->settings = settings;
  // A true sphere (a btSphereShape with no mesh given): its closed forms (core's
  // PrimitiveHydrostatics and PrimitiveMassProperties) instead of the exact path on its tessellation,
  // which is up to 1e-3 lighter and slower, unless the texture path is asked for or something needs
  // the texels (a mass model, deformation). Under waves (a surface with smoothness bounds) its rule
  // on the true sphere (core's SphereHydrostaticsWaves.cpp), or the exact path on its tessellation
  // where the rule does not apply (the water line near a pole). Under a height grid neither holds:
  // there Auto chooses between its tessellation's paths as for any mesh.
  const bool deforming = settings.effects.has(Effect::Deformation);
  const bool flooding = settings.effects.has(Effect::Flooding);
  const bool hollowAllowed = settings.shellDensity > 0.0 || settings.densityMap != nullptr;
  const bool wantsMassModel = hollowAllowed || !settings.pointMasses.empty() ||
                              settings.effects.has(Effect::VariableMass) || deforming || flooding;
  std::optional<double> sphereRadius;
  if (!settings.mesh && settings.meshPath.empty() && body->getCollisionShape()->getShapeType() == SPHERE_SHAPE_PROXYTYPE &&
      settings.method != HydrostaticsMethod::Texture && !wantsMassModel &&
      (settings.method == HydrostaticsMethod::Polyhedral || liquid_.surface->flatHeight() ||
       liquid_.surface->smoothness(0.0))) {
    sphereRadius = double(static_cast<const btSphereShape*>(body->getCollisionShape())->getRadius());
  }
  if (settings.mesh) {
    floating->mesh = settings.mesh;  // the user's, by identity: a copy of it is a mesh of its own
  } else if (settings.meshPath.empty()) {
    // No mesh given: the body's own collision shape, in its frame (ShapeMesh.hpp); interned, so
    // that bodies of one shape, or of shapes alike, share one mesh and hence one model. A
    // primitive of a kind seen before is not tessellated again.
    const std::optional<std::string> primitive = primitiveShapeKey(*body->getCollisionShape(), settings.shape);
    floating->mesh = primitive ? meshes_->findShape(*primitive) : nullptr;
    if (!floating->mesh) {
      Expected<Mesh> fromShape = meshFromCollisionShape(*body->getCollisionShape(), settings.shape);
      if (!fromShape) return Error{"shape: " + fromShape.error().message};
      floating->mesh = meshes_->intern(std::make_shared<const Mesh>(std::move(fromShape).value()));
      if (primitive) meshes_->rememberShape(*primitive, floating->mesh);
    }
  } else {
    RepairReport repairs;
    Expected<Mesh> loaded = loadMesh(settings.meshPath, settings.load, &repairs);
    if (!loaded) return loaded.error();
    if (Status repaired = repairs.requireRepaired(loaded->sourceName); !repaired) return repaired.error();
    floating->mesh = meshes_->intern(std::make_shared<const Mesh>(std::move(loaded).value()));
  }
  const Mesh& mesh = *floating->mesh;
  // A body whose per-body state is only its motion shares its mesh's model (bake, texels, drag
  // patches, mass properties) with the bodies of the same mesh and settings: a crate of a kind.
  // Auto resolved; under waves its pricing prepares the exact path's mesh, kept for the body.
  std::shared_ptr<const PreparedPolyhedron> pricedPrepared;
  const HydrostaticsMethod method = floating->report.method =
      sphereRadius ? HydrostaticsMethod::Polyhedral : resolveMethod(settings, floating->mesh, pricedPrepared);
  const bool texturePath = method == HydrostaticsMethod::Texture &&
                           (settings.effects.has(Effect::Buoyancy) || settings.effects.has(Effect::AddedMass));
  const bool exactPath = method == HydrostaticsMethod::Polyhedral &&
                         (settings.effects.has(Effect::Buoyancy) || settings.effects.has(Effect::AddedMass));
  const bool shareable = !wantsMassModel && !settings.effects.has(Effect::Wetting);
  const int path = texturePath ? 1 : exactPath ? 2 : 0;
  const ModelKey key{floating->mesh.get(), settings.resolution, path, sphereRadius.has_value(),
                     settings.effects.has(Effect::Drag), settings.dragPatchNormalCosine, settings.dragPatchRadiusFraction};
  std::shared_ptr<const SharedBodyModel> shared;
  if (shareable) {
    auto found = models_.find(key);
    if (found != models_.end()) shared = found->second.lock();
  }
  if (shared && shared->backendBody) {
    // The backend shares the first body's texels (both ours do); one that cannot gets this body's own.
    Expected<BackendBodyId> instance = backend_->addInstance(*shared->backendBody);
    if (instance) {
      floating->backendBody = *instance;
      floating->backendTexels = shared->backendTexels;
    } else {
      shared = nullptr;
    }
  }
  if (!shared) {
    if (Status closed = checkClosedMesh(mesh); !closed) return closed.error();  // the message names the mesh
  }

  // Uniform solids: the exact polyhedral mass properties (once per mesh, at registration).
  Expected<MassProperties> unitDensity = shared         ? Expected<MassProperties>(shared->unitDensity)
                                         : sphereRadius ? solidSphereMassProperties(*sphereRadius, 1.0)
                                                        : polyhedralMassProperties(mesh, 1.0);
  floating->sphereRadius = sphereRadius;
  // A btBoxShape given no mesh, on the exact path: under waves core's rule on its faces
  // (BoxHydrostaticsWaves.cpp), its mesh (the box's 12 triangles, ShapeMesh.cpp) where that does
  // not apply.
  if (exactPath && !deforming && !settings.mesh && settings.meshPath.empty() &&
      body->getCollisionShape()->getShapeType() == BOX_SHAPE_PROXYTYPE)
    floating->boxHalfExtents = toEigen(static_cast<const btBoxShape*>(body->getCollisionShape())->getHalfExtentsWithMargin());
  if (!unitDensity) return unitDensity.error();
  if (!(unitDensity->volume > 0.0)) return Error{"mesh: encloses no volume"};
  double density = 0.0;
  if (settings.density) {
    density = *settings.density;
  } else if (settings.mass) {
    density = *settings.mass / unitDensity->volume;
  } else if (hollowAllowed) {
    density = 0.0;  // the shell or the map carries the mass
  } else if (body->getInvMass() > btScalar(0)) {
    density = (1.0 / double(body->getInvMass())) / unitDensity->volume;
  } else {
    return Error{"body: has no mass and the settings give neither density nor mass"};
  }
  MassProperties props = *unitDensity;
  props.mass *= density;
  props.inertia *= density;

  Eigen::Vector3d lower = mesh.positions.front(), upper = lower;
  for (const Eigen::Vector3d& p : mesh.positions) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  const double referenceLength = std::max((upper - lower).maxCoeff(), 1e-6);
  // A rigid body takes its drag patches from its triangles (meshDragPatches: exact areas, a box's
  // faces in tens of patches where a 256^2 bake gives hundreds), on either path, so that its drag
  // needs no bake and costs what its mesh needs; a deforming body re-merges its moved texels.
  const bool meshPatches = !deforming && settings.effects.has(Effect::Drag);
  const bool needsBake = method == HydrostaticsMethod::Texture ||
                         (settings.effects.has(Effect::Drag) && !meshPatches) || wantsMassModel;
  floating->boundsCenter = 0.5 * (lower + upper);
  // The exact path's mesh prepared once (per-triangle constants), unless it moves every step.
  if (shared) {
    floating->exactPrepared = shared->exactPrepared;
  } else if (exactPath && !deforming && pricedPrepared) {
    floating->exactPrepared = std::move(pricedPrepared);
  } else if (exactPath && !deforming) {
    ++statistics_.exactPreparations;
    Expected<PreparedPolyhedron> prepared = PreparedPolyhedron::prepare(floating->mesh);
    if (!prepared) return prepared.error();
    floating->exactPrepared = std::make_shared<const PreparedPolyhedron>(std::move(prepared).value());
  }
  if (shared) {
    floating->model = shared;
    floating->dragPatches = shared->dragPatches;
    floating->dragPatchSet = shared->dragPatchSet;
    floating->totalDragPatchArea = shared->totalDragPatchArea;
    floating->dragDamping = shared->dragDamping;
  } else if (needsBake) {
    BodyGeometrySettings geometrySettings;
    geometrySettings.bake.width = settings.resolution;
    geometrySettings.bake.height = settings.resolution;
    Expected<BodyGeometry> geometry = prepareBodyGeometry(mesh, geometrySettings);
    if (!geometry) return geometry.error();
    if (texturePath) {
      // The cone apex of the backend's mass pass: the bounding box's centre, as the mass model's.
      Expected<BackendBodyId> id = backend_->addBody(geometry->bake, geometry->textures, floating->boundsCenter);
      if (!id) return id.error();
      floating->backendBody = *id;
      floating->backendTexels = geometry->textures.size();
    }
    if (settings.effects.has(Effect::Drag) && !meshPatches) {
      setDragPatches(*floating,
                     mergeTexelsIntoDragPatches(geometry->bake, geometry->textures, settings.dragPatchNormalCosine,
                                                settings.dragPatchRadiusFraction * referenceLength),
                     DragDamping::Secant);
    }
    if (wantsMassModel) {
      // Mass model (docs/design.md "Mass model"): cones from the bounding box's centre.
      MassModel& model = floating->massModel.emplace(geometry->textures, floating->boundsCenter);
      // A deforming body's mass follows its moved vertices per triangle (O(triangles) a step,
      // exact for uniform solids and shells) instead of a pass over its texels.
      if (deforming) {
        if (Status s = model.followTriangles(geometry->bake, geometry->atlas.layout, mesh); !s)
          return Error{"deformation: " + s.error().message};
      }
      // What a deformation keeps (FloatingBodySettings::mass): a body given by its density keeps
      // it; one given by its mass (or Bullet's) keeps that mass; a shell keeps its mass.
      const Conserved solidConserved = settings.density ? Conserved::Density : Conserved::Mass;
      if (Status s = model.setSolidDensity(density, solidConserved); !s) return Error{"density: " + s.error().message};
      if (Status s = model.setShellDensity(settings.shellDensity, Conserved::Mass); !s)
        return Error{"shellDensity: " + s.error().message};
      if (settings.densityMap) {
        std::vector<float> texelDensity = resampleToTexels(*settings.densityMap, geometry->bake);
        const double low = settings.densityRange[0], high = settings.densityRange[1];
        for (float& value : texelDensity) value = float(low + double(value) * (high - low));
        if (Status s = model.setTexelDensity(std::move(texelDensity)); !s) return Error{"densityMap: " + s.error().message};
      }
      for (std::size_t i = 0; i < settings.pointMasses.size(); ++i) {
        if (Expected<std::size_t> added = model.addPointMass(settings.pointMasses[i]); !added) {
          return Error{"pointMasses[" + std::to_string(i) + "]: " + added.error().message};
        }
      }
      model.advanceTo(time_);
      if (flooding) {
        // Paper section 3: the liquid graph, its permeable texels from the PMT, and one point mass
        // per node that carries the node's liquid (docs/design.md "Mass model").
        const FloodingBodySettings& floodingSettings = settings.flooding;
        std::vector<float> permeability;
        if (floodingSettings.permeabilityMap) permeability = resampleToTexels(*floodingSettings.permeabilityMap, geometry->bake);
        Expected<LiquidGraph> graph =
            floodingSettings.manualGraph
                ? buildManualLiquidGraph(geometry->mesh, geometry->textures, permeability, *floodingSettings.manualGraph,
                                         floodingSettings.graph)
                : buildAutomaticLiquidGraph(geometry->mesh, geometry->textures, permeability, floodingSettings.nodeCount,
                                            floodingSettings.graph);
        if (!graph) return Error{"flooding: " + graph.error().message};
        auto state = std::make_unique<FloodingState>(FloodingState{std::move(graph).value(), {}, {}, {}, {}, {}, 0.0});
        // The permeable-texel pass on the controller's backend (the GL one on the GPU).
        Expected<std::unique_ptr<FloodingTexelPass>> texelPass = backend_->makeFloodingPass(state->graph);
        if (!texelPass) return Error{"flooding: " + texelPass.error().message};
        state->texelPass = std::move(texelPass).value();
        for (const LiquidGraphNode& node : state->graph.nodes()) {
          PointMass liquid;
          liquid.position = node.position;
          Expected<std::size_t> added = model.addPointMass(liquid);
          if (!added) return Error{"flooding: " + added.error().message};
          state->pointMasses.push_back(*added);
          state->appliedMass.push_back(0.0);
          state->appliedCentroid.push_back(node.position);
        }
        floating->flooding = std::move(state);
      }
    }
    // The texel mass pass of a model that changes (variable mass) runs on the backend, in the
    // step's one mass batch (core's MassModelsStep): on the texture path's registration, or one
    // for the mass alone (same textures and cone apex as the model's, so the CPU backend's answer
    // has the model's own bits). A deforming body's model sums per triangle: no texel pass.
    if (wantsMassModel && !deforming && settings.effects.has(Effect::VariableMass)) {
      if (floating->backendBody) {
        floating->massBackendBody = floating->backendBody;
      } else {
        Expected<BackendBodyId> id = backend_->addBody(geometry->bake, geometry->textures, floating->boundsCenter);
        if (!id) return Error{"variable mass: " + id.error().message};
        floating->massBackendBody = *id;
        floating->backendTexels = geometry->textures.size();
      }
      floating->massBackendGeometry = floating->massModel->geometryRevision();
    }
    if (deforming) {
      auto state = std::make_unique<DeformationState>();
      state->rest = mesh;
      state->current = std::make_shared<Mesh>(mesh);
      state->bake = std::move(geometry->bake);
      state->layout = std::move(geometry->atlas.layout);
      state->textures = std::move(geometry->textures);
      state->evaluator = SurfaceEvaluator(state->bake, state->layout);
      floating->deformation = std::move(state);
    }
  }
  if (!shared && meshPatches)
    setDragPatches(*floating,
                   meshDragPatches(mesh, settings.dragPatchNormalCosine, settings.dragPatchRadiusFraction * referenceLength),
                   DragDamping::Linearized);

  if (settings.effects.has(Effect::Wetting)) {
    // The liquid texture has its own bake (its resolution may differ from the physics bake's);
    // drag or wetting alone do not need a closed mesh, but registration already checked it.
    const WettingBodySettings& wetting = settings.wetting;
    BodyGeometrySettings wettingGeometry;
    wettingGeometry.bake.width = wettingGeometry.bake.height = wetting.resolution > 0 ? wetting.resolution : settings.resolution;
    wettingGeometry.requireClosed = false;
    Expected<BodyGeometry> geometry = prepareBodyGeometry(mesh, wettingGeometry);
    if (!geometry) return Error{"wetting: " + geometry.error().message};
    Expected<TexelAdjacency> graph = buildTexelAdjacency(geometry->bake, geometry->mesh, geometry->atlas.layout);
    if (!graph) return Error{"wetting: " + graph.error().message};
    // On the controller's backend: core's Wetting on the CPU, the GL compute one on the GPU.
    Expected<std::unique_ptr<BackendWetting>> solver =
        backend_->makeWetting(std::move(graph).value(), geometry->textures, wetting.physics);
    if (!solver) return Error{"wetting.physics: " + solver.error().message};
    Expected<LiquidTexture> texture = makeLiquidTexture(geometry->textures.size(), wetting.material);
    if (!texture) return Error{"wetting.material: " + texture.error().message};
    floating->wetting = std::make_unique<WettingState>(WettingState{std::move(solver).value(), std::move(texture).value(), {}});
    floating->wetting->environment.sources = wetting.sources;
  }

  floating->boundsRadius = 0.5 * (upper - lower).norm();
  floating->referenceLength = referenceLength;

  // Bullet's frame: the shape is wrapped so that the body origin can sit at the centre of mass.
  floating->originalShape = body->getCollisionShape();
  floating->compound = std::make_unique<btCompoundShape>(false, 1);
  floating->compound->addChildShape(btTransform::getIdentity(), floating->originalShape);
  forgetPairs(world_, body);
  body->setCollisionShape(floating->compound.get());

  // Gravity moves into the controller's implicit update: Bullet adds gravity before integrating
  // positions and an action can only act after, so a body balanced by buoyancy would otherwise
  // read a velocity of dt g at rest. The world's gravity is still followed (read each step).
  floating->originalFlags = body->getFlags();
  floating->usesWorldGravity = (body->getFlags() & BT_DISABLE_WORLD_GRAVITY) == 0;
  floating->ownGravity = body->getGravity();
  body->setFlags(body->getFlags() | BT_DISABLE_WORLD_GRAVITY);
  body->setGravity(btVector3(0, 0, 0));

  FloatingBody& registered = *floating;
  bodies_.push_back(std::move(floating));
  if (registered.deformation) {
    registered.mesh = registered.deformation->current;
    if (Status s = attachDeformedCollision(registered); !s) {  // BodyDeformation.cpp
      removeBody(body);
      return s;
    }
    deform(registered);  // the pose at the current time, collision shape included
  }
  if (registered.massModel) {
    Expected<MassProperties> modelled = registered.massModel->properties();
    if (!modelled) {
      removeBody(body);
      return modelled.error();
    }
    props = *modelled;
    registered.appliedMassRevision = registered.massModel->revision();
  }
  if (Status s = applyMassProperties(registered, props); !s) {
    removeBody(body);
    return s;
  }
  // Memory: a shared model counts on the body that made it; the bodies that share it hold none.
  std::size_t bytes = 0;
  if (!shared) {
    if (registered.dragPatches) bytes += registered.dragPatches->capacity() * sizeof(DragPatch);
    if (registered.dragPatchSet) bytes += registered.dragPatchSet->memoryBytes();
    if (registered.backendBody || registered.massBackendBody) bytes += registered.backendTexels * sizeof(TextureHydrostatics::Texel);
    if (registered.exactPrepared) bytes += registered.exactPrepared->memoryBytes();
  }
  registered.report.effectMemoryBytes = bytes;
  registered.report.sharesModel = shared != nullptr;
  if (shareable && !shared) {
    auto model = std::make_shared<SharedBodyModel>();
    model->mesh = registered.mesh;
    model->unitDensity = *unitDensity;
    model->backendBody = registered.backendBody;
    model->backendTexels = registered.backendTexels;
    model->dragPatches = registered.dragPatches;
    model->dragPatchSet = registered.dragPatchSet;
    model->totalDragPatchArea = registered.totalDragPatchArea;
    model->dragDamping = registered.dragDamping;
    model->exactPrepared = registered.exactPrepared;
    registered.model = model;
    models_[key] = model;
  }
  return Ok{};
}

HydrostaticsMethod BuoyancyController::resolveMethod(const FloatingBodySettings& settings,
                                                     const std::shared_ptr<const Mesh>& mesh,
                                                     std::shared_ptr<const PreparedPolyhedron>& prepared) {
  prepared.reset();
  if (settings.method != HydrostaticsMethod::Auto) return settings.method;
  // The choice depends only on the key's parts: a crate of a kind is measured once (a mesh made
  // from a shape or a file is interned, so bodies of shapes alike count as one kind).
  const AutoKey key{mesh.get(), settings.resolution, settings.autoMethodError,
                    settings.effects.has(Effect::Deformation), liquid_.surface.get()};
  auto found = autoChoices_.find(key);
  // Not resolved again: taken from the first body of the mesh (and not counted).
  if (found != autoChoices_.end() && found->second.mesh.lock() == mesh) return found->second.method;
  ++statistics_.autoMethodChoices;
  const HydrostaticsMethod method = resolveHydrostaticsMethod(settings, mesh, *liquid_.surface, &prepared);
  if (prepared) ++statistics_.exactPreparations;
  autoChoices_[key] = AutoChoice{mesh, method};
  return method;
}

Expected<std::size_t> BuoyancyController::addAllBodies(const FloatingBodySettings& defaults) {
  std::size_t added = 0;
  const btCollisionObjectArray& objects = world_.getCollisionObjectArray();
  for (int i = 0; i < objects.size(); ++i) {
    btRigidBody* body = btRigidBody::upcast(objects[i]);
    if (body == nullptr || body->isStaticOrKinematicObject() || find(body) != nullptr) continue;
    if (Status s = addBody(body, defaults); !s) {
      return Error{"collision object " + std::to_string(i) + " (after " + std::to_string(added) +
                   " bodies added): " + s.error().message};
    }
    ++added;
  }
  return added;
}

bool BuoyancyController::removeBody(btRigidBody* body) {
  auto it = std::find_if(bodies_.begin(), bodies_.end(), [&](const auto& f) { return f->body == body; });
  if (it == bodies_.end()) return false;
  FloatingBody& floating = **it;
  const btTransform meshWorld = body->getCenterOfMassTransform() * floating.bodyToMesh.inverse();
  forgetPairs(world_, body);
  body->setCollisionShape(floating.originalShape);
  body->setCenterOfMassTransform(meshWorld);
  if (auto* motionState = dynamic_cast<btDefaultMotionState*>(body->getMotionState())) {
    motionState->m_centerOfMassOffset = btTransform::getIdentity();
    motionState->setWorldTransform(meshWorld);
  }
  if (body->getBroadphaseHandle() != nullptr) world_.updateSingleAabb(body);
  body->setFlags(floating.originalFlags);
  body->setGravity(floating.usesWorldGravity ? world_.getGravity() : floating.ownGravity);
  if (floating.backendBody) {
    // A shared model's texels stay in the backend under the id of the body that made it (the
    // anchor others instance from) until its last user leaves; then the anchor's slot goes too.
    const std::optional<BackendBodyId> anchor = floating.model ? floating.model->backendBody : std::nullopt;
    const bool lastUser = !floating.model || floating.model.use_count() == 1;
    if (anchor != floating.backendBody || lastUser) backend_->releaseBody(*floating.backendBody);
    if (anchor && anchor != floating.backendBody && lastUser) backend_->releaseBody(*anchor);
  }
  if (floating.massBackendBody && floating.massBackendBody != floating.backendBody)
    backend_->releaseBody(*floating.massBackendBody);  // registered for the mass pass alone
  bodies_.erase(it);
  return true;
}

Status BuoyancyController::setMassProperties(btRigidBody* body, const MassProperties& massProperties) {
  FloatingBody* found = find(body);
  if (found == nullptr) return Error{"body: not registered"};
  return applyMassProperties(*found, massProperties);
}

MassModel* BuoyancyController::massModel(const btRigidBody* body) {
  FloatingBody* floating = find(body);
  if (floating == nullptr || !floating->massModel) return nullptr;
  const EffectSet effects = floating->settings.effects;
  if (!effects.has(Effect::VariableMass) && !effects.has(Effect::Deformation)) return nullptr;
  return &*floating->massModel;
}

Status BuoyancyController::applyMassProperties(FloatingBody& found, const MassProperties& massProperties) {
  FloatingBody* floating = &found;
  btRigidBody* body = floating->body;
  if (!(std::isfinite(massProperties.mass) && massProperties.mass > 0.0)) {
    return Error{"mass: must be positive and finite"};
  }
  if (!massProperties.centerOfMass.allFinite()) return Error{"centerOfMass: not finite"};
  Expected<PrincipalFrame> principal = principalFrame(massProperties.inertia);
  if (!principal) return principal.error();

  const bool firstTime = floating->report.massProperties.mass <= 0.0;
  const btTransform bodyWorldBefore = body->getCenterOfMassTransform();
  const btTransform meshWorld = firstTime ? bodyWorldBefore : bodyWorldBefore * floating->bodyToMesh.inverse();

  // Momentum before (docs/design.md "Bullet's frame"): linear P = m v; angular about the new centre
  // L = I w + m (c_old - c_new) x v.
  const double oldMass = firstTime ? 0.0 : floating->report.massProperties.mass;
  const Eigen::Vector3d v = toEigen(body->getLinearVelocity());
  const Eigen::Vector3d w = toEigen(body->getAngularVelocity());
  const Eigen::Vector3d oldCenter = toEigen(bodyWorldBefore.getOrigin());
  const Eigen::Vector3d newCenter = toEigen(meshWorld * toBullet(massProperties.centerOfMass));
  Eigen::Matrix3d oldInertiaWorld = Eigen::Matrix3d::Zero();
  if (!firstTime && body->getInvMass() > btScalar(0)) {
    oldInertiaWorld = toEigen(body->getInvInertiaTensorWorld()).inverse();
  }

  floating->bodyToMesh = btTransform(toBulletBasis(principal->axes), toBullet(massProperties.centerOfMass));
  floating->report.massProperties = massProperties;
  body->setMassProps(btScalar(massProperties.mass), toBullet(principal->moments));
  applyBodyFrame(world_, *floating, meshWorld);
  body->updateInertiaTensor();

  if (!firstTime) {
    const Eigen::Vector3d momentum = oldMass * v;
    const Eigen::Vector3d angularMomentum = oldInertiaWorld * w + oldMass * (oldCenter - newCenter).cross(v);
    const Eigen::Matrix3d newInertiaWorld = toEigen(body->getInvInertiaTensorWorld()).inverse();
    body->setLinearVelocity(toBullet(momentum / massProperties.mass));
    body->setAngularVelocity(toBullet(newInertiaWorld.ldlt().solve(angularMomentum)));
  }
  return Ok{};
}

std::optional<btTransform> BuoyancyController::meshTransform(const btRigidBody* body) const {
  const FloatingBody* floating = find(body);
  if (floating == nullptr) return std::nullopt;
  return body->getCenterOfMassTransform() * floating->bodyToMesh.inverse();
}

const FloatingBodyReport* BuoyancyController::report(const btRigidBody* body) const {
  const FloatingBody* floating = find(body);
  return floating != nullptr ? &floating->report : nullptr;
}

void BuoyancyController::updateAction(btCollisionWorld*, btScalar deltaTimeStep) {
  const double dt = double(deltaTimeStep);
  if (!(dt > 0.0) || !liquid_.surface) return;
  time_ += dt;
  ++statistics_.steps;
  // Read (serial): everything that changes Bullet's bodies or shapes before the forces (deformation,
  // flooding, mass), then each body's kinematics into its task for core's step, once.
  // The kinematics are plain reads of distinct bodies: in parallel.
  Clock::time_point start = Clock::now();
  tasks_.resize(bodies_.size());
  results_.resize(bodies_.size());
  massTasks_.resize(bodies_.size());
  massResults_.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) changeBody(*bodies_[i], massTasks_[i], dt);
  // Core's mass phase (MassModelsStep.hpp): every due texel mass pass in one backend batch, read
  // back once; then each body's new mass to Bullet (serial: frames, shapes, AABBs).
  const MassModelsStepStatistics massed = massStepper_.run(*backend_, massTasks_, massResults_);
  statistics_.massBatches += massed.massBatches;
  statistics_.massBatchBodies += massed.massBatchBodies;
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (massResults_[i]) applyMass(*bodies_[i], *massResults_[i]);
  threads_->forEach(bodies_.size(), [this](std::size_t i) { readBody(*bodies_[i], tasks_[i]); });
  timings_.read += secondsSince(start);
  start = Clock::now();
  wetBodies(dt);
  timings_.wetting += secondsSince(start);
  // Core's phased step (RigidBodiesStep.hpp): plan, one backend batch read back once while the
  // drag runs on the threads, then each body's implicit update in parallel.
  const RigidBodiesStepStatistics stepped = stepper_.run(*backend_, *liquid_.surface, tasks_, results_, parallelFor_, dt);
  statistics_.backendBatches += stepped.backendBatches;
  timings_.plan += stepped.planSeconds;
  timings_.backend += stepped.backendSeconds;
  timings_.drag += stepped.dragSeconds;
  timings_.update += stepped.updateSeconds;
  // Write: velocities and sleeping state to Bullet, each body only its own (in parallel), then the
  // counters added in registration order.
  start = Clock::now();
  threads_->forEach(bodies_.size(), [this](std::size_t i) { writeBody(*bodies_[i], results_[i]); });
  for (const auto& floating : bodies_) addCounters(statistics_, floating->stepCounters);
  timings_.write += secondsSince(start);
  // Soft bodies on the threads: each apply() reads and writes only its own btSoftBody (nodes,
  // activation) and its own scratch, and reads the shared liquid (const) and world info; the
  // counters are added afterwards in registration order, so any thread count gives the same bits.
  start = Clock::now();
  if (!softBodies_.empty()) {
    softApplied_.assign(softBodies_.size(), 0);
    const struct {
      const LiquidSurface& surface;
      SoftBodyLiquid liquid;
      double time, dt;
    } soft{*liquid_.surface, SoftBodyLiquid{liquid_.viscosity, toEigen(liquid_.current)}, time_, dt};
    // Two pointers captured: std::function keeps them without allocating (test_controller.cpp).
    threads_->forEach(softBodies_.size(), [this, &soft](std::size_t i) {
      softApplied_[i] = softBodies_[i].apply(soft.surface, soft.time, soft.dt, soft.liquid).ok();
    });
    for (std::size_t i = 0; i < softBodies_.size(); ++i) {
      if (!softApplied_[i]) {
        ++statistics_.failedQueries;
        continue;
      }
      const SoftBodyReport& done = softBodies_[i].report();  // the same counters as rigid bodies' effects
      if (done.pressureApplied) ++statistics_.hydrostaticsQueries;
      if (done.dragApplied) ++statistics_.dragPasses;
      statistics_.dragPatchesVisited += done.dragTexelsVisited;
    }
  }
  timings_.softBodies += secondsSince(start);
}

Status BuoyancyController::addSoftBody(btSoftBody* body, const SoftBodySettings& settings) {
  for (const SoftBodyBuoyancy& soft : softBodies_)
    if (soft.body() == body) return Error{"soft body is already registered"};
  Expected<SoftBodyBuoyancy> soft = SoftBodyBuoyancy::create(body, settings);
  if (!soft) return soft.error();
  softBodies_.push_back(std::move(soft).value());
  return Ok{};
}

bool BuoyancyController::removeSoftBody(btSoftBody* body) {
  auto it = std::find_if(softBodies_.begin(), softBodies_.end(), [&](const SoftBodyBuoyancy& s) { return s.body() == body; });
  if (it == softBodies_.end()) return false;
  softBodies_.erase(it);
  return true;
}

const SoftBodyReport* BuoyancyController::softBodyReport(const btSoftBody* body) const {
  for (const SoftBodyBuoyancy& soft : softBodies_)
    if (soft.body() == body) return &soft.report();
  return nullptr;
}

void BuoyancyController::changeBody(FloatingBody& floating, MassModelTask& massTask, double dt) {
  const EffectSet effects = floating.settings.effects;
  floating.stepCounters = ControllerStatistics{};
  massTask = MassModelTask{};
  // Variable mass and deformation first: the forces must see this step's body. They change
  // Bullet's body and shape (mass, frame, AABB) and run user callbacks: serial.
  if (floating.deformation) deform(floating);
  if (floating.flooding) flood(floating, dt);  // its liquid into the mass model's point masses
  if (floating.massModel &&
      (floating.flooding || effects.has(Effect::VariableMass) || effects.has(Effect::Deformation))) {
    prepareMass(floating, massTask);
  }
}

void BuoyancyController::readBody(FloatingBody& floating, RigidBodyTask& task) const {
  const btRigidBody* body = floating.body;
  const FloatingBodySettings& settings = floating.settings;
  const EffectSet effects = settings.effects;
  const MassProperties& massProperties = floating.report.massProperties;
  RigidBodyMotion& motion = task.motion;
  motion.meshPose = toPose(body->getCenterOfMassTransform() * floating.bodyToMesh.inverse());
  motion.center = toEigen(body->getCenterOfMassPosition());
  motion.linearVelocity = toEigen(body->getLinearVelocity());
  motion.angularVelocity = toEigen(body->getAngularVelocity());
  motion.mass = massProperties.mass;
  // In double from the mesh-axes inertia: Bullet's float inverse inertia, inverted, loses the
  // small moment of a needle (inverse moments 1e10 and 1e4 kg^-1 m^-2 in one float matrix).
  motion.inertiaWorld = motion.meshPose.rotation * massProperties.inertia * motion.meshPose.rotation.transpose();

  RigidBodyStepInput& input = task.input;
  input = RigidBodyStepInput{};
  input.gravity = toEigen(floating.usesWorldGravity ? world_.getGravity() : floating.ownGravity);
  input.buoyancy = effects.has(Effect::Buoyancy);
  if (effects.has(Effect::AddedMass)) input.addedMassCoefficient = settings.addedMassCoefficient;
  if (effects.has(Effect::Drag)) {
    DragBody& drag = floating.dragBody;
    drag.patches = *floating.dragPatches;
    drag.prepared = floating.dragPatchSet.get();
    drag.totalPatchArea = floating.totalDragPatchArea;
    drag.referenceLength = floating.referenceLength;
    drag.coefficients = settings.drag;
    drag.rotationalDamping = settings.rotationalDamping;
    drag.damping = floating.dragDamping;
    drag.sphereRadius = floating.sphereRadius;      // flat water: the law on its wetted surface's nodes
    drag.boxHalfExtents = floating.boxHalfExtents;  // (the patches' ramp is approximate at the water line)
    input.drag = &drag;
  }
  input.liquid = DragLiquid{liquid_.surface.get(), toEigen(liquid_.current), liquid_.viscosity, time_};
  input.referenceLength = floating.referenceLength;
  input.rest = RestThresholds{settings_.restForceFraction, settings_.restLinearSpeed, settings_.restAngularSpeed};

  task.active = body->isActive();
  task.dynamic = body->getInvMass() > btScalar(0);
  task.wantsHydrostatics = effects.has(Effect::Buoyancy) || effects.has(Effect::AddedMass);
  task.backendBody = floating.backendBody;
  task.exactPrepared = floating.exactPrepared.get();
  task.sphereRadius = floating.sphereRadius;
  task.boxHalfExtents = floating.boxHalfExtents;
  task.exactMesh = floating.mesh.get();
  task.centerOfMass = massProperties.centerOfMass;
  task.boundsCenter = floating.boundsCenter;
  task.boundsRadius = floating.boundsRadius;
}

void BuoyancyController::wetBodies(double dt) {
  // The liquid texture runs whether the body is in the liquid, asleep or not: it dries in the air.
  // A backend that owns a context (GL) is driven from this thread; the CPU's in parallel.
  bool anyThreadSafe = false;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    FloatingBody& floating = *bodies_[i];
    if (!floating.wetting) continue;
    if (floating.wetting->solver->threadSafe()) {
      anyThreadSafe = true;
      continue;
    }
    wet(floating, tasks_[i].motion.meshPose, tasks_[i].input.gravity, dt);
  }
  if (!anyThreadSafe) return;
  threads_->forEach(bodies_.size(), [this, dt](std::size_t i) {
    FloatingBody& floating = *bodies_[i];
    if (floating.wetting && floating.wetting->solver->threadSafe())
      wet(floating, tasks_[i].motion.meshPose, tasks_[i].input.gravity, dt);
  });
}

void BuoyancyController::writeBody(FloatingBody& floating, const RigidBodyTaskResult& result) {
  btRigidBody* body = floating.body;
  FloatingBodyReport& report = floating.report;
  ControllerStatistics& counters = floating.stepCounters;
  counters.hydrostaticsQueries += result.counters.hydrostaticsQueries;
  counters.failedQueries += result.counters.failedQueries;
  counters.dragPasses += result.counters.dragPasses;
  counters.dragPatchesVisited += result.counters.dragPatchesVisited;
  counters.addedMassUpdates += result.counters.addedMassUpdates;
  // Bullet's side of the outcome: the report, the sleeping state and the velocities.
  auto apply = [&] {
    switch (result.plan) {
      case RigidBodyPlan::Asleep:
        ++counters.skippedAsleep;
        return;
      case RigidBodyPlan::Static:
        return;
      case RigidBodyPlan::OutOfLiquid:
        ++counters.skippedOutOfLiquid;
        break;
      case RigidBodyPlan::Computed:
        break;
    }
    report.hydrostatics = result.hydrostatics;
    report.dragForce = report.dragTorque = btVector3(0, 0, 0);
    report.addedMass = 0.0;
    report.atRest = false;
    if (!result.step) return;  // failed: counted, no forces this step
    const RigidBodyStepResult& stepped = *result.step;
    if (result.plan == RigidBodyPlan::OutOfLiquid) {
      body->setLinearVelocity(toBullet(stepped.velocities.linear));  // free fall
      return;
    }
    report.dragForce = toBullet(stepped.drag.force);
    report.dragTorque = toBullet(stepped.drag.torque);
    report.addedMass = stepped.addedMass;
    report.atRest = stepped.atRest;
    // Until at rest the body is kept awake, so that Bullet's sleeping thresholds (0.8 m/s for 2 s)
    // cannot freeze a slow oscillation; a sleeping body that is not at rest is woken.
    if (!body->isActive()) {
      if (report.atRest) {
        ++counters.skippedAsleep;
        return;
      }
      body->activate(true);
    } else if (!report.atRest) {
      body->setDeactivationTime(0);
    }
    body->setLinearVelocity(toBullet(stepped.velocities.linear));
    body->setAngularVelocity(toBullet(stepped.velocities.angular));
  };
  apply();
}

void BuoyancyController::wet(FloatingBody& floating, const Pose& meshPose, const Eigen::Vector3d& gravity, double dt) const {
  WettingState& state = *floating.wetting;
  WettingEnvironment& environment = state.environment;
  environment.liquid = liquid_.surface.get();
  environment.pose = meshPose;
  environment.time = time_;
  // Without downward gravity there is no hydrostatic head; a vanishing g drives no absorption.
  environment.gravity = -gravity.y() > 0.0 ? -gravity.y() : 1e-12;
  ++floating.stepCounters.wettingSteps;
  Expected<WettingStepReport> stepped = state.solver->step(state.texture, environment, dt);
  if (!stepped) {
    ++floating.stepCounters.failedQueries;
    return;
  }
  FloatingBodyReport& report = floating.report;
  report.liquidAbsorbed += stepped->absorbed;
  report.liquidEvaporated += stepped->evaporated;
  // The step's balance is exact (absorbed = held + evaporated): no pass over the texels needed.
  report.liquidHeld += stepped->absorbed - stepped->evaporated;
}

const LiquidTexture* BuoyancyController::liquidTexture(const btRigidBody* body) const {
  const FloatingBody* floating = find(body);
  if (floating == nullptr || !floating->wetting) return nullptr;
  WettingState& state = *floating->wetting;
  // A GPU's liquid is copied back here, when it is read, not every step; null when it cannot be.
  if (!state.solver->sync(state.texture)) return nullptr;
  return &state.texture;
}

void BuoyancyController::prepareMass(FloatingBody& floating, MassModelTask& massTask) const {
  MassModel& model = *floating.massModel;
  model.advanceTo(time_);
  if (model.revision() == floating.appliedMassRevision) return;  // nothing changed: nothing recomputed
  floating.massPassesBefore = model.texelPasses();
  massTask.model = &model;
  // The backend's copy of the texels fits while the user has not moved the model's geometry.
  if (model.geometryRevision() == floating.massBackendGeometry) massTask.backendBody = floating.massBackendBody;
}

void BuoyancyController::applyMass(FloatingBody& floating, const Expected<MassProperties>& properties) {
  MassModel& model = *floating.massModel;
  floating.appliedMassRevision = model.revision();
  ++statistics_.massUpdates;
  statistics_.massTexelPasses += model.texelPasses() - floating.massPassesBefore;
  // A model that cannot be handed to Bullet (no mass left, a flat inertia) keeps the last one.
  if (!properties || !applyMassProperties(floating, *properties)) {
    ++statistics_.failedQueries;
  } else {
    floating.body->activate(true);
  }
  if (!floating.flooding) return;
  FloodingState& state = *floating.flooding;
  const double massBefore = state.massBefore;
  const double massAfter = floating.report.massProperties.mass;
  if (massAfter == massBefore || !(massAfter > 0.0)) return;
  // setMassProperties kept the momentum m v (liquid entering at rest); core's law adds the
  // momentum the liquid brings in and takes out (RigidBodyStep.hpp).
  btRigidBody* body = floating.body;
  const LiquidSurface& surface = *liquid_.surface;
  const Eigen::Vector3d v = toEigen(body->getLinearVelocity());
  const Eigen::Vector3d center = toEigen(body->getCenterOfMassPosition());
  const Eigen::Vector3d liquidVelocity = surface.velocity(center, time_) + toEigen(liquid_.current);
  const Eigen::Vector3d correction = floodingVelocityCorrection(v, liquidVelocity, massBefore, massAfter, surface.density(),
                                                                state.stepped.inflow, state.stepped.outflow);
  body->setLinearVelocity(toBullet(Eigen::Vector3d(v + correction)));
}

void BuoyancyController::flood(FloatingBody& floating, double dt) {
  FloodingState& state = *floating.flooding;
  btRigidBody* body = floating.body;
  const LiquidSurface& surface = *liquid_.surface;
  const Eigen::Vector3d gravity = toEigen(floating.usesWorldGravity ? world_.getGravity() : floating.ownGravity);
  FloodingQuery query;
  query.pose = toPose(body->getCenterOfMassTransform() * floating.bodyToMesh.inverse());
  query.time = time_;
  query.timeStep = dt;
  query.gravity = -gravity.y();
  query.viscosity = liquid_.viscosity;
  FloodingStepResult& stepped = state.stepped;
  stepped = FloodingStepResult{};
  if (query.gravity > 0.0 && query.viscosity > 0.0) {  // no weight or no viscosity: Darcy has nothing to say
    Expected<FloodingStepResult> result = state.graph.step(surface, query, state.texelPass.get());
    if (!result) {
      ++statistics_.failedQueries;
    } else {
      stepped = *result;
      ++statistics_.floodingSteps;
      statistics_.permeableTexelsVisited += stepped.texelsVisited;
    }
  }
  floating.report.liquidVolume = state.graph.heldLiquid();

  // The liquid's mass at its centroid (which moves with heel: the free surface) enters the mass
  // model; only nodes whose liquid or centroid moved are handed over, so a body at rest with
  // nothing flowing recomputes nothing.
  MassModel& model = *floating.massModel;
  const double density = surface.density();
  const std::vector<LiquidGraphNode>& nodes = state.graph.nodes();
  const std::vector<Eigen::Vector3d>& centroids = state.graph.liquidCentroids();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const double mass = density * nodes[i].liquid;
    if (mass != state.appliedMass[i]) {
      if (model.setPointMassMass(state.pointMasses[i], mass)) state.appliedMass[i] = mass;
    }
    if (mass > 0.0 && centroids[i] != state.appliedCentroid[i]) {
      if (model.setPointMassPosition(state.pointMasses[i], centroids[i])) state.appliedCentroid[i] = centroids[i];
    }
  }
  // The mass phase (applyMass) hands the new mass to Bullet and corrects the velocity for the
  // momentum the liquid brought in and took out.
  state.massBefore = floating.report.massProperties.mass;
}

const LiquidGraph* BuoyancyController::liquidGraph(const btRigidBody* body) const {
  const FloatingBody* floating = find(body);
  return floating != nullptr && floating->flooding ? &floating->flooding->graph : nullptr;
}

void BuoyancyController::debugDraw(btIDebugDraw* debugDrawer) {
  if (debugDrawer == nullptr || !liquid_.surface) return;
  const LiquidSurface& surface = *liquid_.surface;
  const btVector3 red(1, 0, 0), green(0, 1, 0), blue(0, 0, 1);
  for (const auto& floating : bodies_) {
    const btRigidBody* body = floating->body;
    const double mass = floating->report.massProperties.mass;
    const btVector3 gravity = floating->usesWorldGravity ? world_.getGravity() : floating->ownGravity;
    const double weight = mass * double(gravity.length());
    const double scale = settings_.debugMetersPerNewton > 0.0
                             ? settings_.debugMetersPerNewton
                             : (weight > 0.0 ? floating->referenceLength / weight : 0.0);
    const btVector3 center = body->getCenterOfMassPosition();
    debugDrawer->drawLine(center, center + gravity * btScalar(mass * scale), red);
    const HydrostaticsResult& h = floating->report.hydrostatics;
    if (h.submergedVolume > 0.0) {
      const btVector3 buoyancyCenter = toBullet(h.centerOfBuoyancy);
      debugDrawer->drawLine(buoyancyCenter, buoyancyCenter + toBullet(h.buoyancyForce * scale), green);
    }
    if (!surface.hasFreeSurface()) continue;
    // Waterline: where each triangle's vertices change side of the surface.
    const btTransform meshWorld = body->getCenterOfMassTransform() * floating->bodyToMesh.inverse();
    const Mesh& mesh = *floating->mesh;
    for (const Eigen::Vector3i& tri : mesh.triangles) {
      Eigen::Vector3d corner[3];
      double above[3];
      for (int k = 0; k < 3; ++k) {
        corner[k] = toEigen(meshWorld * toBullet(mesh.positions[std::size_t(tri[k])]));
        above[k] = corner[k].y() - surface.surfaceHeight(corner[k].x(), corner[k].z(), time_);
      }
      btVector3 ends[2];
      int found = 0;
      for (int k = 0; k < 3 && found < 2; ++k) {
        const int n = (k + 1) % 3;
        if ((above[k] < 0.0) != (above[n] < 0.0)) {
          const double t = above[k] / (above[k] - above[n]);
          ends[found++] = toBullet(corner[k] + t * (corner[n] - corner[k]));
        }
      }
      if (found == 2) debugDrawer->drawLine(ends[0], ends[1], blue);
    }
  }
}

}  // namespace hydrotex::bullet
