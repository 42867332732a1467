// SPDX-License-Identifier: Zlib
#pragma once
/// @file PrimitiveMassProperties.hpp
/// Mass properties of primitives in closed form, to go with their closed-form hydrostatics
/// (PrimitiveHydrostatics.hpp): a body floated as a true sphere should weigh as one, not as its
/// tessellated mesh (whose volume is smaller by its volume deficit, up to 1e-3 at the default
/// ShapeTessellation), or it floats at the wrong draft.

#include <Eigen/Core>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mass/MassProperties.hpp"

namespace hydrotex {

/// A solid sphere of `radius` (m) and uniform `density` (kg/m^3) centred at `center` (m, mesh
/// frame): volume 4/3 pi r^3 (m^3), mass rho V (kg), centre of mass at the centre, inertia
/// 2/5 m r^2 about every axis through it (kg m^2). Errors: a radius or density that is not positive
/// and finite, a centre that is not finite.
Expected<MassProperties> solidSphereMassProperties(double radius, double density,
                                                   const Eigen::Vector3d& center = Eigen::Vector3d::Zero());

}  // namespace hydrotex
