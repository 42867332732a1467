// SPDX-License-Identifier: Zlib
// The floating body's command line and loading, shared by `equilibrium` and `stability`.

#include "FloatingOptions.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <sstream>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/MeshIO.hpp"

namespace hydrotex::tool {

namespace {

std::string number(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

/// "KG@X,Y,Z" as a mass (kg) and a position (m).
Expected<std::pair<double, Eigen::Vector3d>> parsePointMass(const std::string& text) {
  const Error bad{"--point-mass " + text + ": expected KG@X,Y,Z with a positive mass"};
  const std::size_t at = text.find('@');
  if (at == std::string::npos) return bad;
  std::istringstream in(text.substr(0, at) + " " + text.substr(at + 1));
  double mass = 0.0, x = 0.0, y = 0.0, z = 0.0;
  char c1 = 0, c2 = 0;
  if (!(in >> mass >> x >> c1 >> y >> c2 >> z) || c1 != ',' || c2 != ',') return bad;
  std::string rest;
  if (in >> rest) return bad;
  if (!(std::isfinite(mass) && mass > 0.0) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return bad;
  return std::pair{mass, Eigen::Vector3d(x, y, z)};
}

}  // namespace

void addFloatingOptions(CLI::App& verb, FloatingOptions& options) {
  verb.add_option("MESH", options.meshPath, "closed mesh file")->required();
  CLI::Option* mass = verb.add_option("--mass", options.mass, "mass of the hull (kg); point masses add to it");
  CLI::Option* density = verb.add_option("--density", options.density, "uniform density of the hull (kg/m^3)");
  CLI::Option* displacement = verb.add_option(
      "--displacement", options.displacement, "displaced volume of the whole body (m^3): its mass is that of the liquid");
  CLI::Option* shell = verb.add_option(
      "--shell-density", options.shellDensity,
      "areal density of a hull that is a shell (kg/m^2): its mass and centre from its walls, lids of --open-hull left out");
  mass->excludes(density)->excludes(displacement)->excludes(shell);
  density->excludes(displacement)->excludes(shell);
  displacement->excludes(shell);
  verb.add_option_function<std::vector<double>>(
          "--center-of-mass",
          [&options](const std::vector<double>& v) {
            for (double value : v)
              if (!std::isfinite(value)) throw CLI::ValidationError("--center-of-mass", "must be finite numbers");
            options.centerOfMass = Eigen::Vector3d(v[0], v[1], v[2]);
          },
          "X,Y,Z of the hull's centre of mass (m, file coordinates; default: the uniform solid's, or the shell's)")
      ->delimiter(',')
      ->expected(3);
  verb.add_option("--point-mass", options.pointMasses, "KG@X,Y,Z: a mass added at a point (m, file coordinates); repeatable")
      ->take_all();
  verb.add_option("--fluid-density", options.fluidDensity, "kg/m^3 (default 1000)")->check(CLI::PositiveNumber);
  addMeshLoadOptions(verb, options.load);
  verb.add_option("--method", options.method, "exact, texture, or auto (default: exact, which a closed mesh allows)")
      ->check(CLI::IsMember({"exact", "texture", "auto"}));
  addResolutionOption(verb, options.resolution);
  verb.add_option("--backend", options.backend, "cpu (default) or gpu: where the texture path's passes run")
      ->check(CLI::IsMember({"cpu", "gpu"}));
}

Expected<std::unique_ptr<FloatingSetup>> loadFloatingBody(const FloatingOptions& options) {
  if (!options.mass && !options.density && !options.displacement && !options.shellDensity)
    return Error{"give the body's mass: --mass KG, --density KG_M3, --shell-density KG_M2 or --displacement M3"};
  if (options.shellDensity && !(std::isfinite(*options.shellDensity) && *options.shellDensity > 0.0))
    return Error{"--shell-density " + number(*options.shellDensity) + ": must be positive"};
  if (options.mass && !(std::isfinite(*options.mass) && *options.mass > 0.0))
    return Error{"--mass " + number(*options.mass) + ": must be positive"};
  if (options.density && !(std::isfinite(*options.density) && *options.density > 0.0))
    return Error{"--density " + number(*options.density) + ": must be positive"};
  if (options.displacement && !(std::isfinite(*options.displacement) && *options.displacement > 0.0))
    return Error{"--displacement " + number(*options.displacement) + ": must be positive"};
  std::vector<std::pair<double, Eigen::Vector3d>> points;
  for (const std::string& text : options.pointMasses) {
    Expected<std::pair<double, Eigen::Vector3d>> point = parsePointMass(text);
    if (!point) return point.error();
    points.push_back(*point);
  }

  auto setup = std::make_unique<FloatingSetup>();
  RepairReport repairs;
  Expected<Mesh> mesh = loadMesh(options.meshPath, options.load, &repairs);  // --up, --scale, repairs
  if (!mesh) return mesh.error();
  if (Status repaired = repairs.requireRepaired(options.meshPath); !repaired) return repaired.error();
  setup->mesh = std::move(mesh).value();
  setup->mesh.sourceName = options.meshPath;  // messages start with the path, once
  // The same axes as loadMesh's conversion (MeshIO.hpp): --up z is -90 degrees about x.
  if (options.load.up == UpAxis::Z) setup->fromFile << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  setup->fileScale = options.load.scale;

  Expected<MassProperties> solid = polyhedralMassProperties(setup->mesh, 1.0);
  if (!solid) return solid.error();  // its messages start with the mesh's name
  double pointTotal = 0.0;
  Eigen::Vector3d pointMoment = Eigen::Vector3d::Zero();
  for (const auto& [m, p] : points) {
    pointTotal += m;
    pointMoment += m * (setup->fileScale * (setup->fromFile * p));
  }
  double hull = 0.0;
  if (options.mass) hull = *options.mass;
  if (options.density) hull = *options.density * solid->volume;
  Eigen::Vector3d defaultCenter = solid->centerOfMass;
  if (options.shellDensity) {
    // A shell: an open hull's mass is its walls', centred where they are (not in the space under its lid).
    Expected<MassProperties> shell = polyhedralShellMassProperties(setup->mesh, *options.shellDensity);
    if (!shell) return shell.error();
    hull = shell->mass;
    defaultCenter = shell->centerOfMass;
  }
  if (options.displacement) {
    hull = options.fluidDensity * *options.displacement - pointTotal;
    if (hull <= 0.0)
      return Error{"--displacement " + number(*options.displacement) + " m^3: the point masses (" + number(pointTotal) +
                   " kg) already weigh more than the liquid it displaces"};
  }
  const Eigen::Vector3d hullCenter =
      options.centerOfMass ? Eigen::Vector3d(setup->fileScale * (setup->fromFile * *options.centerOfMass)) : defaultCenter;
  setup->body.mass = hull + pointTotal;
  setup->body.centerOfMass = (hull * hullCenter + pointMoment) / setup->body.mass;
  setup->settings.fluidDensity = options.fluidDensity;

  setup->method.method = options.method == "auto" ? "exact" : options.method;
  setup->method.resolution = options.resolution;
  setup->method.backend = options.backend;
  if (setup->method.texture()) {
    BodyGeometrySettings settings;
    settings.bake.width = settings.bake.height = options.resolution;
    Expected<BodyGeometry> body = prepareBodyGeometry(setup->mesh, settings);
    if (!body) return body.error();
    Expected<BackendBody> registered =
        registerWithBackend(options.backend, body->bake, body->textures, setup->body.centerOfMass);
    if (!registered) return Error{options.meshPath + ": " + registered.error().message};
    setup->backend = std::move(registered->backend);
    setup->water = std::make_unique<FlatSurface>(0.0, options.fluidDensity);
    ComputeBackend* backend = setup->backend.get();
    const FlatSurface* water = setup->water.get();
    const BackendBodyId id = registered->id;
    setup->answer = [backend, water, id](const HydrostaticsQuery& query) -> Expected<HydrostaticsResult> {
      HydrostaticsResult result;
      const BackendHydrostaticsQuery batch[] = {{id, query}};
      if (Status done = backend->hydrostatics(*water, batch, std::span(&result, 1)); !done) return done.error();
      return result;
    };
  }
  return setup;
}

Eigen::Vector3d extrinsicDegreesXYZ(const Eigen::Matrix3d& r) {
  const double k = 180.0 / 3.14159265358979323846;
  const double y = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  return Eigen::Vector3d(std::atan2(r(2, 1), r(2, 2)), y, std::atan2(r(1, 0), r(0, 0))) * k;
}

void addFloatingJson(nlohmann::json& out, const FloatingSetup& setup) {
  out["mass"] = setup.body.mass;
  out["center_of_mass"] = toJson(Eigen::Vector3d(setup.fromFile.transpose() * setup.body.centerOfMass / setup.fileScale));
  out["fluid_density"] = setup.settings.fluidDensity;
  setup.method.addTo(out, setup.backend.get());
}

}  // namespace hydrotex::tool
