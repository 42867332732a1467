// SPDX-License-Identifier: Zlib
#pragma once
/// @file Scene.hpp
/// Scene files (JSON) shared by `hydrotex simulate`, the tests and the benchmarks (Box2D's
/// "scenes defined once"): a liquid, an optional seabed and floating bodies, and SceneWorld, a
/// headless Bullet world with a BuoyancyController built from one.

#include <btBulletDynamicsCommon.h>

#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassModel.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"
#include "hydrotex/bullet/FloatingBodySettings.hpp"

namespace hydrotex::bullet {

/// Bullet soft-body material of a body with `soft: true` (scene key `soft_material`; every key
/// optional). Defaults keep a ball's shape (test_soft_body: a 0.25 m ball of 642 nodes stays
/// within 1 mm of its sphere while floating).
struct SoftMaterial {
  double linearStiffness = 1.0;      ///< `linear_stiffness`, 0..1: Bullet's link stiffness m_kLST
  double volumeConservation = 50.0;  ///< `volume_conservation`, >= 0: Bullet's kVC, pull towards the rest volume
  double pressure = 0.0;             ///< `pressure`, >= 0: Bullet's kPR (inner pressure times volume, Pa m^3)
  double damping = 0.01;             ///< `damping`, 0..1: Bullet's kDP, node velocity damping per step
  double shapeMatching = 0.0;        ///< `shape_matching`, 0..1: Bullet's kMT, pull towards the rest shape moved rigidly (pose matching)
  int iterations = 8;                ///< `iterations`, 1..100: Bullet's position solver iterations
  int bendingDistance = 2;           ///< `bending_distance`, 0..4: bending links between nodes up to this many links apart (below 2: none)
};

/// A body given as a Bullet primitive instead of a mesh file (scene key `shape`, e.g.
/// {"type": "capsule", "radius": 0.3, "height": 1.2, "axis": "y"}): its collision shape is this
/// primitive and its mesh is made from it (meshFromCollisionShape, default tessellation).
struct SceneShape {
  /// Which Bullet shape (`type`).
  enum class Type { Box, Sphere, Capsule, Cylinder, Cone };
  Type type = Type::Box;                                     ///< `type`: "box", "sphere", "capsule", "cylinder", "cone"
  Eigen::Vector3d halfExtents = Eigen::Vector3d::Zero();     ///< `half_extents` (m, > 0), box only: btBoxShape's half extents
  double radius = 0.0;                                       ///< `radius` (m, > 0): sphere, capsule, cylinder, cone
  /// `height` (m): capsule: its cylindrical part, >= 0 (Bullet's convention; the capsule is
  /// height + 2 radius long); cylinder and cone: the whole height, > 0.
  double height = 0.0;
  int axis = 1;                                              ///< `axis` "x", "y" (default) or "z": capsule, cylinder, cone
};

/// One body of a scene.
struct SceneBody {
  std::string name;                                          ///< CSV `body` column
  std::shared_ptr<const Mesh> mesh;                          ///< given directly (tests), or ...
  std::string meshPath;                                      ///< ... loaded from this file (`mesh`), or ...
  std::optional<SceneShape> shape;                           ///< ... a Bullet primitive (`shape`)
  MeshLoadSettings load;                                     ///< `up` ("y"/"z"), `scale`, `repair` (bool), `max_hole_fraction`, `open_hull` (bool)
  std::optional<double> density;                             ///< kg/m^3 (uniform solid; kept when it deforms: the mass follows the volume)
  std::optional<double> mass;                                ///< kg (uniform solid; kept when it deforms: the density follows the volume)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();        ///< m, mesh frame origin in the world
  Eigen::Vector3d rotationDegrees = Eigen::Vector3d::Zero(); ///< degrees, extrinsic X, Y, Z
  Eigen::Vector3d linearVelocity = Eigen::Vector3d::Zero();  ///< m/s, of the centre of mass
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero(); ///< rad/s
  int resolution = 256;                                      ///< texels per side
  HydrostaticsMethod method = HydrostaticsMethod::Auto;      ///< hydrostatics path (`method`: "auto", the default, "texture", "polyhedral" or "exact")
  double autoMethodError = 1e-4;                             ///< `auto_method_error`: the texture path's largest error for "auto" (of the volume)
  EffectSet effects{Effect::Buoyancy, Effect::Drag};         ///< effects it pays for
  double shellDensity = 0.0;                                 ///< kg/m^2 (`shell_density`) at rest; a deforming shell keeps its mass
  std::shared_ptr<const ImageMap> densityMap;                ///< `density_map` (PNG, loaded)
  std::array<double, 2> densityRange{0.0, 0.0};              ///< kg/m^3 for black and white (`density_range`)
  std::vector<PointMass> pointMasses;                        ///< `point_masses`: {mass, position, path}
  std::vector<ScaleKeyframe> scaleKeyframes;                 ///< `deform: {type: "scale", keyframes}`
  WettingBodySettings wetting;                               ///< `wetting: {resolution, diffusivity, porosity, permeability, humidity, temperature, sources}`
  FloodingBodySettings flooding;                             ///< `permeability_map`, `permeability`, `wall_thickness`, `porosity`, `interior_permeability`, `opening_conductance`, `liquid_graph`, `liquid_graph_nodes`
  bool soft = false;                                         ///< `soft: true`: a btSoftBody (nodes: the mesh's vertices), buoyancy only; its nodes keep the mass (density: of the rest mesh)
  SoftMaterial softMaterial;                                 ///< `soft_material` (soft bodies only)
};

/// The liquid's free surface.
struct SceneSurface {
  /// Kind of surface.
  enum class Type { Plane, Waves, None };
  Type type = Type::Plane;             ///< plane, Gerstner waves, or none (a uniform medium)
  double height = 0.0;                 ///< m, plane height or the waves' mean level
  std::vector<GerstnerWave> waves;     ///< wave components (Type::Waves)
};

/// A whole scene.
struct Scene {
  std::string sourceName;                               ///< file name for messages
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};             ///< m/s^2
  double dt = 1.0 / 240.0;                              ///< s per step (> 0)
  double duration = 10.0;                               ///< s (>= 0)
  int substeps = 1;                                     ///< fixed sub-steps per step (1..64)
  double fluidDensity = 1000.0;                         ///< kg/m^3
  double viscosity = 1.0e-3;                            ///< Pa s
  Eigen::Vector3d fluidVelocity = Eigen::Vector3d::Zero(); ///< m/s, uniform current
  SceneSurface surface;                                 ///< free surface
  std::optional<double> seabed;                         ///< m, static floor height (none when empty)
  std::vector<SceneBody> bodies;                        ///< rigid bodies (at least one body in all)
  /// Bodies with `soft: true`, in file order; kept apart so that `bodies` and
  /// SceneWorld::bodies() stay index for index.
  std::vector<SceneBody> softBodies;
  /// `threads`: ControllerSettings::threads (0: all cores; >= 1: at most that many).
  int threads = 0;
  /// `backend`: "cpu", "gpu" or "auto" (checkControllerBackend), made by SceneWorld::create's factory.
  std::string backend = "auto";
  /// Number of steps the duration takes (rounded to the nearest whole step).
  long long stepCount() const;
  /// One line naming the first impossible value (non-positive dt, NaN, no bodies, ...), or Ok.
  Status validate() const;
};

