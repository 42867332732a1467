// SPDX-License-Identifier: Zlib
#pragma once
// Bodies given as Bullet primitives in scene files (`shape` instead of `mesh`): parsing and
// building the collision shape. Private to the plugin; Scene.cpp calls these.

#include <btBulletCollisionCommon.h>

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "hydrotex/Expected.hpp"
#include "hydrotex/bullet/Scene.hpp"

namespace hydrotex::bullet::detail {

/// Reads the `shape` object of the scene body at `path` into body.shape: `type` and the sizes
/// that type takes (box: `half_extents`; sphere: `radius`; capsule, cylinder, cone: `radius`,
/// `height`, `axis`). Errors, one line "source: path.shape.key: what": an unknown type or key, a
/// missing, negative or zero size.
Status parseSceneShape(const nlohmann::json& shape, const std::string& path, const std::string& source,
                       SceneBody& body);

/// The Bullet collision shape of `shape`, in the body's frame (centred as Bullet centres it). A
/// cone's margin, which Bullet adds outside it, is kept to 2 % of its smaller size (1 mm..4 cm),
/// as the scene's hulls are; the other primitives hold their margin inside their size.
std::unique_ptr<btCollisionShape> createSceneShape(const SceneShape& shape);

}  // namespace hydrotex::bullet::detail
