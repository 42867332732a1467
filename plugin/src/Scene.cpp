// SPDX-License-Identifier: Zlib
#include "hydrotex/bullet/Scene.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include <BulletSoftBody/btDefaultSoftBodySolver.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>

#include "BulletEigen.hpp"
#include "SceneShape.hpp"
#include "SceneSoftBody.hpp"
#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/Pose.hpp"

namespace hydrotex::bullet {
namespace {

using Json = nlohmann::json;

/// Collision margin of a body's convex hull, as a fraction of its smallest extent (SceneWorld::create).
constexpr double kHullMarginFraction = 0.02;
/// m: the smallest margin given (contacts stay robust for thin bodies).
constexpr double kHullMarginFloor = 1e-3;

/// Reads typed values out of a JSON object, naming the key path in every message, and refusing
/// keys it was not asked about (a typo must not be silently ignored).
class ObjectReader {
 public:
  ObjectReader(const Json& object, std::string path, std::string source)
      : object_(object), path_(std::move(path)), source_(std::move(source)) {}

  std::string keyPath(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  Error error(const std::string& key, const std::string& what) const {
    return Error{source_ + ": " + keyPath(key) + ": " + what};
  }
  const Json* find(const std::string& key) {
    known_.insert(key);
    auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }

  Status number(const std::string& key, double& out) {
    const Json* v = find(key);
    if (v == nullptr) return Ok{};
    if (!v->is_number()) return error(key, "expected a number");
    out = v->get<double>();
    if (!std::isfinite(out)) return error(key, "not finite");
    return Ok{};
  }
  Status optionalNumber(const std::string& key, std::optional<double>& out) {
    if (object_.find(key) == object_.end()) {
      known_.insert(key);
      return Ok{};
    }
    double value = 0.0;
    if (Status s = number(key, value); !s) return s;
    out = value;
    return Ok{};
  }
  Status integer(const std::string& key, int& out) {
    const Json* v = find(key);
    if (v == nullptr) return Ok{};
    if (!v->is_number_integer()) return error(key, "expected an integer");
    const auto value = v->get<long long>();
    if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
      return error(key, "out of range");
    }
    out = static_cast<int>(value);
    return Ok{};
  }
  Status string(const std::string& key, std::string& out) {
    const Json* v = find(key);
    if (v == nullptr) return Ok{};
    if (!v->is_string()) return error(key, "expected a string");
    out = v->get<std::string>();
    return Ok{};
  }
  template <int N>
  Status vector(const std::string& key, Eigen::Matrix<double, N, 1>& out) {
    const Json* v = find(key);
    if (v == nullptr) return Ok{};
    if (!v->is_array() || v->size() != std::size_t(N)) {
      return error(key, "expected an array of " + std::to_string(N) + " numbers");
    }
    for (int i = 0; i < N; ++i) {
      const Json& item = (*v)[std::size_t(i)];
      if (!item.is_number()) return error(key, "expected an array of " + std::to_string(N) + " numbers");
      out[i] = item.get<double>();
      if (!std::isfinite(out[i])) return error(key, "not finite");
    }
    return Ok{};
  }
  /// Error for the first key that nobody asked for.
  Status rejectUnknown() const {
    for (auto it = object_.begin(); it != object_.end(); ++it) {
      if (!known_.count(it.key())) return Error{source_ + ": " + keyPath(it.key()) + ": unknown key"};
    }
    return Ok{};
  }

