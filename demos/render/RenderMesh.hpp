#pragma once
/// @file RenderMesh.hpp
/// A hydrotex::Mesh unrolled for drawing: one vertex per triangle corner with a position (m, mesh
/// frame), a normal smoothed across edges flatter than a crease angle, and the texture coordinate.

#include <Eigen/Core>
#include <vector>

#include "hydrotex/Mesh.hpp"

namespace hydrotex::render {

/// One vertex as the GPU reads it (8 floats, tightly packed).
struct RenderVertex {
  float position[3];  ///< m, mesh frame
  float normal[3];    ///< unit
  float uv[2];        ///< texture coordinate (OpenGL convention: v = 0 is the image's last row)
};

/// Unrolls `mesh`: normals are averaged (area weighted) over the triangles around a vertex whose
/// normals lie within `creaseDegrees` of the corner's own triangle (hard edges stay hard: a ship's
/// deck, a box). Triangles without UVs get (0, 0).
std::vector<RenderVertex> unrollMesh(const Mesh& mesh, double creaseDegrees = 40.0);

}  // namespace hydrotex::render
