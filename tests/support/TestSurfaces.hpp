// SPDX-License-Identifier: Zlib
#pragma once
// Surface textures that several suites bake the same way.
#include <string>
#include <utility>
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
/// The surface `inner` without its smoothness bound (and so without the jets' grid): the exact
/// path, rigid and soft drag then ask its height per vertex or patch, the reference for what they
/// interpolate. `inner` must outlive it.
class SurfaceWithoutSmoothness final : public LiquidSurface {
 public:
  explicit SurfaceWithoutSmoothness(const LiquidSurface& inner) : inner_(inner) {}
  double surfaceHeight(double x, double z, double time) const override { return inner_.surfaceHeight(x, z, time); }
  Eigen::Vector3d velocity(const Eigen::Vector3d& p, double time) const override { return inner_.velocity(p, time); }
  Eigen::Vector3d velocityBelow(const Eigen::Vector3d& p, double height, double time) const override {
    return inner_.velocityBelow(p, height, time);
  }
  double density() const override { return inner_.density(); }
  std::pair<double, double> heightRange(double time) const override { return inner_.heightRange(time); }
  Status validate() const override { return inner_.validate(); }

 private:
  const LiquidSurface& inner_;
};
}  // namespace hydrotex::test
