// SPDX-License-Identifier: Zlib
// Scene bodies given as Bullet primitives (issue 20): `shape: {type, half_extents | radius,
// height, axis}` parsed and turned into btBoxShape, btSphereShape, btCapsuleShape,
// btCylinderShape or btConeShape along x, y or z.
#include "SceneShape.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

namespace hydrotex::bullet::detail {
namespace {

constexpr std::array<const char*, 5> kTypeNames{"box", "sphere", "capsule", "cylinder", "cone"};

/// Reads the number `key` of `shape` into `out`; it must be there, finite and > 0 (or >= 0 when
/// `zeroAllowed`).
Status readSize(const nlohmann::json& shape, const std::string& key, const std::string& where, bool zeroAllowed,
                double& out) {
  const auto it = shape.find(key);
  if (it == shape.end()) return Error{where + "." + key + ": missing (m)"};
  if (!it->is_number()) return Error{where + "." + key + ": expected a number (m)"};
  out = it->get<double>();
  if (!std::isfinite(out) || out < 0.0 || (!zeroAllowed && out == 0.0)) {
    return Error{where + "." + key + ": " + it->dump() + (zeroAllowed ? " must be >= 0 (m)" : " must be > 0 (m)")};
  }
  return Ok{};
}

}  // namespace

Status parseSceneShape(const nlohmann::json& shape, const std::string& path, const std::string& source,
                       SceneBody& body) {
  const std::string where = source + ": " + path + ".shape";
  if (!shape.is_object()) return Error{where + ": expected an object {\"type\": ..., sizes}"};
  const auto typeIt = shape.find("type");
  if (typeIt == shape.end() || !typeIt->is_string()) {
    return Error{where + ".type: missing (box, sphere, capsule, cylinder or cone)"};
  }
  const std::string typeName = typeIt->get<std::string>();
  const auto found = std::find(kTypeNames.begin(), kTypeNames.end(), typeName);
  if (found == kTypeNames.end()) {
    return Error{where + ".type: '" + typeName + "' is not one of box, sphere, capsule, cylinder, cone"};
  }
  SceneShape result;
  result.type = SceneShape::Type(found - kTypeNames.begin());
  std::set<std::string> known{"type"};
  if (result.type == SceneShape::Type::Box) {
    known.insert("half_extents");
    const auto it = shape.find("half_extents");
    if (it == shape.end()) return Error{where + ".half_extents: missing ([x, y, z] m, half the box's size)"};
    if (!it->is_array() || it->size() != 3) return Error{where + ".half_extents: expected [x, y, z] (m)"};
    for (int i = 0; i < 3; ++i) {
      const nlohmann::json& item = (*it)[std::size_t(i)];
      if (!item.is_number()) return Error{where + ".half_extents: expected [x, y, z] (m)"};
      result.halfExtents[i] = item.get<double>();
      if (!(std::isfinite(result.halfExtents[i]) && result.halfExtents[i] > 0.0)) {
        return Error{where + ".half_extents: " + it->dump() + " must all be > 0 (m)"};
      }
    }
  } else {
    known.insert("radius");
    if (Status s = readSize(shape, "radius", where, false, result.radius); !s) return s;
    if (result.type != SceneShape::Type::Sphere) {
      known.insert({"height", "axis"});
      const bool capsule = result.type == SceneShape::Type::Capsule;
      if (Status s = readSize(shape, "height", where, capsule, result.height); !s) return s;
      if (const auto it = shape.find("axis"); it != shape.end()) {
        const std::string axis = it->is_string() ? it->get<std::string>() : it->dump();
        if (axis != "x" && axis != "y" && axis != "z") return Error{where + ".axis: '" + axis + "' is not x, y or z"};
        result.axis = axis[0] - 'x';
      }
    }
  }
  for (auto it = shape.begin(); it != shape.end(); ++it) {
    if (!known.count(it.key())) return Error{where + "." + it.key() + ": unknown key for a " + typeName};
  }
  body.shape = result;
  return Ok{};
}

std::unique_ptr<btCollisionShape> createSceneShape(const SceneShape& shape) {
  const btScalar r = btScalar(shape.radius), h = btScalar(shape.height);
  switch (shape.type) {
    case SceneShape::Type::Box:
      return std::make_unique<btBoxShape>(
          btVector3(btScalar(shape.halfExtents.x()), btScalar(shape.halfExtents.y()), btScalar(shape.halfExtents.z())));
    case SceneShape::Type::Sphere:
      return std::make_unique<btSphereShape>(r);
    case SceneShape::Type::Capsule:
      if (shape.axis == 0) return std::make_unique<btCapsuleShapeX>(r, h);
      if (shape.axis == 2) return std::make_unique<btCapsuleShapeZ>(r, h);
      return std::make_unique<btCapsuleShape>(r, h);
    case SceneShape::Type::Cylinder: {
      btVector3 half(r, r, r);
      half[shape.axis] = btScalar(0.5) * h;
      if (shape.axis == 0) return std::make_unique<btCylinderShapeX>(half);
      if (shape.axis == 2) return std::make_unique<btCylinderShapeZ>(half);
      return std::make_unique<btCylinderShape>(half);
    }
    case SceneShape::Type::Cone: {
      std::unique_ptr<btConeShape> cone;
      if (shape.axis == 0) {
        cone = std::make_unique<btConeShapeX>(r, h);
      } else if (shape.axis == 2) {
        cone = std::make_unique<btConeShapeZ>(r, h);
      } else {
        cone = std::make_unique<btConeShape>(r, h);
      }
      // Bullet grows a cone by its margin (0.04 m by default): keep it small for small cones.
      const double margin = std::clamp(0.02 * std::min(2.0 * shape.radius, shape.height), 1e-3, 0.04);
      cone->setMargin(btScalar(std::min(double(cone->getMargin()), margin)));
      return cone;
    }
  }
  return nullptr;
}

}  // namespace hydrotex::bullet::detail
