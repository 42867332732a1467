// SPDX-License-Identifier: Zlib
#pragma once
/// @file CutCornerLanes.hpp
/// Private to core: the exact path's triangles that a flat water line cuts (PolyhedralFlatSums.hpp),
/// several at a time in SIMD lanes. A cut triangle adds the triangle at its odd corner (the one
/// under when one is, the one dry when two are), signed; its moments take about 90 operations,
/// which dominate a fine mesh's query (Wigley hull of 4,222 triangles floating: 264 of the 1,115
/// triangles its crossed leaves hold are cut, and they took about half of its 13.5 us). The law
/// is written once for a number type (addCutCorner): double for one triangle, DoubleLanes (SSE2)
/// or QuadLanes (AVX2, CutCornerLanesAvx2.cpp) for two or four, each lane with the same
/// operations in the same order, so a lane rounds as the scalar law does; only the order of the
/// sums over triangles differs.
///
/// The AVX2 unit is compiled with -mavx2, so it must not emit any function another unit also
/// emits: the batch and the sums are plain data, and everything instantiated there depends on
/// the lane type, which has internal linkage.

#include <cstdint>

#include "DoubleLanes.hpp"

namespace hydrotex::detail {

/// The 10 upward-weighted body moments of a wetted surface (PolyhedralFlatSums.hpp) in a number
/// type T: Sum |A| (m^2), Sum a_up (m^2), Sum p a_up (m^3), Sum p p^T a_up (m^4; xx, xy, xz, yy,
/// yz, zz), a_up the upward (world y) component of an element's area vector.
template <class T>
struct UpwardSums {
  T sumArea = T(0.0);
  T sumAUp = T(0.0);
  T sumPAUp[3] = {T(0.0), T(0.0), T(0.0)};
  T sumPPAUp[6] = {T(0.0), T(0.0), T(0.0), T(0.0), T(0.0), T(0.0)};
};

/// Adds the corner triangle a, q = a + s (b - a), r = a + t (c - a) of the triangle (a, b, c)
/// (body frame, m; counter-clockwise seen from outside) whose area is `area` and whose a_up is
/// `aUp`, both already times the sign (+1 adds the corner, -1 takes it away): the corner lies in
/// the triangle's plane with its orientation, so its area and a_up are s t times the whole's (no
/// cross product or square root). Its centroid and mean p p^T come from the edge midpoints (exact
/// for quadratics: Strang and Fix 1973, table 4.1), as triangleConstants' do.
template <class T>
inline void addCutCorner(UpwardSums<T>& m, const T a[3], const T b[3], const T c[3], T s, T t, T area, T aUp) {
  const T scale = s * t;
  const T cornerUp = scale * aUp;
  m.sumArea += scale * area;
  m.sumAUp += cornerUp;
  const T third = T(1.0 / 3.0), half = T(0.5);
  T mid[3][3];  // edge midpoints of (a, q, r)
  for (int i = 0; i < 3; ++i) {
    const T q = a[i] + (b[i] - a[i]) * s;
    const T r = a[i] + (c[i] - a[i]) * t;
    m.sumPAUp[i] += ((a[i] + q + r) * third) * cornerUp;
    mid[0][i] = half * (a[i] + q);
    mid[1][i] = half * (q + r);
    mid[2][i] = half * (r + a[i]);
  }
  static constexpr int kPair[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  for (int pair = 0; pair < 6; ++pair) {
    const int i = kPair[pair][0], j = kPair[pair][1];
    m.sumPPAUp[pair] += ((mid[0][i] * mid[0][j] + mid[1][i] * mid[1][j] + mid[2][i] * mid[2][j]) * third) * cornerUp;
  }
}

/// Cut triangles gathered for the lanes, in columns: each turned (keeping its orientation) so
/// that its odd corner comes first, with the depths at its corners (m, > 0 under) and its area
/// and a_up times the sign. `count` is kept a multiple of four by pad(): a padded entry (depths
/// 1, 0, 0 and zero area) adds zeros.
struct CutCornerBatch {
  static constexpr unsigned kCapacity = 32;
  double corner[9][kCapacity];  ///< odd corner a (x, y, z), then b, then c (m, body frame)
  double depth[3][kCapacity];   ///< at a, b, c (m)
  double area[kCapacity];       ///< sign |A| (m^2)
  double aUp[kCapacity];        ///< sign a_up (m^2)
  unsigned count = 0;

  /// Fills the last lanes of a group of four with entries that add zeros.
  void pad() {
    for (; count % 4 != 0; ++count) {
      for (auto& column : corner) column[count] = 0.0;
      depth[0][count] = 1.0;
      depth[1][count] = depth[2][count] = 0.0;
      area[count] = aUp[count] = 0.0;
    }
  }
};

/// Adds the batch's corners (count a multiple of L::kWidth) to `out`, L::kWidth at a time.
template <class L>
inline void sumCutCornerLanes(const CutCornerBatch& in, UpwardSums<double>& out) {
  UpwardSums<L> lanes;
  for (unsigned e = 0; e < in.count; e += L::kWidth) {
    L p[3][3];
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i) p[c][i] = L::loadDoubles(in.corner[3 * c + i] + e);
    const L da = L::loadDoubles(in.depth[0] + e), db = L::loadDoubles(in.depth[1] + e),
            dc = L::loadDoubles(in.depth[2] + e);
    addCutCorner(lanes, p[0], p[1], p[2], da / (da - db), da / (da - dc), L::loadDoubles(in.area + e),
                 L::loadDoubles(in.aUp + e));
  }
  out.sumArea += lanes.sumArea.sum();
  out.sumAUp += lanes.sumAUp.sum();
  for (int i = 0; i < 3; ++i) out.sumPAUp[i] += lanes.sumPAUp[i].sum();
  for (int pair = 0; pair < 6; ++pair) out.sumPPAUp[pair] += lanes.sumPPAUp[pair].sum();
}

/// Adds the batch's corners to `out` one by one (the scalar law; where there are no lanes).
inline void sumCutCornersOneByOne(const CutCornerBatch& in, UpwardSums<double>& out) {
  for (unsigned e = 0; e < in.count; ++e) {
    double p[3][3];
    for (int c = 0; c < 3; ++c)
      for (int axis = 0; axis < 3; ++axis) p[c][axis] = in.corner[3 * c + axis][e];
    const double da = in.depth[0][e], db = in.depth[1][e], dc = in.depth[2][e];
    addCutCorner<double>(out, p[0], p[1], p[2], da / (da - db), da / (da - dc), in.area[e], in.aUp[e]);
  }
}

/// sumCutCornerLanes in AVX2 lanes (CutCornerLanesAvx2.cpp); false, having added nothing, where
/// the processor or the build has no AVX2 or HYDROTEX_DISABLE_AVX2 is set.
bool sumCutCornersAvx2(const CutCornerBatch& in, UpwardSums<double>& out);

}  // namespace hydrotex::detail
