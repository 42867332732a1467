// SPDX-License-Identifier: Zlib
#pragma once
/// @file LocalSurfaceModel.hpp
/// Private to core: local quadratic models of a wavy surface over a body's parts, shared by the
/// texture path's hierarchy under waves (its tiles) and the exact path's (its triangle nodes and
/// triangles; issue 19 items 1 and 2). A model is the second-order Taylor expansion, at a
/// footprint's centre, of the bicubic Hermite interpolant of a few surface jets
/// (SurfaceJetGrid); its error bound over a footprint of radius rho is
///   |eta - q| <= M3 rho^3 / 6 + e0 + e1 rho + e2 rho^2 / 2,
/// M3 the surface's third-derivative bound (Taylor's remainder) and e0..e2 the interpolation's
/// bounds on height, slope and curvature (hermiteError). A part wholly under its model adds its
/// moments (the flat part, depth -y', transformed once for all parts) and the moments weighted
/// by the model (the wave part, WavePart): with p = rho g (q - y') every sum that is linear in q
/// follows from the moments Sum A, Sum p A, Sum p p A; the first-moment sums (torque, centre of
/// buoyancy) take the quadratic term at the part's centre (an O(rho^3) error, within the bound's
/// order).

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <optional>

#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex::detail {

/// A local model: the interpolated jet at a footprint's centre (local x, z: world less the
/// frame origin o) and its error bound (m) over the footprint.
struct SurfaceModel {
  SurfaceJet jet;
  double centerX = 0.0, centerZ = 0.0;
  double h = 0.0;      ///< the jet's height in the frame o (m)
  double bound = 0.0;  ///< |surface - model| over the footprint (m)

  /// Height (frame o) at the local point (x, z).
  double at(double x, double z) const {
    const double ux = x - centerX, uz = z - centerZ;
    return h + jet.slopeX * ux + jet.slopeZ * uz +
           0.5 * (jet.curvatureXX * ux * ux + 2.0 * jet.curvatureXZ * ux * uz + jet.curvatureZZ * uz * uz);
  }
  /// Slope of the model at the local point (x, z).
  void slope(double x, double z, double& slopeX, double& slopeZ) const {
    const double ux = x - centerX, uz = z - centerZ;
    slopeX = jet.slopeX + jet.curvatureXX * ux + jet.curvatureXZ * uz;
    slopeZ = jet.slopeZ + jet.curvatureXZ * ux + jet.curvatureZZ * uz;
  }
  /// The same quadratic expanded about the local point (x, z): the wave part's first moments take
  /// its quadratic term at the expansion point (WavePart), so a part under a wider part's model
  /// is best added about its own centre.
  SurfaceModel recentered(double x, double z) const {
    SurfaceModel out = *this;
    out.h = at(x, z);
    out.jet.height += out.h - h;
    slope(x, z, out.jet.slopeX, out.jet.slopeZ);
    out.centerX = x;
    out.centerZ = z;
    return out;
  }
  /// The largest |second directional derivative| of the model (1/m): its Hessian's spectral norm.
  double curvatureNorm() const {
    const double mean = 0.5 * (jet.curvatureXX + jet.curvatureZZ), half = 0.5 * (jet.curvatureXX - jet.curvatureZZ);
    return std::abs(mean) + std::sqrt(half * half + jet.curvatureXZ * jet.curvatureXZ);
  }
  /// Bounds of the height over the box |x - x_c| <= reachX, |z - z_c| <= reachZ around the
  /// local point (x_c, z_c), widened by the error bound.
  void range(double x, double z, double reachX, double reachZ, double& lowest, double& highestModel) const {
    const double ux = x - centerX, uz = z - centerZ;
    const double slopeX = jet.slopeX + jet.curvatureXX * ux + jet.curvatureXZ * uz;
    const double slopeZ = jet.slopeZ + jet.curvatureXZ * ux + jet.curvatureZZ * uz;
    const double spread = std::abs(slopeX) * reachX + std::abs(slopeZ) * reachZ +
                          0.5 * (std::abs(jet.curvatureXX) * reachX * reachX +
                                 2.0 * std::abs(jet.curvatureXZ) * reachX * reachZ +
                                 std::abs(jet.curvatureZZ) * reachZ * reachZ);
    const double middle = at(x, z);
    lowest = middle - spread - bound;
    highestModel = middle + spread + bound;
  }
};

