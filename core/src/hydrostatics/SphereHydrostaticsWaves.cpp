// SPDX-License-Identifier: Zlib
/// @file SphereHydrostaticsWaves.cpp
/// A true sphere under waves (issue 19 item 4: a primitive's own path), where the exact path would
/// clip its tessellation (17,160 triangles for ShapeTessellation's default, whose volume is 1e-3
/// short of the sphere's) against local surface models. Every quantity is a sum over the wetted
/// surface (HydrostaticSums.hpp: the pressure sums, and the cap's integrals by the divergence
/// theorem), so a quadrature rule on the wetted part of the sphere gives all of them, for the
/// sphere itself rather than a polyhedron inside it:
/// - polar angle theta from an axis along the surface's upward normal above the centre, azimuth
///   phi about it. Over the sphere the interpolated surface (the one integrated) departs from its
///   tangent plane there by at most E = K r^2 / 2 and its slope by at most G = K r (K: a bound
///   of its curvature over the footprint's cells), so that the depth along a meridian,
///   (h0 - y_c) - R |N| cos(theta) + E (N the plane's normal (-h_x, 1, -h_z)), rises strictly
///   wherever sin(theta) > G / |N|: when the cap of that half-angle around the upper pole lies
///   wholly over the surface and the one around the lower pole wholly under it, each meridian
///   crosses the water line once, at theta_w(phi), found by Newton's method in its bracket;
/// - on each meridian the wet arc [theta_w, pi] takes K Gauss-Legendre nodes (area element
///   R^2 sin(theta)), and the M meridians are equally spaced (the trapezoidal rule, which
///   converges geometrically for a smooth periodic integrand): each node adds its point, outward
///   area vector and depth to the sums as an element of the exact path does;
/// - the heights come from a grid of surface jets over the sphere's footprint (SurfaceJetGrid,
///   bicubic Hermite), within the exact path's interpolation error (kExactSurfaceModelTolerance
///   / 30), so that a body's drag reads the same jets.
/// Where the water line may pass near a pole (the sphere all but dry or all but submerged under a
/// curved surface) the rule is not used: the caller takes the exact path on the mesh.

#include "hydrostatics/SphereHydrostaticsWaves.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <numbers>
#include <string>

#include "hydrostatics/GaussLegendre.hpp"
#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex::detail {
namespace {

constexpr int kMaxPolarNodes = kMaxGaussNodes;
constexpr int kMaxAzimuths = 512;

/// sin and cos of `a` in [0, pi] (rad) to about an ulp of 1, where libm's sincos took 15 % of a
/// sphere's update under waves (callgrind, bench_peers): a = pi/2 + b, sin a = cos b and
/// cos a = -sin b with |b| <= pi/2, by their Taylor series to b^21 and b^22 (the first terms left
/// out are under 1.3e-18).
inline void sineCosineToPi(double a, double& sine, double& cosine) {
  // (-1)^n / (2n + 1)! and (-1)^n / (2n)!, n = 0 .. 10 and 0 .. 11.
  static constexpr double kSine[] = {1.0, -1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0, -1.0 / 39916800.0,
                                     1.0 / 6227020800.0, -1.0 / 1307674368000.0, 1.0 / 355687428096000.0,
                                     -1.0 / 121645100408832000.0, 1.0 / 51090942171709440000.0};
  static constexpr double kCosine[] = {1.0, -1.0 / 2.0, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0,
                                       1.0 / 479001600.0, -1.0 / 87178291200.0, 1.0 / 20922789888000.0,
                                       -1.0 / 6402373705728000.0, 1.0 / 2432902008176640000.0,
                                       -1.0 / 1124000727777607680000.0};
  const double b = a - 0.5 * std::numbers::pi, q = b * b;
  double sinB = kSine[std::size(kSine) - 1], cosB = kCosine[std::size(kCosine) - 1];
  for (std::size_t n = std::size(kSine) - 1; n-- > 0;) sinB = sinB * q + kSine[n];
  for (std::size_t n = std::size(kCosine) - 1; n-- > 0;) cosB = cosB * q + kCosine[n];
  sine = cosB;
  cosine = -sinB * b;
}

}  // namespace

