// SPDX-License-Identifier: Zlib
// Mass properties from texel sums (paper sections 2.1-2.3; docs/design.md "Mass model").
// Solid: the texel of area vector A at position p and the reference point c bound a cone of
// volume v = (p - c) . A / 3 (divergence theorem: the cones tile the solid, signed, so that the
// sum of v is the enclosed volume exactly; docs/references.md "Mass properties"), with its centroid at
// c + 3/4 (p - c). Its second moment about c: with q = c + s (x - c), s in [0, 1], over a flat
// base B of distance h from c, dV = s^2 h ds dA and
//   integral (q - c)(q - c)^T dV = (1/5) h integral_B (x - c)(x - c)^T dA
//                                = 3/5 v ((p - c)(p - c)^T + C_B),
// C_B the covariance of the base about its centroid; for a parallelogram of edges eu, ev:
// C_B = (eu eu^T + ev ev^T) / 12. Shell: areal density times texel area at the texel position,
// with the same covariance. Central inertia: I = trace(S) Id - S, S the central second moment.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include "hydrotex/mass/MassProperties.hpp"
#include "mass/MassMoments.hpp"
#include "mass/Vector3Lanes.hpp"

namespace hydrotex {
namespace {

// Texels per block: accumulated in float lanes inside a block (32 terms per lane keep float
// rounding near 1e-7), in double across blocks.
constexpr std::size_t kBlock = 256;
constexpr std::size_t kLanes = 8;

// Float lanes of one block's sums: independent accumulators the compiler turns into SIMD
// registers without reassociating anything.
struct BlockSums {
  float mass[kLanes] = {}, fx[kLanes] = {}, fy[kLanes] = {}, fz[kLanes] = {};
  float sxx[kLanes] = {}, syy[kLanes] = {}, szz[kLanes] = {}, sxy[kLanes] = {}, sxz[kLanes] = {}, syz[kLanes] = {};
  float weightedAbs[kLanes] = {};
  float lowest[kLanes] = {};
};

// One block of kBlock texels of a density map: cone mass w = rho v, w d, w d d^T, the
// density-weighted |v| and the lowest density (to report negative or NaN densities).
void accumulateBlock(const float* __restrict dx, const float* __restrict dy, const float* __restrict dz,
                     const float* __restrict vol, const float* __restrict density, BlockSums& out) {
  BlockSums s;
  for (std::size_t l = 0; l < kLanes; ++l) s.lowest[l] = std::numeric_limits<float>::max();
  for (std::size_t i = 0; i < kBlock; i += kLanes) {
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::size_t k = i + l;
      const float rho = density[k];
      const float w = rho * vol[k];
      const float x = dx[k], y = dy[k], z = dz[k];
      const float wx = w * x, wy = w * y, wz = w * z;
      s.mass[l] += w;
      s.fx[l] += wx;
      s.fy[l] += wy;
      s.fz[l] += wz;
      s.sxx[l] += wx * x;
      s.syy[l] += wy * y;
      s.szz[l] += wz * z;
      s.sxy[l] += wx * y;
      s.sxz[l] += wx * z;
      s.syz[l] += wy * z;
      s.weightedAbs[l] += rho * std::fabs(vol[k]);
      s.lowest[l] = rho < s.lowest[l] ? rho : s.lowest[l];
    }
  }
  out = s;
}

// The symmetric matrix of six sums xx yy zz xy xz yz.
Eigen::Matrix3d symmetric(const double* s) {
  Eigen::Matrix3d m;
  m << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
  return m;
}

// sums[m] += terms[m] for every m.
template <std::size_t N>
void addTo(double (&sums)[N], const double* terms) {
  for (std::size_t m = 0; m < N; ++m) sums[m] += terms[m];
}

// One block of TextureMassIntegrator::update as structure-of-arrays (in L1 cache), filled from
// the packed textures, and the per-texel patch covariance scale computed from it.
struct BlockScratch {
  alignas(64) float ax[kBlock], ay[kBlock], az[kBlock];   // area vector
  alignas(64) float ux[kBlock], uy[kBlock], uz[kBlock];   // texel edge along u
  alignas(64) float vx[kBlock], vy[kBlock], vz[kBlock];   // texel edge along v
  alignas(64) float area[kBlock];
  alignas(64) float scale[kBlock];                        // C = scale (eu eu^T + ev ev^T)
};

// Cone volumes v = (p - c) . A / 3 of one block.
void coneVolumes(const float* __restrict x, const float* __restrict y, const float* __restrict z,
                 const BlockScratch& s, float* __restrict v) {
  for (std::size_t k = 0; k < kBlock; ++k) v[k] = (x[k] * s.ax[k] + y[k] * s.ay[k] + z[k] * s.az[k]) * (1.0f / 3.0f);
}

// Covariance of each texel's patch about its position, C = (eu eu^T + ev ev^T) / 12 for a whole
// flat parallelogram, scaled by the covered fraction |A| / |eu x ev| for a partly covered texel
// (at most 1; 0 where the edges span nothing): the factor in front of the outer products. Plain
// loops over one block: vectorised, branch-free.
void patchCovarianceScales(BlockScratch& s) {
  const float* __restrict ux = s.ux;
  const float* __restrict uy = s.uy;
  const float* __restrict uz = s.uz;
  const float* __restrict vx = s.vx;
  const float* __restrict vy = s.vy;
  const float* __restrict vz = s.vz;
  const float* __restrict area = s.area;
  float* __restrict scale = s.scale;
  for (std::size_t k = 0; k < kBlock; ++k) {
    const float crossX = uy[k] * vz[k] - uz[k] * vy[k], crossY = uz[k] * vx[k] - ux[k] * vz[k];
    const float crossZ = ux[k] * vy[k] - uy[k] * vx[k];
    scale[k] = crossX * crossX + crossY * crossY + crossZ * crossZ;
  }
  // Eigen's packet square root (std::sqrt in a loop keeps a scalar errno path).
  Eigen::Map<Eigen::Array<float, int(kBlock), 1>> spanned(scale);
  spanned = spanned.sqrt();
  for (std::size_t k = 0; k < kBlock; ++k) {
    // min(area / spanned, 1) without a branch: min(area, spanned) / spanned, and 0 / tiny where
    // the edges span nothing.
    scale[k] = std::min(area[k], scale[k]) / std::max(scale[k], std::numeric_limits<float>::min()) * (1.0f / 12.0f);
  }
}

// Texels per SIMD chunk of the block sums (divides kBlock): kLanes float lanes.
using Chunk = Eigen::Array<float, int(kLanes), 1>;
template <std::size_t N>
using Terms = std::array<Chunk, N>;

// The chunk of `values` (one block's array) at texel j.
Chunk chunkAt(const float* values, std::size_t j) { return Eigen::Map<const Chunk, Eigen::Aligned16>(values + j); }

// Sums N per-texel terms over one block, chunk by chunk in float lanes (kBlock / kLanes terms per
// lane), then across lanes in double. A few sums per call so that the accumulators stay in
// registers. `term(j)` gives the N terms of the chunk at texel j.
template <std::size_t N, class Term>
std::array<double, N> blockSums(Term term) {
  Terms<N> lanes;
  for (Chunk& lane : lanes) lane.setZero();
  for (std::size_t j = 0; j < kBlock; j += kLanes) {
    const Terms<N> t = term(j);
    for (std::size_t m = 0; m < N; ++m) lanes[m] += t[m];
  }
  std::array<double, N> sums;
  for (std::size_t m = 0; m < N; ++m) sums[m] = lanes[m].template cast<double>().sum();
  return sums;
}

}  // namespace

