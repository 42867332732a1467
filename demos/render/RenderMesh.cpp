// SPDX-License-Identifier: Zlib
#include "RenderMesh.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace hydrotex::render {

std::vector<RenderVertex> unrollMesh(const Mesh& mesh, double creaseDegrees, const UvLayout* physicsLayout) {
  const std::size_t triangleCount = mesh.triangles.size();
  // Area-weighted face normals (length = twice the area) and the faces around each position.
  std::vector<Eigen::Vector3d> faceNormal(triangleCount);
  std::vector<std::vector<int>> facesAround(mesh.positions.size());
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    faceNormal[t] = (mesh.positions[tri[1]] - mesh.positions[tri[0]]).cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    for (int k = 0; k < 3; ++k) facesAround[tri[k]].push_back(static_cast<int>(t));
  }
  const double creaseCosine = std::cos(creaseDegrees * std::numbers::pi / 180.0);
  const bool hasUvs = mesh.hasUvs();
  const bool hasPhysicsUvs = physicsLayout != nullptr && physicsLayout->uvTriangles.size() == triangleCount;
  std::vector<RenderVertex> vertices;
  vertices.reserve(3 * triangleCount);
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const Eigen::Vector3d own = faceNormal[t].normalized();
    for (int k = 0; k < 3; ++k) {
      const int p = mesh.triangles[t][k];
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int f : facesAround[p])
        if (faceNormal[f].normalized().dot(own) >= creaseCosine) sum += faceNormal[f];
      const Eigen::Vector3d n = sum.norm() > 0.0 ? sum.normalized() : own;
      RenderVertex v{};
      for (int c = 0; c < 3; ++c) {
        v.position[c] = static_cast<float>(mesh.positions[p][c]);
        v.normal[c] = static_cast<float>(n[c]);
      }
      if (hasUvs) {
        const Eigen::Vector2d& uv = mesh.uv.uvs[mesh.uv.uvTriangles[t][k]];
        v.uv[0] = static_cast<float>(uv.x());
        v.uv[1] = static_cast<float>(uv.y());
      }
      v.physicsUv[0] = v.uv[0];
      v.physicsUv[1] = v.uv[1];
      if (hasPhysicsUvs) {
        const Eigen::Vector2d& uv = physicsLayout->uvs[std::size_t(physicsLayout->uvTriangles[t][k])];
        v.physicsUv[0] = static_cast<float>(uv.x());
        v.physicsUv[1] = static_cast<float>(uv.y());
      }
      vertices.push_back(v);
    }
  }
  return vertices;
}

}  // namespace hydrotex::render