/// The horizontal footprint of a part: centre (local x, z), reaches along x and z, and the
/// radius (m) of the disc about the centre that holds it.
struct ModelFootprint {
  double x, z, reachX, reachZ, radius;
};

/// The footprint of a body-frame box (centre, half extents, and a radius that bounds its contents
/// about the centre) under the rotation's rows and the body origin's offset from o.
inline ModelFootprint boxFootprint(const Eigen::Vector3d& center, const Eigen::Vector3d& halfExtent, double radius,
                                   const Eigen::Vector3d& xRow, const Eigen::Vector3d& zRow,
                                   const Eigen::Vector3d& offset) {
  const double reachX = xRow.cwiseAbs().dot(halfExtent), reachZ = zRow.cwiseAbs().dot(halfExtent);
  return ModelFootprint{xRow.dot(center) + offset.x(), zRow.dot(center) + offset.z(), reachX, reachZ,
                        std::min(std::sqrt(reachX * reachX + reachZ * reachZ), radius)};
}

/// The wave part of wholly submerged parts, in the body frame: with q(p) the model's height
/// (frame o) at body point p, W0 = sum q A, W1(j, k) = sum q p_j A_k, and the scalar
/// sum q^2 (r1 . A) (r1 the rotation's y row) for the centre of buoyancy's height.
struct WavePart {
  double w0[3] = {0, 0, 0};
  double w1[3][3] = {};
  double squaredY = 0.0;

  /// Adds a part whose model is q = h + d . v + v^T E v, v = p - c (body frame).
  void add(const TextureHydrostatics::Moments& m, const Eigen::Vector3d& c, double h, const double (&d)[3],
           const double (&e)[3][3], const Eigen::Vector3d& yRow) {
    // Moments::sumPPA's index of the pair (i, j).
    constexpr int kPair[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
    double ec[3], cec = 0.0, dc = 0.0;
    for (int i = 0; i < 3; ++i) {
      ec[i] = e[i][0] * c.x() + e[i][1] * c.y() + e[i][2] * c.z();
      cec += c[i] * ec[i];
      dc += d[i] * c[i];
    }
    const double linear0 = h - dc;  // the linear part is linear0 + d . p
    double quadratic[3];            // sum (v^T E v) A_k
    for (int k = 0; k < 3; ++k) {
      double sum = cec * m.sumA[k];
      for (int i = 0; i < 3; ++i) sum -= 2.0 * ec[i] * m.sumPA[i][k];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) sum += e[i][j] * m.sumPPA[kPair[i][j]][k];
      quadratic[k] = sum;
    }
    for (int k = 0; k < 3; ++k) {
      double sum = linear0 * m.sumA[k] + quadratic[k];
      for (int i = 0; i < 3; ++i) sum += d[i] * m.sumPA[i][k];
      w0[k] += sum;
      for (int j = 0; j < 3; ++j) {
        // The quadratic term's first moment taken at the part's centre.
        double first = linear0 * m.sumPA[j][k] + c[j] * quadratic[k];
        for (int i = 0; i < 3; ++i) first += d[i] * m.sumPPA[kPair[i][j]][k];
        w1[j][k] += first;
      }
    }
    // q^2 ~ (linear0 + d . p)^2 + 2 h (v^T E v): the rest is O(rho^3) on the part.
    double s0 = 0.0, s1[3] = {0, 0, 0}, s2[6] = {0, 0, 0, 0, 0, 0}, quadraticY = 0.0;
    for (int k = 0; k < 3; ++k) {
      s0 += m.sumA[k] * yRow[k];
      quadraticY += quadratic[k] * yRow[k];
      for (int i = 0; i < 3; ++i) s1[i] += m.sumPA[i][k] * yRow[k];
      for (int pair = 0; pair < 6; ++pair) s2[pair] += m.sumPPA[pair][k] * yRow[k];
    }
    double square = linear0 * linear0 * s0 + 2.0 * h * quadraticY;
    for (int i = 0; i < 3; ++i) {
      square += 2.0 * linear0 * d[i] * s1[i];
      for (int j = 0; j < 3; ++j) square += d[i] * d[j] * s2[kPair[i][j]];
    }
    squaredY += square;
  }

