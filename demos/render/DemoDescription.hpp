// SPDX-License-Identifier: Zlib
#pragma once
/// @file DemoDescription.hpp
/// A demo file (data/scenes/demo_*.json): a scene (the same JSON `hydrotex simulate` reads, under
/// the key "scene") plus how to show it: camera, frames, textures, overlays, and the effects it
/// needs, so that a demo whose effect this build lacks says so instead of faking it.

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "Camera.hpp"
#include "GlRenderer.hpp"
#include "hydrotex/Expected.hpp"

namespace hydrotex::render {

/// How one scene body is drawn.
struct BodyLook {
  std::string albedoPath;       ///< PNG (resolved), empty: light gray
  std::string overlayPath;      ///< gray PNG shown in pseudo-colour (permeability, density), empty: none
  Palette palette = Palette::Heat; ///< colour map of the overlay
  double overlayOpacity = 0.7;  ///< 0..1
  double wetnessViewOpacity = 0.0; ///< 0..1: the liquid texture's saturation in pseudo-colour over the wet-shaded albedo (figure 18)
};

/// A static body that gets wet (WetScenery): a body in the scene-file format plus its start.
struct SceneryItem {
  std::string bodyText;            ///< the body object (scene-file keys), as JSON text for parseScene
  double initialSaturation = 0.0;  ///< 0..1, every texel at the start (`initial_saturation`)
  bool pigment = false;            ///< keep a pigment channel (`pigment`: coloured liquid, figure 17)
};

/// Everything in a demo file.
struct DemoDescription {
  std::string name;                      ///< file stem without "demo_", e.g. "ship"
  std::string title;                     ///< one line, printed first
  std::string figure;                    ///< the paper's figure it reproduces
  std::vector<std::string> requires_;    ///< effect names the demo needs ("flooding", "wetting")
  std::string waitingFor;                ///< why it cannot run yet even when the effects exist (empty: nothing)
  std::string sceneText;                 ///< the "scene" object, as JSON text for parseScene
  std::string baseDirectory;             ///< directory of the demo file (scene paths are relative to it)
  int fps = 30;                          ///< frames per second of the video
  int width = 640;                       ///< pixels
  int height = 360;                      ///< pixels
  Camera camera;                         ///< initial camera
  std::string followBody;                ///< body the camera target follows (empty: fixed)
  bool followVertical = false;           ///< follow it up and down too (a balloon), not only across the water
  bool drawForces = true;                ///< weight and buoyancy arrows, waterline
  bool drawPointMasses = true;           ///< crosses at point masses
  double forceArrowLength = 2.0;         ///< m: the weight arrow is drawn this long (buoyancy to the same scale)
  std::map<std::string, BodyLook> looks; ///< by body name
  int sheetFrames = 6;                   ///< frames on the contact sheet
  int sheetColumns = 3;                  ///< columns of the contact sheet
  double sinkFraction = 0.98;            ///< a body has sunk when this fraction of its volume is submerged
  std::vector<SceneryItem> scenery;      ///< static wet bodies (`scenery`), drawn with looks by name
};

/// Reads a demo file. Errors name the file and the key at fault.
Expected<DemoDescription> loadDemoDescription(const std::string& path);

}  // namespace hydrotex::render
