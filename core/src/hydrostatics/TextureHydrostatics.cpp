// SPDX-License-Identifier: Zlib
/// @file TextureHydrostatics.cpp
/// Hydrostatics as texel sums (paper section 2.3.1, generalised to pressure integration as in
/// docs/design.md): each texel is the planar patch p + s eU + t eV, s, t in [-1/2, 1/2], and the part of
/// it under the surface is weighted exactly for that patch (HydrostaticSums.hpp,
/// waterlineFractions). Tiles wholly under a flat surface add precomputed moments in O(1). A texel
/// of pieces on several triangles adds its moment correction (SurfaceTextures::momentCorrection;
/// MomentCorrectionSums) weighted by the submerged share of its pieces' span
/// (correctionWeight): with it the volume and
/// force of a wholly submerged body are the pieces' exact sums at every pose, with no per-pose
/// factor; the first moments (centre of buoyancy, torque) stay second order in the texel size.

#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "hydrostatics/HydrostaticSums.hpp"
#include "bake/TexelPosing.hpp"

namespace hydrotex {

namespace {

/// The radius of a sphere about `parent`'s box centre holding the bounding spheres of its tiles
/// [begin, end) (a group's or a block's), never more than its box's half diagonal; widened by
/// 1e-6 so that rounding cannot put a child's sphere outside.
template <class Tiles, class Parent>
double enclosingRadius(const Tiles& tiles, const Parent& parent) {
  double radius = 0.0;
  for (std::uint32_t g = parent.begin; g < parent.end; ++g)
    radius = std::max(radius, (tiles[g].boundsCenter - parent.boundsCenter).norm() + tiles[g].boundsRadius);
  return std::min(radius * (1.0 + 1e-6), parent.boundsHalfExtent.norm());
}

using Texel = TextureHydrostatics::Texel;
using Moments = TextureHydrostatics::Moments;
using MomentCorrection = TextureHydrostatics::MomentCorrection;

using detail::PosedTexel;
using detail::pose;
using detail::verticalEdges;
using detail::verticalRange;

/// The next correction of the range [cursor, end) when it belongs to packed texel `texel` (then
/// the cursor moves past it), else null: the corrections are sorted by texel, so a loop over a
/// tile's texels takes each texel's own with one comparison.
inline const MomentCorrection* correctionOf(const std::vector<MomentCorrection>& corrections, std::uint32_t& cursor,
                                            std::uint32_t end, std::uint32_t texel) {
  return cursor < end && corrections[cursor].texel == texel ? &corrections[cursor++] : nullptr;
}

/// A texel's moment correction in the world frame: R dM R^T.
inline Eigen::Matrix3d worldMoment(const MomentCorrection& c, const Eigen::Matrix3d& r) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) m(i, k) = c.moment[i][k];
  return r * m * r.transpose();
}

/// One texel under a flat surface at y' = 0 (depth of its centre d = -y'), with its moment
/// correction (null: none).
[[gnu::always_inline]] inline void addFlatTexel(detail::WettedSums& sums, const Texel& t,
                                                const MomentCorrection* correction, const Eigen::Matrix3d& r,
                                                const Eigen::Vector3d& offset) {
  double a, b;
  verticalEdges(t, r, a, b);
  const double depth = -(r(1, 0) * t.position[0] + r(1, 1) * t.position[1] + r(1, 2) * t.position[2] + offset.y());
  const double halfSpan = 0.5 * (std::abs(a) + std::abs(b));
  if (depth <= -(correction ? std::max(halfSpan, double(correction->reach)) : halfSpan)) return;  // dry
  const PosedTexel w = pose(t, r, offset);
  const detail::WaterlineFractions f = detail::waterlineFractions(depth, a, b);  // 0 when the patch is dry
  sums.addElement(w.x, w.y, w.z, w.ax, w.ay, w.az, t.area, f.area, f.depth, f.depthSq, 0.0);
  if (correction) {
    // Only dm(:, 1) = R dM r1 is read under a plane (WettedSums::addFlatMomentCorrection).
    const Eigen::Vector3d r1 = r.row(1).transpose();
    Eigen::Vector3d bodyColumn;
    for (int i = 0; i < 3; ++i)
      bodyColumn[i] = correction->moment[i][0] * r1.x() + correction->moment[i][1] * r1.y() + correction->moment[i][2] * r1.z();
    sums.addFlatMomentCorrection(w.x, w.y, w.z, r * bodyColumn, detail::correctionWeight(depth, halfSpan, correction->reach),
                                 depth);
  }
}