 private:
  const Json& object_;
  std::string path_;
  std::string source_;
  std::set<std::string> known_;
};

#define HYDROTEX_TRY(expr)        \
  do {                            \
    if (Status s_ = (expr); !s_) return s_.error(); \
  } while (false)

// A manual liquid graph file: {"nodes": [{"position": [x, y, z], "capacity": m^3}],
// "edges": [{"nodes": [a, b], "permeability": m^2, "area": m^2, "length": m}]} (mesh frame;
// capacity, area and length optional).
Expected<ManualLiquidGraph> loadLiquidGraphFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot be read"};
  Json json;
  try {
    json = Json::parse(in);
  } catch (const std::exception& e) {
    return Error{path + ": not valid JSON: " + e.what()};
  }
  if (!json.is_object()) return Error{path + ": expected an object with nodes and edges"};
  ObjectReader reader(json, "", path);
  ManualLiquidGraph graph;
  const Json* nodes = reader.find("nodes");
  if (nodes == nullptr || !nodes->is_array() || nodes->empty()) return reader.error("nodes", "expected a non-empty array");
  for (std::size_t i = 0; i < nodes->size(); ++i) {
    const std::string nodePath = "nodes[" + std::to_string(i) + "]";
    if (!(*nodes)[i].is_object()) return Error{path + ": " + nodePath + ": expected an object"};
    ObjectReader nodeReader((*nodes)[i], nodePath, path);
    ManualLiquidNode node;
    if ((*nodes)[i].find("position") == (*nodes)[i].end()) return nodeReader.error("position", "missing ([x, y, z] m)");
    HYDROTEX_TRY(nodeReader.vector<3>("position", node.position));
    HYDROTEX_TRY(nodeReader.optionalNumber("capacity", node.capacity));
    if (node.capacity && !(*node.capacity >= 0.0)) return nodeReader.error("capacity", "must be >= 0 (m^3)");
    HYDROTEX_TRY(nodeReader.rejectUnknown());
    graph.nodes.push_back(node);
  }
  if (const Json* edges = reader.find("edges")) {
    if (!edges->is_array()) return reader.error("edges", "expected an array");
    for (std::size_t e = 0; e < edges->size(); ++e) {
      const std::string edgePath = "edges[" + std::to_string(e) + "]";
      const Json& item = (*edges)[e];
      if (!item.is_object()) return Error{path + ": " + edgePath + ": expected an object"};
      ObjectReader edgeReader(item, edgePath, path);
      ManualLiquidEdge edge;
      const Json* pair = edgeReader.find("nodes");
      if (pair == nullptr || !pair->is_array() || pair->size() != 2 || !(*pair)[0].is_number_unsigned() ||
          !(*pair)[1].is_number_unsigned()) {
        return edgeReader.error("nodes", "expected [a, b] (node indices)");
      }
      const auto a = (*pair)[0].get<std::uint64_t>(), b = (*pair)[1].get<std::uint64_t>();
      if (a >= graph.nodes.size() || b >= graph.nodes.size() || a == b) {
        return edgeReader.error("nodes", "must name two different nodes of the file");
      }
      edge.first = std::uint32_t(a);
      edge.second = std::uint32_t(b);
      HYDROTEX_TRY(edgeReader.number("permeability", edge.permeability));
      if (!(edge.permeability >= 0.0)) return edgeReader.error("permeability", "must be >= 0 (m^2)");
      HYDROTEX_TRY(edgeReader.optionalNumber("area", edge.area));
      if (edge.area && !(*edge.area > 0.0)) return edgeReader.error("area", "must be > 0 (m^2)");
      HYDROTEX_TRY(edgeReader.optionalNumber("length", edge.length));
      if (edge.length && !(*edge.length > 0.0)) return edgeReader.error("length", "must be > 0 (m)");
      HYDROTEX_TRY(edgeReader.rejectUnknown());
      graph.edges.push_back(edge);
    }
  }
  HYDROTEX_TRY(reader.rejectUnknown());
  return graph;
}

/// The flooding keys of a body (paper section 3); they need "flooding" in effects.
Status parseFlooding(ObjectReader& reader, const std::string& baseDirectory, SceneBody& body) {
  FloodingBodySettings& flooding = body.flooding;
  std::string permeabilityMap, graph = "auto";
  HYDROTEX_TRY(reader.string("permeability_map", permeabilityMap));
  HYDROTEX_TRY(reader.number("permeability", flooding.graph.permeability));
  HYDROTEX_TRY(reader.number("wall_thickness", flooding.graph.wallThickness));
  HYDROTEX_TRY(reader.number("porosity", flooding.graph.porosity));
  HYDROTEX_TRY(reader.number("interior_permeability", flooding.graph.interiorPermeability));
  HYDROTEX_TRY(reader.number("opening_conductance", flooding.graph.openingConductance));
  HYDROTEX_TRY(reader.string("liquid_graph", graph));
  HYDROTEX_TRY(reader.integer("liquid_graph_nodes", flooding.nodeCount));
  const bool anyKey = !permeabilityMap.empty() || reader.find("permeability") || reader.find("wall_thickness") ||
                      reader.find("porosity") || reader.find("interior_permeability") || reader.find("liquid_graph") ||
                      reader.find("liquid_graph_nodes") || reader.find("opening_conductance");
  if (!body.effects.has(Effect::Flooding)) {
    if (anyKey) return reader.error("effects", "flooding keys need \"flooding\" in effects");
    return Ok{};
  }
  if (!(flooding.graph.permeability >= 0.0)) return reader.error("permeability", "must be >= 0 (m^2)");
  if (!(flooding.graph.wallThickness > 0.0)) return reader.error("wall_thickness", "must be > 0 (m)");
  if (!(flooding.graph.porosity >= 0.0 && flooding.graph.porosity <= 1.0)) return reader.error("porosity", "must lie in 0..1");
  if (!(flooding.graph.interiorPermeability >= 0.0)) return reader.error("interior_permeability", "must be >= 0 (m^2)");
  if (!(flooding.graph.openingConductance >= 0.0)) return reader.error("opening_conductance", "must be >= 0 (m)");
  if (flooding.nodeCount < 0 || flooding.nodeCount > 1024) return reader.error("liquid_graph_nodes", "must lie in 0..1024");
  if (!permeabilityMap.empty()) {
    const std::filesystem::path mapPath = std::filesystem::path(baseDirectory) / permeabilityMap;
    Expected<ImageMap> image = loadImageMap(mapPath.string());
    if (!image) return reader.error("permeability_map", image.error().message);
    flooding.permeabilityMap = std::make_shared<const ImageMap>(std::move(image).value());
  }
  if (graph != "auto") {
    const std::filesystem::path graphPath = std::filesystem::path(baseDirectory) / graph;
    Expected<ManualLiquidGraph> manual = loadLiquidGraphFile(graphPath.string());
    if (!manual) return reader.error("liquid_graph", manual.error().message);
    flooding.manualGraph = std::make_shared<const ManualLiquidGraph>(std::move(manual).value());
  }
  return Ok{};
}

Expected<SceneSurface> parseSurface(const Json& json, const std::string& path, const std::string& source) {
  if (!json.is_object()) return Error{source + ": " + path + ": expected an object"};
  ObjectReader reader(json, path, source);
  SceneSurface surface;
  std::string type = "plane";
  HYDROTEX_TRY(reader.string("type", type));
  if (type == "plane") {
    surface.type = SceneSurface::Type::Plane;
    HYDROTEX_TRY(reader.number("height", surface.height));
  } else if (type == "waves") {
    surface.type = SceneSurface::Type::Waves;
    HYDROTEX_TRY(reader.number("height", surface.height));
    const Json* waves = reader.find("waves");
    if (waves == nullptr) return reader.error("waves", "missing (a list of waves)");
    if (!waves->is_array() || waves->empty()) return reader.error("waves", "expected a non-empty array");
    for (std::size_t i = 0; i < waves->size(); ++i) {
      const std::string wavePath = reader.keyPath("waves") + "[" + std::to_string(i) + "]";
      const Json& item = (*waves)[i];
      if (!item.is_object()) return Error{source + ": " + wavePath + ": expected an object"};
      ObjectReader waveReader(item, wavePath, source);
      GerstnerWave wave;
      HYDROTEX_TRY(waveReader.number("amplitude", wave.amplitude));
      HYDROTEX_TRY(waveReader.number("wavelength", wave.wavelength));
      HYDROTEX_TRY(waveReader.vector<2>("direction", wave.direction));
      HYDROTEX_TRY(waveReader.number("phase", wave.phase));
      HYDROTEX_TRY(waveReader.number("steepness", wave.steepness));
      HYDROTEX_TRY(waveReader.rejectUnknown());
      if (!(wave.amplitude >= 0.0)) return waveReader.error("amplitude", "must be >= 0");
      if (!(wave.wavelength > 0.0)) return waveReader.error("wavelength", "must be > 0");
      if (wave.direction.norm() == 0.0) return waveReader.error("direction", "must not be zero");
      if (!(wave.steepness >= 0.0 && wave.steepness <= 1.0)) return waveReader.error("steepness", "must lie in [0, 1]");
      surface.waves.push_back(wave);
    }
  } else if (type == "none") {
    surface.type = SceneSurface::Type::None;
  } else {
    return reader.error("type", "'" + type + "' is not one of plane, waves, none");
  }
  HYDROTEX_TRY(reader.rejectUnknown());
  return surface;
}

// `wetting: {resolution, diffusivity, porosity, permeability, layer_thickness, humidity,
// temperature, sources: [{type: "rain" | "sphere", rate, direction, centre, radius, pigment}]}`.
Expected<WettingBodySettings> parseWetting(const Json& json, const std::string& path, const std::string& source) {
  if (!json.is_object()) return Error{source + ": " + path + ": expected an object"};
  ObjectReader reader(json, path, source);
  WettingBodySettings wetting;
  HYDROTEX_TRY(reader.integer("resolution", wetting.resolution));
  if (wetting.resolution != 0 && (wetting.resolution < 16 || wetting.resolution > 4096)) {
    return reader.error("resolution", "must lie in 16..4096 (or 0 for the body's)");
  }
  HYDROTEX_TRY(reader.number("diffusivity", wetting.physics.diffusivity));
  if (!(wetting.physics.diffusivity >= 0.0)) return reader.error("diffusivity", "must be >= 0 (m^2/s)");
  HYDROTEX_TRY(reader.number("porosity", wetting.material.porosity));
  if (!(wetting.material.porosity >= 0.0 && wetting.material.porosity <= 1.0)) return reader.error("porosity", "must lie in 0..1");
  HYDROTEX_TRY(reader.number("permeability", wetting.material.permeability));
  if (!(wetting.material.permeability >= 0.0)) return reader.error("permeability", "must be >= 0 (m^2)");
  HYDROTEX_TRY(reader.number("layer_thickness", wetting.material.layerThickness));
  if (!(wetting.material.layerThickness > 0.0)) return reader.error("layer_thickness", "must be > 0 (m)");
  HYDROTEX_TRY(reader.number("humidity", wetting.physics.relativeHumidity));
  if (!(wetting.physics.relativeHumidity >= 0.0 && wetting.physics.relativeHumidity <= 1.0)) {
    return reader.error("humidity", "must lie in 0..1 (relative humidity)");
  }
  HYDROTEX_TRY(reader.number("temperature", wetting.physics.temperature));
  if (!(wetting.physics.temperature > 200.0 && wetting.physics.temperature < 400.0)) {
    return reader.error("temperature", "must lie in 200..400 (K)");
  }
  if (const Json* sources = reader.find("sources")) {
    if (!sources->is_array()) return reader.error("sources", "expected an array of {type, rate, ...}");
    for (std::size_t i = 0; i < sources->size(); ++i) {
      const std::string sourcePath = reader.keyPath("sources") + "[" + std::to_string(i) + "]";
      if (!(*sources)[i].is_object()) return Error{source + ": " + sourcePath + ": expected an object"};
      ObjectReader sourceReader((*sources)[i], sourcePath, source);
      LiquidSource liquidSource;
      std::string type = "rain";
      HYDROTEX_TRY(sourceReader.string("type", type));
      if (type == "rain") {
        liquidSource.kind = LiquidSourceKind::Rain;
      } else if (type == "sphere") {
        liquidSource.kind = LiquidSourceKind::Sphere;
      } else {
        return sourceReader.error("type", "'" + type + "' is not one of rain, sphere");
      }
      HYDROTEX_TRY(sourceReader.number("rate", liquidSource.rate));
      if (!(liquidSource.rate >= 0.0)) return sourceReader.error("rate", "must be >= 0 (m/s of liquid)");
      HYDROTEX_TRY(sourceReader.vector<3>("direction", liquidSource.direction));
      HYDROTEX_TRY(sourceReader.vector<3>("centre", liquidSource.centre));
      HYDROTEX_TRY(sourceReader.number("radius", liquidSource.radius));
      if (!(liquidSource.radius >= 0.0)) return sourceReader.error("radius", "must be >= 0 (m)");
      HYDROTEX_TRY(sourceReader.number("pigment", liquidSource.pigment));
      if (!(liquidSource.pigment >= 0.0 && liquidSource.pigment <= 1.0)) return sourceReader.error("pigment", "must lie in 0..1");
      HYDROTEX_TRY(sourceReader.rejectUnknown());
      wetting.sources.push_back(liquidSource);
    }
  }
  HYDROTEX_TRY(reader.rejectUnknown());
  return wetting;
}

/// A scene body's mesh file with its axes, scale and repairs; a defect left unrepaired is refused.
Expected<Mesh> loadSceneMesh(const SceneBody& body) {
  RepairReport repairs;
  Expected<Mesh> loaded = loadMesh(body.meshPath, body.load, &repairs);
  if (!loaded) return loaded;
  if (Status repaired = repairs.requireRepaired(loaded->sourceName); !repaired) return repaired.error();
  return loaded;
}

Expected<SceneBody> parseBody(const Json& json, const std::string& path, const std::string& source,
                              const std::string& baseDirectory) {
  if (!json.is_object()) return Error{source + ": " + path + ": expected an object"};
  ObjectReader reader(json, path, source);
  SceneBody body;
  HYDROTEX_TRY(reader.string("name", body.name));
  std::string mesh;
  HYDROTEX_TRY(reader.string("mesh", mesh));
  if (const Json* shape = reader.find("shape")) {
    // A Bullet primitive instead of a mesh file (SceneShape.cpp).
    if (!mesh.empty()) return reader.error("shape", "given with mesh: give one of them");
    HYDROTEX_TRY(detail::parseSceneShape(*shape, path, source, body));
  } else {
    if (mesh.empty()) return reader.error("mesh", "missing (a mesh file, or a shape)");
    const std::filesystem::path meshPath = std::filesystem::path(baseDirectory) / mesh;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(meshPath, ec)) return reader.error("mesh", meshPath.string() + ": no such file");
    body.meshPath = meshPath.string();
  }
  std::string up = "y";
  HYDROTEX_TRY(reader.string("up", up));
  Expected<UpAxis> upAxis = upAxisFromName(up);
  if (!upAxis) return reader.error("up", "'" + up + "' is not y or z");
  body.load.up = *upAxis;
  HYDROTEX_TRY(reader.number("scale", body.load.scale));
  if (!(body.load.scale > 0.0)) return reader.error("scale", "must be > 0 (metres per file unit)");
  if (const Json* repair = reader.find("repair")) {
    if (!repair->is_boolean()) return reader.error("repair", "expected true or false");
    body.load.repair.enabled = repair->get<bool>();
  }
  HYDROTEX_TRY(reader.number("max_hole_fraction", body.load.repair.maxHoleFraction));
  if (const Json* openHull = reader.find("open_hull")) {
    // A boundary loop too large to be a hole is an opening, capped by a massless, open lid.
    if (!openHull->is_boolean()) return reader.error("open_hull", "expected true or false");
    body.load.repair.openHull = openHull->get<bool>();
  }
  if (Status valid = body.load.repair.validate(); !valid) return reader.error("max_hole_fraction", valid.error().message);
  HYDROTEX_TRY(reader.optionalNumber("density", body.density));
  HYDROTEX_TRY(reader.optionalNumber("mass", body.mass));
  HYDROTEX_TRY(reader.vector<3>("position", body.position));
  HYDROTEX_TRY(reader.vector<3>("rotation_deg", body.rotationDegrees));
  HYDROTEX_TRY(reader.vector<3>("linear_velocity", body.linearVelocity));
  HYDROTEX_TRY(reader.vector<3>("angular_velocity", body.angularVelocity));
  HYDROTEX_TRY(reader.integer("resolution", body.resolution));
  std::string method = "auto";
  HYDROTEX_TRY(reader.string("method", method));
  if (method == "texture") {
    body.method = HydrostaticsMethod::Texture;
  } else if (method == "polyhedral" || method == "exact") {
    body.method = HydrostaticsMethod::Polyhedral;
  } else if (method == "auto") {
    body.method = HydrostaticsMethod::Auto;
  } else {
    return reader.error("method", "'" + method + "' is not one of texture, polyhedral, auto");
  }
  HYDROTEX_TRY(reader.number("auto_method_error", body.autoMethodError));
  if (!(body.autoMethodError > 0.0) || !std::isfinite(body.autoMethodError))
    return reader.error("auto_method_error", "must be positive and finite");
  if (const Json* effects = reader.find("effects")) {
    if (!effects->is_array()) return reader.error("effects", "expected an array of effect names");
    body.effects = EffectSet{};
    for (const Json& item : *effects) {
      if (!item.is_string()) return reader.error("effects", "expected an array of effect names");
      const std::optional<Effect> effect = effectFromName(item.get<std::string>());
      if (!effect) return reader.error("effects", "unknown effect '" + item.get<std::string>() + "'");
      body.effects.add(*effect);
    }
  }
  HYDROTEX_TRY(reader.number("shell_density", body.shellDensity));
  if (!(body.shellDensity >= 0.0)) return reader.error("shell_density", "must be >= 0 (kg/m^2)");
  std::string densityMap;
  HYDROTEX_TRY(reader.string("density_map", densityMap));
  const Json* range = reader.find("density_range");
  if (!densityMap.empty()) {
    const std::filesystem::path mapPath = std::filesystem::path(baseDirectory) / densityMap;
    Expected<ImageMap> image = loadImageMap(mapPath.string());
    if (!image) return reader.error("density_map", image.error().message);
    body.densityMap = std::make_shared<const ImageMap>(std::move(image).value());
    if (range == nullptr) return reader.error("density_range", "missing ([min, max] kg/m^3 for black and white)");
  }
  if (range != nullptr) {
    if (densityMap.empty()) return reader.error("density_range", "given without density_map");
    if (!range->is_array() || range->size() != 2 || !(*range)[0].is_number() || !(*range)[1].is_number()) {
      return reader.error("density_range", "expected [min, max] (kg/m^3)");
    }
    body.densityRange = {(*range)[0].get<double>(), (*range)[1].get<double>()};
    if (!(body.densityRange[0] >= 0.0 && body.densityRange[1] >= 0.0) || !std::isfinite(body.densityRange[0]) ||
        !std::isfinite(body.densityRange[1])) {
      return reader.error("density_range", "densities must be >= 0 and finite");
    }
  }
  if (const Json* points = reader.find("point_masses")) {
    if (!points->is_array()) return reader.error("point_masses", "expected an array of {mass, position, path}");
    for (std::size_t i = 0; i < points->size(); ++i) {
      const std::string pointPath = reader.keyPath("point_masses") + "[" + std::to_string(i) + "]";
      const Json& item = (*points)[i];
      if (!item.is_object()) return Error{source + ": " + pointPath + ": expected an object"};
      ObjectReader pointReader(item, pointPath, source);
      PointMass point;
      if (item.find("mass") == item.end()) return pointReader.error("mass", "missing (kg)");
      HYDROTEX_TRY(pointReader.number("mass", point.mass));
      if (!(point.mass >= 0.0)) return pointReader.error("mass", "must be >= 0 (kg)");
      HYDROTEX_TRY(pointReader.vector<3>("position", point.position));
      if (const Json* keys = pointReader.find("path")) {
        if (!keys->is_array()) return pointReader.error("path", "expected an array of [t, x, y, z]");
        for (std::size_t k = 0; k < keys->size(); ++k) {
          const Json& key = (*keys)[k];
          const std::string keyName = "path[" + std::to_string(k) + "]";
          if (!key.is_array() || key.size() != 4) return pointReader.error(keyName, "expected [t, x, y, z]");
          double values[4];
          for (std::size_t c = 0; c < 4; ++c) {
            if (!key[c].is_number()) return pointReader.error(keyName, "expected [t, x, y, z]");
            values[c] = key[c].get<double>();
            if (!std::isfinite(values[c])) return pointReader.error(keyName, "not finite");
          }
          if (k > 0 && !(values[0] > point.path.back().time)) {
            return pointReader.error(keyName, "time must be after the previous key's");
          }
          point.path.push_back({values[0], Eigen::Vector3d(values[1], values[2], values[3])});
        }
        if (point.path.empty()) return pointReader.error("path", "expected at least one key");
      }
      HYDROTEX_TRY(pointReader.rejectUnknown());
      body.pointMasses.push_back(std::move(point));
    }
  }
  if (const Json* deform = reader.find("deform")) {
    const std::string deformPath = reader.keyPath("deform");
    if (!deform->is_object()) return reader.error("deform", "expected {type: \"scale\", keyframes: [...]}");
    ObjectReader deformReader(*deform, deformPath, source);
    std::string type;
    HYDROTEX_TRY(deformReader.string("type", type));
    if (type != "scale") return deformReader.error("type", "'" + type + "' is not one of scale");
    const Json* keys = deformReader.find("keyframes");
    if (keys == nullptr || !keys->is_array() || keys->empty()) {
      return deformReader.error("keyframes", "expected a non-empty array of [t, sx, sy, sz]");
    }
    for (std::size_t k = 0; k < keys->size(); ++k) {
      const Json& key = (*keys)[k];
      const std::string keyName = "keyframes[" + std::to_string(k) + "]";
      if (!key.is_array() || key.size() != 4) return deformReader.error(keyName, "expected [t, sx, sy, sz]");
      double values[4];
      for (std::size_t c = 0; c < 4; ++c) {
        if (!key[c].is_number()) return deformReader.error(keyName, "expected [t, sx, sy, sz]");
        values[c] = key[c].get<double>();
        if (!std::isfinite(values[c])) return deformReader.error(keyName, "not finite");
      }
      if (!(values[1] > 0.0 && values[2] > 0.0 && values[3] > 0.0)) return deformReader.error(keyName, "scales must be > 0");
      if (k > 0 && !(values[0] > body.scaleKeyframes.back().time)) {
        return deformReader.error(keyName, "time must be after the previous key's");
      }
      body.scaleKeyframes.push_back({values[0], Eigen::Vector3d(values[1], values[2], values[3])});
    }
    HYDROTEX_TRY(deformReader.rejectUnknown());
    if (!body.effects.has(Effect::Deformation)) {
      return reader.error("deform", "needs \"deformation\" in effects");
    }
  } else if (body.effects.has(Effect::Deformation)) {
    return reader.error("effects", "'deformation' needs a deform key");
  }
  HYDROTEX_TRY(parseFlooding(reader, baseDirectory, body));
  if (const Json* wetting = reader.find("wetting")) {
    if (Expected<WettingBodySettings> parsed = parseWetting(*wetting, reader.keyPath("wetting"), source); parsed) {
      body.wetting = std::move(parsed).value();
    } else {
      return parsed.error();
    }
    if (!body.effects.has(Effect::Wetting)) return reader.error("wetting", "needs \"wetting\" in effects");
  }
  HYDROTEX_TRY(detail::parseSoftBody(reader.find("soft"), reader.find("soft_material"), path, source, body));
  HYDROTEX_TRY(reader.rejectUnknown());
  const bool hollow = body.shellDensity > 0.0 || body.densityMap != nullptr;
  if (!body.density && !body.mass && !hollow) {
    return Error{source + ": " + path + ": needs density or mass (or a shell_density or density_map)"};
  }
  if (body.density && body.mass) return Error{source + ": " + path + ": give density or mass, not both"};
  if (body.density && !(*body.density > 0.0)) return reader.error("density", "must be > 0");
  if (body.mass && !(*body.mass > 0.0)) return reader.error("mass", "must be > 0");
  if (body.resolution < 16 || body.resolution > 4096) return reader.error("resolution", "must lie in 16..4096");
  if (body.soft) HYDROTEX_TRY(detail::checkSoftBody(body, path, source));
  return body;
}

}  // namespace

