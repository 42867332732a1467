// SPDX-License-Identifier: Zlib
// `hydrotex mass MESH [--method exact|texture] [--resolution N] [--density KG_M3]
//                     [--density-map PNG --density-range MIN,MAX] [--json]`

#include <cmath>
#include <span>
#include <sstream>

#include "ToolSupport.hpp"
#include "Verbs.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/MeshIO.hpp"

namespace hydrotex::tool {

namespace {
struct MassOptions {
  std::string meshPath;
  MethodOptions method;
  MeshLoadSettings load;
  double density = 1000.0;
  std::string densityMapPath;
  std::vector<double> densityRange;
  bool json = false;
};

/// The texture path on the chosen backend; `backendUsed` reports what ran it.
Expected<MassProperties> textureMass(const MassOptions& options, std::unique_ptr<ComputeBackend>& backendUsed) {
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = options.method.resolution;
  settings.load = options.load;
  Expected<BodyGeometry> body = loadBodyGeometry(options.meshPath, settings);
  if (!body) return body.error();

  TextureMassModel model;
  model.solidDensity = options.density;
  if (!options.densityMapPath.empty()) {
    Expected<ImageMap> image = loadImageMap(options.densityMapPath);
    if (!image) return image.error();
    const double low = options.densityRange[0], high = options.densityRange[1];
    model.texelDensity = resampleToTexels(*image, body->bake);
    for (float& value : model.texelDensity) value = static_cast<float>(low + (high - low) * value);
  }
  // The cone apex: the solid's centroid (inside convex bodies; for others the cones are signed
  // and still sum to the body), exact from the mesh, which loadBodyGeometry found closed.
  Expected<MassProperties> solid = polyhedralMassProperties(body->mesh, 1.0);
  if (!solid) return Error{options.meshPath + ": " + solid.error().message};
  Expected<BackendBody> registered =
      registerWithBackend(options.method.backend, body->bake, body->textures, solid->centerOfMass);
  if (!registered) return Error{options.meshPath + ": " + registered.error().message};
  MassProperties result;
  const BackendBodyId ids[] = {registered->id};
  if (Status done = registered->backend->massProperties(ids, std::span(&model, 1), std::span(&result, 1)); !done)
    return Error{options.meshPath + ": " + done.error().message};
  backendUsed = std::move(registered->backend);
  return result;
}

int runMass(const MassOptions& options) {
  if (!options.densityMapPath.empty() && !options.method.texture())
    return reportError(Error{"--density-map needs --method texture (the exact path is uniform)"});
  if (!options.densityMapPath.empty() && options.densityRange.size() != 2)
    return reportError(Error{"--density-map needs --density-range MIN,MAX (kg/m^3 for black and white)"});

  Expected<MassProperties> mass = Error{""};
  std::unique_ptr<ComputeBackend> backend;
  if (!options.method.texture()) {
    RepairReport repairs;
    Expected<Mesh> mesh = loadMesh(options.meshPath, options.load, &repairs);
    if (!mesh) return reportError(mesh.error());
    mesh->sourceName = options.meshPath;  // its messages start with the name: the path, once
    if (Status repaired = repairs.requireRepaired(options.meshPath); !repaired) return reportError(repaired.error());
    mass = polyhedralMassProperties(*mesh, options.density);
    if (!mass) return reportError(mass.error());
  } else {
    mass = textureMass(options, backend);
    if (!mass) return reportError(mass.error());
  }

  nlohmann::json out;
  out["mass"] = mass->mass;
  out["volume"] = mass->volume;
  out["center_of_mass"] = toJson(mass->centerOfMass);
  out["inertia"] = toJson(mass->inertia);
  options.method.addTo(out, backend.get());

  std::ostringstream text;
  text.precision(8);
  text << options.method.describe(options.meshPath) << "\n  mass           " << mass->mass << " kg\n  volume         "
       << mass->volume << " m^3\n  centre of mass " << formatVector(mass->centerOfMass)
       << " m\n  inertia about the centre of mass (kg m^2):\n"
       << formatMatrix(mass->inertia);
  printResult(options.json, out, text.str());
  return 0;
}
}  // namespace

void addMassVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<MassOptions>();
  CLI::App* verb = addVerb(app, action, "mass", "mass, volume, centre of mass and inertia of a closed mesh", options,
                           &runMass);
  verb->add_option("MESH", options->meshPath, "closed mesh file")->required();
  addMethodOptions(*verb, options->method);
  addMeshLoadOptions(*verb, options->load);
  verb->add_option("--density", options->density, "uniform solid density (kg/m^3)")
      ->check(CLI::PositiveNumber);
  verb->add_option("--density-map", options->densityMapPath, "PNG whose gray level sets the density")
      ->check(CLI::ExistingFile);
  verb->add_option("--density-range", options->densityRange, "MIN,MAX density (kg/m^3) for black and white")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::NonNegativeNumber);
}

}  // namespace hydrotex::tool