/// Parses scene JSON `text`; mesh paths are resolved against `baseDirectory`; messages start
/// with `sourceName`. Errors name the key: unknown keys, wrong types, impossible values.
Expected<Scene> parseScene(const std::string& text, const std::string& baseDirectory, const std::string& sourceName);

/// Checks the name of the backend that runs a scene's controller (scene key `backend`, `hydrotex
/// simulate --backend`): "cpu", "gpu" (the GL compute backend) or "auto" (the GL one when an EGL
/// device opens, else the CPU). The message names the value.
Status checkControllerBackend(const std::string& name);

/// Makes the controller's backend from its name (checkControllerBackend's), for SceneWorld::create:
/// the tool and the demos pass hydrotex::gpu::makeBackend; `plugin/` links no GL. A null backend
/// means the controller's own CPU one.
using SceneBackendFactory = std::function<Expected<std::shared_ptr<ComputeBackend>>(const std::string& name)>;

/// Reads and parses the scene file at `path` (mesh paths relative to the file).
Expected<Scene> loadScene(const std::string& path);

/// The liquid surface a scene describes.
std::shared_ptr<const LiquidSurface> makeSceneSurface(const Scene& scene);

/// A headless Bullet world running a scene: world, seabed, bodies (convex hulls of their meshes,
/// with a collision margin of 2 % of the smallest extent, 1 mm..4 cm, since Bullet inflates a hull
/// by its margin; bodies given by `shape`: that Bullet primitive) and the controller.
class SceneWorld {
 public:
  /// Builds the world; errors from the scene, mesh files, the backend and body registration.
  /// `makeBackend` makes the scene's `backend`; without one, "cpu" and "auto" run on the CPU and
  /// "gpu" is refused (this program has no GL backend to give).
  static Expected<std::unique_ptr<SceneWorld>> create(const Scene& scene, const SceneBackendFactory& makeBackend = {});
  ~SceneWorld();
  SceneWorld(const SceneWorld&) = delete;
  SceneWorld& operator=(const SceneWorld&) = delete;

  /// Advances by the scene's dt (its sub-steps included).
  void step();
  /// Simulated time (s).
  double time() const { return time_; }
  /// The Bullet world.
  btDiscreteDynamicsWorld& world() { return *world_; }
  /// The controller.
  BuoyancyController& controller() { return *controller_; }
  /// The bodies, in scene order.
  const std::vector<btRigidBody*>& bodies() const { return bodyPointers_; }
  /// The soft bodies (Scene::softBodies order); a scene with any runs in a btSoftRigidDynamicsWorld.
  const std::vector<btSoftBody*>& softBodies() const { return softBodyPointers_; }
  /// The scene it runs.
  const Scene& scene() const { return scene_; }

 private:
  SceneWorld() = default;
  Scene scene_;
  std::unique_ptr<btDefaultCollisionConfiguration> configuration_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btDefaultMotionState>> motionStates_;
  std::vector<std::unique_ptr<btRigidBody>> rigidBodies_;
  std::vector<btRigidBody*> bodyPointers_;
  std::unique_ptr<BuoyancyController> controller_;
  std::unique_ptr<btSoftBodySolver> softSolver_;
  std::vector<std::unique_ptr<btSoftBody>> softBodies_;
  std::vector<btSoftBody*> softBodyPointers_;
  double time_ = 0.0;
};

}  // namespace hydrotex::bullet