  /// add() for one triangle, expanded about its centroid c: its moments are rank one (Sum A = A,
  /// Sum p A = c A^T, Sum p p^T A = S A^T with S its second moments per area), so every sum is A_k
  /// times a scalar: with ES = Sum e_ij S_ij and cEc, W0 += (h + ES - cEc) A,
  /// W1(j, k) += (l c_j + c_j (ES - cEc) + (S d)_j) A_k (l = h - d . c), and
  /// sum q^2 (r1 . A) += (r1 . A) (l^2 + 2 h (ES - cEc) + 2 l d . c + d^T S d). About 80
  /// multiplications, counted in the source, where add() takes about 160.
  void addTriangle(const double (&a)[3], const double (&c)[3], const double (&secondMoments)[6], double h,
                   const double (&d)[3], const double (&e)[3][3], const Eigen::Vector3d& yRow) {
    constexpr int kPair[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
    double es = 0.0, cec = 0.0, dc = 0.0, sd[3], dsd = 0.0;
    for (int i = 0; i < 3; ++i) {
      dc += d[i] * c[i];
      sd[i] = 0.0;
      for (int j = 0; j < 3; ++j) {
        es += e[i][j] * secondMoments[kPair[i][j]];
        cec += c[i] * e[i][j] * c[j];
        sd[i] += secondMoments[kPair[i][j]] * d[j];
      }
      dsd += d[i] * sd[i];
    }
    const double linear0 = h - dc, quadratic = es - cec;
    for (int k = 0; k < 3; ++k) {
      w0[k] += (h + quadratic) * a[k];
      for (int j = 0; j < 3; ++j) w1[j][k] += (linear0 * c[j] + c[j] * quadratic + sd[j]) * a[k];
    }
    const double ay = a[0] * yRow[0] + a[1] * yRow[1] + a[2] * yRow[2];
    squaredY += ay * (linear0 * linear0 + 2.0 * h * quadratic + 2.0 * linear0 * dc + dsd);
  }

  /// add() for one triangle of area vector `a` from the means over it of the surface's height q
  /// (frame o, m), of q p (p the body-frame point, m^2) and of q^2 (m^2), however found (a
  /// quadrature of the surface's heights): W0 += mean(q) a, W1(j, k) += mean(q p_j) a_k, and
  /// sum q^2 (r1 . A) += (r1 . a) mean(q^2).
  void addMeans(const double (&a)[3], double meanHeight, const double (&meanHeightPoint)[3], double meanSquaredHeight,
                const Eigen::Vector3d& yRow) {
    for (int k = 0; k < 3; ++k) {
      w0[k] += meanHeight * a[k];
      for (int j = 0; j < 3; ++j) w1[j][k] += meanHeightPoint[j] * a[k];
    }
    squaredY += (a[0] * yRow[0] + a[1] * yRow[1] + a[2] * yRow[2]) * meanSquaredHeight;
  }
};

/// Adds one triangle's moments to `m` (body frame: `area` m^2, area vector `a`, centroid `c`, second
/// moments per area `secondMoments`, xx xy xz yy yz zz): rank one, Sum A = a, Sum p A = c a^T,
/// Sum p p A = S a^T.
inline void addTriangleMoments(TextureHydrostatics::Moments& m, double area, const double (&a)[3], const double (&c)[3],
                               const double (&secondMoments)[6]) {
  m.sumArea += area;
  for (int k = 0; k < 3; ++k) {
    m.sumA[k] += a[k];
    for (int i = 0; i < 3; ++i) m.sumPA[i][k] += c[i] * a[k];
    for (int pair = 0; pair < 6; ++pair) m.sumPPA[pair][k] += secondMoments[pair] * a[k];
  }
}

/// The local models of one query under a surface with smoothness bounds, over the body's
/// horizontal footprint, and the sums of the parts wholly under their models. Lives on the stack.
class LocalSurfaceModels {
 public:
  /// Samples (lazily) over the local box [lowX, highX] x [lowZ, highZ] (m, frame o at `origin`),
  /// `spacing` apart, or (spacing 0) as far apart as an interpolation error bound of a thirtieth
  /// of `tolerance` (m) allows (s^4 = 384 e / (2 M4), hermiteError): the curvature's share of a
  /// part's bound then stays under the tolerance (bench_hydrostatics: closer samples cost more
  /// surface evaluations than the parts they let through save).
  /// The grid lives in `keep` when given (the caller's, which outlives the models: the same
  /// body's drag reads its samples after the query, RigidBodiesStep.cpp), else in the models.
  LocalSurfaceModels(const LiquidSurface& surface, double time, const Eigen::Vector3d& origin,
                     const SurfaceSmoothness& smooth, double lowX, double highX, double lowZ, double highZ,
                     double tolerance, double spacing, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& offset,
                     std::optional<SurfaceJetGrid>* keep = nullptr)
      : smooth_(smooth),
        tolerance_(tolerance),
        originHeight_(origin.y()),
        grid_((keep ? *keep : own_)
                  .emplace(surface, time, origin.x(), origin.z(), lowX, highX, lowZ, highZ,
                           std::min(spacing > 0.0 ? spacing : spacingForHeightError(tolerance / 30.0, smooth.fourth),
                                    std::max(highX - lowX, highZ - lowZ)))),
        interpolation_(hermiteError(grid_.spacing(), smooth.fourth)),
        rotation_(rotation),
        offset_(offset),
        xRow_(rotation.row(0).transpose()),
        yRow_(rotation.row(1).transpose()),
        zRow_(rotation.row(2).transpose()) {}

