// SPDX-License-Identifier: Zlib
#pragma once
/// @file WaveTexelLanes.hpp
/// Private to core: the texture path's texels under a wave's local quadratic model
/// (TextureHydrostaticsWaves.cpp, a tile the waterline crosses) several at a time in SIMD lanes:
/// two in SSE2 (DoubleLanes, every x86-64) or four in AVX2 (QuadLanes, WaveTexelLanesAvx2.cpp,
/// where the processor has it). Each lane computes what the scalar loop computes for its texel
/// with the same operations in the same order (no fused multiply-adds): the posed texel, the
/// model's height, the waterline fractions (waterlineFractions) and the element's terms
/// (WettedSums::addElement); only the order of the sums over texels differs (per lane, then
/// across lanes). A texel's moment correction (MomentCorrectionSums) is left to the caller, as is
/// a tile of fewer texels than lanes (the lanes read whole groups of consecutive texels).
///
/// The AVX2 unit is compiled with -mavx2, so it must not emit any function another unit also
/// emits: the input is plain data, the output WettedSums is only added to (no member function
/// called), and everything instantiated depends on the lane type, which has internal linkage there.

#include <cstddef>
#include <cstdint>

#include "DoubleLanes.hpp"
#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex::detail {

/// What sumWaveTexelLanes reads: plain data, frame o (the query's origin), SI units.
struct WaveTexelInput {
  const TextureHydrostatics::Texel* texels;              ///< the packed texels
  std::uint32_t begin, end;                               ///< the tile's texels
  double xRow[3], yRow[3], zRow[3], offset[3];           ///< x' = R p + offset
  /// The model: height h (m, frame o) at (centerX, centerZ), slopes and curvatures there.
  double centerX, centerZ, h, slopeX, slopeZ, curvatureXX, curvatureXZ, curvatureZZ;
  /// The highest the model's heights can be over the tile (m, frame o): a group of texels
  /// wholly over it is dry without its heights.
  double highest;
};

/// Floats in a packed texel, and where its fields start.
inline constexpr unsigned kTexelFloats = sizeof(TextureHydrostatics::Texel) / sizeof(float);
static_assert(sizeof(TextureHydrostatics::Texel) == kTexelFloats * sizeof(float), "a texel is floats only");