struct TextureMassIntegrator::Moments {
  double mass = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();    // about the reference point
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();   // about the reference point
  double volume = 0.0;
};

TextureMassIntegrator::TextureMassIntegrator(const SurfaceTextures& textures, const Eigen::Vector3d& referencePoint)
    : referencePoint_(referencePoint) {
  update(textures);
}

void TextureMassIntegrator::update(const SurfaceTextures& textures) {
  count_ = textures.size();
  const std::size_t blocks = (count_ + kBlock - 1) / kBlock;
  const std::size_t padded = blocks * kBlock;
  // resize keeps the capacity: no allocation when the texel count is unchanged.
  dx_.resize(padded, 0.0f);
  dy_.resize(padded, 0.0f);
  dz_.resize(padded, 0.0f);
  volume_.resize(padded, 0.0f);
  blockCovariance_.resize(blocks * 6);
  blockAbsVolume_.resize(blocks);
  const float cx = static_cast<float>(referencePoint_.x());
  const float cy = static_cast<float>(referencePoint_.y());
  const float cz = static_cast<float>(referencePoint_.z());
  // A texture shorter than the texel count (a malformed input) reads as zeros past its end.
  const std::size_t count = std::min({count_, textures.areaVector.size(), textures.area.size(), textures.edgeU.size(),
                                      textures.edgeV.size()});
  double volumeSum = 0.0, shellArea = 0.0;
  double shellFirst[3] = {}, shellSecond[6] = {}, volumeFirst[3] = {}, volumeSecond[6] = {}, covariance[6] = {};
  BlockScratch scratch;
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t begin = b * kBlock;
    const std::size_t filled = begin < count ? std::min(kBlock, count - begin) : 0;
    // The block as structure-of-arrays (the positions go straight to dx_, dy_, dz_); padding
    // texels are zero, and zero area vector and area add nothing.
    const auto split = [&](auto shifted, const std::vector<Eigen::Vector3f>& packed, float sx, float sy, float sz,
                           float* x, float* y, float* z) {
      if (filled > 0)
        detail::splitTriples<decltype(shifted)::value>(packed[begin].data(), filled, sx, sy, sz, x, y, z, 3 * kBlock,
                                                       3 * (count - begin));
      std::fill(x + filled, x + kBlock, 0.0f);
      std::fill(y + filled, y + kBlock, 0.0f);
      std::fill(z + filled, z + kBlock, 0.0f);
    };
    float* const x = dx_.data() + begin;
    float* const y = dy_.data() + begin;
    float* const z = dz_.data() + begin;
    float* const v = volume_.data() + begin;
    split(std::true_type{}, textures.position, cx, cy, cz, x, y, z);
    split(std::false_type{}, textures.areaVector, 0.0f, 0.0f, 0.0f, scratch.ax, scratch.ay, scratch.az);
    split(std::false_type{}, textures.edgeU, 0.0f, 0.0f, 0.0f, scratch.ux, scratch.uy, scratch.uz);
    split(std::false_type{}, textures.edgeV, 0.0f, 0.0f, 0.0f, scratch.vx, scratch.vy, scratch.vz);
    if (filled > 0) {
      std::copy_n(textures.area.begin() + std::ptrdiff_t(begin), filled, scratch.area);
      for (std::size_t k = begin + kBlock; k < std::min(count, begin + 2 * kBlock); k += 16)
        __builtin_prefetch(textures.area.data() + k);
    }
    std::fill(scratch.area + filled, scratch.area + kBlock, 0.0f);

    coneVolumes(x, y, z, scratch, v);
    patchCovarianceScales(scratch);
    // The sums, a few at a time (each in float lanes over the block, then double).
    const float* const a = scratch.area;
    const float* const scale = scratch.scale;
    double blockVolume = 0.0, blockAbs = 0.0, blockArea = 0.0;
    // The enclosed volume is exact up to rounding: double lanes.
    {
      double lanes[kLanes] = {};
      for (std::size_t i = 0; i < kBlock; i += kLanes)
        for (std::size_t l = 0; l < kLanes; ++l) lanes[l] += double(v[i + l]);
      for (double lane : lanes) blockVolume += lane;
    }
    const auto volumeTerms = blockSums<5>([&](std::size_t j) {
      const Chunk cv = chunkAt(v, j);
      return Terms<5>{cv.abs(), chunkAt(a, j), cv * chunkAt(x, j), cv * chunkAt(y, j), cv * chunkAt(z, j)};
    });
    blockAbs = volumeTerms[0];
    blockArea = volumeTerms[1];
    addTo(volumeFirst, &volumeTerms[2]);
    addTo(volumeSecond, blockSums<6>([&](std::size_t j) {
            const Chunk px = chunkAt(x, j), py = chunkAt(y, j), pz = chunkAt(z, j), cv = chunkAt(v, j);
            const Chunk vx = cv * px, vy = cv * py, vz = cv * pz;
            return Terms<6>{vx * px, vy * py, vz * pz, vx * py, vx * pz, vy * pz};
          }).data());
    // The patch covariances, weighted for the cones (3/5 v) and the shell (a). `offset` picks the
    // outer products' pairs: 0 the diagonal (xx yy zz), 1 the rest (xy yz zx).
    const auto weightedCovariance = [&](auto offset) {
      return blockSums<6>([&](std::size_t j) {
        const Chunk eu[3] = {chunkAt(scratch.ux, j), chunkAt(scratch.uy, j), chunkAt(scratch.uz, j)};
        const Chunk ev[3] = {chunkAt(scratch.vx, j), chunkAt(scratch.vy, j), chunkAt(scratch.vz, j)};
        const Chunk k = chunkAt(scale, j), coneWeight = 0.6f * chunkAt(v, j) * k, shellWeight = chunkAt(a, j) * k;
        constexpr int kOffset = decltype(offset)::value;
        const Chunk outer[3] = {eu[0] * eu[kOffset % 3] + ev[0] * ev[kOffset % 3],
                                eu[1] * eu[(1 + kOffset) % 3] + ev[1] * ev[(1 + kOffset) % 3],
                                eu[2] * eu[(2 + kOffset) % 3] + ev[2] * ev[(2 + kOffset) % 3]};
        return Terms<6>{coneWeight * outer[0],  coneWeight * outer[1],  coneWeight * outer[2],
                        shellWeight * outer[0], shellWeight * outer[1], shellWeight * outer[2]};
      });
    };
    const auto diagonal = weightedCovariance(std::integral_constant<int, 0>{});  // xx yy zz
    const auto across = weightedCovariance(std::integral_constant<int, 1>{});    // xy yz zx
    // In the xx yy zz xy xz yz order: cones, then the shell's.
    const double cone[6] = {diagonal[0], diagonal[1], diagonal[2], across[0], across[2], across[1]};
    const double shellCovariance[6] = {diagonal[3], diagonal[4], diagonal[5], across[3], across[5], across[4]};
    std::copy(std::begin(cone), std::end(cone), &blockCovariance_[6 * b]);
    addTo(covariance, cone);
    addTo(shellSecond, shellCovariance);
    addTo(shellFirst, blockSums<3>([&](std::size_t j) {
            const Chunk ca = chunkAt(a, j);
            return Terms<3>{ca * chunkAt(x, j), ca * chunkAt(y, j), ca * chunkAt(z, j)};
          }).data());
    addTo(shellSecond, blockSums<6>([&](std::size_t j) {
            const Chunk ca = chunkAt(a, j), px = chunkAt(x, j), py = chunkAt(y, j), pz = chunkAt(z, j);
            const Chunk ax = ca * px, ay = ca * py, az = ca * pz;
            return Terms<6>{ax * px, ay * py, az * pz, ax * py, ax * pz, ay * pz};
          }).data());
    blockAbsVolume_[b] = blockAbs;
    volumeSum += blockVolume;
    shellArea += blockArea;
  }
  totalVolume_ = volumeSum;
  // A lid over an opening is no material (Mesh.hpp): its exact moments leave the shell.
  const OpeningMoments lids = textures.openings.about(referencePoint_);
  shellArea_ = shellArea - lids.area;
  shellFirst_ = Eigen::Vector3d(shellFirst[0], shellFirst[1], shellFirst[2]) - lids.first;
  shellSecond_ = symmetric(shellSecond) - lids.second;
  volumeFirst_ = Eigen::Vector3d(volumeFirst[0], volumeFirst[1], volumeFirst[2]);
  volumeSecond_ = symmetric(volumeSecond);
  coneCovariance_ = symmetric(covariance);
}

