// SPDX-License-Identifier: Zlib
// Bad scene files, through the API (parseScene, SceneWorld::create) and `hydrotex simulate`:
// every key given a value of the wrong type, negative densities, impossible time steps, unknown
// effect names, missing or unreadable mesh and image files. Each gives one line naming the key or
// the file and a non-zero exit; never a crash, a hang, or a scene that runs with a wrong value.

#include <catch2/catch.hpp>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "TestPaths.hpp"
#include "ToolRun.hpp"
#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/bullet/Scene.hpp"

using namespace hydrotex;
using hydrotex::test::outputPath;
using hydrotex::test::sourcePath;
using hydrotex::test::writeScratch;
using Json = nlohmann::json;

namespace {

/// A scene that uses every key the parser knows (mesh paths relative to data/meshes).
Json fullScene() {
  return Json::parse(R"({
    "gravity": [0, -9.81, 0], "dt": 0.01, "duration": 0.05, "substeps": 2, "threads": 2, "backend": "cpu",
    "fluid": { "density": 1000, "viscosity": 0.001, "velocity": [0.1, 0, 0],
               "surface": { "type": "waves", "height": 0.1,
                            "waves": [ { "amplitude": 0.1, "wavelength": 10, "direction": [1, 0],
                                         "phase": 0.5, "steepness": 0.3 } ] } },
    "seabed": -5,
    "bodies": [
      { "name": "crate", "mesh": "box.obj", "density": 500, "position": [0, 0, 0],
        "rotation_deg": [0, 10, 0], "linear_velocity": [0, 0, 0], "angular_velocity": [0, 0, 0],
        "resolution": 32, "method": "texture",
        "effects": ["buoyancy", "drag", "variable_mass", "deformation"],
        "shell_density": 1.0, "open_hull": false,
        "point_masses": [ { "mass": 10, "position": [0, 0, 0], "path": [[0, 0, 0, 0], [1, 0.1, 0, 0]] } ],
        "deform": { "type": "scale", "keyframes": [[0, 1, 1, 1], [1, 1.1, 1, 1]] } }
    ]
  })");
}

std::string meshDirectory() { return sourcePath("data/meshes"); }

Expected<bullet::Scene> parse(const Json& json) { return bullet::parseScene(json.dump(), meshDirectory(), "scene.json"); }

/// Visits every value in `json` that sits under an object key or in an array, with the name a
/// message must mention (the key; for an array item, the key of the array it is in) and its path.
void forEachValue(const Json& json, const std::function<void(const Json& value, const std::string& name, const std::string& path)>& visit,
                  const std::string& path = "", const std::string& key = "") {
  if (json.is_object()) {
    for (auto it = json.begin(); it != json.end(); ++it) {
      const std::string childPath = path.empty() ? it.key() : path + "." + it.key();
      visit(it.value(), it.key(), childPath);
      forEachValue(it.value(), visit, childPath, it.key());
    }
  } else if (json.is_array()) {
    for (std::size_t i = 0; i < json.size(); ++i) {
      const std::string childPath = path + "[" + std::to_string(i) + "]";
      visit(json[i], key, childPath);
      forEachValue(json[i], visit, childPath, key);
    }
  }
}

/// Values of every JSON type other than `value`'s (for the integer keys, a fractional number too).
std::vector<Json> wrongTypesFor(const Json& value, const std::string& name) {
  std::vector<Json> wrong;
  if (!value.is_string()) wrong.emplace_back("text");
  if (!value.is_number()) wrong.emplace_back(1.5);
  if (name == "resolution" || name == "substeps" || name == "threads") wrong.emplace_back(2.5);
  if (!value.is_boolean()) wrong.emplace_back(true);
  if (!value.is_null()) wrong.emplace_back(nullptr);
  if (!value.is_array()) wrong.emplace_back(Json::array());
  if (!value.is_object()) wrong.emplace_back(Json::object());
  return wrong;
}

void checkOneLine(const std::string& message, const std::string& needle) {
  INFO(message);
  CHECK(message.find('\n') == std::string::npos);
  CHECK(message.find(needle) != std::string::npos);
}

}  // namespace

TEST_CASE("a gpu scene needs a program that gives the GL backend", "[robustness][scene]") {
  Json gpuScene = fullScene();
  gpuScene["backend"] = "gpu";
  const Expected<bullet::Scene> scene = parse(gpuScene);
  REQUIRE(scene.ok());  // a valid name ...
  CHECK(scene->backend == "gpu");
  // ... that plugin/ alone (no GL linked) cannot make: one line, no world.
  auto world = bullet::SceneWorld::create(*scene);
  REQUIRE_FALSE(world.ok());
  checkOneLine(world.error().message, "was given no GL backend");
}

