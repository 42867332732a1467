// SPDX-License-Identifier: Zlib
/// @file PolyhedralHydrostaticsWaves.cpp
/// The exact path's hierarchy under waves (issue 19 item 2): a prepared mesh's triangle nodes are
/// classified against local quadratic models of the surface over their footprints, as the texture
/// path's tiles are (LocalSurfaceModel.hpp, the same models, bounds and wave part). A node wholly
/// under its model adds its summed constants and their wave part, O(1); one wholly above is
/// skipped (a node too wide for a model within the tolerance is still skipped when wholly over a
/// model with its wider bound, its own or a wider node's above it); a leaf the water line may
/// cross goes triangle by triangle under the leaf's model, or, where the leaf is too wide for
/// one, under a model for each run of its triangles whose footprint allows one (a triangle too
/// wide alone is split into n^2 similar pieces, or, where fewer, a sliver into 2k - 1 pieces of
/// k strips across its length, each piece with its own model). A triangle (or piece) wholly
/// under its model adds its constants to the model's wave part; one the water line crosses is
/// clipped where the model's depth, taken linear between corners, changes sign
/// (WetTriangleClipping.hpp), after a split into m^2 pieces so fine that taking the model linear
/// between their corners moves no depth by more than kExactWaveClipError. So a coarse
/// mesh (a box's 1 m faces) sees the waves across its faces, which the plain exact path's depths,
/// linear between the mesh's own vertices, do not (Advisor.hpp: exactLinearizationError), and a
/// fine one (a ship's hull) pays per triangle only along its water line.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "bake/TexelPosing.hpp"
#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrostatics/LocalSurfaceModel.hpp"
#include "hydrostatics/PolyhedralFlatSums.hpp"
#include "hydrostatics/TriangleQuadrature.hpp"
#include "hydrostatics/WetTriangleClipping.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex::detail {
namespace {

using Moments = TextureHydrostatics::Moments;

/// Adds a wholly wet triangle's moments, from its constants, to `m`.
void addMoments(Moments& m, const TriangleConstants& k) {
  addTriangleMoments(m, k.area, k.areaVector, k.centroid, k.secondMoments);
}

/// Adds a node's summed moments to `m`.
void addMoments(Moments& m, const NodeSums& node) {
  m.sumArea += node.area;
  for (int a = 0; a < 3; ++a) {
    m.sumA[a] += node.areaVector[a];
    for (int i = 0; i < 3; ++i) m.sumPA[i][a] += node.firstMoments[i][a];
    for (int pair = 0; pair < 6; ++pair) m.sumPPA[pair][a] += node.secondMoments[pair][a];
  }
}

/// A triangle's corners in the body frame and posed (frame o), in the mesh's orientation.
struct Corners {
  Eigen::Vector3d body[3];
  Eigen::Vector3d posed[3];
};

/// The corners of piece (i, j, up) of `whole` split into n^2 similar pieces: lattice points
/// L(i, j) = c0 + i/n (c1 - c0) + j/n (c2 - c0); an upward piece is L(i,j), L(i+1,j), L(i,j+1),
/// a downward one L(i+1,j), L(i+1,j+1), L(i,j+1) (both keep the whole's orientation).
Corners piece(const Corners& whole, int n, int i, int j, bool up) {
  const int lattice[2][3][2] = {{{1, 0}, {1, 1}, {0, 1}}, {{0, 0}, {1, 0}, {0, 1}}};
  const double inv = 1.0 / n;
  Corners out;
  for (int c = 0; c < 3; ++c) {
    const double s = (i + lattice[up][c][0]) * inv, t = (j + lattice[up][c][1]) * inv;
    out.body[c] = whole.body[0] + s * (whole.body[1] - whole.body[0]) + t * (whole.body[2] - whole.body[0]);
    out.posed[c] = whole.posed[0] + s * (whole.posed[1] - whole.posed[0]) + t * (whole.posed[2] - whole.posed[0]);
  }
  return out;
}

/// Calls f(piece) for each of the n^2 pieces of `whole`.
template <typename F>
void forEachPiece(const Corners& whole, int n, F&& f) {
  if (n == 1) {
    f(whole);
    return;
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n - i; ++j) {
      f(piece(whole, n, i, j, true));
      if (j < n - i - 1) f(piece(whole, n, i, j, false));
    }
}

/// Calls f(piece) for each of the 2k - 1 pieces of `whole` cut into k strips parallel to the edge
/// opposite corner `apex`: the lines at i/k of the way from the apex to that edge (i = 1..k-1)
/// cut it into a triangle at the apex and k - 1 trapezoids, each halved along a diagonal. A
/// sliver (a cylinder's side: 3 m by 10 cm) cut across its length gets pieces as short as
/// the lattice's n^2 would with k = n pieces a side, in 2n - 1 pieces instead of n^2. Every
/// piece keeps the whole's orientation.
template <typename F>
void forEachStripPiece(const Corners& whole, int apex, int k, F&& f) {
  const int q = (apex + 1) % 3, r = (apex + 2) % 3;
  const double inv = 1.0 / k;
  // Corner `slot` of `out`: the point i/k of the way from the apex to corner `to`.
  const auto at = [&](int to, int i, Corners& out, int slot) {
    const double s = i * inv;
    out.body[slot] = whole.body[apex] + s * (whole.body[to] - whole.body[apex]);
    out.posed[slot] = whole.posed[apex] + s * (whole.posed[to] - whole.posed[apex]);
  };
  for (int i = 0; i < k; ++i) {
    Corners outer;  // (Q_i, Q_i+1, R_i+1): at i = 0 the tip, similar to the whole
    at(q, i, outer, 0);
    at(q, i + 1, outer, 1);
    at(r, i + 1, outer, 2);
    f(outer);
    if (i == 0) continue;
    Corners inner;  // (Q_i, R_i+1, R_i)
    at(q, i, inner, 0);
    at(r, i + 1, inner, 1);
    at(r, i, inner, 2);
    f(inner);
  }
}

/// The radius (m) of posed corners' horizontal footprint about their horizontal centroid
/// (`cx`, `cz`, local m).
double footprintRadius(const Corners& c, double& cx, double& cz) {
  cx = (c.posed[0].x() + c.posed[1].x() + c.posed[2].x()) / 3.0;
  cz = (c.posed[0].z() + c.posed[1].z() + c.posed[2].z()) / 3.0;
  double radius = 0.0;
  for (const Eigen::Vector3d& w : c.posed)
    radius = std::max(radius, (w.x() - cx) * (w.x() - cx) + (w.z() - cz) * (w.z() - cz));
  return std::sqrt(radius);
}

/// The longest horizontal (x, z) edge of posed corners, squared (m^2).
double longestHorizontalEdgeSquared(const Corners& c) {
  double longest = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& a = c.posed[k];
    const Eigen::Vector3d& b = c.posed[(k + 1) % 3];
    longest = std::max(longest, (a.x() - b.x()) * (a.x() - b.x()) + (a.z() - b.z()) * (a.z() - b.z()));
  }
  return longest;
}

