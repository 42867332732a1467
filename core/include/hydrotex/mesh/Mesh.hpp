// SPDX-License-Identifier: Zlib
#pragma once
/// @file Mesh.hpp
/// A triangle mesh with (optional) texture coordinates, as loaded from any file assimp reads.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace hydrotex {

/// Texture coordinates of a mesh: their own vertex list and a UV triangle per mesh triangle.
/// Convention (the one place it is written down): u grows to the right from image column 0;
/// v grows upwards, v = 0 is the image's LAST row (OpenGL/OBJ convention). assimp converts
/// every format it reads (glTF included) to this convention, so image loading needs no
/// per-format flag. See ImageMap.hpp for the row mapping.
struct UvLayout {
  std::vector<Eigen::Vector2d> uvs;          ///< texture coordinates (dimensionless, [0,1] for a bakeable atlas)
  std::vector<Eigen::Vector3i> uvTriangles;  ///< per mesh triangle, indices into uvs (same corner order)
  /// True when every mesh triangle has UVs (size matches the triangle count given).
  bool coversTriangles(std::size_t triangleCount) const {
    return !uvTriangles.empty() && uvTriangles.size() == triangleCount;
  }
};

/// A triangle mesh in metres. Vertices that share a position are merged (so UV seams do not break
/// watertightness); UVs keep their own index stream in `uv`.
struct Mesh {
  std::vector<Eigen::Vector3d> positions;  ///< vertex positions (m), unique
  std::vector<Eigen::Vector3i> triangles;  ///< indices into positions, counter-clockwise seen from outside
  UvLayout uv;                             ///< the artist's texture coordinates; empty when the file had none
  std::string sourceName;                  ///< file name (or generator name) used in messages
  /// Metres per unit that the file itself declared and the import applied (COLLADA's
  /// <unit meter="...">, as the scale of assimp's root node): 1 when the file declares none.
  double fileUnitScale = 1.0;
  /// Triangles (indices into `triangles`, ascending) of lids that repair generated over the
  /// openings of an open hull (RepairSettings::openHull): they close the volume, so that volume and
  /// buoyancy are those of the hull up to its rim, but they are not material. Their texels carry
  /// no shell mass and let liquid through as an open hole (SurfaceTextures::openingArea).
  /// Empty for a closed hull.
  std::vector<std::uint32_t> openingTriangles;

  /// True when the file provided texture coordinates for every triangle.
  bool hasUvs() const { return uv.coversTriangles(triangles.size()); }
  /// True when some triangles are lids over openings (an open hull).
  bool hasOpenings() const { return !openingTriangles.empty(); }
};

}  // namespace hydrotex
