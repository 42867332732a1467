// SPDX-License-Identifier: Zlib
#pragma once
/// @file QuadLanes.hpp
/// Private to core, and only for the units compiled with -mavx2 (core/CMakeLists.txt): four
/// doubles in one AVX2 register with DoubleLanes.hpp's operations (each lane rounds as the scalar
/// law: no fused multiply-adds). In an anonymous namespace, so that everything a unit instantiates
/// with it has internal linkage and no AVX2 code can stand in for another unit's (the linker keeps
/// one copy of a weak function, perhaps the AVX2 one, for every caller).

#if !defined(__AVX2__)
#error "QuadLanes.hpp needs -mavx2"
#endif
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
  static QuadLanes loadFloatsStrided(const float* p, unsigned stride) {
    return QuadLanes(_mm256_cvtps_pd(_mm_set_ps(p[3 * stride], p[2 * stride], p[stride], p[0])));
  }
  static QuadLanes maskOf(int bits) {
    return QuadLanes(_mm256_castsi256_pd(
        _mm256_set_epi64x(bits & 8 ? -1 : 0, bits & 4 ? -1 : 0, bits & 2 ? -1 : 0, bits & 1 ? -1 : 0)));
  }
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
inline QuadLanes minimum(QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_min_pd(a.v, b.v)); }
inline QuadLanes clampUnit(QuadLanes x) {
  return QuadLanes(_mm256_min_pd(_mm256_max_pd(x.v, _mm256_setzero_pd()), _mm256_set1_pd(1.0)));
}
inline QuadLanes positiveMask(QuadLanes x) { return QuadLanes(_mm256_cmp_pd(x.v, _mm256_setzero_pd(), _CMP_GT_OQ)); }
inline int positiveLanes(QuadLanes x) { return _mm256_movemask_pd(positiveMask(x).v); }
inline int maskLanes(QuadLanes mask) { return _mm256_movemask_pd(mask.v); }
inline QuadLanes lessMask(QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)); }
inline QuadLanes select(QuadLanes mask, QuadLanes a, QuadLanes b) { return QuadLanes(_mm256_blendv_pd(b.v, a.v, mask.v)); }

}  // namespace
}  // namespace hydrotex::detail
