// SPDX-License-Identifier: Zlib
#pragma once
// Packed float triples (std::vector<Eigen::Vector3f>: x0 y0 z0 x1 y1 z1 ...) split into
// structure-of-arrays, four triples at a time. Compilers vectorise stride-3 accesses poorly (two
// floats per instruction at best), while a 4x3 transpose is a few shuffles; the per-step pass over
// the textures of a deforming body (TextureMassIntegrator::update) starts with exactly these
// accesses. A plain loop where SSE2 is not available.
#include <algorithm>
#include <cstddef>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hydrotex::detail {

/// Splits `count` packed triples starting at `packed` into x[], y[], z[] (each `count` long), minus
/// (sx, sy, sz) when Shifted. Also asks the cache for the floats `prefetchAhead` past the ones it
/// reads, up to the last of the `available` floats from `packed` (the next block of a pass that
/// splits block by block: a block's short bursts do not last long enough for the hardware
/// prefetcher).
template <bool Shifted>
inline void splitTriples(const float* packed, std::size_t count, float sx, float sy, float sz, float* x, float* y,
                         float* z, std::size_t prefetchAhead, std::size_t available) {
  std::size_t i = 0;
#if defined(__SSE2__)
  const __m128 shiftX = _mm_set1_ps(sx), shiftY = _mm_set1_ps(sy), shiftZ = _mm_set1_ps(sz);
  for (; i + 4 <= count; i += 4) {
    const float* p = packed + 3 * i;
    __builtin_prefetch(packed + std::min(3 * i + prefetchAhead, available - 1));
    const __m128 a = _mm_loadu_ps(p);      // x0 y0 z0 x1
    const __m128 b = _mm_loadu_ps(p + 4);  // y1 z1 x2 y2
    const __m128 c = _mm_loadu_ps(p + 8);  // z2 x3 y3 z3
    // Each row as [r0 r0 r1 r1] and [r2 r2 r3 r3], then lanes 0 and 2 of both.
    const __m128 xLow = a;                                                  // x0 . . x1
    const __m128 xHigh = _mm_shuffle_ps(b, c, _MM_SHUFFLE(1, 1, 2, 2));    // x2 x2 x3 x3
    const __m128 yLow = _mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1));     // y0 y0 y1 y1
    const __m128 yHigh = _mm_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3));    // y2 y2 y3 y3
    const __m128 zLow = _mm_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2));     // z0 z0 z1 z1
    const __m128 zHigh = _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0));    // z2 z2 z3 z3
    __m128 rowX = _mm_shuffle_ps(xLow, xHigh, _MM_SHUFFLE(2, 0, 3, 0));
    __m128 rowY = _mm_shuffle_ps(yLow, yHigh, _MM_SHUFFLE(2, 0, 2, 0));
    __m128 rowZ = _mm_shuffle_ps(zLow, zHigh, _MM_SHUFFLE(2, 0, 2, 0));
    if constexpr (Shifted) {
      rowX = _mm_sub_ps(rowX, shiftX);
      rowY = _mm_sub_ps(rowY, shiftY);
      rowZ = _mm_sub_ps(rowZ, shiftZ);
    }
    _mm_storeu_ps(x + i, rowX);
    _mm_storeu_ps(y + i, rowY);
    _mm_storeu_ps(z + i, rowZ);
  }
#else
  (void)prefetchAhead;  // the plain loop below leaves prefetching to the hardware
  (void)available;
#endif
  for (; i < count; ++i) {
    x[i] = packed[3 * i] - sx;
    y[i] = packed[3 * i + 1] - sy;
    z[i] = packed[3 * i + 2] - sz;
  }
}

}  // namespace hydrotex::detail