long long Scene::stepCount() const {
  if (!(dt > 0.0) || !(duration >= 0.0)) return 0;
  return static_cast<long long>(std::llround(duration / dt));
}

Status Scene::validate() const {
  const std::string prefix = sourceName.empty() ? std::string("scene") : sourceName;
  if (!gravity.allFinite()) return Error{prefix + ": gravity: not finite"};
  if (!(std::isfinite(dt) && dt > 0.0 && dt <= 1.0)) return Error{prefix + ": dt: must lie in (0, 1] s"};
  if (!(std::isfinite(duration) && duration >= 0.0 && duration / dt <= 1e8)) {
    return Error{prefix + ": duration: must be >= 0 and at most 1e8 steps"};
  }
  if (substeps < 1 || substeps > 64) return Error{prefix + ": substeps: must lie in 1..64"};
  if (!(std::isfinite(fluidDensity) && fluidDensity > 0.0)) return Error{prefix + ": fluid.density: must be > 0"};
  if (!(std::isfinite(viscosity) && viscosity >= 0.0)) return Error{prefix + ": fluid.viscosity: must be >= 0"};
  if (!fluidVelocity.allFinite()) return Error{prefix + ": fluid.velocity: not finite"};
  if (seabed && !std::isfinite(*seabed)) return Error{prefix + ": seabed: not finite"};
  if (bodies.empty() && softBodies.empty()) return Error{prefix + ": bodies: at least one body is needed"};
  if (threads < 0) return Error{prefix + ": threads: " + std::to_string(threads) + ": must be >= 0 (0: all cores)"};
  return Ok{};
}