  LocalSurfaceModels(const LocalSurfaceModels&) = delete;
  LocalSurfaceModels& operator=(const LocalSurfaceModels&) = delete;

  /// The jets' interpolant (heights and jets between models).
  SurfaceJetGrid& grid() { return grid_; }
  /// The interpolant's error bounds.
  const HermiteError& interpolation() const { return interpolation_; }
  /// The largest bound a model may have (m).
  double tolerance() const { return tolerance_; }
  /// The surface's smoothness bounds.
  const SurfaceSmoothness& smoothness() const { return smooth_; }
  /// Models interpolated so far (ExactWaveWork::models).
  std::size_t interpolations() const { return interpolations_; }

  /// The bound (m) of a model over a footprint of radius `rho` (m).
  double boundOver(double rho) const {
    return smooth_.third * rho * rho * rho / 6.0 + interpolation_.height + interpolation_.slope * rho +
           0.5 * interpolation_.curvature * rho * rho;
  }

  /// The bound (m) on the mean height over a footprint of radius `rho` (m) found by a quadrature
  /// of degree 4 with positive weights from the interpolant's heights (addSampledTriangle): the
  /// surface's cubic Taylor polynomial about the footprint's centre is within M4 rho^4 / 24 of it
  /// there and is integrated exactly, so the mean is off by at most twice that, plus the
  /// interpolant's height error. (A model's bound, boundOver(), goes as rho^3 and carries the
  /// interpolant's slope and curvature errors: at the exact path's tolerance, 1e-3 m, under
  /// bench_peers' three waves this allows pieces of radius 0.26 m against a model's 0.165 m.)
  double sampledBoundOver(double rho) const {
    const double rho2 = rho * rho;
    return smooth_.fourth * rho2 * rho2 / 12.0 + interpolation_.height;
  }

  /// The model over a footprint; false when its bound exceeds the tolerance or a sample is missing.
  bool over(const ModelFootprint& f, SurfaceModel& model) {
    model.bound = boundOver(f.radius);
    return model.bound <= tolerance_ && interpolateAt(f, model);
  }

  /// The model over a footprint whatever its bound (to classify a part wholly over or under it,
  /// not to integrate under it); false when a sample is missing or the bound is not finite.
  bool anyOver(const ModelFootprint& f, SurfaceModel& model) {
    model.bound = boundOver(f.radius);
    return std::isfinite(model.bound) && interpolateAt(f, model);
  }

  /// Adds wholly submerged moments `m` (body frame) under `model`, expanded about the body-frame
  /// point c (the model's centre).
  void addSubmerged(const TextureHydrostatics::Moments& m, const Eigen::Vector3d& c, const SurfaceModel& model) {
    double d[3], e[3][3];
    modelTerms(model, d, e);
    wave_.add(m, c, model.h, d, e, yRow_);
    under_.add(m);
  }

  /// addSubmerged() for one triangle (body frame: `area` m^2, area vector `a`, centroid `c`, second
  /// moments per area `secondMoments`) under `model`, which must be centred above c.
  void addSubmergedTriangle(double area, const double (&a)[3], const double (&c)[3],
                            const double (&secondMoments)[6], const SurfaceModel& model) {
    double d[3], e[3][3];
    modelTerms(model, d, e);
    wave_.addTriangle(a, c, secondMoments, model.h, d, e, yRow_);
    addTriangleMoments(under_, area, a, c, secondMoments);
  }

