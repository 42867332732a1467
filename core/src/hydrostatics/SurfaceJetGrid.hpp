// SPDX-License-Identifier: Zlib
#pragma once
/// @file SurfaceJetGrid.hpp
/// Private to core: a per-query grid of surface jets (height, slopes, mixed curvature) over a
/// body's horizontal footprint, sampled lazily and interpolated by bicubic Hermite patches, so
/// that the tile hierarchy under waves asks the surface a few dozen times instead of once per
/// texel (a Gerstner height costs a Newton search). Lives on the stack: a query does not allocate.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>

#include "hydrotex/hydrostatics/LiquidSurface.hpp"

namespace hydrotex::detail {

/// Jets sampled on a square grid in a frame translated by `originX`, `originZ` (world), and their
/// bicubic Hermite interpolant with error bounds from the surface's SurfaceSmoothness.
class SurfaceJetGrid {
 public:
  /// Most samples per side: 40 x 40 jets (~60 KiB on the stack, with the cells' polynomials kept).
  static constexpr int kMaxSide = 40;

  /// Covers the local box [lowX, highX] x [lowZ, highZ] (m, relative to the origin) with samples
  /// `spacing` (m) apart, widened when the box would need more than kMaxSide per side.
  SurfaceJetGrid(const LiquidSurface& surface, double time, double originX, double originZ, double lowX,
                 double highX, double lowZ, double highZ, double spacing)
      : surface_(surface), time_(time), originX_(originX), originZ_(originZ), lowX_(lowX), lowZ_(lowZ) {
    const double extent = std::max(highX - lowX, highZ - lowZ);
    spacing_ = std::max(spacing, extent / double(kMaxSide - 1));
    if (!(spacing_ > 0.0)) spacing_ = 1.0;  // a point footprint: one cell
    sideX_ = std::clamp(int(std::ceil((highX - lowX) / spacing_)) + 1, 2, kMaxSide);
    sideZ_ = std::clamp(int(std::ceil((highZ - lowZ) / spacing_)) + 1, 2, kMaxSide);
    std::fill(state_.begin(), state_.begin() + sideX_ * sideZ_, std::uint8_t(kUnsampled));
  }

  /// Sample spacing in use (m).
  double spacing() const { return spacing_; }
  /// Jets asked of the surface so far.
  std::size_t sampled() const { return sampled_; }
  /// The surface and the time (s) its jets are of.
  const LiquidSurface& surface() const { return surface_; }
  double time() const { return time_; }
  /// The frame's origin (m, world x and z): local points are world points less it.
  double originX() const { return originX_; }
  double originZ() const { return originZ_; }
  /// Whether the local point (x, z) (m) lies within the samples, or within `margin` (m) of them
  /// (a point outside is clamped onto the grid's edge, not interpolated).
  bool contains(double x, double z, double margin) const {
    return x >= lowX_ - margin && z >= lowZ_ - margin && x <= lowX_ + (sideX_ - 1) * spacing_ + margin &&
           z <= lowZ_ + (sideZ_ - 1) * spacing_ + margin;
  }

  /// Interpolated height alone (m, world) at the local point (x, z) (m, relative to the origin;
  /// clamped into the grid): the jet's first entry from the same kept cell polynomial as
  /// interpolate(), for a caller that needs no derivatives (drag's patches). False as
  /// interpolate().
  bool height(double x, double z, double& out) {
    int i, j;
    double t, w;
    if (!cell(x, z, i, j, t, w)) return false;
    const CellPolynomial* cellPatch = patch(i, j);
    if (!cellPatch) return false;
    const double(&c)[4][4] = cellPatch->c;
    double q[4];
    for (int k = 0; k < 4; ++k) q[k] = ((c[k][3] * w + c[k][2]) * w + c[k][1]) * w + c[k][0];
    out = ((q[3] * t + q[2]) * t + q[1]) * t + q[0];
    return true;
  }