Status checkControllerBackend(const std::string& name) {
  if (name == "cpu" || name == "gpu" || name == "auto") return Ok{};
  return Error{"\"" + name + "\": expected \"cpu\", \"gpu\" or \"auto\""};
}

Expected<Scene> parseScene(const std::string& text, const std::string& baseDirectory, const std::string& sourceName) {
  const Json json = Json::parse(text, nullptr, false);
  if (json.is_discarded()) return Error{sourceName + ": not valid JSON"};
  if (!json.is_object()) return Error{sourceName + ": expected a JSON object at the top level"};
  ObjectReader reader(json, "", sourceName);
  Scene scene;
  scene.sourceName = sourceName;
  HYDROTEX_TRY(reader.vector<3>("gravity", scene.gravity));
  HYDROTEX_TRY(reader.number("dt", scene.dt));
  HYDROTEX_TRY(reader.number("duration", scene.duration));
  HYDROTEX_TRY(reader.integer("substeps", scene.substeps));
  if (const Json* threads = reader.find("threads")) {
    if (!threads->is_number_integer() || threads->get<long long>() < 0 ||
        threads->get<long long>() > std::numeric_limits<int>::max()) {
      return reader.error("threads", threads->dump() + ": expected a whole number >= 0 (0: all cores)");
    }
    scene.threads = threads->get<int>();
  }
  HYDROTEX_TRY(reader.string("backend", scene.backend));
  if (Status s = checkControllerBackend(scene.backend); !s) return reader.error("backend", s.error().message);
  if (const Json* fluid = reader.find("fluid")) {
    if (!fluid->is_object()) return reader.error("fluid", "expected an object");
    ObjectReader fluidReader(*fluid, "fluid", sourceName);
    HYDROTEX_TRY(fluidReader.number("density", scene.fluidDensity));
    HYDROTEX_TRY(fluidReader.number("viscosity", scene.viscosity));
    HYDROTEX_TRY(fluidReader.vector<3>("velocity", scene.fluidVelocity));
    if (const Json* surface = fluidReader.find("surface")) {
      Expected<SceneSurface> parsed = parseSurface(*surface, "fluid.surface", sourceName);
      if (!parsed) return parsed.error();
      scene.surface = std::move(parsed).value();
    }
    HYDROTEX_TRY(fluidReader.rejectUnknown());
  }
  std::optional<double> seabed;
  HYDROTEX_TRY(reader.optionalNumber("seabed", seabed));
  scene.seabed = seabed;
  const Json* bodies = reader.find("bodies");
  if (bodies == nullptr) return reader.error("bodies", "missing (a list of bodies)");
  if (!bodies->is_array()) return reader.error("bodies", "expected an array");
  std::set<std::string> names;
  for (std::size_t i = 0; i < bodies->size(); ++i) {
    const std::string path = "bodies[" + std::to_string(i) + "]";
    Expected<SceneBody> body = parseBody((*bodies)[i], path, sourceName, baseDirectory);
    if (!body) return body.error();
    if (body->name.empty()) body->name = "body" + std::to_string(i);
    if (!names.insert(body->name).second) return Error{sourceName + ": " + path + ".name: '" + body->name + "' is used twice"};
    (body->soft ? scene.softBodies : scene.bodies).push_back(std::move(body).value());
  }
  HYDROTEX_TRY(reader.rejectUnknown());
  if (Status s = scene.validate(); !s) return s.error();
  return scene;
}

