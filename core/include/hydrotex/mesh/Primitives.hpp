// SPDX-License-Identifier: Zlib
#pragma once
/// @file Primitives.hpp
/// Closed meshes with non-overlapping UV atlases, for tests, benchmarks, demos and assets.
/// Every primitive is watertight, outward-oriented, and its UV triangles lie in [0,1]^2 without
/// overlap (each is a valid physics atlas as it comes).

#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::primitives {

/// Axis-aligned box centred at the origin with the given full extents (m). 12 triangles.
Mesh box(const Eigen::Vector3d& extents);
/// Box with each face split into `divisions` x `divisions` quads (for waterline tests).
Mesh subdividedBox(const Eigen::Vector3d& extents, int divisions);
/// UV sphere of `radius` (m) centred at the origin, `slices` around y and `stacks` pole to pole.
Mesh uvSphere(double radius, int slices, int stacks);
/// Icosphere (subdivided icosahedron) of `radius` (m); 20 * 4^subdivisions triangles.
Mesh icosphere(double radius, int subdivisions);
/// Closed cylinder along the z axis (horizontal when y is up), centred at the origin.
Mesh cylinder(double radius, double length, int segments);
/// Capsule along y centred at the origin: a cylinder of `cylinderLength` (m, >= 0; Bullet's
/// capsule "height") capped by hemispheres of `radius`; `slices` around y, `stacksPerCap` rings
/// per hemisphere; the cylinder gets rows of about the same height, at most `slices` of them (its
/// side is exact with one), and each row's UV lies at its arc length, so texel density is uniform.
Mesh capsule(double radius, double cylinderLength, int slices, int stacksPerCap);
/// Closed cone with its base at y = 0 and apex at y = height.
Mesh cone(double radius, double height, int segments);
/// Torus around the y axis: `majorRadius` to the tube centre, `minorRadius` of the tube.
Mesh torus(double majorRadius, double minorRadius, int majorSegments, int minorSegments);
/// Hemisphere (flat face at y = 0, dome towards +y when `up`, towards -y otherwise).
Mesh hemisphere(double radius, int slices, int stacks, bool up);
/// Closed Wigley hull: half-breadth y(x,z) = (B/2)(1-(2x/L)^2)(1-(z/T)^2) with the keel at depth T
/// below the deck plane (mapped to our axes: length along x, breadth along z, depth along -y),
/// closed by a flat deck at y = 0. Its volume is 4/9 L B T (docs/references.md).
Mesh wigleyHull(double length, double breadth, double draft, int lengthSegments, int depthSegments);

}  // namespace hydrotex::primitives
