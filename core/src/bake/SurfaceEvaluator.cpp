// SPDX-License-Identifier: Zlib
// Per-step PT/VAT re-evaluation from a kept bake (docs/design.md "Exact texels"). The same sums as
// evaluateSurface (SurfaceBake.cpp): a piece's centroid and area vector are linear in its
// triangle's vertices (barycentric centroid, area fraction of the triangle's area vector), and the
// texel edges are the UV-to-surface Jacobian of the pieces' triangles averaged by UV area. What
// depends only on the bake and the layout (fractions, barycentrics, UV shares, the inverse UV edge
// matrix) is prepared once; a step evaluates each triangle once and each piece once, in float
// (the textures are float anyway; a texel sums a handful of pieces, so float sums lose nothing).
#include "hydrotex/bake/SurfaceEvaluator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace hydrotex {
namespace {

// The x, y, z lanes of a four-float register into a packed float triple.
void store(const Eigen::Array4f& lanes, Eigen::Vector3f& out) { out = lanes.head<3>().matrix(); }

}  // namespace

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

  // Pieces per covered texel, in bake order (a malformed bake: every texel has none).
  const std::size_t pieceCount = bake.pieces.size();
  const bool wellFormed = bake.pieceStart.size() == texelCount_ + 1;
  std::vector<std::uint32_t> count(texelCount_, 0);
  std::uint32_t mostPieces = 0;
  for (std::size_t i = 0; wellFormed && i < texelCount_; ++i) {
    const std::size_t begin = bake.pieceStart[i], end = std::min<std::size_t>(bake.pieceStart[i + 1], pieceCount);
    count[i] = end > begin ? std::uint32_t(end - begin) : 0;
    mostPieces = std::max(mostPieces, count[i]);
  }
  // Groups by piece count (counting sort, texels in bake order within a group).
  std::vector<std::size_t> texelsWith(std::size_t(mostPieces) + 1, 0);
  for (std::uint32_t n : count) ++texelsWith[n];
  std::size_t firstTexel = 0, firstPiece = 0;
  std::vector<std::size_t> nextTexel(texelsWith.size(), 0);
  for (std::uint32_t n = 0; n <= mostPieces; ++n) {
    if (texelsWith[n] == 0) continue;
    groups_.push_back(Group{n, firstTexel, texelsWith[n], firstPiece});
    nextTexel[n] = firstTexel;
    firstTexel += texelsWith[n];
    firstPiece += texelsWith[n] * n;
  }
  texelOrder_.resize(texelCount_);
  pieces_.resize(firstPiece);
  correctionSlot_.assign(texelCount_, 0);
  for (std::size_t i = 0; i < texelCount_; ++i) {
    const std::uint32_t n = count[i];
    const std::size_t slot = nextTexel[n]++;
    texelOrder_[slot] = std::uint32_t(i);
    if (n > 1) {  // SurfaceTextures::momentTexel: the texels of several pieces, ascending
      correctionSlot_[slot] = std::uint32_t(momentTexel_.size());
      momentTexel_.push_back(std::uint32_t(i));
    }
    if (n == 0) continue;
    // The slot's pieces: the group's first piece plus n per texel before it in the group.
    const Group& group = *std::find_if(groups_.begin(), groups_.end(), [n](const Group& g) { return g.piecesPerTexel == n; });
    Piece* out = &pieces_[group.firstPiece + (slot - group.firstTexel) * n];
    const TexelPiece* in = &bake.pieces[bake.pieceStart[i]];
    double texelUv = 0.0;
    for (std::uint32_t k = 0; k < n; ++k)
      if (in[k].triangle < triangleCount) texelUv += in[k].areaFraction * uvArea[in[k].triangle];
    for (std::uint32_t k = 0; k < n; ++k) {
      out[k] = Piece{in[k].triangle, in[k].areaFraction, in[k].centroidBary1, in[k].centroidBary2, 0.0f};
      if (texelUv > 0.0 && in[k].triangle < triangleCount)
        out[k].uvShare = static_cast<float>(in[k].areaFraction * uvArea[in[k].triangle] / texelUv);
    }
  }
}