std::optional<Expected<HydrostaticsResult>> waveSphereHydrostatics(double radius, const Eigen::Vector3d& center,
                                                                   const LiquidSurface& surface,
                                                                   const HydrostaticsQuery& query,
                                                                   std::optional<SurfaceJetGrid>* keep,
                                                                   SphereQuadrature rule, SphereQuadrature* used,
                                                                   std::vector<WettedNode>* nodes) {
  if (!keep) {  // a grid of its own (declared only here: GCC zero-fills an empty optional of its 60 KiB)
    std::optional<SurfaceJetGrid> own;
    return waveSphereHydrostatics(radius, center, surface, query, &own, rule, used, nodes);
  }
  if (nodes) nodes->clear();
  if (Status valid = validateHydrostaticsQuery(surface, query); !valid) return Expected<HydrostaticsResult>(valid.error());
  const std::optional<SurfaceSmoothness> smooth = surface.smoothness(query.time);
  if (!surface.hasFreeSurface() || !smooth || !(smooth->third >= 0.0) || !(smooth->fourth >= 0.0) ||
      !std::isfinite(smooth->third + smooth->fourth) || !(radius > 0.0) || !std::isfinite(radius))
    return std::nullopt;
  const double r = radius;
  const Eigen::Vector3d c = query.pose.apply(center);
  // The rule: more azimuths and polar nodes as the sphere grows against the waves (an effective
  // wave number fourth / third, 1/m; test_primitive_hydrostatics measures the error these give:
  // under 1.2e-6 of the answer up to a 1 m sphere in bench_peers' sea).
  const double waveNumber = smooth->third > 0.0 ? smooth->fourth / smooth->third : 0.0;
  const double size = std::min(r * waveNumber, 1e4);  // (beyond, the grid's 40 samples a side decline it)
  if (rule.azimuths <= 0) rule.azimuths = std::clamp(16 + 8 * int(size / 2.0), 16, kMaxAzimuths);
  if (rule.polarNodes <= 0) rule.polarNodes = std::clamp(8 + int(size / 2.0), 8, kMaxPolarNodes);
  rule.azimuths = std::clamp(rule.azimuths, 3, kMaxAzimuths);
  rule.polarNodes = std::clamp(rule.polarNodes, 1, kMaxPolarNodes);
  if (used) *used = rule;

  const Eigen::Vector3d centerOfMass = query.pose.apply(query.centerOfMass);
  const auto notFinite = [nodes](double height) {
    if (nodes) nodes->clear();
    return Expected<HydrostaticsResult>(Error{"sphere hydrostatics: the liquid surface height is not finite (" +
                                              std::to_string(height) + " m)"});
  };
  // Dry: zero, with the surface's density, as the exact path answers.
  const auto dry = [&] {
    HydrostaticsResult none;
    none.fluidDensity = surface.density();
    return Expected<HydrostaticsResult>(none);
  };
  if (c.y() - r >= surface.heightRange(query.time).second) return dry();  // over every crest
  // The exact path's frame (PolyhedralHydrostaticsWaves.cpp): o = (t_x, h(x_G, z_G), t_z).
  const double originHeight = surface.surfaceHeight(centerOfMass.x(), centerOfMass.z(), query.time);
  if (!std::isfinite(originHeight)) return notFinite(originHeight);
  const Eigen::Vector3d origin(query.pose.translation.x(), originHeight, query.pose.translation.z());

  // Jets over the sphere's footprint (local frame: world x, z less the footprint's low corner).
  const double heightError = kExactSurfaceModelTolerance / 30.0;
  const double lowX = c.x() - r, lowZ = c.z() - r;
  SurfaceJetGrid& grid = keep->emplace(surface, query.time, lowX, lowZ, 0.0, 2.0 * r, 0.0, 2.0 * r,
                                      std::min(spacingForHeightError(heightError, smooth->fourth), 2.0 * r));
  const HermiteError interpolation = hermiteError(grid.spacing(), smooth->fourth);
  // Waves too short for the grid's samples over the sphere (the bound's own rounding let through).
  if (!(interpolation.height <= heightError * (1.0 + 1e-9))) return std::nullopt;

  // The tangent plane above the centre and how far the interpolated surface (the one integrated)
  // may depart from it over the sphere's footprint (a disc of radius r about the centre): with K
  // its curvature's bound over the footprint's cells, by the mean value theorem along the radius,
  // at most K r^2 / 2 in height and K r in slope.
  // The bound reads every cell: the grid's jets asked in one batch (four runs side by side, each
  // search started from the last), where its blocks of four took nine (a 50-query probe: the
  // jets' instructions -9 %, the query's -3.6 %).
  grid.sampleAll();
  SurfaceJet centre;
  if (!grid.interpolate(r, r, centre)) return notFinite(NAN);
  // No bound (a jet missing, or a sphere so small that its cells' scale underflows): declined.
  const double curvature = grid.curvatureBound(0.0, 2.0 * r, 0.0, 2.0 * r);
  if (!std::isfinite(curvature)) return std::nullopt;
  const double departure = 0.5 * curvature * r * r, slopeDeparture = curvature * r;
  const Eigen::Vector3d normal = Eigen::Vector3d(-centre.slopeX, 1.0, -centre.slopeZ);
  const double normalLength = normal.norm();
  const Eigen::Vector3d axis = normal / normalLength;  // the polar axis: theta = 0 at c + r axis
  if (!(slopeDeparture < normalLength)) return std::nullopt;
  const double poleSine = slopeDeparture / normalLength, poleCosine = std::sqrt(1.0 - poleSine * poleSine);
  // Depth under the plane along a meridian: (h0 - y_c) - r |N| cos(theta); the surface within
  // `departure` of it.
  const double level = centre.height - c.y(), reach = r * normalLength;
  const bool wholeDry = level + reach + departure < 0.0;
  const bool wholeWet = level - reach - departure > 0.0;
  if (wholeDry) return dry();
  // Otherwise: the cap within theta* of the upper pole wholly over the surface and the one within
  // theta* of the lower pole wholly under it, so that each meridian crosses the water line once.
  const bool oneCrossing = level - reach * poleCosine + departure < 0.0 && level + reach * poleCosine - departure > 0.0;
  if (!wholeWet && !oneCrossing) return std::nullopt;
  const double poleAngle = std::asin(poleSine);
  const double pi = std::numbers::pi;

  const GaussRule& gauss = gaussRule(rule.polarNodes);

  // Two unit vectors across the axis.
  const Eigen::Vector3d across =
      (std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ()).cross(axis).normalized();
  const Eigen::Vector3d across2 = axis.cross(across);
  bool failed = false;  // a height the grid could not give (a jet not finite, or the surface folding)
  // The interpolated height above the world point (x, z).
  const auto heightAt = [&](double x, double z) {
    double height;
    if (!grid.height(x - lowX, z - lowZ, height) || !std::isfinite(height)) {
      failed = true;
      return 0.0;
    }
    return height;
  };
  WettedSums sums;
  // The drag's nodes (`nodes`): every other meridian (each one where they are odd in number), with
  // half the polar nodes (rounded up) on the same wet arcs. Its law is only C1 where a face turns
  // from advancing to retreating; the coarser nodes integrate it within 2.3e-3 of the converged
  // force in bench_peers' sea (a 60-pose probe; test_rigid_body_step: 1.9e-3 over 16), where the
  // rule's own 16 x 8 nodes gave 1.3e-4 for four times the liquid velocities and the mesh's
  // patches were 16 % off.
  const int dragPolarNodes = (rule.polarNodes + 1) / 2, dragStride = rule.azimuths % 2 == 0 ? 2 : 1;
  const GaussRule& dragGauss = gaussRule(dragPolarNodes);
  if (nodes) nodes->reserve(std::size_t(rule.azimuths / dragStride) * std::size_t(dragPolarNodes));
  const double azimuthWeight = 2.0 * pi / rule.azimuths;
  // The water line's polar angle on the last two meridians (Newton's starts: theta_w(phi) is smooth).
  double lastCrossing = NAN, crossingBefore = NAN;
  for (int j = 0; j < rule.azimuths; ++j) {
    const double phi = (j + 0.5) * azimuthWeight;
    const Eigen::Vector3d out = std::cos(phi) * across + std::sin(phi) * across2;  // the meridian's horizontal-ish way
    // The water line on this meridian: D(theta) = h(c + r u) - (y_c + r u_y), u = sin(theta) out +
    // cos(theta) axis, rising in [theta*, pi - theta*] (over it before, under it after).
    double from = 0.0;
    if (!wholeWet) {
      double low = poleAngle, high = pi - poleAngle;
      // Started from the last two meridians' crossings, extrapolated, or the tangent plane's.
      double theta = j >= 2 ? 2.0 * lastCrossing - crossingBefore
                     : j == 1 ? lastCrossing
                              : std::acos(std::clamp(level / reach, -1.0, 1.0));
      theta = std::clamp(theta, low, high);
      for (int iteration = 0; iteration < 60; ++iteration) {
        double sine, cosine;
        sineCosineToPi(theta, sine, cosine);
        const Eigen::Vector3d u = sine * out + cosine * axis;
        const Eigen::Vector3d du = cosine * out - sine * axis;
        const Eigen::Vector3d p = c + r * u;
        SurfaceJet jet;
        if (!grid.interpolate(p.x() - lowX, p.z() - lowZ, jet) || !std::isfinite(jet.height)) return notFinite(NAN);
        const double depth = jet.height - p.y();
        const double rate = r * (jet.slopeX * du.x() + jet.slopeZ * du.z() - du.y());
        (depth > 0.0 ? high : low) = theta;
        // Newton's step, taken when it stays in the bracket (else the bracket halved); within
        // 1e-10 rad the crossing is found (its error moves the sums by about as much, relative).
        const double step = rate > 0.0 ? depth / rate : INFINITY;
        if (std::abs(step) < 1e-10) {
          theta -= step;
          break;
        }
        theta = theta - step > low && theta - step < high ? theta - step : 0.5 * (low + high);
        if (high - low < 1e-10) break;
      }
      from = theta;
      crossingBefore = lastCrossing;
      lastCrossing = theta;
    }
    // The wet arc [from, pi], K Gauss nodes; area element r^2 sin(theta) d(theta) d(phi).
    const double span = pi - from;
    for (int k = 0; k < rule.polarNodes; ++k) {
      double sine, cosine;
      sineCosineToPi(from + span * gauss.node[k], sine, cosine);
      const Eigen::Vector3d u = sine * out + cosine * axis;
      const Eigen::Vector3d p = c + r * u;
      const double area = r * r * sine * span * gauss.weight[k] * azimuthWeight;
      const double height = heightAt(p.x(), p.z());
      const double depth = std::max(height - p.y(), 0.0);
      const Eigen::Vector3d x = p - origin;
      sums.addElement(x.x(), x.y(), x.z(), area * u.x(), area * u.y(), area * u.z(), area, 1.0, depth, depth * depth,
                      height - origin.y());
    }
    if (nodes && j % dragStride == 0) {
      // The meridians 0, 2, 4, ... are equally spaced too: each weighs twice.
      for (int k = 0; k < dragPolarNodes; ++k) {
        double sine, cosine;
        sineCosineToPi(from + span * dragGauss.node[k], sine, cosine);
        const Eigen::Vector3d u = sine * out + cosine * axis;
        const Eigen::Vector3d p = c + r * u;
        const double area = r * r * sine * span * dragGauss.weight[k] * dragStride * azimuthWeight;
        nodes->push_back(WettedNode{p, area * u, area, heightAt(p.x(), p.z())});
      }
    }
  }
  if (failed) return notFinite(NAN);
  sums.setHydrostaticPressure(surface.density() * query.gravity);
  HydrostaticsResult result = finishHydrostatics(sums, origin, surface.density(), query, ForceModel::PressureSums, true);
  if (!std::isfinite(result.submergedVolume) || !result.centerOfBuoyancy.allFinite() || !result.stiffness.allFinite()) {
    if (nodes) nodes->clear();
    return Expected<HydrostaticsResult>(Error{"sphere hydrostatics: non-finite result"});
  }
  return Expected<HydrostaticsResult>(std::move(result));
}

