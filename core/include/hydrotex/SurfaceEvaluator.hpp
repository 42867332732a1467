#pragma once
/// @file SurfaceEvaluator.hpp
/// Per-step re-evaluation of PT, VAT, area and texel edges of a deforming mesh from a kept bake
/// (DESIGN.md "Exact texels"; issue 5 "Deforming bodies"), without allocating and in single
/// precision. evaluateSurface (SurfaceBake.hpp) is the double-precision reference it matches to
/// float rounding.

#include <cstdint>
#include <vector>

#include "hydrotex/Mesh.hpp"
#include "hydrotex/SurfaceBake.hpp"

namespace hydrotex {

/// Everything of a bake and UV layout that does not depend on where the vertices are, arranged
/// for one pass per step: per piece its triangle, area fraction, centroid barycentrics and its
/// share of the texel's UV area (one 20-byte record, read in order); per triangle the
/// UV-to-surface map's coefficients. evaluate() then costs one pass over the triangles (area
/// vector, edges, once per triangle, reused by all its pieces) and one over the pieces; a texel
/// made of one piece (most of them) needs no accumulation at all.
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
  /// Per triangle, evaluated once per step (single precision, one cache line and a bit).
  struct TriangleFrame {
    float p0[3];          // vertex 0 (m)
    float e1[3];          // vertex 1 - vertex 0 (m)
    float e2[3];          // vertex 2 - vertex 0 (m)
    float areaVector[3];  // half e1 x e2 (m^2)
    float area;           // |areaVector| (m^2)
    float edgeU[3];       // d position / du times the texel width (m)
    float edgeV[3];       // d position / dv times the texel height (m)
  };
  /// Per triangle, from the layout: edgeU = cu1 e1 + cu2 e2, edgeV = cv1 e1 + cv2 e2.
  struct UvMap {
    float cu1 = 0.0f, cu2 = 0.0f, cv1 = 0.0f, cv2 = 0.0f;
  };

  int width_ = 0, height_ = 0;
  std::size_t texelCount_ = 0;
  /// What a step needs of one piece, in the order the texels read them.
  struct Piece {
    std::uint32_t triangle = 0;
    float fraction = 0.0f;  // piece UV area / triangle UV area
    float bary1 = 0.0f, bary2 = 0.0f;
    float uvShare = 0.0f;   // piece UV area / texel's covered UV area
  };
  std::vector<std::uint32_t> pieceStart_;   // per covered texel + 1
  std::vector<Piece> pieces_;
  std::vector<UvMap> uvMaps_;               // per layout triangle
  std::vector<TriangleFrame> frames_;       // per mesh triangle, refilled each step
};

}  // namespace hydrotex
