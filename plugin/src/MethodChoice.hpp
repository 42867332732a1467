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

/// An upper bound of |d2 h / ds2| (1/m) of `surface`'s height over every point and direction: 0
/// for a flat surface or a medium, sum A k^2 / (1 - sum Q k A)^2 for Gerstner waves (the
/// trochoid's curvature at its crests, where the horizontal squeeze 1 - Q k A is smallest);
/// empty when unknown (height grids and other surfaces: their kinks have no bound).
std::optional<double> surfaceCurvatureBound(const LiquidSurface& surface);

/// Relative volume error (of the body's volume) that the exact path's linearization of `surface`
/// between the mesh's vertices may make: M2 e^2 / 8 (the largest height error of the linear
/// interpolant over an edge of length e, M2 = surfaceCurvatureBound) times the body's largest
/// bounding-box face (a bound of its water-plane area), over its volume. 0 under a flat surface
/// or a medium; +infinity when the curvature is unknown.
double exactLinearizationError(const Mesh& mesh, double volume, const LiquidSurface& surface);

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