/// One texel under a wavy surface whose local height above the texel is `localHeight` (m, frame
/// o), with the texel taken as a patch under a locally level surface; pressure from the depth.
/// Its moment correction (null: none), with the surface's slope (slopeX, slopeZ) above it, goes
/// into `corrections` (body frame; addWaveCorrections adds them).
inline void addWaveTexel(detail::WettedSums& sums, detail::MomentCorrectionSums& corrections, const Texel& texel,
                         const MomentCorrection* correction, const Eigen::Matrix3d& r, const PosedTexel& w, double a,
                         double b, double depth, double localHeight, double slopeX, double slopeZ, double rhoG) {
  const detail::WaterlineFractions f = detail::waterlineFractions(depth, a, b);
  sums.addElement(w.x, w.y, w.z, w.ax, w.ay, w.az, texel.area, f.area, f.depth, f.depthSq, localHeight);
  const double p = rhoG * f.depth;
  const double fx = -p * w.ax, fy = -p * w.ay, fz = -p * w.az;
  sums.pressureForce[0] += fx;
  sums.pressureForce[1] += fy;
  sums.pressureForce[2] += fz;
  sums.pressureTorque[0] += w.y * fz - w.z * fy;
  sums.pressureTorque[1] += w.z * fx - w.x * fz;
  sums.pressureTorque[2] += w.x * fy - w.y * fx;
  if (correction)
    corrections.add(w.x, w.y, w.z, correction->moment,
                    detail::correctionWeight(depth, 0.5 * (std::abs(a) + std::abs(b)), correction->reach), depth,
                    localHeight, slopeX, slopeZ, r);
}

/// Adds addWaveTexel's moment corrections to `sums`, with their pressure: p = rho g D, so their
/// pressure sums are their depth sums times -rho g.
inline void addWaveCorrections(detail::WettedSums& sums, const detail::MomentCorrectionSums& corrections,
                               const Eigen::Matrix3d& r, double rhoG) {
  detail::WettedSums part;
  corrections.addTo(part, r);
  part.setHydrostaticPressure(rhoG);
  sums.add(part);
}

}  // namespace

void TextureHydrostatics::Moments::add(const Moments& o) {
  sumArea += o.sumArea;
  for (int k = 0; k < 3; ++k) {
    sumA[k] += o.sumA[k];
    for (int i = 0; i < 3; ++i) sumPA[i][k] += o.sumPA[i][k];
    for (int pair = 0; pair < 6; ++pair) sumPPA[pair][k] += o.sumPPA[pair][k];
  }
}