TEST_CASE("the full scene used below is valid and builds a world", "[robustness][scene]") {
  const Expected<bullet::Scene> scene = parse(fullScene());
  INFO((scene ? std::string() : scene.error().message));
  REQUIRE(scene.ok());
  auto world = bullet::SceneWorld::create(*scene);
  INFO((world ? std::string() : world.error().message));
  REQUIRE(world.ok());
  for (int i = 0; i < 5; ++i) (*world)->step();
  CHECK(std::isfinite(double((*world)->bodies()[0]->getCenterOfMassPosition().y())));
}

TEST_CASE("every key with a value of the wrong type is refused, naming the key", "[robustness][scene][bad-input]") {
  const Json base = fullScene();
  std::size_t cases = 0;
  forEachValue(base, [&](const Json& value, const std::string& name, const std::string& path) {
    for (const Json& wrong : wrongTypesFor(value, name)) {
      Json broken = base;
      Json::json_pointer pointer;
      // Translate "a.b[0].c" into a JSON pointer.
      std::string token;
      for (std::size_t i = 0; i <= path.size(); ++i) {
        const char c = i < path.size() ? path[i] : '.';
        if (c == '.' || c == '[' || c == ']') {
          if (!token.empty()) pointer /= token;
          token.clear();
        } else {
          token.push_back(c);
        }
      }
      broken[pointer] = wrong;
      CAPTURE(path, wrong.dump());
      const Expected<bullet::Scene> scene = parse(broken);
      REQUIRE_FALSE(scene.ok());
      checkOneLine(scene.error().message, name);
      CHECK(scene.error().message.rfind("scene.json: ", 0) == 0);
      ++cases;
    }
  });
  CHECK(cases > 150);  // about 40 keys and items, 4-6 wrong types each
}

TEST_CASE("impossible values are refused, naming the key", "[robustness][scene][bad-input]") {
  struct Case {
    std::string pointer;  ///< JSON pointer into fullScene()
    Json value;
    std::string needle;
  };
  const std::vector<Case> cases = {
      {"/fluid/density", -1000.0, "fluid.density"},
      {"/fluid/density", 0.0, "fluid.density"},
      {"/fluid/viscosity", -1.0, "viscosity"},
      {"/bodies/0/density", -5.0, "density"},
      {"/bodies/0/density", 0.0, "density"},
      {"/bodies/0/shell_density", -1.0, "shell_density"},
      {"/bodies/0/point_masses/0/mass", -1.0, "mass"},
      {"/dt", 0.0, "dt"},
      {"/dt", -0.01, "dt"},
      {"/dt", 5.0, "dt"},
      {"/dt", 1e-300, "duration"},
      {"/duration", -1.0, "duration"},
      {"/substeps", 0, "substeps"},
      {"/substeps", 1000, "substeps"},
      {"/threads", -1, "threads: -1"},
      {"/threads", "many", "threads: \"many\""},
      {"/threads", 1e12, "threads"},
      {"/backend", "quantum", "backend: \"quantum\""},
      {"/bodies/0/resolution", 0, "resolution"},
      {"/bodies/0/resolution", 1 << 20, "resolution"},
      {"/bodies/0/effects", Json::array({"buoyancy", "levitation"}), "levitation"},
      {"/bodies/0/method", "magic", "method"},
      {"/bodies/0/mesh", "no_such_mesh.obj", "no_such_mesh.obj"},
      {"/bodies/0/mesh", "", "mesh"},
      {"/bodies/0/unknown_key", 1.0, "unknown_key"},
      {"/fluid/surface/type", "lava", "type"},
      {"/fluid/surface/waves/0/wavelength", 0.0, "wavelength"},
      {"/fluid/surface/waves/0/amplitude", -1.0, "amplitude"},
      {"/fluid/surface/waves/0/steepness", 2.0, "steepness"},
      {"/fluid/surface/waves/0/direction", Json::array({0, 0}), "direction"},
      {"/fluid/surface/waves", Json::array(), "waves"},
      {"/bodies", Json::array(), "bodies"},
      {"/bodies/0/point_masses/0/path/1/0", -1.0, "path[1]"},
      {"/bodies/0/deform/keyframes/1/1", 0.0, "keyframes[1]"},
      {"/bodies/0/deform/keyframes/1/0", 0.0, "keyframes[1]"},
  };
  for (const Case& c : cases) {
    Json broken = fullScene();
    broken[Json::json_pointer(c.pointer)] = c.value;
    CAPTURE(c.pointer, c.value.dump());
    const Expected<bullet::Scene> scene = parse(broken);
    REQUIRE_FALSE(scene.ok());
    checkOneLine(scene.error().message, c.needle);
  }
  // Giving both density and mass, or neither, is refused too.
  Json both = fullScene();
  both["bodies"][0]["mass"] = 10.0;
  CHECK_FALSE(parse(both).ok());
  // Not JSON, the wrong top level, nesting deep enough to break a recursive parser.
  for (const std::string& text : {std::string(""), std::string("{"), std::string("[1, 2]"), std::string("null"),
                                 std::string(100000, '[') + std::string(100000, ']'), std::string("{\"dt\": 1e999}")}) {
    const Expected<bullet::Scene> scene = bullet::parseScene(text, meshDirectory(), "scene.json");
    REQUIRE_FALSE(scene.ok());
    checkOneLine(scene.error().message, "scene.json");
  }
}