Expected<Scene> loadScene(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": no such file"};
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot be read"};
  std::ostringstream text;
  text << in.rdbuf();
  const std::string base = std::filesystem::path(path).parent_path().string();
  return parseScene(text.str(), base.empty() ? "." : base, path);
}

std::shared_ptr<const LiquidSurface> makeSceneSurface(const Scene& scene) {
  switch (scene.surface.type) {
    case SceneSurface::Type::Waves:
      return std::make_shared<GerstnerWaves>(scene.surface.waves, scene.surface.height, scene.fluidDensity,
                                             std::max(1e-9, scene.gravity.norm()));
    case SceneSurface::Type::None:
      return std::make_shared<UniformMedium>(scene.fluidDensity, std::numeric_limits<double>::infinity(), 0.0);
    case SceneSurface::Type::Plane:
    default:
      return std::make_shared<FlatSurface>(scene.surface.height, scene.fluidDensity);
  }
}

Expected<std::unique_ptr<SceneWorld>> SceneWorld::create(const Scene& scene, const SceneBackendFactory& makeBackend) {
  if (Status s = scene.validate(); !s) return s.error();
  std::unique_ptr<SceneWorld> self(new SceneWorld());
  self->scene_ = scene;
  // Soft bodies need Bullet's soft-rigid world; scenes without them keep the plain one.
  const bool soft = !scene.softBodies.empty();
  if (soft) {
    self->configuration_ = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  } else {
    self->configuration_ = std::make_unique<btDefaultCollisionConfiguration>();
  }
  self->dispatcher_ = std::make_unique<btCollisionDispatcher>(self->configuration_.get());
  self->broadphase_ = std::make_unique<btDbvtBroadphase>();
  self->solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
  if (soft) {
    self->softSolver_ = std::make_unique<btDefaultSoftBodySolver>();
    auto softWorld = std::make_unique<btSoftRigidDynamicsWorld>(self->dispatcher_.get(), self->broadphase_.get(),
                                                                self->solver_.get(), self->configuration_.get(),
                                                                self->softSolver_.get());
    btSoftBodyWorldInfo& info = softWorld->getWorldInfo();
    info.m_gravity = toBullet(scene.gravity);
    info.m_broadphase = self->broadphase_.get();
    info.m_dispatcher = self->dispatcher_.get();
    info.air_density = 0;  // the controller's liquid, not Bullet's aerodynamics, acts on the nodes
    info.m_sparsesdf.Initialize();
    self->world_ = std::move(softWorld);
  } else {
    self->world_ = std::make_unique<btDiscreteDynamicsWorld>(self->dispatcher_.get(), self->broadphase_.get(),
                                                             self->solver_.get(), self->configuration_.get());
  }
  self->world_->setGravity(toBullet(scene.gravity));

  LiquidSettings liquid;
  liquid.surface = makeSceneSurface(scene);
  liquid.viscosity = scene.viscosity;
  liquid.current = toBullet(scene.fluidVelocity);
  if (Status s = liquid.validate(); !s) return Error{scene.sourceName + ": fluid: " + s.error().message};
  ControllerSettings controllerSettings;
  controllerSettings.threads = scene.threads;
  if (Status s = checkControllerBackend(scene.backend); !s) return Error{scene.sourceName + ": backend: " + s.error().message};
  if (makeBackend) {
    Expected<std::shared_ptr<ComputeBackend>> backend = makeBackend(scene.backend);
    if (!backend) return Error{scene.sourceName + ": backend: " + backend.error().message};
    controllerSettings.backend = *backend;
  } else if (scene.backend == "gpu") {
    return Error{scene.sourceName + ": backend: \"gpu\": this program was given no GL backend (SceneWorld::create's "
                 "makeBackend; the hydrotex tool and demos pass hydrotex::gpu::makeBackend)"};
  }
  self->controller_ = std::make_unique<BuoyancyController>(*self->world_, liquid, controllerSettings);
  self->world_->addAction(self->controller_.get());

  if (scene.seabed) {
    auto plane = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(*scene.seabed));
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, plane.get());
    auto floor = std::make_unique<btRigidBody>(info);
    self->world_->addRigidBody(floor.get());
    self->shapes_.push_back(std::move(plane));
    self->rigidBodies_.push_back(std::move(floor));
  }

  std::map<std::string, std::shared_ptr<const Mesh>> meshCache;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const SceneBody& sceneBody = scene.bodies[i];
    const std::string prefix = scene.sourceName + ": bodies[" + std::to_string(i) + "]: ";
    std::shared_ptr<const Mesh> mesh = sceneBody.mesh;
    std::unique_ptr<btCollisionShape> collision;
    if (sceneBody.shape && !mesh) {
      // A Bullet primitive: no mesh here, the controller meshes the body's shape.
      collision = detail::createSceneShape(*sceneBody.shape);
    } else if (!mesh) {
      // The same file read with other axes, scale or repairs is another mesh.
      const MeshLoadSettings& load = sceneBody.load;
      const std::string key = sceneBody.meshPath + (load.up == UpAxis::Z ? "|z|" : "|y|") + std::to_string(load.scale) +
                              (load.repair.enabled ? "|repair|" : "|as-is|") + std::to_string(load.repair.maxHoleFraction) +
                              (load.repair.openHull ? "|open" : "");
      auto cached = meshCache.find(key);
      if (cached == meshCache.end()) {
        Expected<Mesh> loaded = loadSceneMesh(sceneBody);
        if (!loaded) return Error{prefix + loaded.error().message};
        cached = meshCache.emplace(key, std::make_shared<const Mesh>(std::move(loaded).value())).first;
      }
      mesh = cached->second;
    }
    if (!collision) {
      if (mesh->positions.empty()) return Error{prefix + "mesh: no vertices"};
      // Collision: the convex hull of the mesh, in the mesh frame (the controller offsets it).
      auto hull = std::make_unique<btConvexHullShape>();
      for (const Eigen::Vector3d& p : mesh->positions) hull->addPoint(toBullet(p), false);
      // Bullet inflates a convex hull by its collision margin (0.04 m by default) beyond its points:
      // a 30 cm clay pot would stand 4 cm proud of the floor, jump there at its first contact and
      // never reach water 3 cm deep. A margin of kHullMarginFraction of the smallest extent keeps
      // contacts robust for large bodies (ships keep Bullet's default) without lifting small ones.
      Eigen::Vector3d lower = mesh->positions.front(), upper = lower;
      for (const Eigen::Vector3d& p : mesh->positions) {
        lower = lower.cwiseMin(p);
        upper = upper.cwiseMax(p);
      }
      const Eigen::Vector3d extent = upper - lower;
      hull->setMargin(btScalar(std::min(double(hull->getMargin()), std::max(kHullMarginFloor, kHullMarginFraction * extent.minCoeff()))));
      hull->recalcLocalAabb();
      collision = std::move(hull);
    }
    const Pose pose = Pose::fromDegreesXYZ(sceneBody.rotationDegrees, sceneBody.position);
    btTransform start(toBulletBasis(pose.rotation), toBullet(pose.translation));
    auto motionState = std::make_unique<btDefaultMotionState>(start);
    btRigidBody::btRigidBodyConstructionInfo info(1, motionState.get(), collision.get(), btVector3(1, 1, 1));
    auto body = std::make_unique<btRigidBody>(info);
    FloatingBodySettings settings;
    settings.mesh = mesh;
    settings.resolution = sceneBody.resolution;
    settings.method = sceneBody.method;
    settings.autoMethodError = sceneBody.autoMethodError;
    settings.density = sceneBody.density;
    settings.mass = sceneBody.mass;
    settings.effects = sceneBody.effects;
    settings.shellDensity = sceneBody.shellDensity;
    settings.densityMap = sceneBody.densityMap;
    settings.densityRange = sceneBody.densityRange;
    settings.pointMasses = sceneBody.pointMasses;
    settings.scaleKeyframes = sceneBody.scaleKeyframes;
    settings.wetting = sceneBody.wetting;
    settings.flooding = sceneBody.flooding;
    if (Status s = self->controller_->addBody(body.get(), settings); !s) return Error{prefix + s.error().message};
    body->setLinearVelocity(toBullet(sceneBody.linearVelocity));
    body->setAngularVelocity(toBullet(sceneBody.angularVelocity));
    self->world_->addRigidBody(body.get());
    self->bodyPointers_.push_back(body.get());
    self->shapes_.push_back(std::move(collision));
    self->motionStates_.push_back(std::move(motionState));
    self->rigidBodies_.push_back(std::move(body));
  }
  for (std::size_t i = 0; i < scene.softBodies.size(); ++i) {
    const SceneBody& sceneBody = scene.softBodies[i];
    const std::string prefix = scene.sourceName + ": soft body '" + sceneBody.name + "': ";
    std::shared_ptr<const Mesh> mesh = sceneBody.mesh;
    if (!mesh) {
      Expected<Mesh> loaded = loadSceneMesh(sceneBody);
      if (!loaded) return Error{prefix + loaded.error().message};
      mesh = std::make_shared<const Mesh>(std::move(loaded).value());
    }
    Expected<std::unique_ptr<btSoftBody>> created = detail::createSceneSoftBody(
        sceneBody, *mesh, static_cast<btSoftRigidDynamicsWorld&>(*self->world_), *self->controller_);
    if (!created) return Error{prefix + created.error().message};
    self->softBodyPointers_.push_back(created->get());
    self->softBodies_.push_back(std::move(created).value());
  }
  return self;
}

SceneWorld::~SceneWorld() {
  if (world_ && controller_) world_->removeAction(controller_.get());
  controller_.reset();  // gives the bodies their own shapes back while they still exist
  for (auto& softBody : softBodies_) {
    if (world_) static_cast<btSoftRigidDynamicsWorld&>(*world_).removeSoftBody(softBody.get());
  }
  for (auto& body : rigidBodies_) {
    if (world_) world_->removeRigidBody(body.get());
  }
}

void SceneWorld::step() {
  // One fixed sub-step per call: stepSimulation's own accumulator, in btScalar, may round
  // dt / substeps to one sub-step too few or too many.
  const btScalar fixed = btScalar(scene_.dt / scene_.substeps);
  for (int i = 0; i < scene_.substeps; ++i) world_->stepSimulation(fixed, 1, fixed);
  time_ += scene_.dt;
}

}  // namespace hydrotex::bullet
