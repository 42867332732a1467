// SPDX-License-Identifier: Zlib
/// @file TextureHydrostaticsWaves.cpp
/// The tile hierarchy under a free surface that is not flat (issue 19 item 1): a unit of texels
/// (a group, a block of 2 x 2 tiles or a tile: the largest whose bound below is within the
/// tolerance) is classified against a local quadratic model of the surface over its footprint,
/// not against a plane (LocalSurfaceModel.hpp: the model, its error bound over a footprint, and
/// the wave part of wholly submerged moments, shared with the exact path's hierarchy). The
/// surface is asked a few dozen times per query instead of once per texel.
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
#include "hydrostatics/LocalSurfaceModel.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrostatics/WaveTexelLanes.hpp"
#include "bake/TexelPosing.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace hydrotex {

namespace {

using Texel = TextureHydrostatics::Texel;
using Moments = TextureHydrostatics::Moments;
using MomentCorrection = TextureHydrostatics::MomentCorrection;
using detail::SurfaceModel;

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

  // The local models (LocalSurfaceModel.hpp) over the body's horizontal footprint.
  double lowX, highX, lowZ, highZ;
  detail::axisRange(boundsCenter_, boundsHalfExtent_, r, 0, offset.x(), lowX, highX);
  detail::axisRange(boundsCenter_, boundsHalfExtent_, r, 2, offset.z(), lowZ, highZ);
  const double tolerance = surfaceModelTolerance_;
  detail::LocalSurfaceModels models(surface, q.time, origin, *smooth, lowX, highX, lowZ, highZ, tolerance,
                                    surfaceSampleSpacing_, r, offset);
  detail::SurfaceJetGrid& grid = models.grid();
  // A tile no local model covers within the tolerance takes its texels' heights from the samples'
  // interpolant, whose pointwise bound (a thirtieth of the tolerance unless a spacing was set) is
  // within it, and asks the surface itself (a Newton search a point) only where it is not.
  const bool interpolatePerTexel = models.interpolation().height <= tolerance;

  detail::WettedSums sums;
  const Eigen::Vector3d xRow = r.row(0).transpose(), yRow = r.row(1).transpose(), zRow = r.row(2).transpose();
  // The corrected texels' moment corrections, in the body frame (rotated once, at the end).
  detail::MomentCorrectionSums corrections;

  using Footprint = detail::ModelFootprint;
  auto footprint = [&](const Tile& box) {
    return detail::boxFootprint(box.boundsCenter, box.boundsHalfExtent, box.boundsRadius, xRow, zRow, offset);
  };
  auto modelOver = [&](const Footprint& f, SurfaceModel& model) { return models.over(f, model); };
  auto addWave = [&](const Moments& m, const Eigen::Vector3d& c, const SurfaceModel& model) {
    models.addSubmerged(m, c, model);
  };
  // The texels of a tile, with the model's heights or (model null) the surface's own, under
  // `modelHighest` (frame o), the highest those heights can be over the tile: the model's range
  // with its bound, or the surface's highest crest. The height needs only the texel's position: a
  // dry texel costs no more. The pose and the model are copied to locals so that the stores into
  // the sums do not make the compiler reload them.
  auto addTexels = [&](const Tile& tile, const SurfaceModel* model, double modelHighest) {
    const double x0 = xRow.x(), x1 = xRow.y(), x2 = xRow.z(), y0 = yRow.x(), y1 = yRow.y(), y2 = yRow.z();
    const double z0 = zRow.x(), z1 = zRow.y(), z2 = zRow.z();
    const double bx = offset.x(), by = offset.y(), bz = offset.z();
    const SurfaceModel m = model ? *model : SurfaceModel{};
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
                      const SurfaceModel& model, double low, double high) {
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
    SurfaceModel model;
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

  // The flat part of the submerged tiles, the corrections, then the wave part.
  models.addFlatPart(sums);
  corrections.addTo(sums, r);
  models.addWavePart(sums);
  // p = rho g D on every element: the pressure sums are the depth sums times -rho g.
  sums.setHydrostaticPressure(surface.density() * q.gravity);
  return detail::finishHydrostatics(sums, origin, surface.density(), q, detail::ForceModel::PressureSums, true);
}

}  // namespace hydrotex