  /// Interpolated jet at the local point (x, z) (m, relative to the origin; clamped into the
  /// grid), from its cell's polynomial (built once, then kept: patch()). False when a sample the
  /// point needs has no jet (the surface folds, or is not finite), or the point is not finite.
  bool interpolate(double x, double z, SurfaceJet& out) {
    int i, j;
    double t, w;
    if (!cell(x, z, i, j, t, w)) return false;
    const CellPolynomial* cellPatch = patch(i, j);
    if (!cellPatch) return false;
    const double(&c)[4][4] = cellPatch->c;
    // q_k(w) = Sum_l c[k][l] w^l and its first two w-derivatives, by Horner; then the sums over
    // t^k for the jet's six entries (derivatives per cell unit, scaled to metres below).
    double q[4], qw[4], qww[4];
    for (int k = 0; k < 4; ++k) {
      q[k] = ((c[k][3] * w + c[k][2]) * w + c[k][1]) * w + c[k][0];
      qw[k] = (3.0 * c[k][3] * w + 2.0 * c[k][2]) * w + c[k][1];
      qww[k] = 6.0 * c[k][3] * w + 2.0 * c[k][2];
    }
    const double inv = 1.0 / spacing_;
    out.height = ((q[3] * t + q[2]) * t + q[1]) * t + q[0];
    out.slopeX = ((3.0 * q[3] * t + 2.0 * q[2]) * t + q[1]) * inv;
    out.slopeZ = (((qw[3] * t + qw[2]) * t + qw[1]) * t + qw[0]) * inv;
    out.curvatureXX = (6.0 * q[3] * t + 2.0 * q[2]) * inv * inv;
    out.curvatureXZ = ((3.0 * qw[3] * t + 2.0 * qw[2]) * t + qw[1]) * inv * inv;
    out.curvatureZZ = (((qww[3] * t + qww[2]) * t + qww[1]) * t + qww[0]) * inv * inv;
    return true;
  }

  /// A bound (1/m) of the interpolant's curvature, the Frobenius norm of its Hessian, over the
  /// cells that meet the local box [lowX, highX] x [lowZ, highZ] (m): each cell's second
  /// derivatives bounded by the sums of its polynomial's coefficients' magnitudes times their
  /// powers' factors (t, w in [0, 1]). Builds those cells' polynomials (sampling their corners);
  /// infinity when a corner has no jet or the box is not finite.
  double curvatureBound(double lowX, double highX, double lowZ, double highZ) {
    int i0, j0, i1, j1;
    double t, w;
    if (!cell(lowX, lowZ, i0, j0, t, w) || !cell(highX, highZ, i1, j1, t, w)) return INFINITY;
    double bound = 0.0;
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const CellPolynomial* cellPatch = patch(i, j);
        if (!cellPatch) return INFINITY;
        const double(&c)[4][4] = cellPatch->c;
        double tt = 0.0, tw = 0.0, ww = 0.0;  // |p_tt|, |p_tw|, |p_ww| at most
        for (int k = 0; k < 4; ++k)
          for (int l = 0; l < 4; ++l) {
            const double a = std::abs(c[k][l]);
            tt += k * (k - 1) * a;
            tw += k * l * a;
            ww += l * (l - 1) * a;
          }
        bound = std::max(bound, std::sqrt(tt * tt + 2.0 * tw * tw + ww * ww));
      }
    return bound / (spacing_ * spacing_);
  }