TEST_CASE("unreadable mesh and image files named in a scene are refused, naming the file", "[robustness][scene][bad-input]") {
  const std::string garbageMesh = writeScratch("robust_scene_garbage.obj", "this is not an obj file\x01\x02\n");
  const std::string openMesh = writeScratch("robust_scene_open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string corruptPng = writeScratch("robust_scene_corrupt.png", "\x89PNG\r\n\x1a\nnot really");
  for (const std::string& mesh : {garbageMesh, openMesh}) {
    Json scene = fullScene();
    scene["bodies"][0]["mesh"] = mesh;
    const Expected<bullet::Scene> parsed = parse(scene);
    // The mesh is read when the world is built (the parser only checks that the file exists).
    if (!parsed) {
      checkOneLine(parsed.error().message, mesh.substr(mesh.rfind('/') + 1));
      continue;
    }
    const auto world = bullet::SceneWorld::create(*parsed);
    REQUIRE_FALSE(world.ok());
    checkOneLine(world.error().message, mesh.substr(mesh.rfind('/') + 1));
  }
  Json withMap = fullScene();
  withMap["bodies"][0]["density_map"] = corruptPng;
  withMap["bodies"][0]["density_range"] = Json::array({100, 900});
  const Expected<bullet::Scene> parsed = parse(withMap);
  REQUIRE_FALSE(parsed.ok());
  checkOneLine(parsed.error().message, "robust_scene_corrupt.png");
  withMap["bodies"][0]["density_map"] = outputPath("robust_no_such_map.png");
  REQUIRE_FALSE(parse(withMap).ok());
  checkOneLine(parse(withMap).error().message, "robust_no_such_map.png");
}

#ifdef HYDROTEX_TOOL_PATH
TEST_CASE("hydrotex simulate refuses bad scenes with one line and a non-zero exit", "[robustness][scene][tool]") {
  using hydrotex::test::requireCleanFailure;
  using hydrotex::test::runTool;
  const std::string meshes = meshDirectory();
  auto sceneFile = [&](const std::string& name, Json json) {
    // Mesh paths in scene files are relative to the file: point them at data/meshes.
    if (json.contains("bodies") && json["bodies"].is_array())
      for (Json& body : json["bodies"])
        if (body.is_object() && body.contains("mesh") && body["mesh"].is_string())
          body["mesh"] = meshes + "/" + body["mesh"].get<std::string>();
    return writeScratch(name, json.dump());
  };
  struct Case {
    std::string pointer;
    Json value;
    std::string needle;
  };
  const std::vector<Case> cases = {
      {"/dt", 0.0, "dt"},
      {"/dt", "fast", "dt"},
      {"/fluid/density", -1.0, "fluid.density"},
      {"/bodies/0/density", -1.0, "density"},
      {"/bodies/0/effects", Json::array({"telekinesis"}), "telekinesis"},
      {"/bodies/0/mesh", "missing_mesh.obj", "missing_mesh.obj"},
      {"/bodies/0/position", Json::array({0, 0}), "position"},
      {"/fluid/surface", "flat", "surface"},
      {"/threads", -1, "threads: -1"},
      {"/threads", "many", "\"many\""},
      {"/backend", "quantum", "\"quantum\""},
  };
  for (const Case& c : cases) {
    Json broken = fullScene();
    broken[Json::json_pointer(c.pointer)] = c.value;
    CAPTURE(c.pointer);
    const std::string path = sceneFile("robust_bad_scene.json", broken);
    requireCleanFailure(runTool("simulate " + path + " --csv " + outputPath("robust_bad_scene.csv"), 120), c.needle);
  }
  requireCleanFailure(runTool("simulate " + writeScratch("robust_not_json.json", "{ \"dt\": "), 120),
                      "robust_not_json.json");
  requireCleanFailure(runTool("simulate " + outputPath("robust_no_such_scene.json"), 120), "robust_no_such_scene.json");
  // The command line's --threads and --backend, refused before the scene is run.
  const std::string valid = sceneFile("robust_valid_scene.json", fullScene());
  requireCleanFailure(runTool("simulate " + valid + " --threads many", 120), "--threads many");
  requireCleanFailure(runTool("simulate " + valid + " --threads -1", 120), "--threads -1");
  requireCleanFailure(runTool("simulate " + valid + " --threads 2x", 120), "--threads 2x");
  requireCleanFailure(runTool("simulate " + valid + " --backend quantum", 120), "quantum");
  // A scene whose mesh exists but is garbage fails when the world is built: still one line.
  Json garbage = fullScene();
  garbage["bodies"][0]["mesh"] = writeScratch("robust_tool_garbage.obj", "garbage\x01\n");
  requireCleanFailure(runTool("simulate " + writeScratch("robust_garbage_mesh.json", garbage.dump()), 120),
                      "robust_tool_garbage.obj");
}
#endif