  /// addSubmergedTriangle() for a triangle whose wave part is given by the means over it of the
  /// surface's height (frame o, m), of the height times the body-frame point (m^2) and of the
  /// squared height (m^2) (WavePart::addMeans).
  void addSampledTriangle(double area, const double (&a)[3], const double (&c)[3], const double (&secondMoments)[6],
                          double meanHeight, const double (&meanHeightPoint)[3], double meanSquaredHeight) {
    wave_.addMeans(a, meanHeight, meanHeightPoint, meanSquaredHeight, yRow_);
    addTriangleMoments(under_, area, a, c, secondMoments);
  }

  /// The height (m, frame o) of the jets' interpolant at the local point (x, z) (m); false when
  /// a sample it needs is missing.
  bool heightAt(double x, double z, double& height) {
    if (!grid_.height(x, z, height)) return false;
    height -= originHeight_;
    return true;
  }

  /// Adds the flat part (depth -y', h' = 0) of the submerged parts' sums to `sums`.
  void addFlatPart(WettedSums& sums) const { sums.addSubmergedMoments(under_, rotation_, offset_); }

  /// Adds the wave part of the submerged parts' sums to `sums`, in the world: sum q A' = R W0,
  /// sum q x' x A' = R (sum q p x A) + b x R W0, sum q x'_x A'_y, and
  /// sum (Q/2 - h' D) A'_y = sum (y'^2 - q^2)/2 A'_y.
  void addWavePart(WettedSums& sums) const {
    const Eigen::Matrix3d& r = rotation_;
    const Eigen::Vector3d& offset = offset_;
    const Eigen::Vector3d w0 = r * Eigen::Vector3d(wave_.w0[0], wave_.w0[1], wave_.w0[2]);
    const Eigen::Vector3d cross(wave_.w1[1][2] - wave_.w1[2][1], wave_.w1[2][0] - wave_.w1[0][2],
                                wave_.w1[0][1] - wave_.w1[1][0]);
    const Eigen::Vector3d w0Cross = r * cross + offset.cross(w0);
    double xFirst = offset.x() * w0.y(), zFirst = offset.z() * w0.y();
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        xFirst += xRow_[j] * yRow_[k] * wave_.w1[j][k];
        zFirst += zRow_[j] * yRow_[k] * wave_.w1[j][k];
      }
    for (int k = 0; k < 3; ++k) {
      sums.sumDA[k] += w0[k];
      sums.sumDxA[k] += w0Cross[k];
    }
    sums.sumDXAy += xFirst;
    sums.sumDZAy += zFirst;
    sums.sumYB -= 0.5 * wave_.squaredY;
  }

 private:
  // The model's jet at the footprint's centre (its bound already set); false when a sample is
  // missing.
  bool interpolateAt(const ModelFootprint& f, SurfaceModel& model) {
    ++interpolations_;
    if (!grid_.interpolate(f.x, f.z, model.jet)) return false;
    model.centerX = f.x;
    model.centerZ = f.z;
    model.h = model.jet.height - originHeight_;
    return true;
  }

  // The model's slope and half curvature in the body frame: q = h + d . v + v^T E v (WavePart).
  void modelTerms(const SurfaceModel& model, double (&d)[3], double (&e)[3][3]) const {
    const SurfaceJet& jet = model.jet;
    for (int i = 0; i < 3; ++i) {
      d[i] = jet.slopeX * xRow_[i] + jet.slopeZ * zRow_[i];
      for (int j = 0; j < 3; ++j)
        e[i][j] = 0.5 * (jet.curvatureXX * xRow_[i] * xRow_[j] +
                         jet.curvatureXZ * (xRow_[i] * zRow_[j] + zRow_[i] * xRow_[j]) +
                         jet.curvatureZZ * zRow_[i] * zRow_[j]);
    }
  }

  SurfaceSmoothness smooth_;
  double tolerance_, originHeight_;
  std::optional<SurfaceJetGrid> own_;  // the grid, unless the caller keeps it
  SurfaceJetGrid& grid_;
  HermiteError interpolation_;
  Eigen::Matrix3d rotation_;
  Eigen::Vector3d offset_, xRow_, yRow_, zRow_;
  TextureHydrostatics::Moments under_;  // wholly submerged parts: the flat part of their sums
  WavePart wave_;                       // and the wave part
  std::size_t interpolations_ = 0;
};

}  // namespace hydrotex::detail
