// SPDX-License-Identifier: Zlib
#pragma once
/// @file WetScenery.hpp
/// Static scenery that gets wet (a beach, a pot drying on a table): a mesh at a fixed pose whose
/// liquid texture the demo runner steps itself with the core Wetting API. The Bullet plugin
/// registers dynamic bodies only, and a static body needs none of its dynamics; stepping the core
/// API directly is the cleaner fit, and it lets a demo start the surface wet (initial saturation),
/// which the plugin's read-only liquid texture does not.

#include <Eigen/Core>
#include <memory>
#include <string>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/wetting/LiquidTexture.hpp"
#include "hydrotex/Pose.hpp"
#include "hydrotex/wetting/Wetting.hpp"
#include "hydrotex/bullet/Scene.hpp"

namespace hydrotex::render {

/// One static wet body and its liquid texture.
class WetScenery {
 public:
  /// From a body in the scene-file format (mesh, position, rotation_deg, wetting: {...}; its other
  /// keys are ignored). `initialSaturation` (0..1) fills every texel at the start; `pigment`
  /// keeps a pigment channel (coloured liquids). Errors: the wetting bake or settings at fault.
  static Expected<std::unique_ptr<WetScenery>> create(const bullet::SceneBody& body, const Mesh& mesh, double initialSaturation,
                                                      bool pigment);

  /// One step of `dt` seconds in `liquid` (null: in the open air) at simulated `time` (s).
  Status step(const LiquidSurface* liquid, double time, double dt);

  /// The baked geometry (its bake orders the liquid texture; its atlas is where it is drawn).
  const BodyGeometry& geometry() const { return geometry_; }
  /// The liquid texture.
  const LiquidTexture& texture() const { return texture_; }
  /// Mesh frame to world.
  const Pose& pose() const { return pose_; }
  /// Liquid held in the layer (m^3).
  double held() const { return held_; }
  /// Liquid absorbed since the start (m^3), from the liquid and the sources.
  double absorbed() const { return absorbed_; }
  /// Liquid evaporated since the start (m^3).
  double evaporated() const { return evaporated_; }

 private:
  WetScenery(BodyGeometry geometry, Wetting solver, LiquidTexture texture, Pose pose, std::vector<LiquidSource> sources);
  BodyGeometry geometry_;
  Wetting solver_;
  LiquidTexture texture_;
  Pose pose_;
  std::vector<LiquidSource> sources_;
  double held_ = 0.0, absorbed_ = 0.0, evaporated_ = 0.0;
};

}  // namespace hydrotex::render
