// SPDX-License-Identifier: Zlib
// `hydrotex hydrostatics MESH [--method exact|texture] [--resolution N] [--translate X,Y,Z]
//   [--rotate-deg RX,RY,RZ] [--water-level H] [--fluid-density KG_M3] [--gravity G] [--json]`

#include <span>
#include <sstream>

#include "ToolSupport.hpp"
#include "Verbs.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex::tool {

namespace {
struct HydrostaticsOptions {
  std::string meshPath;
  MeshLoadSettings load;
  MethodOptions method;
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotateDegrees = Eigen::Vector3d::Zero();
  double waterLevel = 0.0;
  double fluidDensity = 1000.0;
  double gravity = 9.81;
  bool json = false;
};

int runHydrostatics(const HydrostaticsOptions& options) {
  BodyGeometrySettings settings;
  // The exact path needs no bake: the smallest one keeps the shared preparation cheap.
  settings.bake.width = settings.bake.height = options.method.texture() ? options.method.resolution : 16;
  settings.load = options.load;
  Expected<BodyGeometry> body = loadBodyGeometry(options.meshPath, settings);
  if (!body) return reportError(body.error());

  const FlatSurface water(options.waterLevel, options.fluidDensity);
  if (Status valid = water.validate(); !valid) return reportError(valid.error());

  HydrostaticsQuery query;
  query.pose = Pose::fromDegreesXYZ(options.rotateDegrees, options.translate);
  query.gravity = options.gravity;
  // The stiffness's gravity term needs the centre of mass: the uniform solid's, exactly.
  Expected<MassProperties> solid = polyhedralMassProperties(body->mesh, 1.0);
  if (!solid) return reportError(Error{options.meshPath + ": " + solid.error().message});
  query.centerOfMass = solid->centerOfMass;

  Expected<HydrostaticsResult> result = Error{""};
  std::unique_ptr<ComputeBackend> backend;
  if (!options.method.texture()) {
    result = polyhedralHydrostatics(body->mesh, water, query);
  } else {
    Expected<BackendBody> registered =
        registerWithBackend(options.method.backend, body->bake, body->textures, solid->centerOfMass);
    if (!registered) return reportError(Error{options.meshPath + ": " + registered.error().message});
    HydrostaticsResult texture;
    const BackendHydrostaticsQuery batch[] = {{registered->id, query}};
    Status done = registered->backend->hydrostatics(water, batch, std::span(&texture, 1));
    result = done ? Expected<HydrostaticsResult>(texture) : Expected<HydrostaticsResult>(done.error());
    backend = std::move(registered->backend);
  }
  if (!result) return reportError(Error{options.meshPath + ": " + result.error().message});

  nlohmann::json out;
  out["submerged_volume"] = result->submergedVolume;
  out["center_of_buoyancy"] = toJson(result->centerOfBuoyancy);
  out["buoyancy_force"] = toJson(result->buoyancyForce);
  out["torque_about_center_of_mass"] = toJson(result->torqueAboutCenterOfMass);
  out["waterplane_area"] = result->waterplaneArea;
  out["waterplane_centroid"] = toJson(result->waterplaneCentroid);
  out["wetted_area"] = result->wettedArea;
  out["stiffness"] = toJson(result->stiffness);
  options.method.addTo(out, backend.get());

  std::ostringstream text;
  text.precision(8);
  text << options.method.describe(options.meshPath) << ", water at y = " << options.waterLevel << " m\n"
       << "  submerged volume    " << result->submergedVolume << " m^3\n"
       << "  centre of buoyancy  " << formatVector(result->centerOfBuoyancy) << " m\n"
       << "  buoyancy force      " << formatVector(result->buoyancyForce) << " N\n"
       << "  waterplane area     " << result->waterplaneArea << " m^2 at " << formatVector(result->waterplaneCentroid) << "\n"
       << "  wetted area         " << result->wettedArea << " m^2\n"
       << "  stiffness (heave, roll, pitch):\n"
       << formatMatrix(result->stiffness);
  printResult(options.json, out, text.str());
  return 0;
}
}  // namespace

void addHydrostaticsVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<HydrostaticsOptions>();
  CLI::App* verb = addVerb(app, action, "hydrostatics", "submerged volume, buoyancy, waterplane and stiffness at a pose",
                           options, &runHydrostatics);
  verb->add_option("MESH", options->meshPath, "closed mesh file")->required();
  addMethodOptions(*verb, options->method);
  addMeshLoadOptions(*verb, options->load);
  addVector3Option(*verb, "--translate", options->translate, "X,Y,Z translation (m), applied after the rotation");
  addVector3Option(*verb, "--rotate-deg", options->rotateDegrees, "RX,RY,RZ extrinsic X then Y then Z (degrees)");
  verb->add_option("--water-level", options->waterLevel, "height H of the water plane y = H (m)")
      ->check(CLI::Range(-1e9, 1e9));
  verb->add_option("--fluid-density", options->fluidDensity, "kg/m^3 (default 1000)")->check(CLI::PositiveNumber);
  verb->add_option("--gravity", options->gravity, "m/s^2 (default 9.81)")->check(CLI::PositiveNumber);
}

}  // namespace hydrotex::tool
