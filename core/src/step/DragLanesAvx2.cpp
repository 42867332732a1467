// SPDX-License-Identifier: Zlib
/// @file DragLanesAvx2.cpp
/// DragLanes.hpp's sums four patches at a time in AVX2 registers, without fused multiply-adds (as
/// the wetting's AVX2 lanes): each lane rounds as the scalar law does. With them (-mfma),
/// test_hard_cases' needle (1 m x 1 mm x 1 mm, texture path, double-precision Bullet) peaked at
/// 149 rad/s against the test's bound of 110. That needle never settles on the texture path,
/// with any of the lanes: from t = 9.5 s it rolls at 60-90 rad/s to the end (its roll inertia is
/// 8e-11 kg m^2), so a rounding-level change of the drag's sums moves its peaks.
/// core/CMakeLists.txt compiles this file alone with -mavx2 where the compiler takes it;
/// the processor is asked once, at the first call. Everything this file instantiates depends on
/// QuadLanes, which has internal linkage, so no AVX2 code can stand in for another unit's
/// (DragLanes.hpp); `nm` on its object lists no weak function from -O1 up (at -O0 GCC adds
/// the empty constructors of Eigen's placeholders `all` and `last`, which hold no vector code).

#include "Avx2Lanes.hpp"
#include "step/DragLanes.hpp"

#if defined(__AVX2__)
#include <immintrin.h>

namespace hydrotex::detail {
namespace {

/// Four doubles in one AVX2 register, with DoubleLanes' operations.
struct QuadLanes {
  static constexpr unsigned kWidth = 4;
  __m256d v;
  QuadLanes() = default;
  explicit QuadLanes(__m256d lanes) : v(lanes) {}
  QuadLanes(double all) : v(_mm256_set1_pd(all)) {}  // NOLINT: scalars mix in as in the scalar law
  double sum() const {
    const __m128d pair = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
    return _mm_cvtsd_f64(_mm_add_sd(pair, _mm_unpackhi_pd(pair, pair)));
  }
  static QuadLanes loadFloats(const float* p) { return QuadLanes(_mm256_cvtps_pd(_mm_loadu_ps(p))); }
  static QuadLanes loadDoubles(const double* p) { return QuadLanes(_mm256_loadu_pd(p)); }
  static QuadLanes firstLanes(unsigned count) {
    const __m256d first = _mm256_cmp_pd(_mm256_set_pd(3.0, 2.0, 1.0, 0.0), _mm256_set1_pd(double(count)), _CMP_LT_OQ);
    return QuadLanes(_mm256_and_pd(first, _mm256_set1_pd(1.0)));
  }
};
inline QuadLanes operator+(QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_add_pd(a.v, b.v)); }
inline QuadLanes operator-(QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_sub_pd(a.v, b.v)); }
inline QuadLanes operator*(QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_mul_pd(a.v, b.v)); }
inline QuadLanes operator/(QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_div_pd(a.v, b.v)); }
inline QuadLanes operator-(QuadLanes a) { return QuadLanes(_mm256_xor_pd(a.v, _mm256_set1_pd(-0.0))); }
inline QuadLanes& operator+=(QuadLanes& a, QuadLanes b) { return a = a + b; }
inline QuadLanes& operator-=(QuadLanes& a, QuadLanes b) { return a = a - b; }
inline QuadLanes selectPositive(QuadLanes x, double positive, double otherwise) {
  return QuadLanes(_mm256_blendv_pd(_mm256_set1_pd(otherwise), _mm256_set1_pd(positive),
                                    _mm256_cmp_pd(x.v, _mm256_setzero_pd(), _CMP_GT_OQ)));
}
inline QuadLanes absolute(QuadLanes x) { return QuadLanes(_mm256_andnot_pd(_mm256_set1_pd(-0.0), x.v)); }
inline QuadLanes squareRoot(QuadLanes x) { return QuadLanes(_mm256_sqrt_pd(x.v)); }
inline QuadLanes maximum(QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_max_pd(a.v, b.v)); }
inline QuadLanes clampUnit(QuadLanes x) {
  return QuadLanes(_mm256_min_pd(_mm256_max_pd(x.v, _mm256_setzero_pd()), _mm256_set1_pd(1.0)));
}
inline QuadLanes positiveMask(QuadLanes x) { return QuadLanes(_mm256_cmp_pd(x.v, _mm256_setzero_pd(), _CMP_GT_OQ)); }
inline int positiveLanes(QuadLanes x) { return _mm256_movemask_pd(positiveMask(x).v); }
inline QuadLanes select(QuadLanes mask, QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_blendv_pd(b.v, a.v, mask.v)); }

// avx2LanesAllowed, asked at the first sum only: the drag runs per body and step, and the
// environment is a scan of strings.
bool wideLanes() {
  static const bool allowed = avx2LanesAllowed();
  return allowed;
}

}  // namespace

bool sumUniformDragAvx2(const UniformDragInput& in, DragLaneSums& out) {
  if (!wideLanes()) return false;
  sumUniformDragLanes<QuadLanes>(in, out);
  return true;
}

bool sumPosedDragAvx2(const PosedDragInput& in, DragLaneSums& out) {
  if (!wideLanes()) return false;
  sumPosedDragLanes<QuadLanes>(in, out);
  return true;
}

}  // namespace hydrotex::detail

#else

namespace hydrotex::detail {
bool sumUniformDragAvx2(const UniformDragInput&, DragLaneSums&) { return false; }
bool sumPosedDragAvx2(const PosedDragInput&, DragLaneSums&) { return false; }
}  // namespace hydrotex::detail

#endif