Expected<TextureHydrostatics> TextureHydrostatics::build(const SurfaceBake& bake, const SurfaceTextures& textures,
                                                         const TextureHydrostaticsSettings& settings) {
  const std::size_t count = bake.coveredCount();
  if (textures.size() != count || textures.areaVector.size() != count || textures.area.size() != count ||
      textures.edgeU.size() != count || textures.edgeV.size() != count)
    return Error{"texture hydrostatics: surface textures hold " + std::to_string(textures.size()) +
                 " texels, the bake covers " + std::to_string(count)};
  if (bake.width <= 0 || bake.height <= 0 || textures.width != bake.width || textures.height != bake.height)
    return Error{"texture hydrostatics: bake and textures differ in resolution"};
  if (settings.tileSize < 0) return Error{"texture hydrostatics: tile size " + std::to_string(settings.tileSize) + " is negative"};
  if (settings.groupSize < 0) return Error{"texture hydrostatics: group size " + std::to_string(settings.groupSize) + " is negative"};
  if (!(settings.surfaceSampleSpacing >= 0.0) || !std::isfinite(settings.surfaceSampleSpacing))
    return Error{"texture hydrostatics: surface sample spacing is negative or not finite"};
  if (!(settings.surfaceModelTolerance >= 0.0) || !std::isfinite(settings.surfaceModelTolerance))
    return Error{"texture hydrostatics: surface model tolerance is negative or not finite"};

  TextureHydrostatics out;
  // Tiles of 4 texels and groups of about sqrt(width) texels: the group loop grows as
  // width^2 / group^2 and the texel work along the waterline as the tile size; the sweep in
  // bench_hydrostatics puts the best at tile 4, group 16 at 256^2 and group 32..64 at 1024^2.
  out.tileSize_ = settings.tileSize > 0 ? settings.tileSize : 4;
  const int tileSize = out.tileSize_;
  out.groupSize_ = settings.groupSize > 0
                       ? settings.groupSize
                       : std::max(1, int(std::lround(std::sqrt(double(bake.width)) / tileSize)));
  const int groupSize = out.groupSize_;
  out.surfaceSampleSpacing_ = settings.surfaceSampleSpacing;
  out.surfaceModelTolerance_ = settings.surfaceModelTolerance > 0.0 ? settings.surfaceModelTolerance : kDefaultSurfaceModelTolerance;
  const int groupTexels = tileSize * groupSize;
  const int groupsX = (bake.width + groupTexels - 1) / groupTexels;
  const int groupsY = (bake.height + groupTexels - 1) / groupTexels;
  // Tiles within a group in Morton (Z) order, so that every aligned 2 x 2 tiles form a contiguous
  // block: the middle level that the waves hierarchy models when a whole group is too large.
  int mortonSide = 1;
  while (mortonSide < groupSize) mortonSide *= 2;
  const std::size_t tilesPerGroup = std::size_t(mortonSide) * std::size_t(mortonSide);
  auto morton = [](int row, int column) {
    std::size_t code = 0;
    for (int bit = 0; bit < 16; ++bit)
      code |= (std::size_t((row >> bit) & 1) << (2 * bit + 1)) | (std::size_t((column >> bit) & 1) << (2 * bit));
    return code;
  };

  // Counting sort of the texels by (group, tile within the group), so that both are contiguous
  // (the bake's own tile size may differ).
  std::vector<std::uint32_t> tileOf(count);
  std::vector<std::uint32_t> tileCount(std::size_t(groupsX) * std::size_t(groupsY) * tilesPerGroup + 1, 0);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t index = bake.texelIndex[i];
    const int row = int(index / std::uint32_t(bake.width)), column = int(index % std::uint32_t(bake.width));
    if (row >= bake.height) return Error{"texture hydrostatics: bake texel " + std::to_string(i) + " lies outside the image"};
    const int tileRow = row / tileSize, tileColumn = column / tileSize;
    const std::size_t group = std::size_t((tileRow / groupSize) * groupsX + tileColumn / groupSize);
    tileOf[i] = std::uint32_t(group * tilesPerGroup + morton(tileRow % groupSize, tileColumn % groupSize));
    ++tileCount[tileOf[i] + 1];
  }
  for (std::size_t t = 1; t < tileCount.size(); ++t) tileCount[t] += tileCount[t - 1];
  std::vector<std::uint32_t> cursor(tileCount.begin(), tileCount.end() - 1);
  out.texels_.resize(count);
  out.source_.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3f& p = textures.position[i];
    const Eigen::Vector3f& a = textures.areaVector[i];
    const Eigen::Vector3f& u = textures.edgeU[i];
    const Eigen::Vector3f& v = textures.edgeV[i];
    if (!p.allFinite() || !a.allFinite() || !u.allFinite() || !v.allFinite() || !std::isfinite(textures.area[i]))
      return Error{"texture hydrostatics: texel " + std::to_string(i) + " has a non-finite value"};
    out.source_[cursor[tileOf[i]]] = std::uint32_t(i);
    out.texels_[cursor[tileOf[i]]++] = Texel{{p.x(), p.y(), p.z()}, {a.x(), a.y(), a.z()}, textures.area[i],
                                             {u.x(), u.y(), u.z()}, {v.x(), v.y(), v.z()}};
  }
  out.width_ = bake.width;
  out.height_ = bake.height;

  // The moment corrections, by packed texel (a tile's are then one contiguous range).
  const std::size_t corrected = textures.momentTexel.size();
  if (textures.momentCorrection.size() != corrected || textures.momentReach.size() != corrected)
    return Error{"texture hydrostatics: " + std::to_string(corrected) + " corrected texels, " +
                 std::to_string(textures.momentCorrection.size()) + " moment corrections"};
  std::vector<std::uint32_t> packedOf(count);
  for (std::size_t i = 0; i < count; ++i) packedOf[out.source_[i]] = std::uint32_t(i);
  out.corrections_.resize(corrected);
  out.correctionSource_.resize(corrected);
  for (std::size_t c = 0; c < corrected; ++c) {
    if (textures.momentTexel[c] >= count)
      return Error{"texture hydrostatics: moment correction " + std::to_string(c) + " names texel " +
                   std::to_string(textures.momentTexel[c]) + " of " + std::to_string(count)};
    if (!textures.momentCorrection[c].allFinite() || !(textures.momentReach[c] >= 0.0f) ||
        !std::isfinite(textures.momentReach[c]))
      return Error{"texture hydrostatics: moment correction " + std::to_string(c) + " has a non-finite value"};
    out.correctionSource_[c] = std::uint32_t(c);
    out.corrections_[c].texel = packedOf[textures.momentTexel[c]];
  }
  std::vector<std::uint32_t> order(corrected);
  for (std::size_t c = 0; c < corrected; ++c) order[c] = std::uint32_t(c);
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t x, std::uint32_t y) { return out.corrections_[x].texel < out.corrections_[y].texel; });
  {
    std::vector<MomentCorrection> sorted(corrected);
    std::vector<std::uint32_t> sortedSource(corrected);
    for (std::size_t c = 0; c < corrected; ++c) {
      sorted[c] = out.corrections_[order[c]];
      sortedSource[c] = out.correctionSource_[order[c]];
      if (c > 0 && sorted[c].texel == sorted[c - 1].texel)
        return Error{"texture hydrostatics: texel " + std::to_string(textures.momentTexel[sortedSource[c]]) +
                     " has two moment corrections"};
    }
    out.corrections_ = std::move(sorted);
    out.correctionSource_ = std::move(sortedSource);
  }
  out.loadCorrections(textures);

  // Tiles and groups (texel and tile ranges); their moments and bounds come from refresh().
  std::size_t lastGroup = 0, lastBlock = 0;
  for (std::size_t t = 0; t + 1 < tileCount.size(); ++t) {
    if (tileCount[t] == tileCount[t + 1]) continue;
    Tile tile;
    tile.begin = tileCount[t];
    tile.end = tileCount[t + 1];
    auto byTexel = [](const MomentCorrection& c, std::uint32_t texel) { return c.texel < texel; };
    tile.correctionBegin = std::uint32_t(
        std::lower_bound(out.corrections_.begin(), out.corrections_.end(), tile.begin, byTexel) - out.corrections_.begin());
    tile.correctionEnd = std::uint32_t(
        std::lower_bound(out.corrections_.begin(), out.corrections_.end(), tile.end, byTexel) - out.corrections_.begin());
    // A new group starts at the first tile of another group index, a new block at the first
    // tile of another block (4 Morton codes) or group.
    const std::size_t group = t / tilesPerGroup, block = t / 4;
    if (out.groups_.empty() || group != lastGroup) {
      Tile first;
      first.begin = first.end = std::uint32_t(out.tiles_.size());
      out.groups_.push_back(first);
      out.groupBlocks_.push_back(std::uint32_t(out.blocks_.size()));
      lastGroup = group;
    }
    if (out.blocks_.empty() || block != lastBlock || out.groups_.back().begin == out.tiles_.size()) {
      Tile first;
      first.begin = first.end = std::uint32_t(out.tiles_.size());
      out.blocks_.push_back(first);
      lastBlock = block;
    }
    out.groups_.back().end = std::uint32_t(out.tiles_.size() + 1);
    out.blocks_.back().end = std::uint32_t(out.tiles_.size() + 1);
    out.tiles_.push_back(tile);
  }
  out.groupBlocks_.push_back(std::uint32_t(out.blocks_.size()));
  if (out.tiles_.empty()) return Error{"texture hydrostatics: the bake covers no texel"};
  out.refresh();
  return out;
}

