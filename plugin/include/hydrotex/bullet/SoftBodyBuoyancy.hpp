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
#include "hydrotex/LiquidSurface.hpp"
#include "hydrotex/Mesh.hpp"
#include "hydrotex/SurfaceBake.hpp"
#include "hydrotex/SurfaceEvaluator.hpp"

namespace hydrotex::bullet {

/// Settings of a soft body's buoyancy.
struct SoftBodySettings {
  int resolution = 128;  ///< bake texels per side (16..4096); the soft body's faces set the accuracy first
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// What the last apply() did (world frame).
struct SoftBodyReport {
  btVector3 buoyancyForce{0, 0, 0};   ///< N: sum of the pressure forces given to the nodes
  btVector3 buoyancyTorque{0, 0, 0};  ///< N m about the world origin
  double wettedArea = 0.0;            ///< m^2: texel area under the surface (partly wet texels in part)
  double enclosedVolume = 0.0;        ///< m^3: the soft body's current volume from its texels
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
  /// taken uniform over the texel's vertical span), otherwise the medium's pressure at the
  /// texel. g is the length of the soft body's world gravity (m/s^2, along -y as everywhere in
  /// hydrotex). Nodes of zero inverse mass (pinned) take nothing. Error (nothing applied) when dt
  /// is not positive, the soft body's nodes or faces changed in number, or a node is not finite.
  Status apply(const LiquidSurface& surface, double time, double dt);

  /// The soft body.
  btSoftBody* body() const { return body_; }
  /// Last step's forces and volume.
  const SoftBodyReport& report() const { return report_; }
  /// Covered texels of the bake.
  std::size_t texelCount() const { return textures_.size(); }

 private:
  SoftBodyBuoyancy() = default;

  btSoftBody* body_ = nullptr;
  Mesh mesh_;                           // nodes as vertices, faces as triangles (outward)
  SurfaceBake bake_;                    // kept pieces: texel -> face, area fraction, barycentrics
  SurfaceEvaluator evaluator_;
  SurfaceTextures textures_;            // PT/VAT of the current nodes (world frame)
  std::vector<float> texelPressure_;    // Pa, per covered texel, this step
  std::vector<btVector3> nodeForce_;    // N, per node, this step
  std::vector<Eigen::Vector3d> faceAreaVector_;  // m^2, per triangle, this step
  std::size_t faceCount_ = 0;
  SoftBodyReport report_;
};

}  // namespace hydrotex::bullet