  /// Marks the samples that interpolating at the local point (x, z) (m) needs, for sampleMarked().
  void mark(double x, double z) {
    int i, j;
    double t, w;
    if (!cell(x, z, i, j, t, w)) return;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        std::uint8_t& state = state_[std::size_t((j + b) * sideX_ + i + a)];
        if (state == kUnsampled) state = kMarked;
      }
  }

  /// Samples every node not yet sampled (sampleMarked's batches): for a caller that will read the
  /// whole grid (a sphere's rule bounds the curvature over every cell).
  void sampleAll() {
    for (std::size_t k = 0; k < std::size_t(sideX_) * std::size_t(sideZ_); ++k)
      if (state_[k] == kUnsampled) state_[k] = kMarked;
    sampleMarked();
  }

  /// Samples every marked node, row by row in alternating directions, kBatch nodes a call of
  /// LiquidSurface::heightJets: a caller that knows its points beforehand (drag's patches) asks
  /// the surface only for the nodes they need, each started from the one before it (waves).
  void sampleMarked() {
    int indices[kBatch];
    std::size_t count = 0;
    for (int j = 0; j < sideZ_; ++j)
      for (int c = 0; c < sideX_; ++c) {
        const int index = j * sideX_ + (j % 2 == 0 ? c : sideX_ - 1 - c);
        if (state_[std::size_t(index)] != kMarked) continue;
        indices[count++] = index;
        if (count == kBatch) {
          sample<kBatch>(indices, count);
          count = 0;
        }
      }
    if (count > 0) sample<kBatch>(indices, count);
  }

 private:
  // The cell (i, j) holding the local point (x, z), clamped into the grid, and the point's place
  // (t, w) in it (0..1); false for a point that is not finite (int(NaN) is undefined).
  bool cell(double x, double z, int& i, int& j, double& t, double& w) const {
    if (!std::isfinite(x) || !std::isfinite(z)) return false;
    const double gx = std::clamp((x - lowX_) / spacing_, 0.0, double(sideX_ - 1));
    const double gz = std::clamp((z - lowZ_) / spacing_, 0.0, double(sideZ_ - 1));
    i = std::min(int(gx), sideX_ - 2);
    j = std::min(int(gz), sideZ_ - 2);
    t = gx - i;
    w = gz - j;
    return true;
  }

  struct Node {
    double f, fx, fz, fxz;  // height (m relative to nothing: world), slopes, mixed curvature
  };

  // The corners (i + a, j + b) of cell (i, j); false when one has no jet. A cell whose corners
  // are all sampled (most cells: an earlier one sampled them) takes one test of their four
  // states instead of four node() calls.
  bool corners(int i, int j, const Node* (&corner)[2][2]) {
    const std::size_t base = std::size_t(j * sideX_ + i), up = std::size_t(sideX_);
    const std::uint8_t s00 = state_[base], s01 = state_[base + up], s10 = state_[base + 1], s11 = state_[base + 1 + up];
    if ((s00 & s01 & s10 & s11) == kUsable && (s00 | s01 | s10 | s11) == kUsable) {
      corner[0][0] = &nodes_[base];
      corner[0][1] = &nodes_[base + up];
      corner[1][0] = &nodes_[base + 1];
      corner[1][1] = &nodes_[base + 1 + up];
      return true;
    }
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        corner[a][b] = node(i + a, j + b);
        if (!corner[a][b]) return false;
      }
    return true;
  }

  // A cell's bicubic Hermite patch in the power basis, p(t, w) = Sum c[k][l] t^k w^l (t, w in
  // 0..1 across the cell), kept for the last cells asked (consecutive models mostly fall in the
  // same few cells).
  struct CellPolynomial {
    int index = -1;
    double c[4][4];
  };
  // Cells kept, by index modulo this: on bench_peers' box under waves 4, 16 and 64 kept 49, 70
  // and 82 % of the interpolations' cells (callgrind: 59.6, 58.4, 57.8 G instructions against
  // 63.4 G for the Hermite sums at every interpolation).
  static constexpr int kKeptCells = 64;

  // The polynomial of cell (i, j); nullptr when a corner has no jet.
  const CellPolynomial* patch(int i, int j) {
    const int index = j * sideX_ + i;
    CellPolynomial& slot = kept_[std::size_t(index % kKeptCells)];
    if (slot.index == index) return &slot;
    const Node* corner[2][2];
    if (!corners(i, j, corner)) return nullptr;
    // g[alpha][beta]: alpha along x, beta along z, each (value at node 0, slope at node 0, value
    // at node 1, slope at node 1), slopes per cell; the Hermite basis in powers (rows: H00 =
    // 1 - 3t^2 + 2t^3, H10 = t - 2t^2 + t^3, H01 = 3t^2 - 2t^3, H11 = t^3 - t^2): c = M^T g M.
    const double s = spacing_;
    double g[4][4];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const Node& n = *corner[a][b];
        g[2 * a][2 * b] = n.f;
        g[2 * a][2 * b + 1] = s * n.fz;
        g[2 * a + 1][2 * b] = s * n.fx;
        g[2 * a + 1][2 * b + 1] = s * s * n.fxz;
      }
    const auto powers = [](const double (&v)[4], double (&out)[4]) {
      out[0] = v[0];
      out[1] = v[1];
      out[2] = -3.0 * v[0] - 2.0 * v[1] + 3.0 * v[2] - v[3];
      out[3] = 2.0 * v[0] + v[1] - 2.0 * v[2] + v[3];
    };
    double half[4][4];  // M^T g: powers of t by rows of g's z functions
    for (int beta = 0; beta < 4; ++beta) {
      const double column[4] = {g[0][beta], g[1][beta], g[2][beta], g[3][beta]};
      double out[4];
      powers(column, out);
      for (int k = 0; k < 4; ++k) half[k][beta] = out[k];
    }
    for (int k = 0; k < 4; ++k) powers(half[k], slot.c[k]);
    slot.index = index;
    return &slot;
  }

  // The sample (i, j), evaluated on first use; nullptr when the surface gives no jet there.
  const Node* node(int i, int j) {
    const int index = j * sideX_ + i;
    if (state_[std::size_t(index)] == kUnsampled || state_[std::size_t(index)] == kMarked) sampleBlock(i, j);
    return state_[std::size_t(index)] == kUsable ? &nodes_[std::size_t(index)] : nullptr;
  }

  // A node's state: not sampled, sampled (usable), no jet there, marked for sampleMarked().
  enum : std::uint8_t { kUnsampled = 0, kUsable = 1, kUnusable = 2, kMarked = 3 };

  // Samples the unsampled nodes of the kBlock x kBlock block holding (i, j) in one call of
  // LiquidSurface::heightJets, in alternating row directions so that each node is next to the one
  // before it (waves start each search from the last one's rest point: a probe of 400 points 6 cm
  // apart took 120 ns a jet against heightJet()'s 194). Blocks of 2: on bench_peers' box on three waves drag's grid sampled 36 nodes where
  // single nodes took 30, and its drag took 11.2 us against 11.4 (blocks of 4: 64 nodes, 14.8 us).
  static constexpr int kBlock = 2;
  void sampleBlock(int i, int j) {
    const int i0 = i - i % kBlock, j0 = j - j % kBlock;
    const int i1 = std::min(i0 + kBlock, sideX_), j1 = std::min(j0 + kBlock, sideZ_);
    int indices[kBlock * kBlock];
    std::size_t count = 0;
    for (int b = j0; b < j1; ++b)
      for (int c = 0; c < i1 - i0; ++c) {
        const int index = b * sideX_ + ((b - j0) % 2 == 0 ? i0 + c : i1 - 1 - c);
        if (state_[std::size_t(index)] == kUnsampled || state_[std::size_t(index)] == kMarked) indices[count++] = index;
      }
    sample<kBlock * kBlock>(indices, count);
  }

  // Samples the nodes `indices` (in that order, at most `capacity`) in one call of
  // LiquidSurface::heightJets. The capacity is the caller's: GCC zero-fills an array of
  // optionals, and a block's 4 nodes paid for 64 (3.6 KiB a call).
  static constexpr std::size_t kBatch = 64;
  template <std::size_t capacity>
  void sample(const int* indices, std::size_t count) {
    double xs[capacity], zs[capacity];
    std::optional<SurfaceJet> jets[capacity];
    for (std::size_t k = 0; k < count; ++k) {
      xs[k] = originX_ + lowX_ + (indices[k] % sideX_) * spacing_;
      zs[k] = originZ_ + lowZ_ + (indices[k] / sideX_) * spacing_;
    }
    surface_.heightJets(std::span(xs, count), std::span(zs, count), time_, std::span(jets, count));
    sampled_ += count;
    for (std::size_t k = 0; k < count; ++k) {
      const std::optional<SurfaceJet>& jet = jets[k];
      const bool usable = jet && std::isfinite(jet->height) && std::isfinite(jet->slopeX) &&
                          std::isfinite(jet->slopeZ) && std::isfinite(jet->curvatureXZ);
      if (usable) nodes_[std::size_t(indices[k])] = Node{jet->height, jet->slopeX, jet->slopeZ, jet->curvatureXZ};
      state_[std::size_t(indices[k])] = usable ? kUsable : kUnusable;
    }
  }

  const LiquidSurface& surface_;
  double time_, originX_, originZ_, lowX_, lowZ_;
  double spacing_ = 1.0;
  int sideX_ = 2, sideZ_ = 2;
  std::size_t sampled_ = 0;
  std::array<Node, std::size_t(kMaxSide) * kMaxSide> nodes_;
  std::array<std::uint8_t, std::size_t(kMaxSide) * kMaxSide> state_;
  std::array<CellPolynomial, kKeptCells> kept_;  // the cells' polynomials last built (patch())
};

}  // namespace hydrotex::detail

