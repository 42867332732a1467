// SPDX-License-Identifier: Zlib
/// @file BoxHydrostaticsWaves.cpp
/// A box under waves (issue 19 item 4: a primitive's own path), where the exact path clips its 12
/// triangles against local surface models, each too wide for one (pieces of 0.165 m under
/// bench_peers' waves, each clipped again for the model's linearization: about 90 models and 180
/// clipped pieces a query). Every quantity is a sum over the wetted surface (HydrostaticSums.hpp),
/// so a quadrature rule over the wetted part of each face gives all of them, as for a sphere
/// (SphereHydrostaticsWaves.cpp):
/// - a face is a rectangle; t runs up its steeper side (unit e, e_y >= 0, half length b), s across
///   it (unit f, half length a). The interpolated surface (the one integrated) has a slope of at
///   most G over the box's footprint (its slope at the centre plus K times the footprint's
///   half-diagonal, K its curvature's bound over the cells), so the depth D(s, t) = h - y falls
///   strictly up every line of the face where e_y > G |e_h|: each line is wholly wet, wholly dry
///   or crosses the water line once, at t_w(s), found by Newton's method in its bracket. The wet
///   part's outline has a corner where the water line meets the face's lower or upper side: those
///   points are found on both sides (sampled, the depth's slope along a side, G |f_h| + |f_y|,
///   bounding it between samples, and its bend, K |f_h|^2, proving one root at most in a cell
///   where the sign is in doubt; else declined), and the face's s-range is cut there, so that
///   each piece's integrand is smooth in s;
/// - across each piece, Gauss-Legendre nodes; along each line, Gauss-Legendre nodes on [-b, t_w];
///   a face wholly under the surface (by the same bounds) takes the whole of every line, a face
///   wholly over it nothing; a face too flat for the depth to fall up it (a level box's bottom)
///   is taken only wholly wet or wholly dry (sampled on cells, bounded between);
/// - the heights come from a grid of surface jets over the box's footprint (SurfaceJetGrid,
///   bicubic Hermite) within the exact path's interpolation error (kExactSurfaceModelTolerance /
///   30), so that a body's drag reads the same jets.
/// Otherwise (a face the water line crosses that lies too flat against the waves: a level box's
/// bottom or top in the water line, bench_peers' bobbing boxes one query in five) the rule is not
/// used: the caller takes the exact path on the mesh.
/// The body's drag takes nodes of the same pieces under a coarser rule (2 x 2 a piece), each line
/// wet up to its own water line; in flat water (flatBoxDragNodes) the water line on a face is
/// straight and its pieces follow from where it meets the face's sides.

