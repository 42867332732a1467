// SPDX-License-Identifier: Zlib
#include "TestSurfaces.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

namespace hydrotex::test {

Mesh squarePlate(double side, double height) {
  Mesh mesh;
  mesh.sourceName = "plate";
  const double h = 0.5 * side;
  mesh.positions = {{-h, height, -h}, {h, height, -h}, {h, height, h}, {-h, height, h}};
  mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
  mesh.uv.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.uv.uvTriangles = mesh.triangles;
  return mesh;
}

SurfaceBake bakeOf(const Mesh& mesh, int resolution) {
  BakeSettings settings;
  settings.width = settings.height = resolution;
  auto bake = bakeSurface(mesh, mesh.uv, settings);
  REQUIRE(bake.ok());
  return std::move(bake).value();
}

SurfaceTextures texturesOf(const Mesh& mesh, int resolution) { return evaluateSurface(bakeOf(mesh, resolution), mesh, mesh.uv); }

TextureHydrostatics textureHydrostaticsOf(const Mesh& mesh, int resolution, const TextureHydrostaticsSettings& settings) {
  const SurfaceBake bake = bakeOf(mesh, resolution);
  auto body = TextureHydrostatics::build(bake, evaluateSurface(bake, mesh, mesh.uv), settings);
  REQUIRE(body.ok());
  return std::move(body).value();
}

std::vector<Sea> gerstnerSeas() {
  return {{"swell", GerstnerWaves({GerstnerWave{0.10, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                                   GerstnerWave{0.05, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5},
                                   GerstnerWave{0.02, 2.3, Eigen::Vector2d(-0.3, 1.0), 2.0, 0.3}})},
          {"log_waves", GerstnerWaves({GerstnerWave{0.3, 12.0, Eigen::Vector2d(1.0, 0.0), 0.0, 0.5},
                                       GerstnerWave{0.1, 5.0, Eigen::Vector2d(0.6, 0.8), 1.0, 0.5}},
                                      0.0, 1025.0)},
          {"steep", GerstnerWaves({GerstnerWave{0.15, 6.0, Eigen::Vector2d(1.0, 0.3), 0.4, 0.6},
                                   GerstnerWave{0.08, 3.5, Eigen::Vector2d(-0.4, 1.0), 1.3, 0.8},
                                   GerstnerWave{0.05, 2.2, Eigen::Vector2d(0.7, -0.7), 2.0, 0.5}},
                                  0.05, 1025.0)}};
}

std::vector<float> floorHole(const SurfaceTextures& textures, double halfWidth, double xCentre) {
  std::vector<float> values(textures.size(), 0.0f);
  for (std::size_t t = 0; t < textures.size(); ++t) {
    const Eigen::Vector3f n = textures.areaVector[t] / std::max(textures.area[t], 1e-30f);
    const Eigen::Vector3f p = textures.position[t];
    if (n.y() < -0.99f && std::abs(p.x() - xCentre) < halfWidth && std::abs(p.z()) < halfWidth) values[t] = 1.0f;
  }
  return values;
}

}  // namespace hydrotex::test
