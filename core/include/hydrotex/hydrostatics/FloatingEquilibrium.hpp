// SPDX-License-Identifier: Zlib
#pragma once
/// @file FloatingEquilibrium.hpp
/// Where a free body floats in a flat liquid and how stable it is (naval architecture's
/// equilibrium and righting-lever curve; docs/stability.md for the formulas).
///
/// Frame: y up, the liquid's surface at y = 0; x is the body's length, heel is the rotation about
/// x and trim the rotation about z. A pose is parametrized by heel phi, trim theta and the height
/// of the centre of mass G: the mesh is rotated about G by R = Rz(theta) Rx(phi) (extrinsic X then
/// Z, as Pose::fromDegreesXYZ with no Y angle) and G keeps its body-frame x and z in the world.
///
/// Method: the heave is solved exactly at every orientation (the displaced volume is monotone in
/// the height; safeguarded Newton with dV/dh = -A_wp), so that displacement always equals weight;
/// the free angles then minimize the potential energy U = m g y_G - rho g V y_B (stable equilibria
/// are its minima) by Newton iterations on the hydrostatic stiffness (Hydrostatics.hpp, condensed
/// on the heave), with negative curvature flipped (the step always goes downhill), a backtracking
/// line search on U, and a step along the most negative curvature to leave an unstable
/// equilibrium (a saddle of U).

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/Pose.hpp"

namespace hydrotex {

/// What floats: total mass and centre of mass.
struct FloatingBody {
  double mass = 0.0;                                        ///< kg (> 0)
  Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();   ///< m, body frame (inside the mesh's bounds)
};

/// Answers one hydrostatics query in the flat liquid of FloatingSettings (surface y = 0, that
/// density); empty: the exact polyhedral path on the mesh. The texture path plugs in here.
using FloatingHydrostatics = std::function<Expected<HydrostaticsResult>(const HydrostaticsQuery&)>;

/// The liquid, the start and the tolerances.
struct FloatingSettings {
  double fluidDensity = 1000.0;  ///< kg/m^3 (> 0)
  double gravity = 9.81;         ///< m/s^2 (> 0)
  double startHeel = 0.0;        ///< rad, the pose the search starts from (0, 0: upright)
  double startTrim = 0.0;        ///< rad
  /// Relative tolerance: the displaced volume within tolerance * m / rho, the heel and trim
  /// moments within tolerance * m g L (L the diagonal of the mesh's bounding box).
  double tolerance = 1e-10;
  int maxIterations = 100;       ///< Newton iterations on the angles (each with its line search)
};

/// A floating equilibrium found by findFloatingEquilibrium().
struct FloatingEquilibrium {
  Pose pose;                      ///< mesh to world (surface at y = 0)
  double heel = 0.0;              ///< rad, rotation about x
  double trim = 0.0;              ///< rad, rotation about z (after the heel)
  double draft = 0.0;             ///< m, depth of the mesh's deepest vertex below the surface
  HydrostaticsResult hydrostatics;///< at the pose (volume, centre of buoyancy, water plane, stiffness)
  double gmTransverse = 0.0;      ///< m, K(roll, roll) / (m g): metacentric height about x
  double gmLongitudinal = 0.0;    ///< m, K(pitch, pitch) / (m g): about z
  /// True when the pose is a minimum of the potential energy (free heave, heel and trim): the
  /// stiffness condensed on the heave has no negative eigenvalue (neutral counts as stable).
  bool stable = false;
  /// True when the start pose was itself an equilibrium but an unstable one, which the search left
  /// for this (stable) pose.
  bool startUnstable = false;
  double startGmTransverse = 0.0;    ///< m, GM about x at the start pose after the heave is solved
  double startGmLongitudinal = 0.0;  ///< m, GM about z there
  double residualMoment = 0.0;       ///< N m, what is left of the heel and trim moments
  /// False when the iteration limit was met before the tolerance (the pose is the lowest energy
  /// found); a line search that finds no lower energy ends the search as converged (a minimum of
  /// the energy as the hydrostatics path resolves it).
  bool converged = false;
  int iterations = 0;                ///< Newton iterations on the angles
};

/// The free-floating pose of `body` (mesh closed, m; its mass and centre of mass) in a flat liquid
/// at y = 0: displacement equals weight and the centre of buoyancy is vertically in line with G.
/// Errors (one line): a non-positive or non-finite mass, density or gravity; a centre of mass
/// outside the mesh's bounds; an open mesh (exact path); a body at least as heavy as the liquid it
/// can displace (no floating equilibrium: it sinks); a failing hydrostatics answer.
Expected<FloatingEquilibrium> findFloatingEquilibrium(const Mesh& mesh, const FloatingBody& body,
                                                      const FloatingSettings& settings = {},
                                                      const FloatingHydrostatics& answer = {});

/// Which angle a righting-lever curve sweeps.
enum class StabilityAxis {
  Roll,   ///< heel about x; trim free (R = Rz(trim) Rx(heel))
  Pitch,  ///< trim about z; heel free (R = Rx(heel) Rz(trim))
};

/// What rightingLeverCurve() sweeps.
struct StabilityCurveSettings {
  FloatingSettings floating;                  ///< liquid and tolerances (start angles ignored)
  StabilityAxis axis = StabilityAxis::Roll;   ///< swept angle
  double maxAngle = 3.14159265358979323846;   ///< rad, last angle (0 < maxAngle <= pi)
  double step = 2.0 * 3.14159265358979323846 / 180.0;  ///< rad, between samples (0 < step <= maxAngle)
};

/// The righting-lever (GZ) curve at constant displacement, free sinkage and free other angle.
struct RightingLeverCurve {
  std::vector<double> angles;  ///< rad: 0, step, 2 step, ... and maxAngle
  std::vector<double> levers;  ///< m, GZ = righting moment / (m g) (positive: back towards 0)
  std::vector<double> otherAngles;  ///< rad, the free angle (trim for roll, heel for pitch) found
  /// m, slope of GZ at 0 (the stiffness at angle 0, condensed on the free heave and other angle,
  /// over m g): the metacentric height about the swept axis.
  double gm = 0.0;
  double angleOfMaxLever = 0.0;  ///< rad, of the largest GZ (parabola through the largest sample and its neighbours)
  double maxLever = 0.0;         ///< m, that largest GZ
  /// rad, where GZ first falls from positive to zero (linear between samples; levers within
  /// 10 tolerance L of zero count as zero); empty when it does not within maxAngle (or is never
  /// positive).
  std::optional<double> angleOfVanishingStability;
  std::optional<double> area30;  ///< m rad, integral of GZ from 0 to 30 deg (trapezoids); empty when maxAngle < 30 deg
  std::optional<double> area40;  ///< m rad, from 0 to 40 deg; empty when maxAngle < 40 deg
};

/// The righting-lever curve of `body` (see findFloatingEquilibrium for the frame and the errors);
/// also an error for a step or maximum angle out of range.
Expected<RightingLeverCurve> rightingLeverCurve(const Mesh& mesh, const FloatingBody& body,
                                                const StabilityCurveSettings& settings = {},
                                                const FloatingHydrostatics& answer = {});

}  // namespace hydrotex
