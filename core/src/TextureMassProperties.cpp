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

// Covariance of a texel's surface patch about its position, from the texel edges; a partly
// covered texel is scaled by its covered fraction (exact for whole flat texels only).
Eigen::Matrix3d texelCovariance(const Eigen::Vector3d& edgeU, const Eigen::Vector3d& edgeV, double area) {
  const double spanned = edgeU.cross(edgeV).norm();
  const double fraction = spanned > 0.0 ? std::min(1.0, area / spanned) : 0.0;
  return fraction / 12.0 * (edgeU * edgeU.transpose() + edgeV * edgeV.transpose());
}

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
    : referencePoint_(referencePoint), count_(textures.size()) {
  const std::size_t blocks = (count_ + kBlock - 1) / kBlock;
  const std::size_t padded = blocks * kBlock;
  dx_.assign(padded, 0.0f);
  dy_.assign(padded, 0.0f);
  dz_.assign(padded, 0.0f);
  volume_.assign(padded, 0.0f);
  blockCovariance_.assign(blocks * 6, 0.0);
  blockAbsVolume_.assign(blocks, 0.0);
  for (std::size_t i = 0; i < count_; ++i) {
    const Eigen::Vector3d d = textures.position[i].cast<double>() - referencePoint;
    const Eigen::Vector3d areaVector = textures.areaVector[i].cast<double>();
    const double v = d.dot(areaVector) / 3.0;
    const double area = textures.area[i];
    dx_[i] = static_cast<float>(d.x());
    dy_[i] = static_cast<float>(d.y());
    dz_[i] = static_cast<float>(d.z());
    volume_[i] = static_cast<float>(v);
    totalVolume_ += v;
    const Eigen::Matrix3d covariance =
        texelCovariance(textures.edgeU[i].cast<double>(), textures.edgeV[i].cast<double>(), area);
    const std::size_t b = i / kBlock;
    const Eigen::Matrix3d cone = 0.6 * v * covariance;
    blockCovariance_[6 * b + 0] += cone(0, 0);
    blockCovariance_[6 * b + 1] += cone(1, 1);
    blockCovariance_[6 * b + 2] += cone(2, 2);
    blockCovariance_[6 * b + 3] += cone(0, 1);
    blockCovariance_[6 * b + 4] += cone(0, 2);
    blockCovariance_[6 * b + 5] += cone(1, 2);
    blockAbsVolume_[b] += std::abs(v);
    shellArea_ += area;
    shellFirst_ += area * d;
    shellSecond_ += area * (d * d.transpose() + covariance);
  }
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
