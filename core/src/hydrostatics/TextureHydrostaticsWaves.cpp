// SPDX-License-Identifier: Zlib
/// @file TextureHydrostaticsWaves.cpp
/// The tile hierarchy under a free surface that is not flat (issue 19 item 1): a unit of texels
/// (a group, a block of 2 x 2 tiles or a tile: the largest whose bound below is within the
/// tolerance) is classified against a local quadratic model of the surface over its footprint,
/// not against a plane. The model is the second-order Taylor expansion at the unit's centre of a
/// bicubic Hermite interpolant of a few surface samples (SurfaceJetGrid), so the surface is asked
/// a few dozen times per query instead of once per texel. Its error bound over the unit is
///   |eta - q| <= M3 rho^3 / 6 + e0 + e1 rho + e2 rho^2 / 2,
/// rho the footprint's radius about its centre (within the box's horizontal half-diagonal and the
/// texels' bounding radius), M3 the surface's third-derivative bound (Taylor's remainder) and
/// e0..e2 the interpolation's bounds on height, slope and curvature (hermiteError).
/// With it the classification is conservative: a unit or tile is wholly submerged only when its
/// top lies under the model's lowest value over its footprint less the bound, dry only when its
/// bottom lies over the highest plus the bound; then every texel is so in the per-texel answer
/// too. Wholly submerged tiles add their moments (the flat part, depth -y', transformed once for
/// all tiles as the flat hierarchy does) and the moments weighted by the model (the wave part):
/// with p = rho g (q - y') every sum that is linear in q follows from the moments sum A, sum p A,
/// sum p p A; the first-moment sums (torque, centre of buoyancy) take the quadratic term at the
/// unit's centre (an O(rho^3) error, within the bound's order). Crossed tiles go texel by texel
/// with the model's height; tiles whose own bound still exceeds the tolerance (a coarse bake's
/// large tiles, short waves) go texel by texel with the interpolant's height (its own bound e0 is
/// a thirtieth of the tolerance), or with the surface's own, the per-texel answer, where e0 is not
/// within the tolerance (a sample spacing set by hand). The sums' difference from the
/// per-texel answer is far under bound x area: the model's error changes sign over a unit and over
/// the body (test_texture_hydrostatics_waves measures it).

#include <cmath>

#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrostatics/WaveTexelLanes.hpp"
#include "bake/TexelPosing.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex {

namespace {

using Texel = TextureHydrostatics::Texel;
using Moments = TextureHydrostatics::Moments;
using MomentCorrection = TextureHydrostatics::MomentCorrection;

// Moments::sumPPA's index of the pair (i, j).
constexpr int kPair[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};

/// The wave part of wholly submerged tiles, in the body frame: with q(p) the model's height
/// (frame o) at body point p, W0 = sum q A, W1(j, k) = sum q p_j A_k, and the scalar
/// sum q^2 (r1 . A) (r1 the rotation's y row) for the centre of buoyancy's height.
struct WavePart {
  double w0[3] = {0, 0, 0};
  double w1[3][3] = {};
  double squaredY = 0.0;

  /// Adds a tile whose model is q = h + d . v + v^T E v, v = p - c (body frame).
  void add(const Moments& m, const Eigen::Vector3d& c, double h, const double (&d)[3], const double (&e)[3][3],
           const Eigen::Vector3d& yRow) {
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
        // The quadratic term's first moment taken at the tile's centre.
        double first = linear0 * m.sumPA[j][k] + c[j] * quadratic[k];
        for (int i = 0; i < 3; ++i) first += d[i] * m.sumPPA[kPair[i][j]][k];
        w1[j][k] += first;
      }
    }
    // q^2 ~ (linear0 + d . p)^2 + 2 h (v^T E v): the rest is O(rho^3) on the tile.
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
};

}  // namespace