namespace hydrotex::detail {

/// Bounds (m, dimensionless, 1/m) of the error of SurfaceJetGrid's interpolated height, slopes
/// and curvatures for samples `spacing` (m) apart on a surface whose fourth directional
/// derivative is at most `fourth` (1/m^3): the one-dimensional cubic Hermite bounds
/// (s^4/384, sqrt(3)/216 s^3, s^2/12 times the fourth derivative), doubled for the two directions
/// of the tensor product (an estimate: the fifth-order cross terms are left out;
/// test_texture_hydrostatics_waves checks it against the surface).
struct HermiteError {
  double height, slope, curvature;
};
inline HermiteError hermiteError(double spacing, double fourth) {
  const double s2 = spacing * spacing;
  return {2.0 * s2 * s2 / 384.0 * fourth, 2.0 * 0.0080187537387 * s2 * spacing * fourth, 2.0 * s2 / 12.0 * fourth};
}

/// The widest sample spacing (m) whose hermiteError height bound is at most `heightError` (m) on a
/// surface whose fourth directional derivative is at most `fourth` (1/m^3): s^4 = 384 e / (2 M4);
/// infinite for a surface with no fourth derivative (a plane).
inline double spacingForHeightError(double heightError, double fourth) {
  return fourth > 0.0 ? std::pow(384.0 * heightError / (2.0 * fourth), 0.25) : INFINITY;
}

/// The horizontal bounds (m, world) of a set of points, each with a reach around it.
struct Footprint {
  double lowX = INFINITY, highX = -INFINITY, lowZ = INFINITY, highZ = -INFINITY;
  /// Widens the bounds by the point (x, z) and `reach` (m) around it; a point that is not finite
  /// is left out (it is asked of the surface itself, SurfaceHeights::at).
  void add(double x, double z, double reach = 0.0) {
    if (!std::isfinite(x) || !std::isfinite(z)) return;
    lowX = std::min(lowX, x - reach);
    highX = std::max(highX, x + reach);
    lowZ = std::min(lowZ, z - reach);
    highZ = std::max(highZ, z + reach);
  }
};

/// The surface's height above many points of one body at one time (the exact path's vertices,
/// drag's patches, a soft body's vertices or texels): interpolated from jets over their footprint
/// (SurfaceJetGrid, within `heightError`, m) where the surface offers a smoothness bound and the
/// grid takes fewer than `maxSamples` samples, else asked per point. Lives on the stack.
class SurfaceHeights {
 public:
  /// `shared`, when given, is a grid of the same surface and time that an earlier query of the
  /// same body sampled (the exact path's, RigidBodiesStep.cpp): taken instead of a grid of its own
  /// where its spacing keeps `heightError`, so that its samples serve again; a point it does not
  /// cover (kSharedMargin) asks the surface itself.
  SurfaceHeights(const LiquidSurface& surface, double time, const Footprint& footprint, double heightError,
                 double maxSamples = INFINITY, SurfaceJetGrid* shared = nullptr)
      : surface_(surface), time_(time), originX_(footprint.lowX), originZ_(footprint.lowZ) {
    const double width = footprint.highX - footprint.lowX, depth = footprint.highZ - footprint.lowZ;
    if (!std::isfinite(width + depth + originX_ + originZ_) || !(width >= 0.0) || !(depth >= 0.0)) return;  // empty
    const std::optional<SurfaceSmoothness> smooth = surface.smoothness(time);
    if (!smooth || !std::isfinite(smooth->fourth) || !(smooth->fourth >= 0.0)) return;
    if (shared && &shared->surface() == &surface && shared->time() == time &&
        hermiteError(shared->spacing(), smooth->fourth).height <= heightError) {
      grid_ = shared;
      originX_ = shared->originX();
      originZ_ = shared->originZ();
      return;
    }
    const double spacing = std::min(spacingForHeightError(heightError, smooth->fourth), std::max(width, depth));
    if (!(spacing > 0.0)) return;
    const double samples = (std::ceil(width / spacing) + 1.0) * (std::ceil(depth / spacing) + 1.0);
    if (!(samples < maxSamples)) return;
    grid_ = &own_.emplace(surface, time, originX_, originZ_, 0.0, width, 0.0, depth, spacing);
    // kMaxSide samples a side may not meet the bound over a wide footprint: then per point.
    if (!(hermiteError(grid_->spacing(), smooth->fourth).height <= heightError)) {
      own_.reset();
      grid_ = nullptr;
    }
  }
  SurfaceHeights(const SurfaceHeights&) = delete;
  SurfaceHeights& operator=(const SurfaceHeights&) = delete;

