// SPDX-License-Identifier: Zlib
#pragma once
/// @file SoftBodyBuoyancy.hpp
/// Buoyancy of Bullet soft bodies (issue 5, "Deforming bodies"): Bullet computes no hydrostatic
/// force for a btSoftBody. Its surface is baked once in texture space (the soft body's faces are
/// the mesh's triangles, its nodes the vertices); every step PT/VAT are re-evaluated from the
/// moved nodes (SurfaceEvaluator), each texel's pressure force -p A is split over the texel's
/// pieces, and each piece's force goes to the three nodes of its face with the barycentric
/// weights of the piece's centroid (so that the total force and its moment are those of the
/// texels). The soft body keeps its own shape through Bullet (pressure kPR, volume conservation
/// kVC, pose matching kMT).
///
/// With Effect::Drag listed in SoftBodySettings::effects, the nodes also get core's SoftBodyDrag:
/// the rigid bodies' drag law (TexelDrag.hpp: pressure drag along each element's normal, skin
/// friction along it), texel
/// by texel rather than through merged patches (the surface deforms every step): each wetted
/// texel's velocity relative to the liquid is the area-weighted barycentric mean of its pieces'
/// node velocities, only its wet fraction counts, and its force goes to the nodes through its
/// pieces as the pressure does. The nodes' velocities split into the body's rigid motion and a
/// deformation with no momentum; the drag's total force and torque act on the first, the rest of
/// the node forces on the second, each taken semi-implicitly (a secant damping along the motion)
/// and limited so that it can slow that motion relative to the liquid, never speed it up: drag
/// never adds kinetic energy, at any time step, and a body moving as a whole is not deformed by
/// its own drag. Drag sees the node velocities of the end of the last step (without the g dt
/// that Bullet's predictMotion has already added). Bullet's own aerodynamic terms
/// (kDG, kLF) stay as the user set them (0 by default); do not set both. A soft body has no
/// rotational-damping term: its texels see their own velocities, spin included.
///
/// Use it through BuoyancyController::addSoftBody, or on its own: call apply() once per sub-step
/// from an action (btActionInterface), i.e. after Bullet's btSoftBody::predictMotion and before
/// its solveConstraints. Bullet clears node forces (m_f) in solveConstraints, so a force added
/// there would never act; apply() therefore integrates its forces itself, exactly as
/// predictMotion integrates m_f (semi-implicit Euler: v += f / m dt, x += f / m dt^2), and the
/// position solve then derives the velocities from the moved nodes as usual.

#include <cstdint>
#include <vector>

#include <BulletSoftBody/btSoftBody.h>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/bake/SurfaceEvaluator.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/step/SoftBodyDrag.hpp"
#include "hydrotex/bullet/FloatingBodySettings.hpp"