#include "hydrostatics/BoxHydrostaticsWaves.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "hydrostatics/GaussLegendre.hpp"
#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex::detail {
namespace {

/// A face's axes from its two half-side vectors (m, world): t runs up the steeper side (unit e,
/// e_y >= 0, half length b), s across the other (unit f, half length a).
struct FaceAxes {
  Eigen::Vector3d e, f;
  double a, b;
};
FaceAxes faceAxes(const Eigen::Vector3d& first, const Eigen::Vector3d& second) {
  const bool firstSteeper = std::abs(first.y()) * second.norm() >= std::abs(second.y()) * first.norm();
  const Eigen::Vector3d& steep = firstSteeper ? first : second;
  const Eigen::Vector3d& flat = firstSteeper ? second : first;
  const double b = steep.norm(), a = flat.norm();
  return {(steep.y() >= 0.0 ? 1.0 : -1.0) * steep / b, flat / a, a, b};
}

/// waveBoxHydrostatics with a grid to keep (`keep`, not null) and its nodes (`nodes`, cleared by the caller).
std::optional<Expected<HydrostaticsResult>> waveBoxRule(const Eigen::Vector3d& halfExtents, const Eigen::Vector3d& center,
                                                        const LiquidSurface& surface, const HydrostaticsQuery& query,
                                                        std::optional<SurfaceJetGrid>* keep, BoxQuadrature rule,
                                                        BoxQuadrature* used, std::vector<WettedNode>* nodes,
                                                        BoxQuadrature dragRule) {
  if (Status valid = validateHydrostaticsQuery(surface, query); !valid) return Expected<HydrostaticsResult>(valid.error());
  const std::optional<SurfaceSmoothness> smooth = surface.smoothness(query.time);
  if (!surface.hasFreeSurface() || !smooth || !(smooth->third >= 0.0) || !(smooth->fourth >= 0.0) ||
      !std::isfinite(smooth->third + smooth->fourth) || !(halfExtents.minCoeff() > 0.0) || !halfExtents.allFinite())
    return std::nullopt;
  // The rule: more nodes as the box grows against the waves (an effective wave number fourth /
  // third, 1/m, as the sphere's); test_box_hydrostatics_waves measures the error these give.
  const double waveNumber = smooth->third > 0.0 ? smooth->fourth / smooth->third : 0.0;
  const double size = std::min(2.0 * halfExtents.maxCoeff() * waveNumber, 1e4);
  // 6 x 3 for bench_peers' 1 m box (size 3.4): within 1.2e-5 of the volume and 1.5e-5 rho g V m of
  // the torque of the plain exact path on the box cut to 1.7 cm squares, where the prepared mesh
  // was 3.3e-5 rho g V off in force (8 x 4: 8.1e-6 of the volume, for 1.25x the cost; 6 x 2:
  // 4.5e-4); a 40-pose probe.
  if (rule.across <= 0) rule.across = std::clamp(3 + int(size), 4, kMaxGaussNodes);
  if (rule.along <= 0) rule.along = std::clamp(2 + int(size / 3.0), 3, kMaxGaussNodes);
  rule.across = std::clamp(rule.across, 1, kMaxGaussNodes);
  rule.along = std::clamp(rule.along, 1, kMaxGaussNodes);
  if (used) *used = rule;

  const Eigen::Matrix3d& rotation = query.pose.rotation;
  const Eigen::Vector3d c = query.pose.apply(center);
  const Eigen::Vector3d axis[3] = {halfExtents.x() * rotation.col(0), halfExtents.y() * rotation.col(1),
                                   halfExtents.z() * rotation.col(2)};
  // The box's footprint and lowest point (world).
  const Eigen::Vector3d reach = axis[0].cwiseAbs() + axis[1].cwiseAbs() + axis[2].cwiseAbs();
  const double lowX = c.x() - reach.x(), lowZ = c.z() - reach.z(), width = 2.0 * reach.x(), depthZ = 2.0 * reach.z();
  const double lowest = c.y() - reach.y();
  const auto notFinite = [](double height) {
    return Expected<HydrostaticsResult>(Error{"box hydrostatics: the liquid surface height is not finite (" +
                                              std::to_string(height) + " m)"});
  };
  const auto dry = [&] {
    HydrostaticsResult none;
    none.fluidDensity = surface.density();
    return Expected<HydrostaticsResult>(none);
  };
  if (lowest >= surface.heightRange(query.time).second) return dry();  // over every crest
  // The exact path's frame (PolyhedralHydrostaticsWaves.cpp): o = (t_x, h(x_G, z_G), t_z).
  const Eigen::Vector3d centerOfMass = query.pose.apply(query.centerOfMass);
  const double originHeight = surface.surfaceHeight(centerOfMass.x(), centerOfMass.z(), query.time);
  if (!std::isfinite(originHeight)) return notFinite(originHeight);
  const Eigen::Vector3d origin(query.pose.translation.x(), originHeight, query.pose.translation.z());

  // Jets over the footprint (local frame: world x, z less its low corner), every one of them
  // asked at once (the curvature's bound reads every cell).
  const double heightError = kExactSurfaceModelTolerance / 30.0;
  SurfaceJetGrid& grid = keep->emplace(surface, query.time, lowX, lowZ, 0.0, width, 0.0, depthZ,
                                      std::min(spacingForHeightError(heightError, smooth->fourth), std::max(width, depthZ)));
  const HermiteError interpolation = hermiteError(grid.spacing(), smooth->fourth);
  if (!(interpolation.height <= heightError * (1.0 + 1e-9))) return std::nullopt;
  grid.sampleAll();
  // The interpolated surface's slope (at most G) and height range over the footprint (a disc of
  // its half-diagonal about its centre), from its curvature's bound K over the cells.
  SurfaceJet centre;
  // A grid that cannot interpolate (a jet missing where the surface folds, or a box so small that
  // its cells' scale underflows) declines, as a height missing below: the mesh path answers.
  if (!grid.interpolate(0.5 * width, 0.5 * depthZ, centre) || !std::isfinite(centre.height)) return std::nullopt;
  const double curvature = grid.curvatureBound(0.0, width, 0.0, depthZ);
  if (!std::isfinite(curvature)) return std::nullopt;
  const double footprintRadius = 0.5 * std::hypot(width, depthZ);
  const double centreSlope = std::hypot(centre.slopeX, centre.slopeZ);
  const double slopeBound = centreSlope + curvature * footprintRadius;
  const double heightReach = centreSlope * footprintRadius + 0.5 * curvature * footprintRadius * footprintRadius;
  const double surfaceLow = centre.height - heightReach, surfaceHigh = centre.height + heightReach;
  if (lowest >= surfaceHigh) return dry();

  bool failed = false;  // a height the grid could not give (declined)
  const auto jetAt = [&](const Eigen::Vector3d& p, SurfaceJet& jet) {
    if (!grid.interpolate(p.x() - lowX, p.z() - lowZ, jet) || !std::isfinite(jet.height)) {
      failed = true;
      jet = SurfaceJet{};
      jet.height = p.y();
    }
  };
  const auto heightAt = [&](const Eigen::Vector3d& p) {
    double height;
    if (!grid.height(p.x() - lowX, p.z() - lowZ, height) || !std::isfinite(height)) {
      failed = true;
      return p.y();
    }
    return height;
  };
  const GaussRule& across = gaussRule(rule.across);
  const GaussRule& along = gaussRule(rule.along);
  dragRule.across = std::clamp(dragRule.across, 1, kMaxGaussNodes);
  dragRule.along = std::clamp(dragRule.along, 1, kMaxGaussNodes);
  const GaussRule& dragAcross = gaussRule(dragRule.across);
  const GaussRule& dragAlong = gaussRule(dragRule.along);
  WettedSums sums;
  for (int k = 0; k < 3; ++k)
    for (const double side : {-1.0, 1.0}) {
      const Eigen::Vector3d normal = side * rotation.col(k);
      const Eigen::Vector3d faceCenter = c + side * axis[k];
      const Eigen::Vector3d& first = axis[(k + 1) % 3];
      const Eigen::Vector3d& second = axis[(k + 2) % 3];
      const double faceReach = std::abs(first.y()) + std::abs(second.y());
      if (faceCenter.y() - faceReach >= surfaceHigh) continue;  // wholly over the surface
      const bool wholeByBounds = faceCenter.y() + faceReach <= surfaceLow;
      const FaceAxes axes = faceAxes(first, second);
      const double a = axes.a, b = axes.b;
      const Eigen::Vector3d &e = axes.e, &f = axes.f;
      bool whole = wholeByBounds, crossed = false;
      if (!whole && !(e.y() > slopeBound * std::hypot(e.x(), e.z()))) {
        // Too flat for the depth to fall up its lines (a level box's bottom): the rule takes it
        // only wholly wet or wholly dry, by samples on a grid of cells over it, the depth's slope
        // in the face (at most G + |(e_y, f_y)|) bounding it over each cell.
        const int cells = rule.across;
        const double slack = (slopeBound + std::hypot(e.y(), f.y())) * std::hypot(a, b) / cells;
        bool wet = true, dryFace = true;
        for (int i = 0; i < cells && (wet || dryFace); ++i)
          for (int j = 0; j < cells; ++j) {
            const Eigen::Vector3d p = faceCenter + (-a + (2.0 * i + 1.0) * a / cells) * f + (-b + (2.0 * j + 1.0) * b / cells) * e;
            const double depth = heightAt(p) - p.y();
            wet = wet && depth > slack;
            dryFace = dryFace && depth < -slack;
          }
        if (failed) return std::nullopt;
        if (dryFace) continue;
        if (!wet) return std::nullopt;
        whole = true;
      }
      // The face's s-range in pieces, cut where the water line meets its lower or upper side (the
      // wet part's outline has a corner there, which the Gauss nodes must not straddle).
      constexpr int kMaxCuts = 16;
      double cuts[kMaxCuts + 2];
      int cutCount = 0;
      cuts[cutCount++] = -a;
      if (!whole) {
        // Both sides sampled at the middles of cells that tile them; the depth's slope along a
        // side (at most L = G |f_h| + |f_y|) keeps a sample's sign over its cell when |D| > L h.
        // In a cell where it may not, the depth's bend along the side (at most K |f_h|^2) keeps
        // its slope's sign when that slope exceeds K |f_h|^2 h: then the cell holds one root at
        // most, there where its ends' depths differ in sign; else the rule cannot say.
        const int samples = 2 * rule.across;
        const double h = a / samples, horizontal = std::hypot(f.x(), f.z());
        const double slack = (slopeBound * horizontal + std::abs(f.y())) * h;
        const double bend = curvature * horizontal * horizontal;
        bool lowerDry = true, upperWet = true;
        for (const double edge : {-b, b})
          for (int i = 0; i < samples; ++i) {
            const double s = -a + (2.0 * i + 1.0) * h;
            const Eigen::Vector3d p = faceCenter + s * f + edge * e;
            SurfaceJet jet;
            jetAt(p, jet);
            const double depth = jet.height - p.y();
            if (edge < 0.0) lowerDry = lowerDry && depth < -slack;
            if (edge > 0.0) upperWet = upperWet && depth > slack;
            if (std::abs(depth) > slack) continue;
            const double rate = jet.slopeX * f.x() + jet.slopeZ * f.z() - f.y();
            if (!(std::abs(rate) > bend * h)) return std::nullopt;
            const auto depthAt = [&](double position) {
              const Eigen::Vector3d q = faceCenter + position * f + edge * e;
              return heightAt(q) - q.y();
            };
            double low = s - h, high = s + h, lowDepth = depthAt(low), highDepth = depthAt(high);
            if ((lowDepth > 0.0) == (highDepth > 0.0)) continue;  // monotone: no root in the cell
            // The root by bisection (the depth is monotone here), to 1e-12 of the face.
            while (high - low > 1e-12 * (1.0 + a)) {
              const double middle = 0.5 * (low + high), middleDepth = depthAt(middle);
              if ((middleDepth > 0.0) == (lowDepth > 0.0)) {
                low = middle;
                lowDepth = middleDepth;
              } else {
                high = middle;
              }
            }
            if (cutCount > kMaxCuts) return std::nullopt;
            cuts[cutCount++] = 0.5 * (low + high);
          }
        if (failed) return std::nullopt;
        if (lowerDry) continue;  // the face wholly over the surface (its depth falls up every line)
        whole = upperWet;
        crossed = !whole;
        std::sort(cuts + 1, cuts + cutCount);
      }
      cuts[cutCount++] = a;
      // Each piece's lines under a rule (`acrossCount` Gauss-Legendre lines of `acrossRule`,
      // `alongCount` nodes of `alongRule` on each line's wet part): emit(point, weight, height)
      // for each node, with the interpolated height above it.
      const auto walkLines = [&](const GaussRule& acrossRule, int acrossCount, const GaussRule& alongRule, int alongCount,
                                 auto&& emit) {
        for (int piece = 0; piece + 1 < cutCount; ++piece) {
          const double from = cuts[piece], length = cuts[piece + 1] - cuts[piece];
          if (!(length > 0.0)) continue;
          double lastCrossing = 0.0;
          for (int i = 0; i < acrossCount; ++i) {
            const double s = from + length * acrossRule.node[i], acrossWeight = length * acrossRule.weight[i];
            const Eigen::Vector3d base = faceCenter + s * f;
            double top = b;
            if (crossed) {
              // This line wholly dry, wholly wet, or crossed once: D(t) = h(base + t e) - (base + t e)_y
              // falls, D(-b) > 0 > D(b), its root by Newton's method in its bracket.
              const Eigen::Vector3d lower = base - b * e, upper = base + b * e;
              if (heightAt(lower) - lower.y() <= 0.0) continue;
              if (heightAt(upper) - upper.y() < 0.0) {
                double low = -b, high = b, t = std::clamp(lastCrossing, -b, b);
                for (int iteration = 0; iteration < 60; ++iteration) {
                  const Eigen::Vector3d p = base + t * e;
                  SurfaceJet jet;
                  jetAt(p, jet);
                  const double depth = jet.height - p.y();
                  const double rate = jet.slopeX * e.x() + jet.slopeZ * e.z() - e.y();  // < 0
                  (depth > 0.0 ? low : high) = t;
                  const double step = rate < 0.0 ? depth / rate : INFINITY;
                  if (std::abs(step) < 1e-12 * (1.0 + b)) {
                    t -= step;
                    break;
                  }
                  t = t - step > low && t - step < high ? t - step : 0.5 * (low + high);
                  if (high - low < 1e-12 * (1.0 + b)) break;
                }
                top = std::clamp(t, -b, b);
                lastCrossing = top;
              }
            }
            const double span = top + b;
            for (int j = 0; j < alongCount; ++j) {
              const Eigen::Vector3d p = base + (-b + span * alongRule.node[j]) * e;
              emit(p, acrossWeight * span * alongRule.weight[j], heightAt(p));
            }
          }
        }
      };
      walkLines(across, rule.across, along, rule.along, [&](const Eigen::Vector3d& p, double area, double height) {
        const double depth = std::max(height - p.y(), 0.0);
        const Eigen::Vector3d x = p - origin;
        sums.addElement(x.x(), x.y(), x.z(), area * normal.x(), area * normal.y(), area * normal.z(), area, 1.0, depth,
                        depth * depth, height - origin.y());
      });
      // The drag's nodes: the same pieces under its own, coarser rule (the same water line).
      if (nodes)
        walkLines(dragAcross, dragRule.across, dragAlong, dragRule.along,
                  [&](const Eigen::Vector3d& p, double area, double height) {
                    nodes->push_back(WettedNode{p, area * normal, area, height});
                  });
    }
  if (failed) return std::nullopt;
  sums.setHydrostaticPressure(surface.density() * query.gravity);
  HydrostaticsResult result = finishHydrostatics(sums, origin, surface.density(), query, ForceModel::PressureSums, true);
  if (!std::isfinite(result.submergedVolume) || !result.centerOfBuoyancy.allFinite() || !result.stiffness.allFinite())
    return Expected<HydrostaticsResult>(Error{"box hydrostatics: non-finite result"});
  return Expected<HydrostaticsResult>(std::move(result));
}

}  // namespace