  /// Whether the heights are interpolated (false: each point asks the surface).
  bool interpolated() const { return grid_ != nullptr; }

  /// Marks the samples that at(x, z) (world, m) will need, for sampleMarked() (interpolated only).
  void mark(double x, double z) {
    if (grid_ && covered(x, z)) grid_->mark(x - originX_, z - originZ_);
  }
  /// Samples what mark() marked, in as few calls of the surface as SurfaceJetGrid::sampleMarked.
  void sampleMarked() {
    if (grid_) grid_->sampleMarked();
  }

  /// Height (m, world) of the surface above the world point (x, z).
  double at(double x, double z) {
    double height;
    if (grid_ && covered(x, z) && grid_->height(x - originX_, z - originZ_, height)) return height;
    return surface_.surfaceHeight(x, z, time_);
  }

  /// at() for each world point (x[i], z[i]) into `out` (same sizes): asked of the surface in one
  /// call (LiquidSurface::surfaceHeights) when not interpolated.
  void at(std::span<const double> x, std::span<const double> z, std::span<double> out) {
    if (!grid_) {
      surface_.surfaceHeights(x, z, time_, out);
      return;
    }
    for (std::size_t i = 0; i < x.size() && i < z.size() && i < out.size(); ++i) out[i] = at(x[i], z[i]);
  }

 private:
  // How far (m) outside a shared grid a point may lie and still take its edge's samples: the
  // rounding of drag's single-precision patch positions on a mesh whose bounds the grid covers.
  static constexpr double kSharedMargin = 1e-6;
  // Whether the world point (x, z) takes the grid (an own grid covers its footprint).
  bool covered(double x, double z) const {
    return own_.has_value() || grid_->contains(x - originX_, z - originZ_, kSharedMargin);
  }

  const LiquidSurface& surface_;
  double time_, originX_, originZ_;
  std::optional<SurfaceJetGrid> own_;
  SurfaceJetGrid* grid_ = nullptr;  // own_'s, a shared one, or none (per point)
};

}  // namespace hydrotex::detail