/// Adds the element terms of the texels [in.begin, reached) to `out` (frame o), L::kWidth at a
/// time, and returns `reached`: in.end, or in.begin for a tile of fewer texels than lanes. The
/// last group ends at in.end, its lanes that the group before it took masked. A corrected texel's
/// element terms are those of any texel (waterlineFractions gives zeros under -halfSpan, where
/// its pieces' reach may still wet its correction): the caller adds the corrections.
template <class L>
inline std::uint32_t sumWaveTexelLanes(const WaveTexelInput& in, WettedSums& out) {
  constexpr unsigned W = L::kWidth;
  using Texel = TextureHydrostatics::Texel;
  constexpr unsigned kPosition = offsetof(Texel, position) / sizeof(float);
  constexpr unsigned kAreaVector = offsetof(Texel, areaVector) / sizeof(float);
  constexpr unsigned kArea = offsetof(Texel, area) / sizeof(float);
  constexpr unsigned kEdgeU = offsetof(Texel, edgeU) / sizeof(float);
  constexpr unsigned kEdgeV = offsetof(Texel, edgeV) / sizeof(float);
  if (in.end - in.begin < W) return in.begin;
  const L x0 = in.xRow[0], x1 = in.xRow[1], x2 = in.xRow[2];
  const L y0 = in.yRow[0], y1 = in.yRow[1], y2 = in.yRow[2];
  const L z0 = in.zRow[0], z1 = in.zRow[1], z2 = in.zRow[2];
  const L bx = in.offset[0], by = in.offset[1], bz = in.offset[2];
  const L centerX = in.centerX, centerZ = in.centerZ, h0 = in.h, slopeX = in.slopeX, slopeZ = in.slopeZ;
  const L cxx = in.curvatureXX, cxz = in.curvatureXZ, czz = in.curvatureZZ, highest = in.highest;
  const L zero = 0.0, one = 1.0, half = 0.5;
  WettedLaneSums<L> lanes{};  // value-initialized: zeros
  for (std::uint32_t next = in.begin; next < in.end;) {
    // The group [i, i + W): its lanes before `next` were the last group's.
    const std::uint32_t i = next + W <= in.end ? next : in.end - W;
    const int taken = (1 << (next - i)) - 1;
    next = i + W;
    const float* p = reinterpret_cast<const float*>(in.texels + i);
    auto field = [p](unsigned k) { return L::loadFloatsStrided(p + k, kTexelFloats); };
    const L px = field(kPosition), py = field(kPosition + 1), pz = field(kPosition + 2);
    const L a = y0 * field(kEdgeU) + y1 * field(kEdgeU + 1) + y2 * field(kEdgeU + 2);
    const L b = y0 * field(kEdgeV) + y1 * field(kEdgeV + 1) + y2 * field(kEdgeV + 2);
    const L halfSpan = half * (absolute(a) + absolute(b));
    const L y = y0 * px + y1 * py + y2 * pz + by;
    // Over the highest the model reaches (the scalar loop's test): dry without their heights.
    if ((maskLanes(lessMask(y - halfSpan, highest)) & ~taken) == 0) continue;
    const L x = x0 * px + x1 * py + x2 * pz + bx;
    const L z = z0 * px + z1 * py + z2 * pz + bz;
    const L ux = x - centerX, uz = z - centerZ;
    const L height = h0 + slopeX * ux + slopeZ * uz + half * (cxx * ux * ux + L(2.0) * cxz * ux * uz + czz * uz * uz);
    const L d = height - y;
    // Wet: d > -halfSpan (a NaN height is dry), and not the last group's.
    const int wetBits = maskLanes(lessMask(-halfSpan, d)) & ~taken;
    if (wetBits == 0) continue;
    const L wet = L::maskOf(wetBits);
    // waterlineFractions(d, a, b), every case in every lane, then the lane's own chosen.
    const L large = maximum(absolute(a), absolute(b)), small = minimum(absolute(a), absolute(b));
    const L variance = (large * large + small * small) / L(12.0);
    const L spread = half * (large - small);
    const L q[4] = {maximum(d + halfSpan, zero), maximum(d + spread, zero), maximum(d - spread, zero),
                    maximum(d - halfSpan, zero)};
    L s2 = q[0] * q[0], s3 = s2 * q[0], s4 = s2 * s2;
    for (int k = 1; k < 4; ++k) {
      const L q2 = q[k] * q[k];
      if (k == 3) {
        s2 += q2;
        s3 += q2 * q[k];
        s4 += q2 * q2;
      } else {
        s2 -= q2;
        s3 -= q2 * q[k];
        s4 -= q2 * q2;
      }
    }
    const L inverse = one / (large * small);
    const L generalFraction = s2 * half * inverse, generalMean = s3 / L(6.0) * inverse,
            generalMeanSq = s4 / L(12.0) * inverse;
    const L high = maximum(d + half * large, zero), low = maximum(d - half * large, zero);
    const L inverseLarge = one / large;
    const L lineFraction = (high - low) * inverseLarge, lineMean = half * (high * high - low * low) * inverseLarge,
            lineMeanSq = (high * high * high - low * low * low) / L(3.0) * inverseLarge;
    const L general = lessMask(L(1e-6) * large, small);
    const L partialFraction = select(general, generalFraction, lineFraction);
    const L partialMeanSq = select(general, generalMeanSq, lineMeanSq) - partialFraction * variance;
    const L crossing = lessMask(d, halfSpan);  // else wholly under: {1, d, d^2}
    const L fraction = select(wet, select(crossing, partialFraction, one), zero);
    const L depth = select(wet, select(crossing, select(general, generalMean, lineMean), d), zero);
    const L depthSq = select(wet, select(crossing, partialMeanSq, d * d), zero);
    const L localHeight = select(wet, height, zero);
    // WettedSums::addElement on the posed area vector.
    const L ax = field(kAreaVector), ay = field(kAreaVector + 1), az = field(kAreaVector + 2);
    const L wx = x0 * ax + x1 * ay + x2 * az, wy = y0 * ax + y1 * ay + y2 * az, wz = z0 * ax + z1 * ay + z2 * az;
    addElementTerms(lanes, x, y, z, wx, wy, wz, field(kArea), fraction, depth, depthSq, localHeight);
  }
  addLaneTotals(out, lanes);
  return in.end;
}

/// sumWaveTexelLanes with QuadLanes where the processor has AVX2 and HYDROTEX_DISABLE_AVX2 is not
/// set (asked once): true, `reached` set; false (nothing added) elsewhere.
bool sumWaveTexelsAvx2(const WaveTexelInput& in, WettedSums& out, std::uint32_t& reached);

}  // namespace hydrotex::detail