void flatSphereDragNodes(double radius, const Eigen::Vector3d& center, double level, std::vector<WettedNode>& nodes,
                         SphereQuadrature rule) {
  nodes.clear();
  const double r = radius;
  // The cap below the level: polar angles (from straight up) past theta_w, cos(theta_w) = (level - y_c) / r.
  if (!(r > 0.0) || !(level - center.y() > -r)) return;  // dry (or no sphere)
  const int azimuths = std::clamp(rule.azimuths, 3, kMaxAzimuths), polarNodes = std::clamp(rule.polarNodes, 1, kMaxPolarNodes);
  const GaussRule& gauss = gaussRule(polarNodes);
  const double pi = std::numbers::pi;
  const double from = std::acos(std::clamp((level - center.y()) / r, -1.0, 1.0)), span = pi - from;
  const double azimuthWeight = 2.0 * pi / azimuths;
  nodes.reserve(std::size_t(azimuths) * std::size_t(polarNodes));
  // The wet arc is the same on every meridian: its nodes' sines and cosines once; the meridians'
  // directions by turning the first one by 2 pi / M each (rounding grows by an ulp a turn).
  double polarSine[kMaxPolarNodes], polarCosine[kMaxPolarNodes];
  for (int k = 0; k < polarNodes; ++k) sineCosineToPi(from + span * gauss.node[k], polarSine[k], polarCosine[k]);
  const double turnCosine = std::cos(azimuthWeight), turnSine = std::sin(azimuthWeight);
  double outX = std::cos(0.5 * azimuthWeight), outZ = std::sin(0.5 * azimuthWeight);
  for (int j = 0; j < azimuths; ++j) {
    for (int k = 0; k < polarNodes; ++k) {
      const double sine = polarSine[k];
      const Eigen::Vector3d u(sine * outX, polarCosine[k], sine * outZ);
      const double area = r * r * sine * span * gauss.weight[k] * azimuthWeight;
      nodes.push_back(WettedNode{center + r * u, area * u, area, level});
    }
    const double turnedX = outX * turnCosine - outZ * turnSine;
    outZ = outX * turnSine + outZ * turnCosine;
    outX = turnedX;
  }
}

}  // namespace hydrotex::detail
