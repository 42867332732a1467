// Per-step PT/VAT re-evaluation from a kept bake (DESIGN.md "Exact texels"). The same sums as
// evaluateSurface (SurfaceBake.cpp): a piece's centroid and area vector are linear in its
// triangle's vertices (barycentric centroid, area fraction of the triangle's area vector), and the
// texel edges are the UV-to-surface Jacobian of the pieces' triangles averaged by UV area. What
// depends only on the bake and the layout (fractions, barycentrics, UV shares, the inverse UV edge
// matrix) is prepared once; a step evaluates each triangle once and each piece once, in float
// (the textures are float anyway; a texel sums a handful of pieces, so float sums lose nothing).
#include "hydrotex/SurfaceEvaluator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace hydrotex {

SurfaceEvaluator::SurfaceEvaluator(const SurfaceBake& bake, const UvLayout& layout)
    : width_(bake.width), height_(bake.height), texelCount_(bake.coveredCount()) {
  const double texelU = bake.width > 0 ? 1.0 / bake.width : 0.0;
  const double texelV = bake.height > 0 ? 1.0 / bake.height : 0.0;
  const std::size_t triangleCount = layout.uvTriangles.size();
  uvMaps_.assign(triangleCount, UvMap{});
  std::vector<double> uvArea(triangleCount, 0.0);
  const int uvCount = static_cast<int>(layout.uvs.size());
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const Eigen::Vector3i& uvTri = layout.uvTriangles[t];
    if ((uvTri.array() < 0).any() || (uvTri.array() >= uvCount).any()) continue;  // carries nothing
    const Eigen::Vector2d d1 = layout.uvs[uvTri[1]] - layout.uvs[uvTri[0]];
    const Eigen::Vector2d d2 = layout.uvs[uvTri[2]] - layout.uvs[uvTri[0]];
    const double det = d1.x() * d2.y() - d2.x() * d1.y();
    if (det == 0.0 || !std::isfinite(det)) continue;
    uvArea[t] = 0.5 * std::abs(det);
    // e = dPdu du + dPdv dv for both edges; inverting the 2x2 UV edge matrix gives
    // dPdu = (e1 d2.y - e2 d1.y) / det, dPdv = (e2 d1.x - e1 d2.x) / det.
    UvMap& map = uvMaps_[t];
    map.cu1 = static_cast<float>(d2.y() / det * texelU);
    map.cu2 = static_cast<float>(-d1.y() / det * texelU);
    map.cv1 = static_cast<float>(-d2.x() / det * texelV);
    map.cv2 = static_cast<float>(d1.x() / det * texelV);
  }

  const std::size_t pieceCount = bake.pieces.size();
  pieceStart_ = bake.pieceStart;
  if (pieceStart_.size() != texelCount_ + 1) {  // a malformed bake: evaluate nothing
    pieceStart_.assign(texelCount_ + 1, 0);
  }
  pieces_.resize(pieceCount);
  for (std::size_t k = 0; k < pieceCount; ++k) {
    const TexelPiece& piece = bake.pieces[k];
    pieces_[k] = Piece{piece.triangle, piece.areaFraction, piece.centroidBary1, piece.centroidBary2, 0.0f};
  }
  for (std::size_t i = 0; i < texelCount_; ++i) {
    const std::uint32_t begin = pieceStart_[i], end = std::min<std::uint32_t>(pieceStart_[i + 1], std::uint32_t(pieceCount));
    double texelUv = 0.0;
    for (std::uint32_t k = begin; k < end; ++k)
      if (pieces_[k].triangle < triangleCount) texelUv += pieces_[k].fraction * uvArea[pieces_[k].triangle];
    if (!(texelUv > 0.0)) continue;
    for (std::uint32_t k = begin; k < end; ++k)
      if (pieces_[k].triangle < triangleCount)
        pieces_[k].uvShare = static_cast<float>(pieces_[k].fraction * uvArea[pieces_[k].triangle] / texelUv);
  }
}

