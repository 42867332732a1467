// SPDX-License-Identifier: Zlib
#pragma once
/// @file DoubleLanes.hpp
/// Private to core: two doubles in one SSE2 register (every x86-64), with the arithmetic that the
/// laws written once for a number type use (the drag law, TexelDragLaw.hpp; the texels under a
/// wave's local model, WaveTexelLanes.hpp): each operation lane by lane, as the scalar one, so
/// each lane rounds as the scalar law does. QuadLanes.hpp has the same operations on four lanes
/// (AVX2). HYDROTEX_DOUBLE_LANES is defined where they exist.

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>

namespace hydrotex::detail {

struct DoubleLanes {
  static constexpr unsigned kWidth = 2;
  __m128d v;
  DoubleLanes() = default;
  explicit DoubleLanes(__m128d lanes) : v(lanes) {}
  DoubleLanes(double both) : v(_mm_set1_pd(both)) {}  // NOLINT: scalars mix in as in the scalar law
  double sum() const { return _mm_cvtsd_f64(_mm_add_sd(v, _mm_unpackhi_pd(v, v))); }
  /// Two floats from `p`, widened.
  static DoubleLanes loadFloats(const float* p) {
    return DoubleLanes(_mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)))));
  }
  static DoubleLanes loadDoubles(const double* p) { return DoubleLanes(_mm_loadu_pd(p)); }
  /// Lane k from p[k * stride] (floats), widened.
  static DoubleLanes loadFloatsStrided(const float* p, unsigned stride) {
    return DoubleLanes(_mm_set_pd(double(p[stride]), double(p[0])));
  }
  /// All bits set in the lanes whose bit is set in `bits` (bit k: lane k), none elsewhere.
  static DoubleLanes maskOf(int bits) {
    return DoubleLanes(_mm_castsi128_pd(_mm_set_epi64x(bits & 2 ? -1 : 0, bits & 1 ? -1 : 0)));
  }
  /// 1 in the first `count` lanes, 0 in the others.
  static DoubleLanes firstLanes(unsigned count) {
    return DoubleLanes(_mm_set_pd(count > 1 ? 1.0 : 0.0, count > 0 ? 1.0 : 0.0));
  }
};
inline DoubleLanes operator+(DoubleLanes a, DoubleLanes b) { return DoubleLanes(_mm_add_pd(a.v, b.v)); }
inline DoubleLanes operator-(DoubleLanes a, DoubleLanes b) { return DoubleLanes(_mm_sub_pd(a.v, b.v)); }
inline DoubleLanes operator*(DoubleLanes a, DoubleLanes b) { return DoubleLanes(_mm_mul_pd(a.v, b.v)); }
inline DoubleLanes operator/(DoubleLanes a, DoubleLanes b) { return DoubleLanes(_mm_div_pd(a.v, b.v)); }
inline DoubleLanes operator-(DoubleLanes a) { return DoubleLanes(_mm_xor_pd(a.v, _mm_set1_pd(-0.0))); }
inline DoubleLanes& operator+=(DoubleLanes& a, DoubleLanes b) { return a = a + b; }
inline DoubleLanes& operator-=(DoubleLanes& a, DoubleLanes b) { return a = a - b; }
inline DoubleLanes selectPositive(DoubleLanes x, double positive, double otherwise) {
  const __m128d mask = _mm_cmpgt_pd(x.v, _mm_setzero_pd());
  return DoubleLanes(_mm_or_pd(_mm_and_pd(mask, _mm_set1_pd(positive)), _mm_andnot_pd(mask, _mm_set1_pd(otherwise))));
}
inline DoubleLanes absolute(DoubleLanes x) { return DoubleLanes(_mm_andnot_pd(_mm_set1_pd(-0.0), x.v)); }
inline DoubleLanes squareRoot(DoubleLanes x) { return DoubleLanes(_mm_sqrt_pd(x.v)); }
inline DoubleLanes maximum(DoubleLanes a, DoubleLanes b) { return DoubleLanes(_mm_max_pd(a.v, b.v)); }
/// b where a is not < b (a NaN in a gives b), as a < b ? a : b lane by lane.
inline DoubleLanes minimum(DoubleLanes a, DoubleLanes b) { return DoubleLanes(_mm_min_pd(a.v, b.v)); }
/// x clamped to [0, 1] lane by lane.
inline DoubleLanes clampUnit(DoubleLanes x) {
  return DoubleLanes(_mm_min_pd(_mm_max_pd(x.v, _mm_setzero_pd()), _mm_set1_pd(1.0)));
}
/// All bits set in the lanes where x > 0, none elsewhere (for select).
inline DoubleLanes positiveMask(DoubleLanes x) { return DoubleLanes(_mm_cmpgt_pd(x.v, _mm_setzero_pd())); }
/// Bit k set where lane k of x is > 0.
inline int positiveLanes(DoubleLanes x) { return _mm_movemask_pd(positiveMask(x).v); }
/// Bit k set where lane k of `mask` (positiveMask) is set.
inline int maskLanes(DoubleLanes mask) { return _mm_movemask_pd(mask.v); }
/// All bits set in the lanes where a < b, none elsewhere (nor where either is NaN).
inline DoubleLanes lessMask(DoubleLanes a, DoubleLanes b) { return DoubleLanes(_mm_cmplt_pd(a.v, b.v)); }
/// a where `mask` (positiveMask) is set, b elsewhere.
inline DoubleLanes select(DoubleLanes mask, DoubleLanes a, DoubleLanes b) {
  return DoubleLanes(_mm_or_pd(_mm_and_pd(mask.v, a.v), _mm_andnot_pd(mask.v, b.v)));
}

}  // namespace hydrotex::detail

#define HYDROTEX_DOUBLE_LANES 1
#endif