// Most pieces per side of a triangle split for its models, and of a piece split for clipping
// (a counting probe: the 1 m box under peers_waves' waves took 239 model pieces a query over
// its 11 triangles below the crests, about 22 each, so n = 4 or 5).
constexpr int kMaxModelSplit = 16;
constexpr int kMaxClipSplit = 16;
// Most strips a triangle is cut into for its models (forEachStripPiece): as many pieces as the
// lattice's kMaxModelSplit^2 would take at most.
constexpr int kMaxModelStrips = kMaxModelSplit * kMaxModelSplit / 2;
// The share of the model tolerance a strip's piece may take. At the whole tolerance a 3 m log
// (test_polyhedral_hydrostatics_waves) under bench_peers' swell was 8.3e-5 V and 1.4e-4 rho g V
// off the per-texel answer where the lattice's n^2 sliver pieces (each 1/n as wide as a strip's,
// and so far inside their bound) had been 1.4e-5 V and 2.6e-5; at half, 5.3e-6 V and 1.5e-5,
// for 1.25x the strips' cost (and 4.8x under the lattice's: 304 against 1,460 us a query).
constexpr double kStripToleranceShare = 0.5;
// A node too wide for a model within the tolerance asks a model with a wider bound to find it
// wholly over the surface, unless a wider node above it has one and its footprint reaches more
// than this share of that node's: then it is tested against that model. Probe, 100 poses under
// bench_peers' swell, two passes (2-core reference machine): a model per node (1.0) against
// 0.5 / 0.0, us a query: Wigley hull 113.7-115.4 against 109.0-110.6 / 131.6-134.4 (models
// 480 -> 306 / 485, its nodes opened more at 0), ship 571.5-574.5 against 546.9-547.9 /
// 528-534, the 17,160-face sphere 69.8-70.1 against 67.0-67.9 / 66.3-67.7; box unchanged.
constexpr double kWideRefresh = 0.5;

}  // namespace