void SurfaceEvaluator::evaluate(const Mesh& mesh, SurfaceTextures& out) {
  // Per triangle, once per step: vertex 0, edges, area vector and the texel edges on the surface.
  const std::size_t triangleCount = mesh.triangles.size();
  frames_.resize(triangleCount);  // allocates only when the mesh grew
  const int vertexCount = static_cast<int>(mesh.positions.size());
  for (std::size_t t = 0; t < triangleCount; ++t) {
    const Eigen::Vector3i& tri = mesh.triangles[t];
    TriangleFrame& f = frames_[t];
    if ((tri.array() < 0).any() || (tri.array() >= vertexCount).any()) {
      f = TriangleFrame{};  // carries nothing
      continue;
    }
    // Edges and the cross product in double: a small triangle far from the origin keeps its area.
    const Eigen::Vector3d& p0 = mesh.positions[tri[0]];
    const Eigen::Vector3d e1 = mesh.positions[tri[1]] - p0, e2 = mesh.positions[tri[2]] - p0;
    const Eigen::Vector3d areaVector = 0.5 * e1.cross(e2);
    const UvMap map = t < uvMaps_.size() ? uvMaps_[t] : UvMap{};
    for (int c = 0; c < 3; ++c) {
      f.p0[c] = static_cast<float>(p0[c]);
      f.e1[c] = static_cast<float>(e1[c]);
      f.e2[c] = static_cast<float>(e2[c]);
      f.areaVector[c] = static_cast<float>(areaVector[c]);
      f.edgeU[c] = static_cast<float>(map.cu1 * e1[c] + map.cu2 * e2[c]);
      f.edgeV[c] = static_cast<float>(map.cv1 * e1[c] + map.cv2 * e2[c]);
    }
    f.area = static_cast<float>(areaVector.norm());
  }

  out.width = width_;
  out.height = height_;
  out.position.resize(texelCount_);
  out.areaVector.resize(texelCount_);
  out.area.resize(texelCount_);
  out.edgeU.resize(texelCount_);
  out.edgeV.resize(texelCount_);
  const Piece* const pieces = pieces_.data();
  const TriangleFrame* const frames = frames_.data();
  const std::size_t pieceCount = pieces_.size();

  for (std::size_t i = 0; i < texelCount_; ++i) {
    const std::uint32_t begin = pieceStart_[i];
    const std::uint32_t end = std::min<std::uint32_t>(pieceStart_[i + 1], std::uint32_t(pieceCount));
    Eigen::Vector3f& position = out.position[i];
    Eigen::Vector3f& areaVector = out.areaVector[i];
    Eigen::Vector3f& edgeU = out.edgeU[i];
    Eigen::Vector3f& edgeV = out.edgeV[i];
    if (end == begin + 1 && pieces[begin].triangle < triangleCount) {
      // One piece: its centroid is the position (no shift: centroid . A is the flux itself).
      const Piece& piece = pieces[begin];
      const TriangleFrame& f = frames[piece.triangle];
      const float area = piece.fraction * f.area;
      const float keep = area > 0.0f ? 1.0f : 0.0f;  // a texel of no area sits at the origin
      for (int c = 0; c < 3; ++c) {
        position[c] = keep * (f.p0[c] + piece.bary1 * f.e1[c] + piece.bary2 * f.e2[c]);
        areaVector[c] = piece.fraction * f.areaVector[c];
        edgeU[c] = piece.uvShare * f.edgeU[c];
        edgeV[c] = piece.uvShare * f.edgeV[c];
      }
      out.area[i] = area;
      continue;
    }
    float a[3] = {0, 0, 0}, weighted[3] = {0, 0, 0}, eu[3] = {0, 0, 0}, ev[3] = {0, 0, 0};
    float area = 0.0f, flux = 0.0f;  // flux: sum of centroid . piece area vector
    for (std::uint32_t k = begin; k < end; ++k) {
      const Piece& piece = pieces[k];
      if (piece.triangle >= triangleCount) continue;  // a bake of another mesh: skip, never crash
      const TriangleFrame& f = frames[piece.triangle];
      const float pieceArea = piece.fraction * f.area;
      for (int c = 0; c < 3; ++c) {
        const float centroid = f.p0[c] + piece.bary1 * f.e1[c] + piece.bary2 * f.e2[c];
        const float pieceAreaVector = piece.fraction * f.areaVector[c];
        a[c] += pieceAreaVector;
        weighted[c] += pieceArea * centroid;
        flux += centroid * pieceAreaVector;
        eu[c] += piece.uvShare * f.edgeU[c];
        ev[c] += piece.uvShare * f.edgeV[c];
      }
      area += pieceArea;
    }
    const Eigen::Vector3f sumA(a[0], a[1], a[2]);
    const float squared = sumA.squaredNorm();
    // Both reciprocals at once (independent divisions overlap; dependent ones would not).
    const float inverseArea = area > 0.0f ? 1.0f / area : 0.0f;
    const float inverseSquared = squared > 0.0f ? 1.0f / squared : 0.0f;
    Eigen::Vector3f p(weighted[0] * inverseArea, weighted[1] * inverseArea, weighted[2] * inverseArea);
    // The shift along A that makes p . A the exact flux, left out where the pieces nearly cancel
    // (as in evaluateSurface, which explains why).
    if (squared > 1e-2f * area * area && squared > 0.0f) p += sumA * ((flux - p.dot(sumA)) * inverseSquared);
    position = p;
    areaVector = sumA;
    out.area[i] = area;
    edgeU = Eigen::Vector3f(eu[0], eu[1], eu[2]);
    edgeV = Eigen::Vector3f(ev[0], ev[1], ev[2]);
  }
}

}  // namespace hydrotex