template <std::uint32_t Pieces>
void SurfaceEvaluator::evaluateGroup(const Group& group, std::uint32_t piecesPerTexel, std::uint32_t nullFrame,
                                     SurfaceTextures& out) const {
  // Pieces > 0: the count known at compile time (the loops over pieces unroll); 0: any count.
  const std::uint32_t n = Pieces > 0 ? Pieces : piecesPerTexel;
  const Piece* piece = pieces_.data() + group.firstPiece;
  const std::uint32_t* texel = texelOrder_.data() + group.firstTexel;
  const TriangleFrame* const frames = frames_.data();
  for (std::size_t t = 0; t < group.texelCount; ++t, piece += n) {
    const std::uint32_t i = texel[t];
    if constexpr (Pieces == 1) {
      // One piece: its centroid is the position (no shift: centroid . A is the flux itself).
      // A piece naming a triangle the mesh lacks reads the zero frame: it carries nothing.
      const TriangleFrame& f = frames[std::min(piece->triangle, nullFrame)];
      const Eigen::Array4f scaled = piece->fraction * f.areaVector;  // area vector; w: area
      const float keep = scaled[3] > 0.0f ? 1.0f : 0.0f;             // a texel of no area sits at the origin
      store(keep * (f.p0 + piece->bary1 * f.e1 + piece->bary2 * f.e2), out.position[i]);
      store(scaled, out.areaVector[i]);
      out.area[i] = scaled[3];
      store(piece->uvShare * f.edgeU, out.edgeU[i]);
      store(piece->uvShare * f.edgeV, out.edgeV[i]);
    } else {
      // Sums over the pieces, w lanes: the area (a), zero (the others).
      Eigen::Array4f a = Eigen::Array4f::Zero(), weighted = Eigen::Array4f::Zero();
      Eigen::Array4f fluxTerms = Eigen::Array4f::Zero(), eu = Eigen::Array4f::Zero(), ev = Eigen::Array4f::Zero();
      Eigen::Array4f centroids[Pieces > 0 ? Pieces : 1], pieceAreaVectors[Pieces > 0 ? Pieces : 1];
      for (std::uint32_t k = 0; k < n; ++k) {
        const Piece& p = piece[k];
        const TriangleFrame& f = frames[std::min(p.triangle, nullFrame)];  // zero frame: adds nothing
        const Eigen::Array4f pieceAreaVector = p.fraction * f.areaVector;
        const Eigen::Array4f centroid = f.p0 + p.bary1 * f.e1 + p.bary2 * f.e2;
        if constexpr (Pieces > 0) {
          centroids[k] = centroid;
          pieceAreaVectors[k] = pieceAreaVector;
        }
        a += pieceAreaVector;
        weighted += pieceAreaVector[3] * centroid;
        fluxTerms += centroid * pieceAreaVector;  // summed: centroid . piece area vector
        eu += p.uvShare * f.edgeU;
        ev += p.uvShare * f.edgeV;
      }
      const float area = a[3], flux = fluxTerms.sum();
      const Eigen::Vector3f sumA(a[0], a[1], a[2]);
      const float squared = sumA.squaredNorm();
      // Both reciprocals at once (independent divisions overlap; dependent ones would not).
      const float inverseArea = area > 0.0f ? 1.0f / area : 0.0f;
      const float inverseSquared = squared > 0.0f ? 1.0f / squared : 0.0f;
      Eigen::Vector3f position(weighted[0] * inverseArea, weighted[1] * inverseArea, weighted[2] * inverseArea);
      // The shift along A that makes p . A the exact flux, left out where the pieces nearly cancel
      // (as in evaluateSurface, which explains why).
      if (squared > 1e-2f * area * area && squared > 0.0f)
        position += sumA * ((flux - position.dot(sumA)) * inverseSquared);
      out.position[i] = position;
      out.areaVector[i] = sumA;
      out.area[i] = area;
      store(eu, out.edgeU[i]);
      store(ev, out.edgeV[i]);
      if (n < 2) continue;  // a texel of no pieces (a malformed bake) has no entry
      // SurfaceTextures::momentCorrection: Sum_k (c_k - p) A_k^T (A is the sum of the A_k), the
      // differences first (they are of the texel's size, where c_k A_k^T - p A^T would cancel).
      Eigen::Matrix3f correction = Eigen::Matrix3f::Zero();
      float reach = 0.0f;  // SurfaceTextures::momentReach
      for (std::uint32_t k = 0; k < n; ++k) {
        Eigen::Array4f centroid, pieceAreaVector;
        if constexpr (Pieces > 0) {
          centroid = centroids[k];
          pieceAreaVector = pieceAreaVectors[k];
        } else {
          const TriangleFrame& f = frames[std::min(piece[k].triangle, nullFrame)];
          pieceAreaVector = piece[k].fraction * f.areaVector;
          centroid = f.p0 + piece[k].bary1 * f.e1 + piece[k].bary2 * f.e2;
        }
        const Eigen::Vector3f pieceA = pieceAreaVector.head<3>().matrix();
        const Eigen::Vector3f offset = centroid.head<3>().matrix() - position;
        correction += offset * pieceA.transpose();
        reach = std::max(reach, offset.norm());
      }
      out.momentReach[correctionSlot_[group.firstTexel + t]] = reach;
      out.momentCorrection[correctionSlot_[group.firstTexel + t]] = correction;
    }
  }
}

void SurfaceEvaluator::evaluate(const Mesh& mesh, SurfaceTextures& out) {
  // Per triangle, once per step: vertex 0, edges, area vector and the texel edges on the surface;
  // one zero frame after them for pieces naming a triangle the mesh lacks.
  const std::size_t triangleCount = mesh.triangles.size();
  frames_.resize(triangleCount + 1);  // allocates only when the mesh grew
  frames_[triangleCount] = TriangleFrame{};
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
    f.areaVector[3] = static_cast<float>(areaVector.norm());
  }

  out.width = width_;
  out.height = height_;
  out.position.resize(texelCount_);
  out.areaVector.resize(texelCount_);
  out.area.resize(texelCount_);
  out.edgeU.resize(texelCount_);
  out.edgeV.resize(texelCount_);
  if (out.momentTexel != momentTexel_) out.momentTexel = momentTexel_;
  out.momentCorrection.resize(momentTexel_.size());
  out.momentReach.resize(momentTexel_.size());
  const auto nullFrame = static_cast<std::uint32_t>(triangleCount);
  for (const Group& group : groups_) {
    switch (group.piecesPerTexel) {
      case 1: evaluateGroup<1>(group, 1, nullFrame, out); break;
      case 2: evaluateGroup<2>(group, 2, nullFrame, out); break;
      case 3: evaluateGroup<3>(group, 3, nullFrame, out); break;
      default: evaluateGroup<0>(group, group.piecesPerTexel, nullFrame, out); break;
    }
  }
}

}  // namespace hydrotex