namespace {

// Texels per chunk of a tile's moment sums: the texels are copied to fixed-size double arrays
// and every sum is one vectorised reduction over the chunk (Eigen's redux). Double throughout:
// the hierarchy must give the brute-force sums to double rounding (test_texture_hydrostatics).
constexpr std::uint32_t kChunk = 16;
using ChunkArray = Eigen::Array<double, int(kChunk), 1>;

// Adds the moments of the first `count` (at most kChunk) of `texels` to `m`.
void addChunkMoments(Moments& m, const Texel* texels, std::uint32_t count) {
  ChunkArray p[3], a[3];
  ChunkArray area;
  for (std::uint32_t i = 0; i < count; ++i) {  // to structure of arrays
    const Texel& t = texels[i];
    for (int c = 0; c < 3; ++c) {
      p[c][i] = t.position[c];
      a[c][i] = t.areaVector[c];
    }
    area[i] = t.area;
  }
  for (std::uint32_t i = count; i < kChunk; ++i) {  // padding adds nothing (set one by one: no memset)
    for (int c = 0; c < 3; ++c) p[c][i] = a[c][i] = 0.0;
    area[i] = 0.0;
  }
  m.sumArea += area.sum();
  static constexpr int kPairs[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};  // Moments::sumPPA order
  for (int c = 0; c < 3; ++c) {
    m.sumA[c] += a[c].sum();
    for (int row = 0; row < 3; ++row) m.sumPA[row][c] += (p[row] * a[c]).sum();
  }
  for (int pair = 0; pair < 6; ++pair) {
    const ChunkArray product = p[kPairs[pair][0]] * p[kPairs[pair][1]];
    for (int c = 0; c < 3; ++c) m.sumPPA[pair][c] += (product * a[c]).sum();
  }
}

// Adds a texel's moment correction dM to `m`: sumPA += dM, sumPPA_k(i, j) += p_i dM_jk + dM_ik p_j
// (MomentCorrectionSums' terms, in the body frame).
void addCorrectionMoments(Moments& m, const Texel& t, const MomentCorrection& c) {
  static constexpr int kPairs[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};  // Moments::sumPPA order
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) m.sumPA[i][k] += c.moment[i][k];
  for (int pair = 0; pair < 6; ++pair) {
    const int i = kPairs[pair][0], j = kPairs[pair][1];
    for (int k = 0; k < 3; ++k)
      m.sumPPA[pair][k] += double(t.position[i]) * c.moment[j][k] + double(c.moment[i][k]) * t.position[j];
  }
}

}  // namespace

