// Generates the bundled meshes in data/meshes from the closed primitives of the core library, so
// that every asset can be rebuilt and changed. Usage: hydrotex_generate_assets OUTPUT_DIR

#include <Eigen/Geometry>
#include <cstdio>
#include <string>
#include <vector>

#include "hydrotex/MeshIO.hpp"
#include "hydrotex/Primitives.hpp"

namespace {

/// Applies a rigid rotation and translation to every vertex (UVs untouched).
hydrotex::Mesh transformed(hydrotex::Mesh mesh, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& offset) {
  for (Eigen::Vector3d& p : mesh.positions) p = rotation * p + offset;
  return mesh;
}

struct Asset {
  std::string file;
  hydrotex::Mesh mesh;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: hydrotex_generate_assets OUTPUT_DIR\n");
    return 2;
  }
  const std::string dir = std::string(argv[1]) + "/";
  namespace prim = hydrotex::primitives;
  const Eigen::Matrix3d upright = Eigen::AngleAxisd(-EIGEN_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();

  std::vector<Asset> assets = {
      // 1 m cube: the box of the closed-form tests.
      {"box.obj", prim::box(Eigen::Vector3d(1.0, 1.0, 1.0))},
      // Sphere of radius 0.5 m.
      {"sphere.obj", prim::uvSphere(0.5, 48, 24)},
      // Spar buoy: a vertical cylinder, radius 0.4 m, 2 m tall, centred at the origin.
      {"buoy.obj", transformed(prim::cylinder(0.4, 2.0, 48), upright, Eigen::Vector3d::Zero())},
      // Log: a horizontal cylinder (axis along z), radius 0.25 m, 3 m long.
      {"log.obj", prim::cylinder(0.25, 3.0, 48)},
      // Torus (non-convex): major radius 1 m, tube radius 0.25 m.
      {"torus.obj", prim::torus(1.0, 0.25, 64, 24)},
      // Wigley hull: L = 4 m, B = 0.4 m, T = 0.25 m, deck at y = 0.
      {"wigley.obj", prim::wigleyHull(4.0, 0.4, 0.25, 64, 16)},
  };
  for (const Asset& asset : assets) {
    hydrotex::Status saved = hydrotex::saveMesh(asset.mesh, dir + asset.file);
    if (!saved) {
      std::fprintf(stderr, "hydrotex_generate_assets: %s\n", saved.error().message.c_str());
      return 1;
    }
    std::printf("%s: %zu triangles\n", asset.file.c_str(), asset.mesh.triangles.size());
  }
  return 0;
}
