// SPDX-License-Identifier: Zlib
// Soft bodies in scene files (issue 5, "Deforming bodies": `soft: true` with Bullet's soft-body
// material keys). The material keys map one to one onto btSoftBody's configuration; the defaults
// keep a ball's shape (test_soft_body).
#include "SceneSoftBody.hpp"

#include <BulletSoftBody/btSoftBodyHelpers.h>

#include <cmath>
#include <set>
#include <vector>

#include "BulletEigen.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/Pose.hpp"

namespace hydrotex::bullet::detail {

namespace {

// Reads one number of `material`, checking its range [low, high].
Status readNumber(const nlohmann::json& material, const std::string& key, double low, double high,
                  const std::string& where, double& out) {
  const auto it = material.find(key);
  if (it == material.end()) return Ok{};
  if (!it->is_number()) return Error{where + "." + key + ": expected a number"};
  const double value = it->get<double>();
  if (!(value >= low && value <= high)) return Error{where + "." + key + ": must lie in " + std::to_string(low) + ".." + std::to_string(high)};
  out = value;
  return Ok{};
}

Status readInteger(const nlohmann::json& material, const std::string& key, int low, int high,
                   const std::string& where, int& out) {
  const auto it = material.find(key);
  if (it == material.end()) return Ok{};
  if (!it->is_number_integer()) return Error{where + "." + key + ": expected an integer"};
  const long long value = it->get<long long>();
  if (value < low || value > high) return Error{where + "." + key + ": must lie in " + std::to_string(low) + ".." + std::to_string(high)};
  out = int(value);
  return Ok{};
}

}  // namespace

Status parseSoftBody(const nlohmann::json* soft, const nlohmann::json* material, const std::string& path,
                     const std::string& source, SceneBody& body) {
  const std::string where = source + ": " + path;
  if (soft != nullptr) {
    if (!soft->is_boolean()) return Error{where + ".soft: expected true or false"};
    body.soft = soft->get<bool>();
  }
  if (material == nullptr) return Ok{};
  const std::string materialPath = where + ".soft_material";
  if (!body.soft) return Error{materialPath + ": needs \"soft\": true"};
  if (!material->is_object()) return Error{materialPath + ": expected an object"};
  static const std::set<std::string> known = {"linear_stiffness", "volume_conservation", "pressure",
                                              "damping", "shape_matching", "iterations", "bending_distance"};
  for (auto it = material->begin(); it != material->end(); ++it)
    if (!known.count(it.key())) return Error{materialPath + "." + it.key() + ": unknown key"};
  SoftMaterial& m = body.softMaterial;
  if (Status s = readNumber(*material, "linear_stiffness", 1e-6, 1.0, materialPath, m.linearStiffness); !s) return s;
  if (Status s = readNumber(*material, "volume_conservation", 0.0, 1e6, materialPath, m.volumeConservation); !s) return s;
  if (Status s = readNumber(*material, "pressure", 0.0, 1e12, materialPath, m.pressure); !s) return s;
  if (Status s = readNumber(*material, "damping", 0.0, 1.0, materialPath, m.damping); !s) return s;
  if (Status s = readNumber(*material, "shape_matching", 0.0, 1.0, materialPath, m.shapeMatching); !s) return s;
  if (Status s = readInteger(*material, "iterations", 1, 100, materialPath, m.iterations); !s) return s;
  if (Status s = readInteger(*material, "bending_distance", 0, 4, materialPath, m.bendingDistance); !s) return s;
  return Ok{};
}

Status checkSoftBody(const SceneBody& body, const std::string& path, const std::string& source) {
  const std::string where = source + ": " + path + ": soft: ";
  if (body.shape) return Error{where + "a soft body needs a mesh (its vertices become the nodes), not a shape"};
  if (body.shellDensity > 0.0 || body.densityMap) return Error{where + "a soft body takes density or mass, no shell_density or density_map"};
  if (!body.pointMasses.empty()) return Error{where + "a soft body takes no point_masses"};
  if (!body.scaleKeyframes.empty()) return Error{where + "a soft body deforms by itself: no deform"};
  // Auto (the default) resolves to the texture path for every deforming body, so a soft body takes it.
  if (body.method == HydrostaticsMethod::Polyhedral)
    return Error{where + "a soft body takes the texture method only (method \"texture\" or \"auto\")"};
  if (body.effects.has(Effect::Wetting) || body.effects.has(Effect::Flooding) || body.effects.has(Effect::VariableMass) ||
      body.effects.has(Effect::Deformation) || body.effects.has(Effect::AddedMass))
    return Error{where + "a soft body takes buoyancy and drag only (no wetting, flooding, variable_mass, deformation or added_mass)"};
  if (body.angularVelocity.squaredNorm() > 0.0) return Error{where + "a soft body takes no angular_velocity"};
  return Ok{};
}

Expected<std::unique_ptr<btSoftBody>> createSceneSoftBody(const SceneBody& body, const Mesh& mesh,
                                                          btSoftRigidDynamicsWorld& world,
                                                          BuoyancyController& controller) {
  double mass = body.mass.value_or(0.0);
  if (!body.mass) {
    Expected<MassProperties> properties = polyhedralMassProperties(mesh, body.density.value_or(0.0));
    if (!properties) return Error{"soft body mass: " + properties.error().message};
    mass = properties->mass;
  }
  const Pose pose = Pose::fromDegreesXYZ(body.rotationDegrees, body.position);
  std::vector<btScalar> vertices;
  vertices.reserve(3 * mesh.positions.size());
  for (const Eigen::Vector3d& p : mesh.positions) {
    const Eigen::Vector3d placed = pose.apply(p);
    for (int c = 0; c < 3; ++c) vertices.push_back(btScalar(placed[c]));
  }
  std::vector<int> triangles;
  triangles.reserve(3 * mesh.triangles.size());
  for (const Eigen::Vector3i& t : mesh.triangles)
    for (int c = 0; c < 3; ++c) triangles.push_back(t[c]);
  std::unique_ptr<btSoftBody> soft(btSoftBodyHelpers::CreateFromTriMesh(world.getWorldInfo(), vertices.data(), triangles.data(),
                                                                        int(mesh.triangles.size())));
  const SoftMaterial& m = body.softMaterial;
  soft->m_materials[0]->m_kLST = btScalar(m.linearStiffness);
  if (m.bendingDistance >= 2) soft->generateBendingConstraints(m.bendingDistance, soft->m_materials[0]);
  soft->m_cfg.piterations = m.iterations;
  soft->m_cfg.kVC = btScalar(m.volumeConservation);
  soft->m_cfg.kPR = btScalar(m.pressure);
  soft->m_cfg.kDP = btScalar(m.damping);
  soft->setTotalMass(btScalar(mass), true);
  soft->m_cfg.kMT = btScalar(m.shapeMatching);
  soft->setPose(true, m.shapeMatching > 0.0);  // the rest volume (kVC) and rest shape (kMT) they pull towards
  soft->setVelocity(toBullet(body.linearVelocity));
  SoftBodySettings settings;
  settings.resolution = body.resolution;
  settings.effects = body.effects;  // buoyancy and drag (checkSoftBody refused the others)
  if (Status s = controller.addSoftBody(soft.get(), settings); !s) return s.error();
  world.addSoftBody(soft.get());
  return soft;
}

}  // namespace hydrotex::bullet::detail
