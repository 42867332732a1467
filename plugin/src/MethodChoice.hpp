// SPDX-License-Identifier: Zlib
#pragma once
/// @file MethodChoice.hpp
/// Private to the plugin: which hydrostatics path a body runs (HydrostaticsMethod::Auto resolved
/// at registration by core's advisor).

#include "hydrotex/bullet/FloatingBodySettings.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::bullet {

/// `settings.method` unless it is Auto; for Auto, Texture for a deforming body, else core's
/// adviseHydrostatics on `mesh` at the body's resolution with the target settings.autoMethodError:
/// Texture when the texture path meets it and is faster than the exact path, Polyhedral otherwise
/// (also when the advisor cannot measure the mesh: addBody then names the mesh's defect itself).
HydrostaticsMethod resolveHydrostaticsMethod(const FloatingBodySettings& settings, const Mesh& mesh);

}  // namespace hydrotex::bullet
