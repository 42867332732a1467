// Mass properties from texel sums (paper sections 2.1-2.3; DESIGN.md "Mass model").
// Solid: the texel of area vector A at position p and the reference point c bound a cone of
// volume v = (p - c) . A / 3 (divergence theorem: the cones tile the solid, signed, so that the
// sum of v is the enclosed volume exactly; REFERENCES.md "Mass properties"), with its centroid at
// c + 3/4 (p - c). Its second moment about c: with q = c + s (x - c), s in [0, 1], over a flat
// base B of distance h from c, dV = s^2 h ds dA and
//   integral (q - c)(q - c)^T dV = (1/5) h integral_B (x - c)(x - c)^T dA
//                                = 3/5 v ((p - c)(p - c)^T + C_B),
// C_B the covariance of the base about its centroid; for a parallelogram of edges eu, ev:
// C_B = (eu eu^T + ev ev^T) / 12. Shell: areal density times texel area at the texel position,
// with the same covariance. Central inertia: I = trace(S) Id - S, S the central second moment.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "hydrotex/MassProperties.hpp"

namespace hydrotex {
namespace {

// Texels per block: accumulated in float lanes inside a block (32 terms per lane keep float
// rounding near 1e-7), in double across blocks.
constexpr std::size_t kBlock = 256;
constexpr std::size_t kLanes = 8;
// Texels per SIMD chunk in TextureMassIntegrator::update (divides kBlock).
constexpr std::size_t kChunk = 8;
using Chunk = Eigen::Array<float, int(kChunk), 1>;

// Float lanes of one block's sums: independent accumulators the compiler turns into SIMD
// registers without reassociating anything.
struct BlockSums {
  float mass[kLanes] = {}, fx[kLanes] = {}, fy[kLanes] = {}, fz[kLanes] = {};
  float sxx[kLanes] = {}, syy[kLanes] = {}, szz[kLanes] = {}, sxy[kLanes] = {}, sxz[kLanes] = {}, syz[kLanes] = {};
  float weightedAbs[kLanes] = {};
  float lowest[kLanes] = {};
};

// One block of kBlock texels: cone mass w = rho v, w d, w d d^T, and (density maps only) the
// density-weighted |v| and the lowest density (to report negative or NaN densities).
template <bool Mapped>
void accumulateBlock(const float* __restrict dx, const float* __restrict dy, const float* __restrict dz,
                     const float* __restrict vol, const float* __restrict density, float uniform, BlockSums& out) {
  BlockSums s;
  for (std::size_t l = 0; l < kLanes; ++l) s.lowest[l] = Mapped ? std::numeric_limits<float>::max() : uniform;
  for (std::size_t i = 0; i < kBlock; i += kLanes) {
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::size_t k = i + l;
      const float rho = Mapped ? density[k] : uniform;
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
      if constexpr (Mapped) {
        s.weightedAbs[l] += rho * std::fabs(vol[k]);
        s.lowest[l] = rho < s.lowest[l] ? rho : s.lowest[l];
      }
    }
  }
  out = s;
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
  // resize keeps the capacity: no allocation when the texel count is unchanged. The padding
  // beyond count_ is zeroed once and never written.
  dx_.resize(padded, 0.0f);
  dy_.resize(padded, 0.0f);
  dz_.resize(padded, 0.0f);
  volume_.resize(padded, 0.0f);
  blockCovariance_.resize(blocks * 6);
  blockAbsVolume_.resize(blocks);
  const float cx = static_cast<float>(referencePoint_.x());
  const float cy = static_cast<float>(referencePoint_.y());
  const float cz = static_cast<float>(referencePoint_.z());
  // The textures as 3 x n float matrices (Vector3f is three packed floats).
  using Rows = Eigen::Map<const Eigen::Array<float, 3, Eigen::Dynamic>>;
  const Rows position(textures.position.empty() ? nullptr : textures.position.front().data(), 3, Eigen::Index(count_));
  const Rows areaVector(textures.areaVector.empty() ? nullptr : textures.areaVector.front().data(), 3, Eigen::Index(count_));
  const Rows edgeU(textures.edgeU.empty() ? nullptr : textures.edgeU.front().data(), 3, Eigen::Index(count_));
  const Rows edgeV(textures.edgeV.empty() ? nullptr : textures.edgeV.front().data(), 3, Eigen::Index(count_));
  double volumeSum = 0.0, shellArea = 0.0;
  double shell[9] = {};  // first x y z, second xx yy zz xy xz yz
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t begin = b * kBlock, end = std::min(count_, begin + kBlock);
    // A block in chunks of kChunk texels held in fixed-size Eigen arrays (SIMD, no branch); the
    // sums stay in float lanes over the block (kBlock / kChunk terms each, as in evaluate) and
    // are added in double across blocks.
    Chunk cone[6], absVolume = Chunk::Zero(), area = Chunk::Zero(), shellBlock[9];
    for (Chunk& c : cone) c.setZero();
    for (Chunk& c : shellBlock) c.setZero();
    // The enclosed volume is exact up to rounding: summed in double lanes (no dependent chain).
    Eigen::Array<double, int(kChunk), 1> blockVolume = Eigen::Array<double, int(kChunk), 1>::Zero();
    for (std::size_t chunk = begin; chunk < end; chunk += kChunk) {
      const Eigen::Index first = Eigen::Index(chunk), n = Eigen::Index(std::min(kChunk, end - chunk));
      // A whole chunk loads fixed-size (no loop set-up); the last one is padded with zeros, which
      // add nothing.
      auto load = [&](const Rows& rows, Eigen::Index row, float shift) {
        if (n == Eigen::Index(kChunk)) return Chunk(rows.row(row).segment<int(kChunk)>(first).transpose() - shift);
        Chunk out = Chunk::Zero();
        for (Eigen::Index j = 0; j < n; ++j) out[j] = rows(row, first + j) - shift;
        return out;
      };
      const Chunk x = load(position, 0, cx), y = load(position, 1, cy), z = load(position, 2, cz);
      const Chunk ax = load(areaVector, 0, 0.0f), ay = load(areaVector, 1, 0.0f), az = load(areaVector, 2, 0.0f);
      const Chunk ux = load(edgeU, 0, 0.0f), uy = load(edgeU, 1, 0.0f), uz = load(edgeU, 2, 0.0f);
      const Chunk vx = load(edgeV, 0, 0.0f), vy = load(edgeV, 1, 0.0f), vz = load(edgeV, 2, 0.0f);
      Chunk a = Chunk::Zero();
      for (Eigen::Index j = 0; j < n; ++j) a[j] = textures.area[chunk + std::size_t(j)];
      // (x, y, z) of padding texels is -c: harmless, their area vector and area are zero.
      const Chunk v = (x * ax + y * ay + z * az) * (1.0f / 3.0f);
      // The arrays are padded to whole blocks, so a whole chunk always fits.
      Eigen::Map<Chunk>(dx_.data() + chunk) = x;
      Eigen::Map<Chunk>(dy_.data() + chunk) = y;
      Eigen::Map<Chunk>(dz_.data() + chunk) = z;
      Eigen::Map<Chunk>(volume_.data() + chunk) = v;
      blockVolume += v.cast<double>();
      // Covariance of the texel's patch about its position, (eu eu^T + ev ev^T) / 12 for a whole
      // flat parallelogram, scaled by the covered fraction |A| / |eu x ev| for a partly covered
      // texel (at most 1).
      const Chunk crossX = uy * vz - uz * vy, crossY = uz * vx - ux * vz, crossZ = ux * vy - uy * vx;
      const Chunk spanned = (crossX * crossX + crossY * crossY + crossZ * crossZ).sqrt();
      const Chunk k = (spanned > 0.0f).select((a / spanned).min(1.0f), 0.0f) * (1.0f / 12.0f);
      const Chunk c[6] = {k * (ux * ux + vx * vx), k * (uy * uy + vy * vy), k * (uz * uz + vz * vz),
                          k * (ux * uy + vx * vy), k * (ux * uz + vx * vz), k * (uy * uz + vy * vz)};
      const Chunk w = 0.6f * v;
      for (int m = 0; m < 6; ++m) cone[m] += w * c[m];
      absVolume += v.abs();
      area += a;
      shellBlock[0] += a * x;
      shellBlock[1] += a * y;
      shellBlock[2] += a * z;
      shellBlock[3] += a * (x * x + c[0]);
      shellBlock[4] += a * (y * y + c[1]);
      shellBlock[5] += a * (z * z + c[2]);
      shellBlock[6] += a * (x * y + c[3]);
      shellBlock[7] += a * (x * z + c[4]);
      shellBlock[8] += a * (y * z + c[5]);
    }
    for (std::size_t m = 0; m < 6; ++m) blockCovariance_[6 * b + m] = cone[m].cast<double>().sum();
    blockAbsVolume_[b] = absVolume.cast<double>().sum();
    volumeSum += blockVolume.sum();
    shellArea += area.cast<double>().sum();
    for (std::size_t m = 0; m < 9; ++m) shell[m] += shellBlock[m].cast<double>().sum();
  }
  totalVolume_ = volumeSum;
  shellArea_ = shellArea;
  shellFirst_ = Eigen::Vector3d(shell[0], shell[1], shell[2]);
  shellSecond_ << shell[3], shell[6], shell[7], shell[6], shell[4], shell[8], shell[7], shell[8], shell[5];
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
  const float uniform = static_cast<float>(model.solidDensity);
  float lowestDensity = mapped ? std::numeric_limits<float>::max() : uniform;
  const std::size_t blocks = blockAbsVolume_.size();
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t begin = b * kBlock;
    const float* density = mapped ? model.texelDensity.data() + begin : nullptr;
    // The density map is not padded: the last block reads a zero-padded copy.
    float tail[kBlock];
    if (mapped && begin + kBlock > count_) {
      std::fill(std::begin(tail), std::end(tail), 0.0f);
      std::copy(model.texelDensity.begin() + begin, model.texelDensity.end(), tail);
      density = tail;
    }
    const float* dx = dx_.data() + begin;
    const float* dy = dy_.data() + begin;
    const float* dz = dz_.data() + begin;
    const float* vol = volume_.data() + begin;
    BlockSums sums;
    if (mapped)
      accumulateBlock<true>(dx, dy, dz, vol, density, uniform, sums);
    else
      accumulateBlock<false>(dx, dy, dz, vol, density, uniform, sums);
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
    const double meanDensity =
        mapped ? (blockAbsVolume_[b] > 0.0 ? blockWeightedAbs / blockAbsVolume_[b] : 0.0) : model.solidDensity;
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
  if (mapped && (!(lowestDensity >= 0.0f) || !std::isfinite(m.mass)))
    return Error{"density map has a negative or non-finite density"};
  m.second(1, 0) = m.second(0, 1);
  m.second(2, 0) = m.second(0, 2);
  m.second(2, 1) = m.second(1, 2);
  // The shell: uniform areal density over geometry-only sums prepared once.
  m.mass += model.shellDensity * shellArea_;
  m.first += model.shellDensity * shellFirst_;
  m.second += model.shellDensity * shellSecond_;
  m.volume = totalVolume_;
  return finish(m);
}

MassProperties TextureMassIntegrator::finish(const Moments& moments) const {
  MassProperties result;
  result.mass = moments.mass;
  result.volume = moments.volume;
  if (!(moments.mass > 0.0)) {
    result.centerOfMass = referencePoint_;
    return result;
  }
  const Eigen::Vector3d offset = moments.first / moments.mass;  // centre relative to the reference point
  result.centerOfMass = referencePoint_ + offset;
  const Eigen::Matrix3d central = moments.second - moments.mass * offset * offset.transpose();
  result.inertia = central.trace() * Eigen::Matrix3d::Identity() - central;
  return result;
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