std::optional<Expected<HydrostaticsResult>> wavePolyhedralHydrostatics(const Mesh& mesh,
                                                                       const PreparedTriangles& prepared,
                                                                       const LiquidSurface& surface,
                                                                       const HydrostaticsQuery& query,
                                                                       ExactWaveWork* work,
                                                                       std::optional<SurfaceJetGrid>* keep) {
  const std::optional<SurfaceSmoothness> smooth = surface.smoothness(query.time);
  if (!smooth || !(smooth->third >= 0.0) || !(smooth->fourth >= 0.0) || !std::isfinite(smooth->third) ||
      !std::isfinite(smooth->fourth) || prepared.nodes.empty())
    return std::nullopt;
  const Eigen::Matrix3d& r = query.pose.rotation;
  const Eigen::Vector3d& t = query.pose.translation;
  // The frame origin, force model and water plane of the texture path under waves:
  // o = (t_x, h(x_G, z_G), t_z), pressure sums, the stiffness about the plane through o.
  const Eigen::Vector3d centerOfMass = query.pose.apply(query.centerOfMass);
  const double originHeight = surface.surfaceHeight(centerOfMass.x(), centerOfMass.z(), query.time);
  if (!std::isfinite(originHeight))
    return Expected<HydrostaticsResult>(Error{"exact hydrostatics: the liquid surface height is not finite (" +
                                              std::to_string(originHeight) + " m) above the centre of mass"});
  const Eigen::Vector3d origin(t.x(), originHeight, t.z());
  const Eigen::Vector3d offset = t - origin;
  const double highest = surface.heightRange(query.time).second - origin.y();
  const Eigen::Vector3d xRow = r.row(0).transpose(), zRow = r.row(2).transpose();

  const TriangleNode& root = prepared.nodes.front();
  const Eigen::Vector3d rootCenter(root.center[0], root.center[1], root.center[2]);
  const Eigen::Vector3d rootHalf(root.halfExtent[0], root.halfExtent[1], root.halfExtent[2]);
  double lowX, highX, lowZ, highZ;
  axisRange(rootCenter, rootHalf, r, 0, offset.x(), lowX, highX);
  axisRange(rootCenter, rootHalf, r, 2, offset.z(), lowZ, highZ);
  LocalSurfaceModels models(surface, query.time, origin, *smooth, lowX, highX, lowZ, highZ,
                            kExactSurfaceModelTolerance, 0.0, r, offset, keep);
  WettedSums sums;
  bool surfaceFailed = false;  // a corner's height from the surface itself was not finite
  ExactWaveWork done;          // what the walk does (`work`)
  // The wet parts of clipped triangles, summed in lanes a batch at a time (WetTriangleClipping.hpp).
  WetTriangleBatch wetBatch;

  // Clips the triangle `c` where the depth below the model (or, model null, below the surface's own
  // heights at its corners) changes sign, split first so that the model, taken linear between
  // the pieces' corners, moves no depth by more than kExactWaveClipError: the linear
  // interpolant's error on a triangle is at most |E| e^2 / 6 (|E| the model's largest second
  // derivative, e the longest horizontal edge: Sum lambda_i |x - x_i|^2 <= e^2 / 3).
  // `cornerHeights` (may be null): the model's heights at c's corners, already known (addUnder),
  // which an unsplit triangle takes instead of asking the model again.
  auto clip = [&](const Corners& c, const SurfaceModel* model, double curvature, double edgeSquared,
                  const double* cornerHeights = nullptr) {
    int m = 1;
    if (model) {
      const double needed = std::sqrt(edgeSquared * curvature / (6.0 * kExactWaveClipError));
      m = std::clamp(int(std::ceil(needed)), 1, kMaxClipSplit);
    }
    if (m == 1 && cornerHeights) {
      ++done.clippedTriangles;
      SurfaceVertex corner[3];
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d& w = c.posed[k];
        if (!std::isfinite(cornerHeights[k])) surfaceFailed = true;
        corner[k] = {w.x(), w.y(), w.z(), cornerHeights[k] - w.y()};
      }
      const SurfaceVertex* whole[3] = {&corner[0], &corner[1], &corner[2]};
      batchClippedWetTriangle(wetBatch, sums, whole);
      return;
    }
    // The (m + 1)(m + 2) / 2 lattice points L(i, j) = c0 + i/m (c1 - c0) + j/m (c2 - c0), row i
    // holding m + 1 - i of them, each with its depth, then the m^2 pieces between them.
    done.clippedTriangles += std::size_t(m * m);
    if (!model) done.surfaceHeights += std::size_t((m + 1) * (m + 2) / 2);
    SurfaceVertex lattice[(kMaxClipSplit + 1) * (kMaxClipSplit + 2) / 2];
    const double inv = 1.0 / m;
    const Eigen::Vector3d u = (c.posed[1] - c.posed[0]) * inv, v = (c.posed[2] - c.posed[0]) * inv;
    int count = 0;
    for (int i = 0; i <= m; ++i)
      for (int j = 0; j <= m - i; ++j) {
        const Eigen::Vector3d w = c.posed[0] + double(i) * u + double(j) * v;
        const double height = model ? model->at(w.x(), w.z())
                                    : surface.surfaceHeight(w.x() + origin.x(), w.z() + origin.z(), query.time) -
                                          origin.y();
        if (!std::isfinite(height)) surfaceFailed = true;
        lattice[count++] = {w.x(), w.y(), w.z(), height - w.y()};
      }
    const auto at = [&](int i, int j) { return &lattice[i * (m + 1) - i * (i - 1) / 2 + j]; };
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m - i; ++j) {
        const SurfaceVertex* up[3] = {at(i, j), at(i + 1, j), at(i, j + 1)};
        batchClippedWetTriangle(wetBatch, sums, up);
        if (j < m - i - 1) {
          const SurfaceVertex* down[3] = {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
          batchClippedWetTriangle(wetBatch, sums, down);
        }
      }
  };
  // The triangle `c` under `model` (`curvature`: its curvatureNorm()): true when wholly under it
  // (the caller adds its moments to the model's wave part); wholly over, nothing; else clipped.
  // `knownHeights` (may be null): the model's heights at c's corners, already asked.
  auto addUnder = [&](const Corners& c, const SurfaceModel& model, double curvature,
                      const double* knownHeights = nullptr) {
    ++done.pieces;
    const double edgeSquared = longestHorizontalEdgeSquared(c);
    const double margin = curvature * edgeSquared / 6.0;
    double lowest = INFINITY, highestDepth = -INFINITY, height[3];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& w = c.posed[k];
      height[k] = knownHeights ? knownHeights[k] : model.at(w.x(), w.z());
      const double depth = height[k] - w.y();
      lowest = std::min(lowest, depth);
      highestDepth = std::max(highestDepth, depth);
    }
    if (lowest > margin) return true;
    if (highestDepth >= -margin) clip(c, &model, curvature, edgeSquared, height);
    return false;
  };
  // A triangle too wide for one model that lies wholly under the surface (a box's bottom face):
  // true when added, its flat part from its constants and its wave part from the means of the
  // jets' interpolant over n^2 similar pieces, each by the six-point rule of degree 4
  // (TriangleQuadrature.hpp), within sampledBoundOver() of the surface's means. That bound goes
  // as rho^4 where a model's goes as rho^3 with the interpolant's slope and curvature errors
  // besides, so the pieces are wider than a model's (0.26 against 0.165 m under bench_peers'
  // waves) and each costs six heights, not a model. The caller has found it wholly under (its
  // corners deeper under a model over its whole footprint than that model's wider bound and its
  // curvature's reach between them: addAlone's sideOf). False (nothing added) where no
  // n <= kMaxModelSplit meets the tolerance or a height is missing.
  auto addSampled = [&](const Corners& c, const TriangleConstants& k, double radius) {
    int n = 1;
    while (n < kMaxModelSplit && models.sampledBoundOver(radius / n) > models.tolerance()) ++n;
    if (models.sampledBoundOver(radius / n) > models.tolerance()) return false;
    double meanHeight = 0.0, meanHeightPoint[3] = {0.0, 0.0, 0.0}, meanSquaredHeight = 0.0;
    bool found = true;
    forEachPiece(c, n, [&](const Corners& p) {
      for (const TriangleQuadraturePoint& point : kTriangleRuleDegree4) {
        const Eigen::Vector3d posed = point.a * p.posed[0] + point.b * p.posed[1] + point.c * p.posed[2];
        double height;
        if (!models.heightAt(posed.x(), posed.z(), height)) {
          found = false;
          continue;
        }
        const Eigen::Vector3d body = point.a * p.body[0] + point.b * p.body[1] + point.c * p.body[2];
        const double weighted = point.weight * height;
        meanHeight += weighted;
        for (int a = 0; a < 3; ++a) meanHeightPoint[a] += weighted * body[a];
        meanSquaredHeight += weighted * height;
      }
    });
    if (!found) return false;
    // The n^2 pieces have equal areas: the triangle's means are their means' mean.
    const double share = 1.0 / double(n * n);
    for (double& m : meanHeightPoint) m *= share;
    models.addSampledTriangle(k.area, k.areaVector, k.centroid, k.secondMoments, meanHeight * share, meanHeightPoint,
                              meanSquaredHeight * share);
    done.sampledPieces += std::size_t(n * n);
    return true;
  };
  // A triangle with a model of its own, or split into pieces that each have one: n^2 similar
  // pieces, or 2k - 1 strips across its length where that takes fewer (a sliver).
  auto addAlone = [&](const Corners& c, const TriangleConstants& k) {
    double cx, cz;
    const double radius = footprintRadius(c, cx, cz);
    // A model over the whole footprint with its wider bound: the triangle wholly under it is
    // sampled (addSampled); the triangle, or a piece of it, wholly over it is dry and asks no
    // model of its own.
    SurfaceModel whole;
    const bool hasWhole = models.anyOver(ModelFootprint{cx, cz, 0.0, 0.0, radius}, whole);
    const double wholeCurvature = hasWhole ? whole.curvatureNorm() : 0.0;
    // +1 when `p` lies wholly under the surface by that model, -1 wholly over, 0 either: its
    // corners' depths under the model beyond its bound and its sag between them.
    const auto sideOf = [&](const Corners& p) {
      if (!hasWhole) return 0;
      const double margin = wholeCurvature * longestHorizontalEdgeSquared(p) / 6.0 + whole.bound;
      bool under = true, over = true;
      for (const Eigen::Vector3d& w : p.posed) {
        const double depth = whole.at(w.x(), w.z()) - w.y();
        under = under && depth > margin;
        over = over && -depth > margin;
      }
      return under ? 1 : over ? -1 : 0;
    };
    const int side = sideOf(c);
    if (side < 0 || (side > 0 && addSampled(c, k, radius))) return;
    const auto fits = [&](double pieceRadius) { return models.boundOver(pieceRadius) <= models.tolerance(); };
    int n = 1;
    while (n < kMaxModelSplit && !fits(radius / n)) ++n;
    const bool latticeFits = fits(radius / n);
    // The piece under a model over its own footprint (`pieceRadius` about its centroid), or, with no
    // model within the tolerance there, clipped under the surface's own heights at its corners.
    const auto addPiece = [&](const Corners& p, double px, double pz, double pieceRadius, bool isWhole) {
      if (sideOf(p) < 0) return;
      SurfaceModel model;
      if (!models.over(ModelFootprint{px, pz, 0.0, 0.0, pieceRadius}, model)) {
        clip(p, nullptr, 0.0, 0.0);
        return;
      }
      if (!addUnder(p, model, model.curvatureNorm())) return;
      const TriangleConstants pk = isWhole ? k : triangleConstants(p.body[0].data(), p.body[1].data(), p.body[2].data());
      models.addSubmergedTriangle(pk.area, pk.areaVector, pk.centroid, pk.secondMoments, model);
    };
    if (n > 1) {
      // Strips parallel to the shortest horizontal edge (the apex opposite it): the widest ones,
      // at that edge, decide how many (the strips' lengths along the other edges are all 1/k of
      // theirs, their widths grow towards it).
      int shortest = 0;
      double shortestSquared = INFINITY;
      for (int e = 0; e < 3; ++e) {
        const Eigen::Vector3d& a = c.posed[e];
        const Eigen::Vector3d& b = c.posed[(e + 1) % 3];
        const double squared = (a.x() - b.x()) * (a.x() - b.x()) + (a.z() - b.z()) * (a.z() - b.z());
        if (squared < shortestSquared) {
          shortestSquared = squared;
          shortest = e;
        }
      }
      const int apex = (shortest + 2) % 3;
      // The widest strip's two pieces, (Q_k-1, Q, R) and (Q_k-1, R, R_k-1) (forEachStripPiece's
      // last two), are the widest: their footprint radius (m) for k strips.
      const int toQ = (apex + 1) % 3, toR = (apex + 2) % 3;
      const auto widestRadius = [&](int strips) {
        const double s = double(strips - 1) / strips;
        Corners outer, inner;
        outer.posed[0] = inner.posed[0] = c.posed[apex] + s * (c.posed[toQ] - c.posed[apex]);
        outer.posed[1] = c.posed[toQ];
        outer.posed[2] = inner.posed[1] = c.posed[toR];
        inner.posed[2] = c.posed[apex] + s * (c.posed[toR] - c.posed[apex]);
        double px, pz;
        return std::max(footprintRadius(outer, px, pz), footprintRadius(inner, px, pz));
      };
      // Fewer pieces than the lattice's n^2: at most `most` strips; the fewest that fit, by
      // bisection (the widest strip narrows as k grows).
      const int most = latticeFits ? std::min(kMaxModelStrips, n * n / 2) : kMaxModelStrips;
      const auto stripFits = [&](double pieceRadius) {
        return models.boundOver(pieceRadius) <= kStripToleranceShare * models.tolerance();
      };
      if (most >= 2 && stripFits(widestRadius(most))) {
        int low = 1, high = most;  // low does not fit (n > 1), high does
        while (high - low > 1) {
          const int middle = (low + high) / 2;
          (stripFits(widestRadius(middle)) ? high : low) = middle;
        }
        forEachStripPiece(c, apex, high, [&](const Corners& p) {
          double px, pz;
          const double pieceRadius = footprintRadius(p, px, pz);
          addPiece(p, px, pz, pieceRadius, false);
        });
        return;
      }
    }
    if (!latticeFits) {
      // Waves too short for models over kMaxModelSplit^2 pieces: the plain path's way, the
      // surface's own heights at the corners, linear between them (bounded work, not 256 pieces).
      clip(c, nullptr, 0.0, 0.0);
      return;
    }
    forEachPiece(c, n, [&](const Corners& p) {
      const double px = (p.posed[0].x() + p.posed[1].x() + p.posed[2].x()) / 3.0;
      const double pz = (p.posed[0].z() + p.posed[1].z() + p.posed[2].z()) / 3.0;
      addPiece(p, px, pz, radius / n, n == 1);
    });
  };

  const auto& positions = mesh.positions;
  const std::vector<TriangleNode>& nodes = prepared.nodes;
  // The open leaf's distinct vertices (PreparedTriangles::leafVertices), posed once each: a vertex
  // is shared by up to six of the leaf's triangles.
  Eigen::Vector3d leafPosed[kMaxLeafVertices];
  // Poses leaf `node`'s vertices into leafPosed; returns how many.
  auto poseLeaf = [&](std::size_t node) {
    const std::uint32_t first = prepared.vertexBegin[node], end = prepared.vertexBegin[node + 1];
    for (std::uint32_t v = first; v < end; ++v) leafPosed[v - first] = r * positions[prepared.leafVertices[v]] + offset;
    return end - first;
  };
  // Triangle k of the posed leaf into `c`; false when it lies over every crest.
  auto leafTriangle = [&](std::uint32_t k, Corners& c) {
    const Eigen::Vector3i& tri = prepared.triangles[k];
    const std::array<std::uint8_t, 3>& place = prepared.leafCorners[k];
    double lowest = INFINITY;
    for (int a = 0; a < 3; ++a) {
      c.body[a] = positions[std::size_t(tri[a])];
      c.posed[a] = leafPosed[place[std::size_t(a)]];
      lowest = std::min(lowest, c.posed[a].y());
    }
    return lowest < highest;
  };
  // Triangles of a leaf that take one model: their corners, indices and horizontal bounds.
  struct Group {
    Corners corners[kMaxLeafTriangles];  // a group lies within one leaf
    std::uint32_t index[kMaxLeafTriangles];
    int count = 0;
    double lowX = INFINITY, highX = -INFINITY, lowZ = INFINITY, highZ = -INFINITY;
    static double radius(double lx, double hx, double lz, double hz) {
      return 0.5 * std::sqrt((hx - lx) * (hx - lx) + (hz - lz) * (hz - lz));
    }
    static bool fitsAlone(double lx, double hx, double lz, double hz, const LocalSurfaceModels& m) {
      return m.boundOver(radius(lx, hx, lz, hz)) <= m.tolerance();
    }
    bool fits(double lx, double hx, double lz, double hz, const LocalSurfaceModels& m) const {
      return count < int(kMaxLeafTriangles) && fitsAlone(std::min(lowX, lx), std::max(highX, hx), std::min(lowZ, lz), std::max(highZ, hz), m);
    }
    void clear() {
      count = 0;
      lowX = lowZ = INFINITY;
      highX = highZ = -INFINITY;
    }
    void add(const Corners& c, std::uint32_t k, double lx, double hx, double lz, double hz) {
      corners[count] = c;
      index[count++] = k;
      lowX = std::min(lowX, lx);
      highX = std::max(highX, hx);
      lowZ = std::min(lowZ, lz);
      highZ = std::max(highZ, hz);
    }
  };
  // The group's triangles under one model over its footprint (centre of its bounds); its wholly
  // wet ones' moments added about their mean centroid (body frame), under the model expanded
  // there. Empties the group.
  auto flush = [&](Group& g) {
    if (g.count == 0) return;
    const ModelFootprint f{0.5 * (g.lowX + g.highX), 0.5 * (g.lowZ + g.highZ), 0.5 * (g.highX - g.lowX),
                           0.5 * (g.highZ - g.lowZ), Group::radius(g.lowX, g.highX, g.lowZ, g.highZ)};
    SurfaceModel model;
    if (!models.over(f, model)) {
      for (int member = 0; member < g.count; ++member) addAlone(g.corners[member], prepared.constant(g.index[member]));
    } else {
      const double curvature = model.curvatureNorm();
      Moments submerged;
      Eigen::Vector3d body = Eigen::Vector3d::Zero(), posed = Eigen::Vector3d::Zero();
      int under = 0;
      for (int member = 0; member < g.count; ++member) {
        if (!addUnder(g.corners[member], model, curvature)) continue;
        addMoments(submerged, prepared.constant(g.index[member]));
        for (int a = 0; a < 3; ++a) {
          body += g.corners[member].body[a];
          posed += g.corners[member].posed[a];
        }
        ++under;
      }
      if (under > 0) {
        body /= 3.0 * under;
        posed /= 3.0 * under;
        models.addSubmerged(submerged, body, model.recentered(posed.x(), posed.z()));
      }
    }
    g.clear();
  };
  // The model of the widest node open on the walk that has one: it covers the node's subtree
  // (its descendants take it, as the texture path's tiles take their group's) until the walk
  // leaves the subtree at `end`. The parts of the subtree wholly under it are summed and added
  // once, at the end, about the node's centre (where the model is centred), as the texture
  // path sums a unit's submerged tiles (TextureHydrostaticsWaves.cpp): as the node would have
  // been, wholly under, so within the model's bound and WavePart's O(rho^3) first moments over
  // the node's footprint. (Each part expanded about its own centre cost a WavePart::add
  // apiece; summed, bench_peers' queries under waves take 7.2 % fewer instructions on the
  // 17,160-face sphere and 2.9 % on the Wigley hull; the box and the 320-face hull within 0.3 %.)
  struct Covering {
    std::size_t end;
    SurfaceModel model;
    double curvature;         // model.curvatureNorm()
    Eigen::Vector3d center;   // the node's (body frame), below the model's centre
    Moments under;            // the subtree's parts wholly under the model so far
    bool anyUnder = false;
  };
  std::optional<Covering> covering;
  // Adds what the covering model's subtree had wholly under it, and ends the covering.
  const auto endCovering = [&] {
    if (covering->anyUnder) models.addSubmerged(covering->under, covering->center, covering->model);
    covering.reset();
  };
  // The model, with its wider bound, of the nearest node open on the walk that asked one (a node
  // with none within the tolerance): it bounds the surface over the node's subtree too, so a
  // descendant is tested against it for lying wholly over the surface (until the walk leaves the
  // subtree at `end`), and asks a model of its own only when its footprint is under
  // kWideRefresh of the wide model's (its bound then at most an eighth as wide in the
  // third-order term).
  struct Wide {
    std::size_t end;
    SurfaceModel model;
    double radius;
  };
  std::optional<Wide> wide;
  for (std::size_t i = 0; i < nodes.size();) {
    if (covering && i >= covering->end) endCovering();
    if (wide && i >= wide->end) wide.reset();
    const TriangleNode& node = nodes[i];
    ++done.nodes;
    const Eigen::Vector3d center(node.center[0], node.center[1], node.center[2]);
    const Eigen::Vector3d half(node.halfExtent[0], node.halfExtent[1], node.halfExtent[2]);
    double low, high;
    verticalRange(center, half, r, offset.y(), low, high);
    if (low >= highest) {  // above every crest
      i = node.next;
      continue;
    }
    const ModelFootprint f = boxFootprint(center, half, INFINITY, xRow, zRow, offset);
    if (!covering) {
      SurfaceModel model;
      if (models.over(f, model)) {
        covering = Covering{node.next, model, model.curvatureNorm(), center, Moments{}};
      } else {
        // Too wide for a model within the tolerance, but a model with its wider bound still
        // finds a node wholly over the surface (a ship's deck between crests).
        if (!wide || f.radius < kWideRefresh * wide->radius) {
          if (models.anyOver(f, model)) wide = Wide{node.next, model, f.radius};
        }
        if (wide) {
          double modelLow, modelHigh;
          wide->model.range(f.x, f.z, f.reachX, f.reachZ, modelLow, modelHigh);
          if (low >= modelHigh) {
            i = node.next;
            continue;
          }
        }
      }
    }
    if (covering) {
      const SurfaceModel& model = covering->model;
      double modelLow, modelHigh;
      model.range(f.x, f.z, f.reachX, f.reachZ, modelLow, modelHigh);
      if (low >= modelHigh) {
        i = node.next;
        continue;
      }
      if (high <= modelLow) {
        addMoments(covering->under, prepared.sums[i]);
        covering->anyUnder = true;
        i = node.next;
        continue;
      }
    }
    if (node.next != i + 1) {  // an inner node the water line may cross: its children
      ++i;
      continue;
    }
    // A leaf under a covering model: its triangles one by one; when every one of them is wholly
    // under the model, the node's summed moments instead of theirs.
    if (covering) {
      // The wholly wet triangles are listed first, so that a leaf wholly under pays no
      // per-triangle moments. Each vertex asks the model once.
      const std::uint32_t vertices = poseLeaf(i);
      double leafHeight[kMaxLeafVertices];
      for (std::uint32_t v = 0; v < vertices; ++v) leafHeight[v] = covering->model.at(leafPosed[v].x(), leafPosed[v].z());
      std::uint32_t listed[kMaxLeafTriangles], under = 0;
      for (std::uint32_t k = node.begin; k < node.end; ++k) {
        Corners c;
        if (!leafTriangle(k, c)) continue;
        const std::array<std::uint8_t, 3>& place = prepared.leafCorners[k];
        const double heights[3] = {leafHeight[place[0]], leafHeight[place[1]], leafHeight[place[2]]};
        if (addUnder(c, covering->model, covering->curvature, heights)) listed[under++] = k;
      }
      if (under == node.end - node.begin) {
        addMoments(covering->under, prepared.sums[i]);
      } else {
        for (std::uint32_t l = 0; l < under; ++l) addMoments(covering->under, prepared.constant(listed[l]));
      }
      covering->anyUnder = covering->anyUnder || under > 0;
      i = node.next;
      continue;
    }
    // A leaf too wide for one model: its triangles in runs (in the leaf's order) as long as their
    // footprint keeps a model within the tolerance, a model per run; a triangle too wide alone
    // is split (addAlone). On the 162-vertex hull under peers_waves' waves, 145 triangles a query
    // took a model each.
    Group group;
    poseLeaf(i);
    for (std::uint32_t k = node.begin; k < node.end; ++k) {
      Corners c;
      if (!leafTriangle(k, c)) continue;
      double fromX = INFINITY, toX = -INFINITY, fromZ = INFINITY, toZ = -INFINITY;
      for (const Eigen::Vector3d& w : c.posed) {
        fromX = std::min(fromX, w.x());
        toX = std::max(toX, w.x());
        fromZ = std::min(fromZ, w.z());
        toZ = std::max(toZ, w.z());
      }
      if (group.count > 0 && !group.fits(fromX, toX, fromZ, toZ, models)) flush(group);
      if (group.count == 0 && !Group::fitsAlone(fromX, toX, fromZ, toZ, models)) {
        addAlone(c, prepared.constant(k));
        continue;
      }
      group.add(c, k, fromX, toX, fromZ, toZ);
    }
    flush(group);
    i = node.next;
  }
  if (covering) endCovering();
  if (wetBatch.count > 0) flushWetTriangles(wetBatch, sums);
  if (work) {
    done.models = models.interpolations();
    done.jets = models.grid().sampled();
    *work = done;
  }
  if (surfaceFailed)
    return Expected<HydrostaticsResult>(
        Error{"exact hydrostatics: the liquid surface height is not finite at a corner of a wet triangle"});

  models.addFlatPart(sums);
  models.addWavePart(sums);
  sums.setHydrostaticPressure(surface.density() * query.gravity);
  HydrostaticsResult result = finishHydrostatics(sums, origin, surface.density(), query, ForceModel::PressureSums, true);
  if (!std::isfinite(result.submergedVolume) || !result.centerOfBuoyancy.allFinite() || !result.stiffness.allFinite())
    return Expected<HydrostaticsResult>(Error{"exact hydrostatics: non-finite result (a vertex of the mesh is NaN or infinite)"});
  return Expected<HydrostaticsResult>(std::move(result));
}

}  // namespace hydrotex::detail
