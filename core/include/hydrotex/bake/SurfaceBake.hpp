// SPDX-License-Identifier: Zlib
#pragma once
/// @file SurfaceBake.hpp
/// The exact texel bake (docs/design.md "Exact texels"): every texel square is clipped against every UV
/// triangle that overlaps it, and the resulting pieces are kept, so that the position texture (PT)
/// and vector-area texture (VAT) are exact and can be re-evaluated from moved vertices without
/// rasterizing again (deforming meshes).

#include <cstdint>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// Bake resolution. Any size from 16 to 4096 texels per side (powers of two or not).
struct BakeSettings {
  int width = 256;        ///< texels along u (16..4096)
  int height = 256;       ///< texels along v (16..4096)
  int tileSize = 16;      ///< texels per tile side for the hierarchy (docs/design.md "Hierarchy")
  /// One-line reason when a setting is out of range.
  Status validate() const;
};

/// One piece of one triangle inside one texel: the polygon (texel square clipped to the UV
/// triangle). Positions and area vectors of a piece are linear in the triangle's vertices, so
/// these numbers are enough to re-evaluate from moved vertices.
struct TexelPiece {
  std::uint32_t triangle = 0;   ///< mesh triangle index
  float areaFraction = 0.0f;    ///< piece UV area / triangle UV area (0..1]
  float centroidBary1 = 0.0f;   ///< barycentric coordinate of the piece's UV centroid on vertex 1
  float centroidBary2 = 0.0f;   ///< ... on vertex 2 (vertex 0's is 1 - b1 - b2)
};

/// The baked layout: which texels are covered and by which pieces. Covered texels are stored
/// compactly (uncovered texels cost nothing) and ordered tile by tile (tiles in row-major order,
/// texels in row-major order within a tile), so that a tile's texels are one contiguous range.
struct SurfaceBake {
  int width = 0;                            ///< texels along u
  int height = 0;                           ///< texels along v
  int tileSize = 16;                        ///< texels per tile side
  std::vector<std::uint32_t> texelIndex;    ///< per covered texel: row * width + column (row 0 is v = 1, see Mesh.hpp)
  std::vector<std::uint32_t> pieceStart;    ///< per covered texel: first piece; size = covered + 1
  std::vector<TexelPiece> pieces;           ///< all pieces, grouped by covered texel
  std::vector<std::uint32_t> tileStart;     ///< per tile (row-major): first covered texel; size = tiles + 1

  /// Number of covered texels.
  std::size_t coveredCount() const { return texelIndex.size(); }
  /// Tiles along u.
  int tilesX() const { return (width + tileSize - 1) / tileSize; }
  /// Tiles along v.
  int tilesY() const { return (height + tileSize - 1) / tileSize; }
};

/// Area moments of the lids over a mesh's openings (Mesh::openingTriangles), exact from their
/// triangles: what a shell summed over the texels leaves out, since a lid is no material. A texel
/// on the rim holds pieces of lid and wall at one position, so subtracting the lid's exact
/// moments from the texels' sums keeps the walls' centre of mass exact where a per-texel share
/// would move the walls' part of such texels towards the lid.
struct OpeningMoments {
  double area = 0.0;                                 ///< m^2
  Eigen::Vector3d first = Eigen::Vector3d::Zero();   ///< integral of x dA about the mesh origin (m^3)
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  ///< integral of x x^T dA about the mesh origin (m^4)
  /// The same moments about `point` (m, mesh frame): integrals of (x - point) dA and
  /// (x - point)(x - point)^T dA.
  OpeningMoments about(const Eigen::Vector3d& point) const {
    OpeningMoments out;
    out.area = area;
    out.first = first - area * point;
    out.second = second - first * point.transpose() - point * first.transpose() + area * point * point.transpose();
    return out;
  }
};

