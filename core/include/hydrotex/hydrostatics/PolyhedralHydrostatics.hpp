// SPDX-License-Identifier: Zlib
#pragma once
/// @file PolyhedralHydrostatics.hpp
/// The exact reference path (docs/design.md "Exact reference"): the closed triangle mesh is clipped
/// against the liquid surface in double precision and every quantity is integrated exactly over
/// the wetted part of the surface (divergence theorem with fields that vanish on the surface).
/// Any closed mesh, convex or not. O(triangles). Under a flat surface exact for the mesh; under
/// waves and height grids exact for the surface linearized between the mesh's vertices.

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// Height error bound (m) of the surface heights interpolated under waves by the plain exact path
/// (polyhedralHydrostaticsUnchecked) and the texel pressures (texelPressures), 3.3e-6 m: a thirtieth of 1e-4 m, the interpolation
/// bound of a model tolerance of 1e-4 m. (The texture path's default model tolerance is 3e-3 m,
/// TextureHydrostaticsSettings::surfaceModelTolerance, so its heights carry a bound of 1e-4 m:
/// this one is thirty times finer.)
inline constexpr double kExactWaveHeightError = 1e-4 / 30.0;

/// Under waves, the largest error bound (m) of a local surface model that a prepared mesh's
/// triangle node, triangle or piece of a triangle takes (LocalSurfaceModel.hpp). A third of the
/// texture path's default (TextureHydrostaticsSettings::surfaceModelTolerance, 3e-3): a triangle
/// node spans more than the texture path's tiles and groups of texels do, so its model's error
/// is nearer its bound. At 3e-3 a wholly submerged 4 m Wigley hull under three waves had forces
/// 4.5e-4 rho g V off a mesh subdivided to 2 cm edges, at 1e-3 5.2e-5 (the texture path: 3.0e-5);
/// the 1 m box, the hull of 162 vertices and a 1,280-triangle sphere within 3.6e-5 at both.
inline constexpr double kExactSurfaceModelTolerance = 1e-3;

/// Under waves, the most (m) that a prepared mesh's triangle the water line crosses may move a
/// depth by taking its local model linear between corners: such a triangle is split into pieces
/// until that bound holds, then each is clipped (PolyhedralHydrostaticsWaves.cpp).
inline constexpr double kExactWaveClipError = 3e-4;

/// Exact hydrostatics of `mesh` (body frame, m) posed by `query` in `surface`.
/// Surfaces:
/// - flat (flatHeight()): exact; the force is Archimedes' rho g V up (N) at the centre of buoyancy.
/// - any other free surface (Gerstner waves, height grids): the surface height is asked once per
///   vertex of the triangles that may be wet (those not wholly above heightRange()'s highest
///   point), the depth d = h(x, z, t) - y (m) is taken linear over each triangle, each triangle is
///   clipped where d changes sign, and the pressure rho g d (Pa) is integrated exactly over the
///   wetted part: force and torque are pressure sums (N, N m), volume (m^3) and centre of
///   buoyancy (m) those under the surface linearized between vertices. The difference from the
///   true surface is O(edge^2 x the surface's curvature) per unit of wetted area: mesh finely
///   against the wavelength. Frame origin and stiffness as the texture path's under waves: the
///   water plane is the cap's horizontal projection, the stiffness the flat-water formula about
///   the plane y = h(x_G, z_G) through the centre of mass's vertical (N/m, N, N m/rad).
/// - a uniform medium (no free surface): every triangle submerged; exact volume and centre of
///   buoyancy, force from the pressure at each triangle's centroid times its area vector, exact
///   when the density is constant.
/// Errors: an invalid query (see validateHydrostaticsQuery), an empty or open mesh (an edge not
/// shared by exactly two triangles in opposite directions), an index out of range, a vertex that
/// is not finite, or a surface height that is not finite (NaN; the message names the point).
/// The closedness check costs O(triangles log triangles); call polyhedralHydrostaticsUnchecked()
/// per step once the mesh is known to be closed.
Expected<HydrostaticsResult> polyhedralHydrostatics(const Mesh& mesh, const LiquidSurface& surface,
                                                    const HydrostaticsQuery& query);

/// As polyhedralHydrostatics() without the closedness check (the caller vouches for it; indices
/// are still range-checked, once per call). Allocation-free in a medium; under a flat surface a
/// per-thread scratch of one depth per vertex (8 bytes) grows to the largest mesh the thread has
/// seen and is reused; under 20 ns per triangle is the goal there (bench_hydrostatics). A body
/// queried every step is faster still on a PreparedPolyhedron (PreparedPolyhedron.hpp: the checks
/// made once, each triangle's constants kept; the same bits, save under Gerstner waves, where it
/// models the surface over its triangle nodes and is the more accurate). Under other free surfaces a
/// per-thread scratch of one entry per vertex (32 bytes) grows likewise; the cost is then
/// dominated by the surface's height queries, one per vertex that may be wet, unless the surface
/// offers jets and a smoothness bound (Gerstner waves) and a grid of jets over the body's footprint
/// at kExactWaveHeightError needs fewer samples than the mesh has vertices: the vertices' heights
/// are then interpolated from it (bicubic Hermite, as the texture path's hierarchy).
Expected<HydrostaticsResult> polyhedralHydrostaticsUnchecked(const Mesh& mesh, const LiquidSurface& surface,
                                                             const HydrostaticsQuery& query);

/// Status of the closedness check alone, MeshValidation's (validateMesh + requireClosed on the
/// topology): every edge used by exactly two triangles, once in each direction, and a positive
/// enclosed volume (not inside out). The message names the mesh and counts the offending edges.
Status checkClosedMesh(const Mesh& mesh);

}  // namespace hydrotex