void TextureHydrostatics::loadCorrections(const SurfaceTextures& textures) {
  for (std::size_t c = 0; c < corrections_.size(); ++c) {
    const Eigen::Matrix3f& m = textures.momentCorrection[correctionSource_[c]];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) corrections_[c].moment[i][k] = m(i, k);
    corrections_[c].reach = textures.momentReach[correctionSource_[c]];
  }
}

void TextureHydrostatics::refresh() {
  Eigen::Vector3d bodyLow = Eigen::Vector3d::Constant(INFINITY), bodyHigh = Eigen::Vector3d::Constant(-INFINITY);
  double tripleVolume = 0.0;
  total_ = Moments{};
  for (Tile& group : groups_) {
    Eigen::Vector3d groupLow = Eigen::Vector3d::Constant(INFINITY), groupHigh = Eigen::Vector3d::Constant(-INFINITY);
    group.moments = Moments{};
    for (std::uint32_t g = group.begin; g < group.end; ++g) {
      Tile& tile = tiles_[g];
      tile.moments = Moments{};
      for (std::uint32_t c = tile.begin; c < tile.end; c += kChunk)
        addChunkMoments(tile.moments, texels_.data() + c, std::min(kChunk, tile.end - c));
      for (std::uint32_t c = tile.correctionBegin; c < tile.correctionEnd; ++c)
        addCorrectionMoments(tile.moments, texels_[corrections_[c].texel], corrections_[c]);
      // Bounds in float (the texels are float), widened below by a few float ulps.
      float low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
      for (std::uint32_t i = tile.begin; i < tile.end; ++i) {
        const Texel& texel = texels_[i];
        for (int c = 0; c < 3; ++c) {
          // The patch p + s eU + t eV lies within p +- (|eU| + |eV|) / 2 per axis.
          const float reach = 0.5f * (std::fabs(texel.edgeU[c]) + std::fabs(texel.edgeV[c]));
          low[c] = std::min(low[c], texel.position[c] - reach);
          high[c] = std::max(high[c], texel.position[c] + reach);
        }
      }
      // A corrected texel's pieces lie within its reach of p (they may lie beyond its patch).
      for (std::uint32_t c = tile.correctionBegin; c < tile.correctionEnd; ++c) {
        const Texel& texel = texels_[corrections_[c].texel];
        for (int axis = 0; axis < 3; ++axis) {
          low[axis] = std::min(low[axis], texel.position[axis] - corrections_[c].reach);
          high[axis] = std::max(high[axis], texel.position[axis] + corrections_[c].reach);
        }
      }
      tripleVolume += tile.moments.sumPA[0][0] + tile.moments.sumPA[1][1] + tile.moments.sumPA[2][2];
      Eigen::Vector3d lowD(low[0], low[1], low[2]), highD(high[0], high[1], high[2]);
      const Eigen::Vector3d slack = 1e-6 * (highD - lowD).cwiseAbs() + 1e-7 * (lowD.cwiseAbs() + highD.cwiseAbs());
      lowD -= slack;
      highD += slack;
      tile.boundsCenter = 0.5 * (lowD + highD);
      tile.boundsHalfExtent = 0.5 * (highD - lowD);
      // The patch p + s eU + t eV lies within |p - c| + (|eU| + |eV|) / 2 of the centre c.
      double radius = 0.0;
      for (std::uint32_t i = tile.begin; i < tile.end; ++i) {
        const Texel& texel = texels_[i];
        const Eigen::Vector3d p(texel.position[0], texel.position[1], texel.position[2]);
        const Eigen::Vector3d u(texel.edgeU[0], texel.edgeU[1], texel.edgeU[2]);
        const Eigen::Vector3d v(texel.edgeV[0], texel.edgeV[1], texel.edgeV[2]);
        radius = std::max(radius, (p - tile.boundsCenter).norm() + 0.5 * (u.norm() + v.norm()));
      }
      for (std::uint32_t c = tile.correctionBegin; c < tile.correctionEnd; ++c) {
        const Texel& texel = texels_[corrections_[c].texel];
        const Eigen::Vector3d p(texel.position[0], texel.position[1], texel.position[2]);
        radius = std::max(radius, (p - tile.boundsCenter).norm() + corrections_[c].reach);
      }
      tile.boundsRadius = std::min(radius * (1.0 + 1e-6), tile.boundsHalfExtent.norm());
      group.moments.add(tile.moments);
      groupLow = groupLow.cwiseMin(lowD);
      groupHigh = groupHigh.cwiseMax(highD);
    }
    group.boundsCenter = 0.5 * (groupLow + groupHigh);
    group.boundsHalfExtent = 0.5 * (groupHigh - groupLow);
    group.boundsRadius = enclosingRadius(tiles_, group);
    total_.add(group.moments);
    bodyLow = bodyLow.cwiseMin(groupLow);
    bodyHigh = bodyHigh.cwiseMax(groupHigh);
  }
  // Blocks of 2 x 2 tiles: moments and bounds from their tiles.
  for (Tile& block : blocks_) {
    Eigen::Vector3d low = Eigen::Vector3d::Constant(INFINITY), high = Eigen::Vector3d::Constant(-INFINITY);
    block.moments = Moments{};
    for (std::uint32_t g = block.begin; g < block.end; ++g) {
      const Tile& tile = tiles_[g];
      block.moments.add(tile.moments);
      low = low.cwiseMin(tile.boundsCenter - tile.boundsHalfExtent);
      high = high.cwiseMax(tile.boundsCenter + tile.boundsHalfExtent);
    }
    block.boundsCenter = 0.5 * (low + high);
    block.boundsHalfExtent = 0.5 * (high - low);
    block.boundsRadius = enclosingRadius(tiles_, block);
  }
  boundsCenter_ = 0.5 * (bodyLow + bodyHigh);
  boundsHalfExtent_ = 0.5 * (bodyHigh - bodyLow);
  enclosedVolume_ = tripleVolume / 3.0;
}

