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
  pieceTriangle_.resize(pieceCount);
  pieceFraction_.resize(pieceCount);
  pieceBary1_.resize(pieceCount);
  pieceBary2_.resize(pieceCount);
  pieceUvShare_.assign(pieceCount, 0.0f);
  for (std::size_t k = 0; k < pieceCount; ++k) {
    const TexelPiece& piece = bake.pieces[k];
    pieceTriangle_[k] = piece.triangle;
    pieceFraction_[k] = piece.areaFraction;
    pieceBary1_[k] = piece.centroidBary1;
    pieceBary2_[k] = piece.centroidBary2;
  }
  for (std::size_t i = 0; i < texelCount_; ++i) {
    const std::uint32_t begin = pieceStart_[i], end = std::min<std::uint32_t>(pieceStart_[i + 1], std::uint32_t(pieceCount));
    double texelUv = 0.0;
    for (std::uint32_t k = begin; k < end; ++k)
      if (pieceTriangle_[k] < triangleCount) texelUv += pieceFraction_[k] * uvArea[pieceTriangle_[k]];
    if (!(texelUv > 0.0)) continue;
    for (std::uint32_t k = begin; k < end; ++k)
      if (pieceTriangle_[k] < triangleCount)
        pieceUvShare_[k] = static_cast<float>(pieceFraction_[k] * uvArea[pieceTriangle_[k]] / texelUv);
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
  const std::uint32_t* const triangleOf = pieceTriangle_.data();
  const float* const fractionOf = pieceFraction_.data();
  const float* const bary1Of = pieceBary1_.data();
  const float* const bary2Of = pieceBary2_.data();
  const float* const shareOf = pieceUvShare_.data();
  const TriangleFrame* const frames = frames_.data();
  const std::size_t pieceCount = pieceTriangle_.size();

  for (std::size_t i = 0; i < texelCount_; ++i) {
    const std::uint32_t begin = pieceStart_[i];
    const std::uint32_t end = std::min<std::uint32_t>(pieceStart_[i + 1], std::uint32_t(pieceCount));
    Eigen::Vector3f& position = out.position[i];
    Eigen::Vector3f& areaVector = out.areaVector[i];
    Eigen::Vector3f& edgeU = out.edgeU[i];
    Eigen::Vector3f& edgeV = out.edgeV[i];
    if (end == begin + 1 && triangleOf[begin] < triangleCount) {
      // One piece: its centroid is the position (no shift: centroid . A is the flux itself).
      const TriangleFrame& f = frames[triangleOf[begin]];
      const float fraction = fractionOf[begin], b1 = bary1Of[begin], b2 = bary2Of[begin];
      const float area = fraction * f.area;
      for (int c = 0; c < 3; ++c) {
        position[c] = area > 0.0f ? f.p0[c] + b1 * f.e1[c] + b2 * f.e2[c] : 0.0f;
        areaVector[c] = fraction * f.areaVector[c];
        edgeU[c] = shareOf[begin] * f.edgeU[c];
        edgeV[c] = shareOf[begin] * f.edgeV[c];
      }
      out.area[i] = area;
      continue;
    }
    float a[3] = {0, 0, 0}, weighted[3] = {0, 0, 0}, eu[3] = {0, 0, 0}, ev[3] = {0, 0, 0};
    float area = 0.0f, flux = 0.0f;  // flux: sum of centroid . piece area vector
    for (std::uint32_t k = begin; k < end; ++k) {
      if (triangleOf[k] >= triangleCount) continue;  // a bake of another mesh: skip, never crash
      const TriangleFrame& f = frames[triangleOf[k]];
      const float fraction = fractionOf[k], b1 = bary1Of[k], b2 = bary2Of[k], share = shareOf[k];
      const float pieceArea = fraction * f.area;
      for (int c = 0; c < 3; ++c) {
        const float centroid = f.p0[c] + b1 * f.e1[c] + b2 * f.e2[c];
        const float pieceAreaVector = fraction * f.areaVector[c];
        a[c] += pieceAreaVector;
        weighted[c] += pieceArea * centroid;
        flux += centroid * pieceAreaVector;
        eu[c] += share * f.edgeU[c];
        ev[c] += share * f.edgeV[c];
      }
      area += pieceArea;
    }
    const Eigen::Vector3f sumA(a[0], a[1], a[2]);
    Eigen::Vector3f p = area > 0.0f ? Eigen::Vector3f(weighted[0] / area, weighted[1] / area, weighted[2] / area)
                                    : Eigen::Vector3f::Zero();
    // The shift along A that makes p . A the exact flux, left out where the pieces nearly cancel
    // (as in evaluateSurface, which explains why).
    const float squared = sumA.squaredNorm();
    if (squared > 1e-2f * area * area && squared > 0.0f) p += sumA * ((flux - p.dot(sumA)) / squared);
    position = p;
    areaVector = sumA;
    out.area[i] = area;
    edgeU = Eigen::Vector3f(eu[0], eu[1], eu[2]);
    edgeV = Eigen::Vector3f(ev[0], ev[1], ev[2]);
  }
}

}  // namespace hydrotex
