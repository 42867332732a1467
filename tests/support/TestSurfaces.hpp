// SPDX-License-Identifier: Zlib
#pragma once
// Surface textures that several suites bake the same way.
#include <string>
#include <vector>

#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"
#include "hydrotex/mesh/Mesh.hpp"

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
/// The texture path of `mesh` baked from its own UVs at resolution x resolution texels (the test
/// fails when the bake or the build does).
TextureHydrostatics textureHydrostaticsOf(const Mesh& mesh, int resolution, const TextureHydrostaticsSettings& settings = {});

/// A named Gerstner sea.
struct Sea {
  std::string name;
  GerstnerWaves waves;
};
/// The seas the wave suites share: bench_hydrostatics' three-wave swell, the log_waves scene's
/// waves (data/scenes/log_waves.json: two components, 0.3 m at 12 m and 0.1 m at 5 m, in sea
/// water), and the GL parity test's three steep crossing waves (sum Q k A = 0.38).
std::vector<Sea> gerstnerSeas();
}  // namespace hydrotex::test
