// SPDX-License-Identifier: Zlib
#pragma once
/// @file MethodChoice.hpp
/// Private to the plugin: which hydrostatics path a body runs (HydrostaticsMethod::Auto resolved
/// at registration by core's advisor and, under waves, the exact path's linearization error).

#include <memory>
#include <optional>

#include "hydrotex/bullet/FloatingBodySettings.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::bullet {

/// `settings.method` unless it is Auto; for Auto, Texture for a deforming body, else the exact
/// path when core's cost model (modeledMicrosecondsPerQuery; under waves, modeledExactMicroseconds
/// of the prepared mesh's counted work) finds it the cheaper and its error
/// (core's preparedExactSurfaceError) is within settings.autoMethodError;
/// else core's adviseHydrostatics measures the texture path's error at the body's resolution (in
/// flat water, times modeled): the texture path when it meets the target and is the cheaper or the
/// exact path does not meet it, the exact path when it meets the target, else whichever errs less.
/// Polyhedral when the mesh cannot be measured (addBody then names the mesh's defect itself).
/// `prepared`, when given, receives the prepared mesh made to price the exact path under waves
/// (null where none was made), so that a body that then runs it is not prepared again.
HydrostaticsMethod resolveHydrostaticsMethod(const FloatingBodySettings& settings, const std::shared_ptr<const Mesh>& mesh,
                                             const LiquidSurface& surface,
                                             std::shared_ptr<const PreparedPolyhedron>* prepared = nullptr);

}  // namespace hydrotex::bullet