std::optional<Expected<HydrostaticsResult>> waveBoxHydrostatics(const Eigen::Vector3d& halfExtents,
                                                                const Eigen::Vector3d& center,
                                                                const LiquidSurface& surface,
                                                                const HydrostaticsQuery& query,
                                                                std::optional<SurfaceJetGrid>* keep, BoxQuadrature rule,
                                                                BoxQuadrature* used, std::vector<WettedNode>* nodes,
                                                                BoxQuadrature dragRule) {
  if (!keep) {  // a grid of its own (declared only here: GCC zero-fills an empty optional of its 60 KiB)
    std::optional<SurfaceJetGrid> own;
    return waveBoxHydrostatics(halfExtents, center, surface, query, &own, rule, used, nodes, dragRule);
  }
  if (nodes) nodes->clear();
  std::optional<Expected<HydrostaticsResult>> answer =
      waveBoxRule(halfExtents, center, surface, query, keep, rule, used, nodes, dragRule);
  if (nodes && !(answer && *answer)) nodes->clear();  // nodes only with an answer
  return answer;
}

void flatBoxDragNodes(const Eigen::Vector3d& halfExtents, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& center,
                      double level, std::vector<WettedNode>& nodes, BoxQuadrature rule) {
  nodes.clear();
  if (!(halfExtents.minCoeff() > 0.0) || !halfExtents.allFinite() || !center.allFinite() || !std::isfinite(level)) return;
  const int acrossCount = std::clamp(rule.across, 1, kMaxGaussNodes), alongCount = std::clamp(rule.along, 1, kMaxGaussNodes);
  const GaussRule& across = gaussRule(acrossCount);
  const GaussRule& along = gaussRule(alongCount);
  const Eigen::Vector3d axis[3] = {halfExtents.x() * rotation.col(0), halfExtents.y() * rotation.col(1),
                                   halfExtents.z() * rotation.col(2)};
  for (int k = 0; k < 3; ++k)
    for (const double side : {-1.0, 1.0}) {
      const Eigen::Vector3d normal = side * rotation.col(k);
      const Eigen::Vector3d faceCenter = center + side * axis[k];
      const Eigen::Vector3d& first = axis[(k + 1) % 3];
      const Eigen::Vector3d& second = axis[(k + 2) % 3];
      if (faceCenter.y() - std::abs(first.y()) - std::abs(second.y()) >= level) continue;  // wholly dry
      // The depth level - y falls up every line (t), which is wholly wet, wholly dry or crossed
      // once, at t_w(s) = (level - y_c - s f_y) / e_y.
      const FaceAxes axes = faceAxes(first, second);
      const double a = axes.a, b = axes.b;
      const Eigen::Vector3d &e = axes.e, &f = axes.f;
      const double rise = level - faceCenter.y();
      // The s-range cut where the water line meets the lower or upper side (t = -b, b): the wet
      // part's outline has a corner there.
      double cuts[4] = {-a, 0.0, 0.0, 0.0};
      int cutCount = 1;
      if (e.y() > 0.0 && f.y() != 0.0)
        for (const double edge : {-b, b}) {
          const double s = (rise - edge * e.y()) / f.y();
          if (s > -a && s < a) cuts[cutCount++] = s;
        }
      if (cutCount == 3 && cuts[2] < cuts[1]) std::swap(cuts[1], cuts[2]);
      cuts[cutCount++] = a;
      for (int piece = 0; piece + 1 < cutCount; ++piece) {
        const double from = cuts[piece], length = cuts[piece + 1] - cuts[piece];
        if (!(length > 0.0)) continue;
        for (int i = 0; i < acrossCount; ++i) {
          const double s = from + length * across.node[i], acrossWeight = length * across.weight[i];
          // The line's wet part, [-b, top]: a level face (e_y = 0) is wholly wet below the level.
          const double top = e.y() > 0.0 ? std::clamp((rise - s * f.y()) / e.y(), -b, b) : (rise > 0.0 ? b : -b);
          const double span = top + b;
          if (!(span > 0.0)) continue;
          const Eigen::Vector3d base = faceCenter + s * f;
          for (int j = 0; j < alongCount; ++j) {
            const double area = acrossWeight * span * along.weight[j];
            nodes.push_back(WettedNode{base + (-b + span * along.node[j]) * e, area * normal, area, level});
          }
        }
      }
    }
}

}  // namespace hydrotex::detail