/// Per covered texel surface quantities, in the body (mesh) frame, evaluated from a bake and the
/// mesh's current vertex positions. Same order as SurfaceBake::texelIndex.
struct SurfaceTextures {
  int width = 0;                               ///< texels along u
  int height = 0;                              ///< texels along v
  /// PT: area-weighted centroid of the texel's pieces (m), shifted along the area vector so that
  /// position . areaVector equals the exact sum over pieces (so enclosed volumes are exact).
  std::vector<Eigen::Vector3f> position;
  /// VAT: sum over pieces of piece area times the triangle's geometric unit normal (m^2).
  std::vector<Eigen::Vector3f> areaVector;
  /// Scalar area of the texel's pieces (m^2).
  std::vector<float> area;
  /// The texel square's edges mapped to the surface (m): d position / d u times the texel width
  /// (1 / width), averaged over the pieces weighted by their UV area. Used to place the waterline
  /// inside a texel.
  std::vector<Eigen::Vector3f> edgeU;
  /// Same for d position / d v times the texel height (1 / height); v grows upwards (towards
  /// row 0, Mesh.hpp).
  std::vector<Eigen::Vector3f> edgeV;
  /// Per texel, the part of it on lids over openings (Mesh::openingTriangles), which carries no
  /// shell and no drag and lets liquid through as an open hole: its area (m^2), area vector
  /// (m^2) and area-weighted centroid (m; the texel's position where it has none). Kept apart
  /// from the texel's own sums because a packed atlas may put pieces of a lid and of a wall
  /// (even the bottom, facing the other way) in one texel, whose position is then neither's.
  /// All three are empty when the mesh has no openings (a closed hull): no part anywhere.
  std::vector<float> openingArea;
  std::vector<Eigen::Vector3f> openingAreaVector;  ///< see openingArea
  std::vector<Eigen::Vector3f> openingPosition;    ///< see openingArea
  /// The lids' exact area moments (zero for a closed hull), for the shell (MassProperties.hpp).
  OpeningMoments openings;
  /// Texels with pieces of more than one triangle (ascending indices into the vectors above):
  /// the only ones whose single position cannot carry their pieces' first area moment, which
  /// momentCorrection then does. Fixed by the bake (a deforming mesh keeps the list). Empty for
  /// a layout whose texels each lie in one triangle.
  std::vector<std::uint32_t> momentTexel;
  /// Per entry of momentTexel: Sum_k c_k A_k^T - p A^T (m^3, body frame), c_k and A_k the
  /// pieces' centroids and area vectors, p and A the texel's position and area vector as stored
  /// (float). Sum over texels of p A^T plus these equals Sum over pieces of c_k A_k^T, the exact
  /// Int x n^T dA of the pieces' flat polygons (V I for a closed mesh), so the volume sums of a
  /// wholly submerged body are exact at every orientation (docs/design.md "Exact texels"). Its
  /// trace is zero up to rounding (p . A is the pieces' flux); zero for coplanar pieces.
  std::vector<Eigen::Matrix3f> momentCorrection;
  /// Per entry of momentTexel: the largest distance from p to a piece's centroid (m). Where a
  /// packed atlas puts pieces of distant faces in one texel (a lid and a bottom), the correction
  /// is weighted by the submerged share of p's vertical span +- this, not of the texel's patch.
  std::vector<float> momentReach;

  /// Number of covered texels.
  std::size_t size() const { return position.size(); }
};

/// Bakes the UV layout of `mesh` at the given resolution. Errors: settings out of range, a UV
/// layout that does not cover every triangle, indices out of range, non-finite UVs or positions,
/// UVs outside [0,1]^2 (by more than 1e-6), a UV triangle of zero area whose 3D area is not zero.
/// Triangles degenerate both in UV and in 3D carry nothing and are skipped.
Expected<SurfaceBake> bakeSurface(const Mesh& mesh, const UvLayout& layout, const BakeSettings& settings);

/// Evaluates PT, VAT, area and edges from a bake and vertex positions (the mesh's own, or moved
/// ones of the same topology: deforming bodies). O(triangles + pieces). A texel whose pieces'
/// area vectors nearly cancel (|A| < 0.1 area: it straddles opposite-facing charts) keeps its
/// unshifted centroid. Pieces naming a triangle the mesh lacks are skipped (never a crash).
/// openingArea, openingAreaVector, openingPosition and openings are filled when the mesh has openings (at these vertices; a
/// deforming body keeps those of its rest mesh: SurfaceEvaluator leaves them as they are).
SurfaceTextures evaluateSurface(const SurfaceBake& bake, const Mesh& mesh, const UvLayout& layout);

}  // namespace hydrotex
