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
