// SPDX-License-Identifier: Zlib
#pragma once
// Surface textures that several suites bake the same way.
#include <vector>

#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex::test {
/// Square plate of side `side` (m) in the plane y = `height` (m), facing +y, its UVs filling
/// [0,1]^2 with u along x (u = 0 at x = -side / 2) and v along z.
Mesh squarePlate(double side, double height = 0.0);
/// The exact bake of `mesh` from its own UVs at resolution x resolution texels (the test fails
/// when the bake does).
SurfaceBake bakeOf(const Mesh& mesh, int resolution);
/// PT/VAT of `mesh` baked from its own UVs at resolution x resolution texels (the test fails
/// when the bake does).
SurfaceTextures texturesOf(const Mesh& mesh, int resolution);
/// 1 on a box's floor (texels facing down) within |x - xCentre|, |z| < halfWidth (m): a hole in
/// a permeability map; 0 elsewhere.
std::vector<float> floorHole(const SurfaceTextures& textures, double halfWidth, double xCentre = 0.0);
}  // namespace hydrotex::test