std::optional<HydrostaticsResult> TextureHydrostatics::queryWaves(const LiquidSurface& surface,
                                                                  const HydrostaticsQuery& q) const {
  const std::optional<SurfaceSmoothness> smooth = surface.smoothness(q.time);
  if (!smooth || !(smooth->third >= 0.0) || !(smooth->fourth >= 0.0) || !std::isfinite(smooth->third) ||
      !std::isfinite(smooth->fourth))
    return std::nullopt;
  const Eigen::Matrix3d& r = q.pose.rotation;
  const Eigen::Vector3d& t = q.pose.translation;
  const Eigen::Vector3d centerOfMass = q.pose.apply(q.centerOfMass);
  const Eigen::Vector3d origin(t.x(), surface.surfaceHeight(centerOfMass.x(), centerOfMass.z(), q.time), t.z());
  if (!std::isfinite(origin.y())) return std::nullopt;  // the per-texel path reports it
  const Eigen::Vector3d offset = t - origin;
  const double highest = surface.heightRange(q.time).second - origin.y();

  // Samples over the body's horizontal footprint, as far apart as an interpolation error bound of
  // a thirtieth of the tolerance allows (s^4 = 384 e / (2 M4), hermiteError): the curvature's
  // share of a group's bound then stays under the tolerance (bench_hydrostatics: closer samples
  // cost more surface evaluations than the groups they let through save).
  double lowX, highX, lowZ, highZ;
  detail::axisRange(boundsCenter_, boundsHalfExtent_, r, 0, offset.x(), lowX, highX);
  detail::axisRange(boundsCenter_, boundsHalfExtent_, r, 2, offset.z(), lowZ, highZ);
  const double tolerance = surfaceModelTolerance_;
  double spacing = surfaceSampleSpacing_;
  if (!(spacing > 0.0))
    spacing = detail::spacingForHeightError(tolerance / 30.0, smooth->fourth);
  spacing = std::min(spacing, std::max(highX - lowX, highZ - lowZ));
  detail::SurfaceJetGrid grid(surface, q.time, origin.x(), origin.z(), lowX, highX, lowZ, highZ, spacing);
  const detail::HermiteError interpolation = detail::hermiteError(grid.spacing(), smooth->fourth);
  // A tile no local model covers within the tolerance takes its texels' heights from the samples'
  // interpolant, whose pointwise bound (a thirtieth of the tolerance unless a spacing was set) is
  // within it, and asks the surface itself (a Newton search a point) only where it is not.
  const bool interpolatePerTexel = interpolation.height <= tolerance;

  detail::WettedSums sums;
  Moments under;  // wholly submerged tiles: the flat part of their sums
  WavePart wave;  // and the wave part
  const Eigen::Vector3d xRow = r.row(0).transpose(), yRow = r.row(1).transpose(), zRow = r.row(2).transpose();
  // The corrected texels' moment corrections, in the body frame (rotated once, at the end).
  detail::MomentCorrectionSums corrections;

  // A local model: the interpolated jet at a footprint's centre (local x, z) and its error bound
  // over the footprint's half-diagonal rho.
  struct Model {
    SurfaceJet jet;
    double centerX, centerZ, h, bound;
    // Height (frame o) at the local point (x, z).
    double at(double x, double z) const {
      const double ux = x - centerX, uz = z - centerZ;
      return h + jet.slopeX * ux + jet.slopeZ * uz +
             0.5 * (jet.curvatureXX * ux * ux + 2.0 * jet.curvatureXZ * ux * uz + jet.curvatureZZ * uz * uz);
    }
    // Slope of the model at the local point (x, z).
    void slope(double x, double z, double& slopeX, double& slopeZ) const {
      const double ux = x - centerX, uz = z - centerZ;
      slopeX = jet.slopeX + jet.curvatureXX * ux + jet.curvatureXZ * uz;
      slopeZ = jet.slopeZ + jet.curvatureXZ * ux + jet.curvatureZZ * uz;
    }
    // Bounds of the height over the box |x - x_c| <= reachX, |z - z_c| <= reachZ around the
    // local point (x_c, z_c), widened by the error bound.
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
  // The footprint of a body-frame box: centre (local x, z) and horizontal reaches.
  struct Footprint {
    double x, z, reachX, reachZ, radius;  // radius: of the disc about (x, z) that holds it
  };
  auto footprint = [&](const Tile& box) {
    const double reachX = xRow.cwiseAbs().dot(box.boundsHalfExtent), reachZ = zRow.cwiseAbs().dot(box.boundsHalfExtent);
    return Footprint{xRow.dot(box.boundsCenter) + offset.x(), zRow.dot(box.boundsCenter) + offset.z(), reachX, reachZ,
                     std::min(std::sqrt(reachX * reachX + reachZ * reachZ), box.boundsRadius)};
  };
  // The model over a footprint; false when its bound exceeds the tolerance or a sample is missing.
  auto modelOver = [&](const Footprint& f, Model& model) {
    const double rho = f.radius;
    model.bound = smooth->third * rho * rho * rho / 6.0 + interpolation.height + interpolation.slope * rho +
                  0.5 * interpolation.curvature * rho * rho;
    if (!(model.bound <= tolerance) || !grid.interpolate(f.x, f.z, model.jet)) return false;
    model.centerX = f.x;
    model.centerZ = f.z;
    model.h = model.jet.height - origin.y();
    return true;
  };
  // Adds the wave part of wholly submerged moments `m` under `model`, expanded about the
  // body-frame point c (the model's centre).
  auto addWave = [&](const Moments& m, const Eigen::Vector3d& c, const Model& model) {
    const SurfaceJet& jet = model.jet;
    double d[3], e[3][3];
    for (int i = 0; i < 3; ++i) {
      d[i] = jet.slopeX * xRow[i] + jet.slopeZ * zRow[i];
      for (int j = 0; j < 3; ++j)
        e[i][j] = 0.5 * (jet.curvatureXX * xRow[i] * xRow[j] + jet.curvatureXZ * (xRow[i] * zRow[j] + zRow[i] * xRow[j]) +
                         jet.curvatureZZ * zRow[i] * zRow[j]);
    }
    wave.add(m, c, model.h, d, e, yRow);
    under.add(m);
  };
  // The texels of a tile, with the model's heights or (model null) the surface's own, under
  // `modelHighest` (frame o), the highest those heights can be over the tile: the model's range
  // with its bound, or the surface's highest crest. The height needs only the texel's position: a
  // dry texel costs no more. The pose and the model are copied to locals so that the stores into
  // the sums do not make the compiler reload them.
  auto addTexels = [&](const Tile& tile, const Model* model, double modelHighest) {
    const double x0 = xRow.x(), x1 = xRow.y(), x2 = xRow.z(), y0 = yRow.x(), y1 = yRow.y(), y2 = yRow.z();
    const double z0 = zRow.x(), z1 = zRow.y(), z2 = zRow.z();
    const double bx = offset.x(), by = offset.y(), bz = offset.z();
    const Model m = model ? *model : Model{};
    // Texel i, with its moment correction (null: none); its element terms unless `element` is
    // false (the lanes took them).
    auto addTexel = [&](std::uint32_t i, const MomentCorrection* moment, bool element) {
      const Texel& texel = texels_[i];
      const double a = y0 * texel.edgeU[0] + y1 * texel.edgeU[1] + y2 * texel.edgeU[2];
      const double b = y0 * texel.edgeV[0] + y1 * texel.edgeV[1] + y2 * texel.edgeV[2];
      const double halfSpan = 0.5 * (std::abs(a) + std::abs(b));
      const double span = moment ? std::max(halfSpan, double(moment->reach)) : halfSpan;  // its pieces' reach
      const double px = texel.position[0], py = texel.position[1], pz = texel.position[2];
      const double y = y0 * px + y1 * py + y2 * pz + by;
      // Over the highest surface it can meet: dry, no height asked.
      if (y - span >= modelHighest) return;
      const double x = x0 * px + x1 * py + x2 * pz + bx;
      const double z = z0 * px + z1 * py + z2 * pz + bz;
      // A corrected texel needs the slope too (MomentCorrectionSums): the model's, or
      // the surface's jet where it has one.
      double slopeX = 0.0, slopeZ = 0.0;
      double height;
      SurfaceJet sample;
      if (model) {
        height = m.at(x, z);
        if (moment) m.slope(x, z, slopeX, slopeZ);
      } else if (interpolatePerTexel && (moment ? grid.interpolate(x, z, sample) : grid.height(x, z, sample.height))) {
        height = sample.height - origin.y();
        slopeX = sample.slopeX;
        slopeZ = sample.slopeZ;
      } else if (const std::optional<SurfaceJet> jet =
                     moment ? surface.heightJet(x + origin.x(), z + origin.z(), q.time) : std::nullopt) {
        height = jet->height - origin.y();
        slopeX = jet->slopeX;
        slopeZ = jet->slopeZ;
      } else {
        height = surface.surfaceHeight(x + origin.x(), z + origin.z(), q.time) - origin.y();
      }
      if (!(height - y > -span)) return;  // dry (or a NaN height)
      if (element) {
        const detail::WaterlineFractions f = detail::waterlineFractions(height - y, a, b);
        const double ax = texel.areaVector[0], ay = texel.areaVector[1], az = texel.areaVector[2];
        sums.addElement(x, y, z, x0 * ax + x1 * ay + x2 * az, y0 * ax + y1 * ay + y2 * az, z0 * ax + z1 * ay + z2 * az,
                        texel.area, f.area, f.depth, f.depthSq, height);
      }
      if (moment)
        corrections.add(x, y, z, moment->moment, detail::correctionWeight(height - y, halfSpan, moment->reach),
                             height - y, height, slopeX, slopeZ, r);
    };
    // Under a model, the texels' element terms in SIMD lanes up to `reached` (WaveTexelLanes.hpp)
    // and the moment corrections before it here; every texel from it here. A tile whose texels
    // nearly all carry a correction (a finely tessellated mesh's: 94 % of the 17,160-triangle
    // sphere's at 256^2) is all here: its corrections cost what the whole texel does.
    std::uint32_t reached = tile.begin;
    std::uint32_t correction = tile.correctionBegin;  // the next of the tile's moment corrections
#ifdef HYDROTEX_DOUBLE_LANES
    if (model && 4 * (tile.correctionEnd - tile.correctionBegin) <= 3 * (tile.end - tile.begin)) {
      const detail::WaveTexelInput lanes{texels_.data(), tile.begin, tile.end,
                                         {x0, x1, x2}, {y0, y1, y2}, {z0, z1, z2}, {bx, by, bz},
                                         m.centerX, m.centerZ, m.h, m.jet.slopeX, m.jet.slopeZ,
                                         m.jet.curvatureXX, m.jet.curvatureXZ, m.jet.curvatureZZ, modelHighest};
      if (!detail::sumWaveTexelsAvx2(lanes, sums, reached))
        reached = detail::sumWaveTexelLanes<detail::DoubleLanes>(lanes, sums);
      for (; correction < tile.correctionEnd && corrections_[correction].texel < reached; ++correction)
        addTexel(corrections_[correction].texel, &corrections_[correction], false);
    }
#endif
    for (std::uint32_t i = reached; i < tile.end; ++i) {
      const bool corrected = correction < tile.correctionEnd && corrections_[correction].texel == i;
      addTexel(i, corrected ? &corrections_[correction++] : nullptr, true);
    }
  };

  // A unit (a group, a block or a tile, holding the tiles [firstTile, lastTile)) under one model:
  // O(1) when wholly under or over it, else its tiles against the unit's band (cheap), then
  // against the model over each tile alone.
  auto addUnder = [&](const Tile& unit, std::uint32_t firstTile, std::uint32_t lastTile, const Footprint& f,
                      const Model& model, double low, double high) {
    double unitLow, unitHigh;
    model.range(f.x, f.z, f.reachX, f.reachZ, unitLow, unitHigh);
    if (low >= unitHigh) return;
    if (high <= unitLow) {
      addWave(unit.moments, unit.boundsCenter, model);
      return;
    }
    Moments submerged;
    bool anySubmerged = false;
    for (std::uint32_t g = firstTile; g < lastTile; ++g) {
      const Tile& tile = tiles_[g];
      detail::verticalRange(tile.boundsCenter, tile.boundsHalfExtent, r, offset.y(), low, high);
      if (low >= highest || low >= unitHigh) continue;
      if (high <= unitLow) {
        submerged.add(tile.moments);
        anySubmerged = true;
        continue;
      }
      const Footprint tileFootprint = footprint(tile);
      double tileLow, tileHigh;
      model.range(tileFootprint.x, tileFootprint.z, tileFootprint.reachX, tileFootprint.reachZ, tileLow, tileHigh);
      if (low >= tileHigh) continue;
      if (high <= tileLow) {
        submerged.add(tile.moments);
        anySubmerged = true;
        continue;
      }
      addTexels(tile, &model, tileHigh);
    }
    if (anySubmerged) addWave(submerged, unit.boundsCenter, model);
  };

  // The largest unit whose model's bound is within the tolerance: the group, else its blocks of
  // 2 x 2 tiles, else its tiles, else the surface per texel.
  for (std::size_t groupIndex = 0; groupIndex < groups_.size(); ++groupIndex) {
    const Tile& group = groups_[groupIndex];
    double low, high;
    detail::verticalRange(group.boundsCenter, group.boundsHalfExtent, r, offset.y(), low, high);
    if (low >= highest) continue;
    Model model;
    const Footprint groupFootprint = footprint(group);
    if (modelOver(groupFootprint, model)) {
      addUnder(group, group.begin, group.end, groupFootprint, model, low, high);
      continue;
    }
    for (std::uint32_t k = groupBlocks_[groupIndex]; k < groupBlocks_[groupIndex + 1]; ++k) {
      const Tile& block = blocks_[k];
      detail::verticalRange(block.boundsCenter, block.boundsHalfExtent, r, offset.y(), low, high);
      if (low >= highest) continue;
      const Footprint blockFootprint = footprint(block);
      if (modelOver(blockFootprint, model)) {
        addUnder(block, block.begin, block.end, blockFootprint, model, low, high);
        continue;
      }
      for (std::uint32_t g = block.begin; g < block.end; ++g) {
        const Tile& tile = tiles_[g];
        detail::verticalRange(tile.boundsCenter, tile.boundsHalfExtent, r, offset.y(), low, high);
        if (low >= highest) continue;
        const Footprint tileFootprint = footprint(tile);
        if (modelOver(tileFootprint, model))
          addUnder(tile, g, g + 1, tileFootprint, model, low, high);
        else
          addTexels(tile, nullptr, highest);
      }
    }
  }

  // The flat part (depth -y', h' = 0) of the submerged tiles, then the wave part in the world:
  // sum q A' = R W0, sum q x' x A' = R (sum q p x A) + b x R W0, sum q x'_x A'_y, and
  // sum (Q/2 - h' D) A'_y = sum (y'^2 - q^2)/2 A'_y.
  sums.addSubmergedMoments(under, r, offset);
  corrections.addTo(sums, r);
  const Eigen::Vector3d w0 = r * Eigen::Vector3d(wave.w0[0], wave.w0[1], wave.w0[2]);
  const Eigen::Vector3d cross(wave.w1[1][2] - wave.w1[2][1], wave.w1[2][0] - wave.w1[0][2],
                              wave.w1[0][1] - wave.w1[1][0]);
  const Eigen::Vector3d w0Cross = r * cross + offset.cross(w0);
  double xFirst = offset.x() * w0.y(), zFirst = offset.z() * w0.y();
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) {
      xFirst += xRow[j] * yRow[k] * wave.w1[j][k];
      zFirst += zRow[j] * yRow[k] * wave.w1[j][k];
    }
  for (int k = 0; k < 3; ++k) {
    sums.sumDA[k] += w0[k];
    sums.sumDxA[k] += w0Cross[k];
  }
  sums.sumDXAy += xFirst;
  sums.sumDZAy += zFirst;
  sums.sumYB -= 0.5 * wave.squaredY;
  // p = rho g D on every element: the pressure sums are the depth sums times -rho g.
  const double rhoG = surface.density() * q.gravity;
  for (int k = 0; k < 3; ++k) {
    sums.pressureForce[k] = -rhoG * sums.sumDA[k];
    sums.pressureTorque[k] = -rhoG * sums.sumDxA[k];
  }
  return detail::finishHydrostatics(sums, origin, surface.density(), q, detail::ForceModel::PressureSums, true);
}

}  // namespace hydrotex