Expected<MassProperties> TextureMassIntegrator::evaluate(const TextureMassModel& model) const {
  const bool mapped = !model.texelDensity.empty();
  if (mapped && model.texelDensity.size() != count_)
    return Error{"density map has " + std::to_string(model.texelDensity.size()) + " texels, the bake has " +
                 std::to_string(count_)};
  if (!std::isfinite(model.solidDensity) || model.solidDensity < 0.0)
    return Error{"solid density " + std::to_string(model.solidDensity) + " kg/m^3 is negative or not finite"};
  if (!std::isfinite(model.shellDensity) || model.shellDensity < 0.0)
    return Error{"shell density " + std::to_string(model.shellDensity) + " kg/m^2 is negative or not finite"};

  Moments m;
  if (!mapped) {
    // A uniform solid: its density times the geometry-only cone sums (update), no texel pass.
    const double density = model.solidDensity;
    m.mass = density * totalVolume_;
    m.first = 0.75 * density * volumeFirst_;
    m.second = density * (0.6 * volumeSecond_ + coneCovariance_);
  } else {
    float lowestDensity = std::numeric_limits<float>::max();
    const std::size_t blocks = blockAbsVolume_.size();
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t begin = b * kBlock;
      const float* density = model.texelDensity.data() + begin;
      // The density map is not padded: the last block reads a zero-padded copy.
      float tail[kBlock];
      if (begin + kBlock > count_) {
        std::fill(std::begin(tail), std::end(tail), 0.0f);
        std::copy(model.texelDensity.begin() + std::ptrdiff_t(begin), model.texelDensity.end(), tail);
        density = tail;
      }
      BlockSums sums;
      accumulateBlock(dx_.data() + begin, dy_.data() + begin, dz_.data() + begin, volume_.data() + begin, density,
                      sums);
      double blockMass = 0.0, blockWeightedAbs = 0.0;
      Eigen::Vector3d first = Eigen::Vector3d::Zero();
      double s[6] = {};
      for (std::size_t l = 0; l < kLanes; ++l) {
        blockMass += sums.mass[l];
        first += Eigen::Vector3d(sums.fx[l], sums.fy[l], sums.fz[l]);
        s[0] += sums.sxx[l];
        s[1] += sums.syy[l];
        s[2] += sums.szz[l];
        s[3] += sums.sxy[l];
        s[4] += sums.sxz[l];
        s[5] += sums.syz[l];
        blockWeightedAbs += sums.weightedAbs[l];
        lowestDensity = std::min(lowestDensity, sums.lowest[l]);
      }
      // The cone covariance terms were summed per block without density; weight them by the
      // block's mean density (exact where the density is uniform over the block).
      const double meanDensity = blockAbsVolume_[b] > 0.0 ? blockWeightedAbs / blockAbsVolume_[b] : 0.0;
      const double* c = &blockCovariance_[6 * b];
      m.mass += blockMass;
      m.first += 0.75 * first;
      m.second(0, 0) += 0.6 * s[0] + meanDensity * c[0];
      m.second(1, 1) += 0.6 * s[1] + meanDensity * c[1];
      m.second(2, 2) += 0.6 * s[2] + meanDensity * c[2];
      m.second(0, 1) += 0.6 * s[3] + meanDensity * c[3];
      m.second(0, 2) += 0.6 * s[4] + meanDensity * c[4];
      m.second(1, 2) += 0.6 * s[5] + meanDensity * c[5];
    }
    if (!(lowestDensity >= 0.0f) || !std::isfinite(m.mass))
      return Error{"density map has a negative or non-finite density"};
    m.second(1, 0) = m.second(0, 1);
    m.second(2, 0) = m.second(0, 2);
    m.second(2, 1) = m.second(1, 2);
  }
  // The shell: uniform areal density over geometry-only sums prepared once.
  m.mass += model.shellDensity * shellArea_;
  m.first += model.shellDensity * shellFirst_;
  m.second += model.shellDensity * shellSecond_;
  m.volume = totalVolume_;
  return finish(m);
}

MassProperties TextureMassIntegrator::finish(const Moments& moments) const {
  return detail::massPropertiesFromMoments({moments.mass, moments.first, moments.second, moments.volume},
                                           referencePoint_);
}

MassProperties textureMassProperties(const SurfaceTextures& textures, const TextureMassModel& model) {
  const TextureMassIntegrator integrator(textures, model.referencePoint);
  Expected<MassProperties> result = integrator.evaluate(model);
  if (result.ok()) return *result;
  MassProperties invalid;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  invalid.mass = invalid.volume = nan;
  invalid.centerOfMass.setConstant(nan);
  invalid.inertia.setConstant(nan);
  return invalid;
}

}  // namespace hydrotex