namespace hydrotex::bullet {

/// Settings of a soft body's buoyancy.
struct SoftBodySettings {
  int resolution = 128;  ///< bake texels per side (16..4096); the soft body's faces set the accuracy first
  /// The effects this soft body pays for: Effect::Buoyancy and Effect::Drag only (the others are
  /// an error in validate()). Drag costs nothing unless listed.
  EffectSet effects{Effect::Buoyancy, Effect::Drag};
  /// Drag law coefficients (with Effect::Drag), as FloatingBodySettings::drag.
  DragCoefficients drag;
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// What the liquid is besides its surface (BuoyancyController's LiquidSettings): what drag needs.
struct SoftBodyLiquid {
  double viscosity = 1.0e-3;                                 ///< dynamic viscosity (Pa s); 0: no skin friction
  Eigen::Vector3d current = Eigen::Vector3d::Zero();         ///< uniform current (m/s, world) added to the surface's velocity
};

/// What the last apply() did (world frame).
struct SoftBodyReport {
  btVector3 buoyancyForce{0, 0, 0};   ///< N: sum of the pressure forces given to the nodes
  btVector3 buoyancyTorque{0, 0, 0};  ///< N m about the world origin
  btVector3 dragForce{0, 0, 0};       ///< N: sum of the drag forces of the texels (before the per-node limit)
  btVector3 dragTorque{0, 0, 0};      ///< N m about the nodes' centre of mass (softBodyMotion)
  double dragPower = 0.0;             ///< W: rate of work of the drag on the nodes this step (<= 0)
  double wettedArea = 0.0;            ///< m^2: texel area under the surface (partly wet texels in part)
  double enclosedVolume = 0.0;        ///< m^3: the soft body's current volume from its texels
  /// m^3: volume below the local surface, -sum(mean wet depth x A_y) over the texels (exact for a
  /// closed surface cut by a plane: the waterplane adds nothing); enclosedVolume in a medium
  /// without free surface.
  double submergedVolume = 0.0;
  bool pressureApplied = false;       ///< this step gave pressure forces (Effect::Buoyancy listed)
  bool dragApplied = false;           ///< this step evaluated drag (Effect::Drag listed)
  std::uint64_t dragTexelsVisited = 0;///< texels whose drag was evaluated this step (wet ones)
  std::uint64_t steps = 0;            ///< apply() calls that applied forces
};

/// Buoyancy of one btSoftBody: its bake, kept from registration, and per-step buffers (no
/// allocation per step).
class SoftBodyBuoyancy {
 public:
  /// Bakes the closed surface of `body` (its faces, at the nodes' current positions) at
  /// settings.resolution. Faces oriented inwards are taken reversed. Error when `body` is null,
  /// has no faces, is not closed, or the settings are out of range.
  static Expected<SoftBodyBuoyancy> create(btSoftBody* body, const SoftBodySettings& settings = {});

  /// Gives the soft body's nodes the pressure forces of `surface` at `time` (s) for one sub-step
  /// of `dt` seconds (see the file comment): per texel, for a free surface p = rho g (mean depth
  /// of the wet part of the texel, depth from the local surface height above the texel's centre,
  /// the texel a parallelogram cut by a level surface: core's texelPressures), otherwise the medium's pressure at the
  /// texel. g is the length of the soft body's world gravity (m/s^2, along -y as everywhere in
  /// hydrotex). With Effect::Drag, the drag of `liquid` (see the file comment). Nodes of zero
  /// inverse mass (pinned) take nothing. Error (nothing applied) when dt is not positive, the
  /// soft body's nodes or faces changed in number, or a node is not finite.
  Status apply(const LiquidSurface& surface, double time, double dt, const SoftBodyLiquid& liquid = {});

  /// The settings it was created with.
  const SoftBodySettings& settings() const { return settings_; }

  /// The soft body.
  btSoftBody* body() const { return body_; }
  /// Last step's forces and volume.
  const SoftBodyReport& report() const { return report_; }
  /// Covered texels of the bake.
  std::size_t texelCount() const { return textures_.size(); }

 private:
  SoftBodyBuoyancy() = default;
  void applyDrag(const LiquidSurface& surface, double time, double dt, const SoftBodyLiquid& liquid, SoftBodyReport& report);

  btSoftBody* body_ = nullptr;
  Mesh mesh_;                           // nodes as vertices, faces as triangles (outward)
  SurfaceBake bake_;                    // kept pieces: texel -> face, area fraction, barycentrics
  SurfaceEvaluator evaluator_;
  SurfaceTextures textures_;            // PT/VAT of the current nodes (world frame)
  std::vector<float> texelWetFraction_; // 0..1, per covered texel, this step
  std::vector<float> texelPressure_;    // Pa, per covered texel, this step
  std::vector<Eigen::Vector3d> nodeForce_;  // N, per node, this step (pressure)
  std::vector<Eigen::Vector3d> nodeVelocity_;    // m/s, per node, at the end of the last step (Effect::Drag)
  std::vector<Eigen::Vector3d> velocityChange_;  // m/s, per node, the drag's change this step (Effect::Drag)
  std::vector<double> nodeMass_;                 // kg, 0 for pinned nodes (Effect::Drag)
  SoftBodyDrag drag_;                            // core's drag step and its scratch (Effect::Drag)
  SoftBodySettings settings_;
  std::vector<Eigen::Vector3d> faceAreaVector_;  // m^2, per triangle, this step
  std::size_t faceCount_ = 0;
  SoftBodyReport report_;
};

}  // namespace hydrotex::bullet
