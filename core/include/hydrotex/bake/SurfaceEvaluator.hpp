// SPDX-License-Identifier: Zlib
#pragma once
/// @file SurfaceEvaluator.hpp
/// Per-step re-evaluation of PT, VAT, area and texel edges of a deforming mesh from a kept bake
/// (docs/design.md "Exact texels"; issue 5 "Deforming bodies"), without allocating and in single
/// precision. evaluateSurface (SurfaceBake.hpp) is the double-precision reference it matches to
/// float rounding.

#include <cstdint>
#include <vector>

#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// Everything of a bake and UV layout that does not depend on where the vertices are, arranged
/// for one pass per step: per piece its triangle, area fraction, centroid barycentrics and its
/// share of the texel's UV area (one 20-byte record, read in order); per triangle the
/// UV-to-surface map's coefficients. evaluate() then costs one pass over the triangles (area
/// vector, edges, once per triangle, reused by all its pieces) and one over the pieces. The texels
/// are visited grouped by their number of pieces (one piece: most of them, no accumulation; two;
/// three; ...), so that the loops over a texel's pieces have a fixed length and the per-texel
/// path never mispredicts a branch.
class SurfaceEvaluator {
 public:
  /// An evaluator for nothing (evaluate() gives empty textures).
  SurfaceEvaluator() = default;
  /// Prepares for `bake` of a mesh with UV layout `layout` (the layout the bake was made from).
  /// Pieces naming a triangle the layout lacks carry nothing.
  SurfaceEvaluator(const SurfaceBake& bake, const UvLayout& layout);

  /// Writes PT, VAT, area and edges of the covered texels for the current vertex positions of
  /// `mesh` (same topology as at the bake) into `out`, reusing its buffers: no allocation once
  /// `out` has had the texel count. Same meaning as evaluateSurface(); values agree with it to
  /// float rounding (positions to ~1e-7 of the mesh size). Triangles with vertex indices out of
  /// range, and pieces naming a triangle the mesh lacks, carry nothing (never a crash).
  void evaluate(const Mesh& mesh, SurfaceTextures& out);

  /// Number of covered texels the output has.
  std::size_t texelCount() const { return texelCount_; }
  /// Number of pieces evaluated per step.
  std::size_t pieceCount() const { return pieces_.size(); }

 private:
  /// Per triangle, evaluated once per step, as four-float SIMD registers (single precision,
  /// w lanes zero except the area's).
  struct TriangleFrame {
    Eigen::Array4f p0 = Eigen::Array4f::Zero();          // vertex 0 (m)
    Eigen::Array4f e1 = Eigen::Array4f::Zero();          // vertex 1 - vertex 0 (m)
    Eigen::Array4f e2 = Eigen::Array4f::Zero();          // vertex 2 - vertex 0 (m)
    Eigen::Array4f areaVector = Eigen::Array4f::Zero();  // half e1 x e2 (m^2); w: its norm (m^2)
    Eigen::Array4f edgeU = Eigen::Array4f::Zero();       // d position / du times the texel width (m)
    Eigen::Array4f edgeV = Eigen::Array4f::Zero();       // d position / dv times the texel height (m)
  };
  /// Per triangle, from the layout: edgeU = cu1 e1 + cu2 e2, edgeV = cv1 e1 + cv2 e2.
  struct UvMap {
    float cu1 = 0.0f, cu2 = 0.0f, cv1 = 0.0f, cv2 = 0.0f;
  };

  /// What a step needs of one piece, in the order the texels are visited.
  struct Piece {
    std::uint32_t triangle = 0;
    float fraction = 0.0f;  // piece UV area / triangle UV area
    float bary1 = 0.0f, bary2 = 0.0f;
    float uvShare = 0.0f;   // piece UV area / texel's covered UV area
  };
  /// Texels with the same number of pieces, visited together.
  struct Group {
    std::uint32_t piecesPerTexel = 0;
    std::size_t firstTexel = 0;  // into texelOrder_
    std::size_t texelCount = 0;
    std::size_t firstPiece = 0;  // into pieces_
  };
  template <std::uint32_t Pieces>
  void evaluateGroup(const Group& group, std::uint32_t piecesPerTexel, std::uint32_t nullFrame, SurfaceTextures& out) const;

  int width_ = 0, height_ = 0;
  std::size_t texelCount_ = 0;
  std::vector<std::uint32_t> texelOrder_;   // covered texel (SurfaceTextures index) per visit
  std::vector<std::uint32_t> correctionSlot_;  // per visit of a texel of several pieces: its momentCorrection entry
  std::vector<std::uint32_t> momentTexel_;     // SurfaceTextures::momentTexel of the bake
  std::vector<Group> groups_;
  std::vector<Piece> pieces_;               // grouped as the texels are visited
  std::vector<UvMap> uvMaps_;               // per layout triangle
  std::vector<TriangleFrame> frames_;       // per mesh triangle and a zero one, refilled each step
};

}  // namespace hydrotex