Status TextureHydrostatics::update(const SurfaceTextures& textures) {
  const std::size_t count = texels_.size();
  if (textures.size() != count || textures.areaVector.size() != count || textures.area.size() != count ||
      textures.edgeU.size() != count || textures.edgeV.size() != count) {
    valid_ = false;
    return Error{"texture hydrostatics: moved textures hold " + std::to_string(textures.size()) +
                 " texels, the build had " + std::to_string(count)};
  }
  if (textures.width != width_ || textures.height != height_) {
    valid_ = false;
    return Error{"texture hydrostatics: moved textures differ in resolution from the build"};
  }
  if (textures.momentCorrection.size() != corrections_.size() || textures.momentReach.size() != corrections_.size()) {
    valid_ = false;
    return Error{"texture hydrostatics: moved textures hold " + std::to_string(textures.momentCorrection.size()) +
                 " moment corrections, the build had " + std::to_string(corrections_.size())};
  }
  loadCorrections(textures);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t from = source_[i];
    Texel& t = texels_[i];
    const Eigen::Vector3f& p = textures.position[from];
    const Eigen::Vector3f& a = textures.areaVector[from];
    const Eigen::Vector3f& u = textures.edgeU[from];
    const Eigen::Vector3f& v = textures.edgeV[from];
    t = Texel{{p.x(), p.y(), p.z()}, {a.x(), a.y(), a.z()}, textures.area[from],
              {u.x(), u.y(), u.z()}, {v.x(), v.y(), v.z()}};
  }
  refresh();
  // A non-finite texel value reaches the body's moments or bounds: one check instead of 13 per texel.
  bool finite = std::isfinite(total_.sumArea) && boundsCenter_.allFinite() && boundsHalfExtent_.allFinite();
  for (int k = 0; k < 3 && finite; ++k) {
    finite = std::isfinite(total_.sumA[k]);
    for (int i = 0; i < 3; ++i) finite = finite && std::isfinite(total_.sumPA[i][k]);
    for (int pair = 0; pair < 6; ++pair) finite = finite && std::isfinite(total_.sumPPA[pair][k]);
  }
  valid_ = finite;
  if (!finite) return Error{"texture hydrostatics: a moved texel has a non-finite value"};
  return Ok{};
}

