// SPDX-License-Identifier: Zlib
#pragma once
/// @file PrimitiveHydrostatics.hpp
/// Hydrostatics of primitives in closed form, where a closed form is exact and cheap (issue 19
/// item 4): a true sphere under a flat surface (a spherical cap); and under waves, where nothing
/// is closed form, a true sphere by a quadrature rule on its wetted surface (the exact path's sums
/// for the sphere itself, not for a tessellation inside it). The answer is the exact path's
/// HydrostaticsResult (same frames, same stiffness convention, Hydrostatics.hpp), so a caller may
/// take either. What has no such form here:
/// - a box is a 12-triangle polyhedron: the exact path (polyhedralHydrostatics) is exact for it;
/// - a cylinder, capsule or cone at an arbitrary tilt cut by a plane has no cheap closed form
///   (the cut of a tilted cylinder's end caps gives elliptic-segment integrals; a capsule adds
///   two spherical caps cut obliquely): they take the exact path on their tessellated mesh;
/// - under height grids (no smoothness bounds) nothing: the exact or texture path.

#include <Eigen/Core>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"

namespace hydrotex {

/// The part of a sphere below a horizontal plane: a spherical cap (docs/references.md
/// "Hydrostatics": sphere cap).
struct SphericalCap {
  double height = 0.0;          ///< m, the cap's height d: 0 (dry) .. 2 r (wholly under)
  double volume = 0.0;          ///< m^3, pi d^2 (3 r - d) / 3
  /// m, how far the cap's centroid lies below the sphere's centre: 3 (2 r - d)^2 / (4 (3 r - d));
  /// 0 when the cap is empty (no centroid; the caller gives none).
  double centroidDepthBelowCenter = 0.0;
  double waterplaneRadius = 0.0;///< m, radius of the circle the plane cuts: sqrt(d (2 r - d))
  double wettedArea = 0.0;      ///< m^2, the spherical zone under the plane: 2 pi r d
};

/// The cap of a sphere of `radius` (m, > 0) below a plane `planeAboveCenter` (m) above its centre
/// (negative: the plane lies below the centre). Heights beyond +-r give the whole sphere or
/// nothing.
SphericalCap sphericalCap(double radius, double planeAboveCenter);

/// Exact hydrostatics of a solid sphere of `radius` (m) centred at `center` (m, body frame: where
/// the sphere lies in the frame that query.pose places) under a flat `surface` (flatHeight()):
/// volume and centre of buoyancy of the cap, Archimedes' force rho g V up (N) at the centre of
/// buoyancy with its torques about the centre of mass and the body origin (N m), the water plane
/// (a disc, m^2; its centroid on the surface), the wetted zone (m^2) and the stiffness (N/m, N,
/// N m/rad) from the disc's moments about O = (x_G, h, z_G) (Hydrostatics.hpp). O(1): no mesh.
/// Under a surface with smoothness bounds (Gerstner waves): the exact path's sums under waves (its
/// frame, pressure sums and water plane, PolyhedralHydrostatics.hpp) over the true sphere, by a
/// product rule on its wetted surface (Gauss-Legendre nodes on each meridian's wet arc, equally
/// spaced meridians about the surface's normal above the centre; 16 x 8 nodes for a 0.5 m sphere
/// in bench_peers' sea, within 1.2e-6 rho g V of the rule at 256 x 48) and surface heights
/// interpolated from jets within kExactSurfaceModelTolerance / 30 (3.3e-5 m). It declines where
/// the water line may pass near a pole, or cross a meridian twice (the sphere all but dry or all
/// but submerged under a curved surface, or large against the waves): an error there.
/// Errors: an invalid query (validateHydrostaticsQuery), a radius that is not positive and finite,
/// a centre that is not finite, a surface that is neither flat nor offers smoothness bounds (height
/// grids, media: use the exact or the texture path), the rule declining, or a surface height that
/// is not finite.
Expected<HydrostaticsResult> sphereHydrostatics(double radius, const Eigen::Vector3d& center,
                                                const LiquidSurface& surface, const HydrostaticsQuery& query);

}  // namespace hydrotex
