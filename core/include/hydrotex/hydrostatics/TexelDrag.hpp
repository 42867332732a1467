// SPDX-License-Identifier: Zlib
#pragma once
/// @file TexelDrag.hpp
/// Hydrodynamic drag on a body's surface, texel by texel (docs/design.md "The data flow":
/// Hydrodynamics): each surface element feels a pressure drag along its normal and a skin
/// friction along the surface, from its velocity relative to the liquid. Pure functions with
/// fixed-size inputs and outputs (no Bullet, no allocation per call).
///
/// For speed, texels of one bake tile that face the same way are merged into one drag patch
/// (mergeTexelsIntoDragPatches): the pressure law is linear in the area vector and the patch is
/// small, so the merged force differs from the texel sum only through the variation of the
/// relative velocity across the patch (rotation) and the quadratic terms.

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// Coefficients of the per-element drag law (dimensionless unless stated).
struct DragCoefficients {
  /// Pressure drag coefficient of a face advancing into the liquid (about 1 for bluff bodies).
  double advancingPressure = 1.0;
  /// Pressure drag coefficient of a face retreating from the liquid (wake suction; 0 ignores it).
  double retreatingPressure = 0.0;
  /// Linear pressure damping (m/s): force rho * this * v_n * |A| on every wetted face, both
  /// directions. Stands in for wave radiation damping, which dominates the decay of heave and roll
  /// oscillations; 0.5 m/s gives a damping ratio of about 0.1 to a 1 m box floating half immersed.
  double linearPressureVelocity = 0.5;
  /// Multiplier on the skin friction coefficient (1: flat-plate friction, 0: none).
  double skinFrictionScale = 1.0;
};

/// One surface element (a texel or a merged patch), body frame.
struct DragPatch {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();    ///< area-weighted centroid (m)
  Eigen::Vector3f areaVector = Eigen::Vector3f::Zero();  ///< sum of texel area vectors (m^2), outward
  float area = 0.0f;                                     ///< sum of texel areas (m^2)
  float radius = 0.0f;                                   ///< m, bounds the patch around `position`
};

/// Skin friction coefficient of a flat plate at Reynolds number `reynolds` (>= 0):
/// max(Blasius laminar 1.328 / sqrt(Re), ITTC 1957 0.075 / (log10(max(Re, 1e4)) - 2)^2).
/// The clamp at 1e4 keeps the ITTC line finite where it is not meant to apply and makes the
/// maximum continuous. Finite for every input (Re clamped below at 1).
double skinFrictionCoefficient(double reynolds);

/// Drag force (N) on one wetted element with outward area vector `areaVector` (m^2), scalar
/// `area` (m^2), moving at `relativeVelocity` (m/s, element minus liquid) through liquid of
/// `density` (kg/m^3) and dynamic `viscosity` (Pa s); `referenceLength` (m, > 0) sets the
/// Reynolds number of the friction. Pressure along the unit normal n = A/|A| with
/// v_n = v . n: -rho |A| (C/2 |v_n| v_n + c_lin v_n) n, C the advancing or retreating coefficient;
/// friction along the tangential velocity v_t: -rho/2 C_f |v_t| v_t area.
Eigen::Vector3d texelDragForce(const Eigen::Vector3d& areaVector, double area, const Eigen::Vector3d& relativeVelocity,
                               double density, double viscosity, double referenceLength,
                               const DragCoefficients& coefficients);

/// As texelDragForce with the skin friction coefficient `frictionCoefficient` given (already
/// scaled): callers evaluating many elements of one body compute it once from the body's
/// Reynolds number instead of once per element.
Eigen::Vector3d texelDragForceWithFriction(const Eigen::Vector3d& areaVector, double area,
                                           const Eigen::Vector3d& relativeVelocity, double density,
                                           double frictionCoefficient, const DragCoefficients& coefficients);

/// Merges the covered texels of each bake tile into patches of texels whose unit normals lie
/// within `normalCosine` (e.g. 0.9) of the patch's first texel and whose centroids lie within
/// `maxPatchRadius` (m) of it: the radius bounds how much of the lever arm (rotational damping,
/// which goes as the second moment of the area) merging loses, as (radius / lever arm)^2: a tenth
/// of a cube's size loses about 1 % of the torque of a spinning cube, a fifth 4 %; a body spinning
/// about its long axis has shorter lever arms and loses more (test_texel_drag.cpp). Texels with no area are skipped;
/// the part of a texel on a lid over an opening (SurfaceTextures::openingArea) feels no drag. `textures` must match `bake` (same covered
/// count); a mismatch returns an empty list.
std::vector<DragPatch> mergeTexelsIntoDragPatches(const SurfaceBake& bake, const SurfaceTextures& textures,
                                                  double normalCosine = 0.9,
                                                  double maxPatchRadius = std::numeric_limits<double>::infinity());

}  // namespace hydrotex
