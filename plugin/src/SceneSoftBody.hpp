// SPDX-License-Identifier: Zlib
#pragma once
// Soft bodies in scene files (`soft: true`, `soft_material`): parsing and building the btSoftBody.
// Private to the plugin; Scene.cpp calls these.

#include <memory>
#include <string>

#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <nlohmann/json.hpp>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"
#include "hydrotex/bullet/Scene.hpp"

namespace hydrotex::bullet::detail {

/// Reads `soft` (a boolean) and `soft_material` (an object of SoftMaterial's keys; only with
/// `soft: true`) of the scene body at `path`; either may be null (absent). Messages name
/// "source: path.key".
Status parseSoftBody(const nlohmann::json* soft, const nlohmann::json* material, const std::string& path,
                     const std::string& source, SceneBody& body);

/// A soft body takes its mass (`density` or `mass`), pose, velocity, resolution, material and the
/// effects `buoyancy` and `drag`, and nothing of the rigid bodies' mass model or other effects:
/// error naming the first key that a soft body cannot honour.
Status checkSoftBody(const SceneBody& body, const std::string& path, const std::string& source);

/// Builds the btSoftBody of `body` from `mesh` (its vertices become the nodes, its triangles the
/// faces, placed at the body's pose), gives it its material, mass (`mass`, or `density` times the
/// mesh's volume) and velocity, adds it to `world` and registers it with `controller`.
Expected<std::unique_ptr<btSoftBody>> createSceneSoftBody(const SceneBody& body, const Mesh& mesh,
                                                          btSoftRigidDynamicsWorld& world,
                                                          BuoyancyController& controller);

}  // namespace hydrotex::bullet::detail