Expected<HydrostaticsResult> TextureHydrostatics::query(const LiquidSurface& surface, const HydrostaticsQuery& q,
                                                        TexelTraversal traversal) const {
  if (Status valid = validateHydrostaticsQuery(surface, q); !valid) return valid.error();
  if (!valid_) return Error{"texture hydrostatics: the last update had a non-finite or mismatched texel"};
  const Eigen::Matrix3d& r = q.pose.rotation;
  const Eigen::Vector3d& t = q.pose.translation;
  detail::WettedSums sums;
  const auto allCorrections = std::uint32_t(corrections_.size());

  if (!surface.hasFreeSurface()) {
    // A medium: every texel is submerged; pressure from the medium at each texel centre.
    const Eigen::Vector3d origin = t;
    std::uint32_t cursor = 0;
    detail::MomentCorrectionSums moments;  // the corrections' depth sums, rotated once at the end
    for (std::uint32_t i = 0; i < texels_.size(); ++i) {
      const Texel& texel = texels_[i];
      const PosedTexel w = pose(texel, r, Eigen::Vector3d::Zero());
      sums.addElement(w.x, w.y, w.z, w.ax, w.ay, w.az, texel.area, 1.0, -w.y, w.y * w.y, 0.0);
      const Eigen::Vector3d x(w.x, w.y, w.z);
      const double p = surface.pressure(x + origin, q.time, q.gravity);
      const Eigen::Vector3d force = -p * Eigen::Vector3d(w.ax, w.ay, w.az);
      Eigen::Vector3d torque = x.cross(force);
      Eigen::Vector3d totalForce = force;
      if (const MomentCorrection* correction = correctionOf(corrections_, cursor, allCorrections, i)) {
        // The pressure's first-order term over the pieces (MomentCorrectionSums' law): a
        // liquid at rest has grad p = -rho(x) g e_y, so Sum g(c_k) A_k gains grad g . dm(:, k)
        // with g = -p (force) and -p x_i (torque).
        moments.add(w.x, w.y, w.z, correction->moment, 1.0, -w.y, 0.0, 0.0, 0.0, r);
        const Eigen::Matrix3d dm = worldMoment(*correction, r);
        const double rhoG = surface.densityAt(x + origin) * q.gravity;
        const Eigen::Vector3d gradientTerm = rhoG * dm.row(1).transpose();  // -grad p . dm(:, k)
        totalForce += gradientTerm;
        // -(p dm(i, j) + x_i grad p . dm(:, j)) for the torque's x_i A_j.
        const Eigen::Matrix3d torqueMoment = -p * dm + x * gradientTerm.transpose();
        torque += Eigen::Vector3d(torqueMoment(1, 2) - torqueMoment(2, 1), torqueMoment(2, 0) - torqueMoment(0, 2),
                                  torqueMoment(0, 1) - torqueMoment(1, 0));
      }
      for (int k = 0; k < 3; ++k) {
        sums.pressureForce[k] += totalForce[k];
        sums.pressureTorque[k] += torque[k];
      }
    }
    moments.addTo(sums, r);
    return detail::finishHydrostatics(sums, origin, surface.density(), q, detail::ForceModel::PressureSums, false);
  }

  if (const std::optional<double> flat = surface.flatHeight()) {
    const Eigen::Vector3d origin(t.x(), *flat, t.z());
    const Eigen::Vector3d offset = t - origin;  // (0, t_y - h, 0)
    if (traversal == TexelTraversal::BruteForce) {
      std::uint32_t cursor = 0;
      for (std::uint32_t i = 0; i < texels_.size(); ++i)
        addFlatTexel(sums, texels_[i], correctionOf(corrections_, cursor, allCorrections, i), r, offset);
    } else {
      double low, high;
      verticalRange(boundsCenter_, boundsHalfExtent_, r, offset.y(), low, high);
      if (low >= 0.0) return detail::finishHydrostatics(sums, origin, surface.density(), q, detail::ForceModel::Archimedes, true);
      Moments under;
      if (high <= 0.0) {
        under = total_;
      } else {
        for (const Tile& group : groups_) {
          verticalRange(group.boundsCenter, group.boundsHalfExtent, r, offset.y(), low, high);
          if (low >= 0.0) continue;
          if (high <= 0.0) {
            under.add(group.moments);
            continue;
          }
          for (std::uint32_t g = group.begin; g < group.end; ++g) {
            const Tile& tile = tiles_[g];
            verticalRange(tile.boundsCenter, tile.boundsHalfExtent, r, offset.y(), low, high);
            if (low >= 0.0) continue;
            if (high <= 0.0) {
              under.add(tile.moments);
              continue;
            }
            if (tile.correctionBegin == tile.correctionEnd) {  // one-piece texels only: no correction to look up
              for (std::uint32_t i = tile.begin; i < tile.end; ++i) addFlatTexel(sums, texels_[i], nullptr, r, offset);
              continue;
            }
            std::uint32_t cursor = tile.correctionBegin;
            for (std::uint32_t i = tile.begin; i < tile.end; ++i)
              addFlatTexel(sums, texels_[i], correctionOf(corrections_, cursor, tile.correctionEnd, i), r, offset);
          }
        }
      }
      sums.addSubmergedMoments(under, r, offset);
    }
    return detail::finishHydrostatics(sums, origin, surface.density(), q, detail::ForceModel::Archimedes, true);
  }

  // Surfaces with jets (waves): tiles against a local model of the surface (TextureHydrostaticsWaves.cpp).
  if (traversal == TexelTraversal::Hierarchy)
    if (std::optional<HydrostaticsResult> result = queryWaves(surface, q)) return *result;

  // Waves and grids, per texel: the local surface height above each texel centre, the texel taken
  // as a patch under a locally level surface (the surface's slope over one texel is neglected).
  const Eigen::Vector3d centerOfMass = q.pose.apply(q.centerOfMass);
  const Eigen::Vector3d origin(t.x(), surface.surfaceHeight(centerOfMass.x(), centerOfMass.z(), q.time), t.z());
  if (!std::isfinite(origin.y())) return Error{"texture hydrostatics: the liquid surface height is not finite"};
  const Eigen::Vector3d offset = t - origin;
  const double rhoG = surface.density() * q.gravity;
  // Tiles and texels wholly above the surface's highest point are dry without asking the
  // surface, which costs far more than the texel (Gerstner: a Newton search per call).
  const double highest = surface.heightRange(q.time).second - origin.y();
  detail::MomentCorrectionSums corrections;
  for (const Tile& tile : tiles_) {
    double low, high;
    verticalRange(tile.boundsCenter, tile.boundsHalfExtent, r, offset.y(), low, high);
    if (low >= highest) continue;
    std::uint32_t cursor = tile.correctionBegin;
    for (std::uint32_t i = tile.begin; i < tile.end; ++i) {
      const Texel& texel = texels_[i];
      const MomentCorrection* correction = correctionOf(corrections_, cursor, tile.correctionEnd, i);
      double a, b;
      verticalEdges(texel, r, a, b);
      // A corrected texel's pieces reach farther than its patch where they lie far apart.
      const double halfSpan = 0.5 * (std::abs(a) + std::abs(b));
      const double span = correction ? std::max(halfSpan, double(correction->reach)) : halfSpan;
      const PosedTexel w = pose(texel, r, offset);
      if (w.y - span >= highest) continue;
      // A corrected texel takes the surface's jet where it has one: its slope enters the correction.
      const std::optional<SurfaceJet> jet =
          correction ? surface.heightJet(w.x + origin.x(), w.z + origin.z(), q.time) : std::nullopt;
      const double localHeight =
          (jet ? jet->height : surface.surfaceHeight(w.x + origin.x(), w.z + origin.z(), q.time)) - origin.y();
      const double depth = localHeight - w.y;
      if (!(depth > -span)) continue;  // dry (or a NaN height)
      addWaveTexel(sums, corrections, texel, correction, r, w, a, b, depth, localHeight, jet ? jet->slopeX : 0.0,
                   jet ? jet->slopeZ : 0.0, rhoG);
    }
  }
  addWaveCorrections(sums, corrections, r, rhoG);
  return detail::finishHydrostatics(sums, origin, surface.density(), q, detail::ForceModel::PressureSums, true);
}

}  // namespace hydrotex
