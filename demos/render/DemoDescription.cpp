// SPDX-License-Identifier: Zlib
#include "DemoDescription.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace hydrotex::render {
namespace {

using Json = nlohmann::json;

Expected<Eigen::Vector3d> vector3(const Json& json, const std::string& where) {
  if (!json.is_array() || json.size() != 3) return Error{where + ": expected [x, y, z]"};
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    if (!json[std::size_t(i)].is_number()) return Error{where + ": expected [x, y, z]"};
    v[i] = json[std::size_t(i)].get<double>();
  }
  return v;
}

}  // namespace

Expected<DemoDescription> loadDemoDescription(const std::string& path) {
  std::ifstream file(path);
  if (!file) return Error{path + ": cannot open demo file"};
  std::stringstream text;
  text << file.rdbuf();
  const Json json = Json::parse(text.str(), nullptr, false);
  if (json.is_discarded() || !json.is_object()) return Error{path + ": not a JSON object"};
  DemoDescription demo;
  const std::filesystem::path filePath(path);
  demo.name = filePath.stem().string();
  if (demo.name.rfind("demo_", 0) == 0) demo.name = demo.name.substr(5);
  demo.baseDirectory = filePath.parent_path().string();
  auto resolve = [&](const std::string& relative) { return (filePath.parent_path() / relative).lexically_normal().string(); };
  static const char* known[] = {"title", "figure", "requires", "waiting_for", "scene", "fps", "size", "camera", "overlays", "bodies", "contact_sheet", "sink_fraction", "scenery"};
  for (auto it = json.begin(); it != json.end(); ++it)
    if (std::find(std::begin(known), std::end(known), it.key()) == std::end(known)) return Error{path + ": " + it.key() + ": unknown key"};
  try {
    demo.title = json.value("title", demo.name);
    demo.figure = json.value("figure", "");
    demo.waitingFor = json.value("waiting_for", "");
    if (json.contains("requires"))
      for (const Json& effect : json.at("requires")) demo.requires_.push_back(effect.get<std::string>());
    if (!json.contains("scene") || !json.at("scene").is_object()) return Error{path + ": scene: missing (a scene object)"};
    demo.sceneText = json.at("scene").dump();
    demo.fps = json.value("fps", 30);
    if (demo.fps < 1 || demo.fps > 240) return Error{path + ": fps: must lie in 1..240"};
    if (json.contains("size")) {
      demo.width = json.at("size").at(0).get<int>();
      demo.height = json.at("size").at(1).get<int>();
    }
    if (json.contains("camera")) {
      const Json& camera = json.at("camera");
      if (camera.contains("eye")) {
        Expected<Eigen::Vector3d> eye = vector3(camera.at("eye"), path + ": camera.eye");
        if (!eye) return eye.error();
        demo.camera.eye = *eye;
      }
      if (camera.contains("target")) {
        Expected<Eigen::Vector3d> target = vector3(camera.at("target"), path + ": camera.target");
        if (!target) return target.error();
        demo.camera.target = *target;
      }
      demo.camera.verticalFovDegrees = camera.value("fov", 40.0);
      demo.followBody = camera.value("follow", "");
      demo.followVertical = camera.value("follow_vertical", false);
    }
    if (json.contains("overlays")) {
      demo.drawForces = json.at("overlays").value("forces", true);
      demo.drawPointMasses = json.at("overlays").value("point_masses", true);
      demo.forceArrowLength = json.at("overlays").value("force_arrow_length", 2.0);
      if (!(demo.forceArrowLength > 0.0)) return Error{path + ": overlays.force_arrow_length: must be > 0 (m)"};
    }
    if (json.contains("bodies"))
      for (auto it = json.at("bodies").begin(); it != json.at("bodies").end(); ++it) {
        BodyLook look;
        if (it->contains("albedo")) look.albedoPath = resolve(it->at("albedo").get<std::string>());
        if (it->contains("overlay")) look.overlayPath = resolve(it->at("overlay").get<std::string>());
        const std::string palette = it->value("palette", "heat");
        if (palette == "heat") look.palette = Palette::Heat;
        else if (palette == "viridis") look.palette = Palette::Viridis;
        else if (palette == "wetness") look.palette = Palette::Wetness;
        else return Error{path + ": bodies." + it.key() + ".palette: '" + palette + "' is not one of heat, viridis, wetness"};
        look.overlayOpacity = it->value("overlay_opacity", 0.7);
        look.wetnessViewOpacity = it->value("wetness_view", 0.0);
        if (!(look.wetnessViewOpacity >= 0.0 && look.wetnessViewOpacity <= 1.0))
          return Error{path + ": bodies." + it.key() + ".wetness_view: must lie in 0..1"};
        demo.looks[it.key()] = look;
      }
    if (json.contains("contact_sheet")) {
      demo.sheetFrames = json.at("contact_sheet").value("frames", 6);
      demo.sheetColumns = json.at("contact_sheet").value("columns", 3);
    }
    demo.sinkFraction = json.value("sink_fraction", 0.98);
    if (json.contains("scenery")) {
      if (!json.at("scenery").is_array()) return Error{path + ": scenery: expected an array of bodies"};
      for (std::size_t i = 0; i < json.at("scenery").size(); ++i) {
        Json body = json.at("scenery").at(i);
        const std::string where = path + ": scenery[" + std::to_string(i) + "]";
        if (!body.is_object()) return Error{where + ": expected a body object"};
        SceneryItem item;
        item.initialSaturation = body.value("initial_saturation", 0.0);
        if (!(item.initialSaturation >= 0.0 && item.initialSaturation <= 1.0)) return Error{where + ".initial_saturation: must lie in 0..1"};
        item.pigment = body.value("pigment", false);
        body.erase("initial_saturation");
        body.erase("pigment");
        item.bodyText = body.dump();
        demo.scenery.push_back(std::move(item));
      }
    }
  } catch (const Json::exception& e) {
    return Error{path + ": " + e.what()};
  }
  return demo;
}

}  // namespace hydrotex::render
