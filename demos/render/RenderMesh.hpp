// SPDX-License-Identifier: Zlib
#pragma once
/// @file RenderMesh.hpp
/// A hydrotex::Mesh unrolled for drawing: one vertex per triangle corner with a position (m, mesh
/// frame), a normal smoothed across edges flatter than a crease angle, the texture coordinate and
/// a second coordinate in the physics atlas (where a body's liquid texture lives).

#include <Eigen/Core>
#include <vector>

#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::render {

/// One vertex as the GPU reads it (10 floats, tightly packed).
struct RenderVertex {
  float position[3];  ///< m, mesh frame
  float normal[3];    ///< unit
  float uv[2];        ///< texture coordinate (OpenGL convention: v = 0 is the image's last row)
  float physicsUv[2]; ///< coordinate in the physics atlas (the liquid texture's layout); = uv without one
};

/// Unrolls `mesh`: normals are averaged (area weighted) over the triangles around a vertex whose
/// normals lie within `creaseDegrees` of the corner's own triangle (hard edges stay hard: a ship's
/// deck, a box). Triangles without UVs get (0, 0). `physicsLayout` (one UV triangle per mesh
/// triangle, e.g. PhysicsAtlas::layout) gives physicsUv; null or of another triangle count: the
/// mesh's own UVs.
std::vector<RenderVertex> unrollMesh(const Mesh& mesh, double creaseDegrees = 40.0, const UvLayout* physicsLayout = nullptr);

}  // namespace hydrotex::render
