// SPDX-License-Identifier: Zlib
#pragma once
/// @file DebugLineCollector.hpp
/// A btIDebugDraw that keeps the lines it is given (world frame) so that the renderer can draw
/// them as overlays: BuoyancyController::debugDraw's weight (red) at the centre of mass, buoyancy
/// (green) at the centre of buoyancy and waterline (blue), as in the paper's figure 9.

#include <btBulletDynamicsCommon.h>

#include <Eigen/Core>
#include <vector>

namespace hydrotex::render {

/// One coloured line segment (world frame, m; colour in [0, 1]).
struct DebugLine {
  Eigen::Vector3f from;    ///< m
  Eigen::Vector3f to;      ///< m
  Eigen::Vector3f colour;  ///< linear RGB
};

/// Collects lines; clear() between frames.
class DebugLineCollector final : public btIDebugDraw {
 public:
  /// Keeps the segment.
  void drawLine(const btVector3& from, const btVector3& to, const btVector3& color) override;
  /// Contact points are drawn as a short line along the normal.
  void drawContactPoint(const btVector3& point, const btVector3& normal, btScalar distance, int lifeTime,
                        const btVector3& color) override;
  /// Bullet's warnings go to stderr.
  void reportErrorWarning(const char* warningString) override;
  /// Text is not drawn (no font in a headless renderer).
  void draw3dText(const btVector3& /*location*/, const char* /*textString*/) override {}
  /// Bullet's debug flags.
  void setDebugMode(int debugMode) override { mode_ = debugMode; }
  /// Bullet's debug flags.
  int getDebugMode() const override { return mode_; }

  /// The lines collected since the last clear().
  const std::vector<DebugLine>& lines() const { return lines_; }
  /// Adds a line directly (point-mass markers and the like).
  void add(const Eigen::Vector3f& from, const Eigen::Vector3f& to, const Eigen::Vector3f& colour) { lines_.push_back({from, to, colour}); }
  /// Forgets every line.
  void clear() { lines_.clear(); }

 private:
  std::vector<DebugLine> lines_;
  int mode_ = DBG_DrawWireframe;
};

}  // namespace hydrotex::render
