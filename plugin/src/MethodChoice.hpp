// SPDX-License-Identifier: Zlib
#pragma once
/// @file MethodChoice.hpp
/// Private to the plugin: which hydrostatics path a body runs (HydrostaticsMethod::Auto resolved
/// at registration by core's advisor and, under waves, the exact path's linearization error).

#include <optional>

#include "hydrotex/bullet/FloatingBodySettings.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::bullet {

/// `settings.method` unless it is Auto; for Auto, Texture for a deforming body, else core's
/// adviseHydrostatics on `mesh` at the body's resolution (in flat water) with the target
/// settings.autoMethodError, and under a surface that is not flat the exact path's linearization
/// error (exactLinearizationError) beside it: the advisor's choice when the exact path's error is
/// within the target too, else the texture path when it meets the target, else whichever has the
/// smaller error. Polyhedral when the advisor cannot measure the mesh (addBody then names the
/// mesh's defect itself).
HydrostaticsMethod resolveHydrostaticsMethod(const FloatingBodySettings& settings, const Mesh& mesh,
                                             const LiquidSurface& surface);

}  // namespace hydrotex::bullet
