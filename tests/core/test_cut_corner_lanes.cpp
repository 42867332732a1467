// SPDX-License-Identifier: Zlib
// The exact path's cut triangles in SIMD lanes (core's private CutCornerLanes.hpp): the corner
// triangle a, a + s (b - a), a + t (c - a) of each cut triangle, summed by the scalar law, the
// SSE2 lanes and the AVX2 lanes where the processor has them, against the corner's moments from
// another closed form (cross product, and the mean of p p^T over a triangle from its vertex a
// and edges X, Y: a a^T + (a (X+Y)^T + (X+Y) a^T) / 3 + (X X^T + Y Y^T) / 6 + (X Y^T + Y X^T) / 12).
// And the prepared path's wet triangles under waves (WetTriangleClipping.hpp) in a batch, summed
// one by one and in lanes, against the scalar law triangle by triangle.
#include <catch2/catch.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <array>
#include <random>
#include <vector>

#include "hydrostatics/CutCornerLanes.hpp"       // private to core (core/src)
#include "hydrostatics/WetTriangleClipping.hpp"  // private to core (core/src)

using namespace hydrotex;

namespace {

/// One cut triangle: corners (odd corner first), depths, sign, and the up direction.
struct Cut {
  Eigen::Vector3d a, b, c;
  double da, db, dc, sign;
};

/// The reference sums of the corners of `cuts` under `up`, and a bound of their terms' sizes.
detail::UpwardSums<double> reference(const std::vector<Cut>& cuts, const Eigen::Vector3d& up, double& scale) {
  detail::UpwardSums<double> sums;
  scale = 0.0;
  for (const Cut& cut : cuts) {
    const double s = cut.da / (cut.da - cut.db), t = cut.da / (cut.da - cut.dc);
    const Eigen::Vector3d x = s * (cut.b - cut.a), y = t * (cut.c - cut.a);
    const Eigen::Vector3d areaVector = 0.5 * cut.sign * x.cross(y);
    const double aUp = up.dot(areaVector);
    const Eigen::Vector3d centroid = cut.a + (x + y) / 3.0;
    const Eigen::Vector3d e = x + y;
    const Eigen::Matrix3d meanPP = cut.a * cut.a.transpose() + (cut.a * e.transpose() + e * cut.a.transpose()) / 3.0 +
                                   (x * x.transpose() + y * y.transpose()) / 6.0 +
                                   (x * y.transpose() + y * x.transpose()) / 12.0;
    sums.sumArea += cut.sign * areaVector.norm();
    sums.sumAUp += aUp;
    for (int i = 0; i < 3; ++i) sums.sumPAUp[i] += centroid[i] * aUp;
    static constexpr int kPair[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (int pair = 0; pair < 6; ++pair) sums.sumPPAUp[pair] += meanPP(kPair[pair][0], kPair[pair][1]) * aUp;
    // |p| <= reach and |p p^T| <= reach^2 for p in the triangle (reach >= 1): each sum's terms.
    const double reach = 1.0 + cut.a.norm() + cut.b.norm() + cut.c.norm();
    scale += reach * reach * (std::abs(aUp) + areaVector.norm());
  }
  return sums;
}

/// `cuts` in a batch (their whole area and a_up times the sign, as the exact path fills it).
detail::CutCornerBatch batchOf(const std::vector<Cut>& cuts, const Eigen::Vector3d& up) {
  detail::CutCornerBatch batch;
  for (const Cut& cut : cuts) {
    const unsigned e = batch.count++;
    const Eigen::Vector3d corners[3] = {cut.a, cut.b, cut.c};
    const double depths[3] = {cut.da, cut.db, cut.dc};
    for (int c = 0; c < 3; ++c) {
      for (int axis = 0; axis < 3; ++axis) batch.corner[3 * c + axis][e] = corners[c][axis];
      batch.depth[c][e] = depths[c];
    }
    const Eigen::Vector3d areaVector = 0.5 * (cut.b - cut.a).cross(cut.c - cut.a);
    batch.area[e] = cut.sign * areaVector.norm();
    batch.aUp[e] = cut.sign * up.dot(areaVector);
  }
  batch.pad();
  return batch;
}

void requireNear(const detail::UpwardSums<double>& got, const detail::UpwardSums<double>& want, double scale) {
  // The same terms by another formula and in another order: 1e-12 of a bound of the terms'
  // sizes is ~5000 ulps, far above the rounding of the sums and far below any error of the law.
  const auto near = [&](double x, double y) { return std::abs(x - y) <= 1e-12 * scale; };
  CHECK(near(got.sumArea, want.sumArea));
  CHECK(near(got.sumAUp, want.sumAUp));
  for (int i = 0; i < 3; ++i) CHECK(near(got.sumPAUp[i], want.sumPAUp[i]));
  for (int pair = 0; pair < 6; ++pair) CHECK(near(got.sumPPAUp[pair], want.sumPPAUp[pair]));
}

}  // namespace

TEST_CASE("cut triangles' corners: scalar law and SIMD lanes against another closed form", "[hydrostatics][exact][lanes]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Vector3d up = Eigen::Vector3d(0.1, 0.97, -0.2).normalized();
  // Batches of 1 to 32 cut triangles (padding to four lanes: 1, 2, 3 entries added), one or two
  // corners under, with random signs and sizes up to 2 m about points up to 3 m away.
  for (unsigned size = 1; size <= detail::CutCornerBatch::kCapacity; ++size) {
    std::vector<Cut> cuts;
    for (unsigned k = 0; k < size; ++k) {
      Cut cut;
      cut.a = 3.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      cut.b = cut.a + 2.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      cut.c = cut.a + 2.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      // The odd corner on one side of the water line, the others on the other.
      const double sign = unit(rng) > 0.0 ? 1.0 : -1.0;
      cut.da = sign * (0.01 + std::abs(unit(rng)));
      cut.db = -sign * (0.01 + std::abs(unit(rng)));
      cut.dc = -sign * (0.01 + std::abs(unit(rng)));
      cut.sign = sign;
      cuts.push_back(cut);
    }
    double scale = 0.0;
    const detail::UpwardSums<double> want = reference(cuts, up, scale);
    const detail::CutCornerBatch batch = batchOf(cuts, up);
    CAPTURE(size);
    CHECK(batch.count % 4 == 0);
    CHECK(batch.count - size < 4);

    detail::UpwardSums<double> scalar;
    detail::sumCutCornersOneByOne(batch, scalar);  // the padded entries too: they add zeros
    requireNear(scalar, want, scale);
#ifdef HYDROTEX_DOUBLE_LANES
    detail::UpwardSums<double> pairs;
    detail::sumCutCornerLanes<detail::DoubleLanes>(batch, pairs);
    requireNear(pairs, want, scale);
#endif
    detail::UpwardSums<double> quads;
    if (detail::sumCutCornersAvx2(batch, quads)) requireNear(quads, want, scale);
  }
}

TEST_CASE("wet triangles under waves: the batch, one by one and in SIMD lanes, against the scalar law",
          "[hydrostatics][exact][lanes][waves]") {
  // 100 triangles with random corners and depths (some wholly wet, some wholly dry, most cut):
  // each clipped and added by the scalar law (addClippedWetTriangle), and the same through a batch
  // of 32 (batchClippedWetTriangle: flushed when full, then at the end). One by one, the batch adds
  // the same wet parts in the same order, so the sums are equal to the bit; in lanes only the order
  // of the sums differs: within 1e-12 of a bound of the terms' sizes.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<std::array<detail::SurfaceVertex, 3>> triangles;
  double scale = 0.0;
  for (int k = 0; k < 100; ++k) {
    std::array<detail::SurfaceVertex, 3> t;
    const Eigen::Vector3d a = 3.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    double reach = 1.0 + a.norm();
    for (detail::SurfaceVertex& v : t) {
      const Eigen::Vector3d p = a + Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      v = {p.x(), p.y(), p.z(), 0.5 * unit(rng) + (k % 5 == 0 ? 1.0 : k % 7 == 0 ? -1.0 : 0.0)};
      reach += p.norm() + std::abs(v.depth);
    }
    scale += reach * reach * reach * reach;
    triangles.push_back(t);
  }
  const auto run = [&](bool lanes) {
    detail::WettedSums sums;
    detail::WetTriangleBatch batch;
    for (const auto& t : triangles) {
      const detail::SurfaceVertex* p[3] = {&t[0], &t[1], &t[2]};
      if (lanes) {
        detail::batchClippedWetTriangle(batch, sums, p);
      } else {
        detail::addClippedWetTriangle(sums, p);
      }
    }
    if (batch.count > 0) detail::flushWetTriangles(batch, sums);
    return sums;
  };
  const detail::WettedSums want = run(false);
  const detail::WettedSums got = run(true);
  CHECK(want.wettedArea > 1.0);  // many triangles wet
  const auto fields = [](const detail::WettedSums& s) {
    return std::vector<double>{s.sumDA[0], s.sumDA[1], s.sumDA[2], s.sumDxA[0], s.sumDxA[1], s.sumDxA[2],
                               s.sumDXAy, s.sumDZAy, s.sumYB, s.sumAy, s.sumXAy, s.sumZAy,
                               s.sumXXAy, s.sumXZAy, s.sumZZAy, s.wettedArea};
  };
  const std::vector<double> w = fields(want), g = fields(got);
  for (std::size_t i = 0; i < w.size(); ++i) {
    CAPTURE(i, w[i], g[i]);
    CHECK(std::abs(w[i] - g[i]) <= 1e-12 * scale);
  }
  // One by one: the same wet parts in the same order, the same bits.
  detail::WettedSums oneByOne, direct;
  detail::WetTriangleBatch batch;
  for (const auto& t : triangles) {
    const detail::SurfaceVertex* p[3] = {&t[0], &t[1], &t[2]};
    if (batch.count + 2 > detail::WetTriangleBatch::kCapacity) {
      batch.pad();
      detail::sumWetTrianglesOneByOne(batch, oneByOne);
      batch.count = 0;
    }
    detail::forEachWetPart(p, [&](const detail::SurfaceVertex& a, const detail::SurfaceVertex& b,
                                  const detail::SurfaceVertex& c, double da, double db, double dc) {
      batch.add(a, b, c, da, db, dc);
      detail::addWetTriangle(direct, a, b, c, da, db, dc);
    });
  }
  batch.pad();
  detail::sumWetTrianglesOneByOne(batch, oneByOne);
  CHECK(fields(oneByOne) == fields(direct));
  CHECK(fields(direct) == w);
#ifdef HYDROTEX_DOUBLE_LANES
  detail::WettedSums pairs;
  detail::WetTriangleBatch all;
  for (const auto& t : triangles) {
    const detail::SurfaceVertex* p[3] = {&t[0], &t[1], &t[2]};
    if (all.count + 2 > detail::WetTriangleBatch::kCapacity) {
      all.pad();
      detail::sumWetTriangleLanes<detail::DoubleLanes>(all, pairs);
      all.count = 0;
    }
    detail::forEachWetPart(p, [&](const detail::SurfaceVertex& a, const detail::SurfaceVertex& b,
                                  const detail::SurfaceVertex& c, double da, double db, double dc) {
      all.add(a, b, c, da, db, dc);
    });
  }
  all.pad();
  detail::sumWetTriangleLanes<detail::DoubleLanes>(all, pairs);
  const std::vector<double> p2 = fields(pairs);
  for (std::size_t i = 0; i < w.size(); ++i) CHECK(std::abs(w[i] - p2[i]) <= 1e-12 * scale);
#endif
}
