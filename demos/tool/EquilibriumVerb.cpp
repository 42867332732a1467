// SPDX-License-Identifier: Zlib
// `hydrotex equilibrium MESH (--mass KG | --density KG_M3 | --displacement M3) [--center-of-mass X,Y,Z]
//   [--point-mass KG@X,Y,Z ...] [--fluid-density KG_M3] [--up y|z] [--start-deg HEEL,TRIM]
//   [--method exact|texture|auto] [--json]`: where a free body floats and its metacentric heights.

#include <sstream>

#include "FloatingOptions.hpp"
#include "ToolSupport.hpp"
#include "Verbs.hpp"

namespace hydrotex::tool {

namespace {
struct EquilibriumOptions {
  FloatingOptions body;
  std::vector<double> startDegrees;
  bool json = false;
};

int runEquilibrium(const EquilibriumOptions& options) {
  Expected<std::unique_ptr<FloatingSetup>> setup = loadFloatingBody(options.body);
  if (!setup) return reportError(setup.error());
  FloatingSetup& s = **setup;
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  if (!options.startDegrees.empty()) {
    s.settings.startHeel = options.startDegrees[0] * kDeg;
    s.settings.startTrim = options.startDegrees[1] * kDeg;
  }
  Expected<FloatingEquilibrium> eq = findFloatingEquilibrium(s.mesh, s.body, s.settings, s.answer);
  if (!eq) return reportError(eq.error());

  // The pose of the mesh as the file has it: the up axis's rotation first.
  const Eigen::Matrix3d rotation = eq->pose.rotation * s.fromFile;
  const Eigen::Vector3d rotationDegrees = extrinsicDegreesXYZ(rotation);
  nlohmann::json out;
  out["draft"] = eq->draft;
  out["heel_deg"] = eq->heel / kDeg;
  out["trim_deg"] = eq->trim / kDeg;
  out["pose"] = {{"translation", toJson(eq->pose.translation)}, {"rotation_deg", toJson(rotationDegrees)}};
  out["displaced_volume"] = eq->hydrostatics.submergedVolume;
  out["center_of_buoyancy"] = toJson(eq->hydrostatics.centerOfBuoyancy);
  out["gm_transverse"] = eq->gmTransverse;
  out["gm_longitudinal"] = eq->gmLongitudinal;
  out["waterplane_area"] = eq->hydrostatics.waterplaneArea;
  out["stable"] = eq->stable;
  out["start_unstable"] = eq->startUnstable;
  out["start_gm_transverse"] = eq->startGmTransverse;
  out["start_gm_longitudinal"] = eq->startGmLongitudinal;
  out["converged"] = eq->converged;
  out["iterations"] = eq->iterations;
  out["residual_moment"] = eq->residualMoment;
  addFloatingJson(out, s);

  std::ostringstream text;
  text.precision(8);
  text << s.method.describe(options.body.meshPath) << ", floating in " << s.settings.fluidDensity
       << " kg/m^3, surface at y = 0 (y up)\n"
       << "  mass                " << s.body.mass << " kg\n"
       << "  draft               " << eq->draft << " m (deepest point below the surface)\n"
       << "  heel                " << eq->heel / kDeg << " deg (about x)\n"
       << "  trim                " << eq->trim / kDeg << " deg (about z)\n"
       << "  displaced volume    " << eq->hydrostatics.submergedVolume << " m^3\n"
       << "  centre of buoyancy  " << formatVector(eq->hydrostatics.centerOfBuoyancy) << " m\n"
       << "  GM transverse       " << eq->gmTransverse << " m\n"
       << "  GM longitudinal     " << eq->gmLongitudinal << " m\n"
       << "  waterplane area     " << eq->hydrostatics.waterplaneArea << " m^2\n"
       << "  stable              " << (eq->stable ? "yes" : "no") << "\n"
       << "  pose                translation " << formatVector(eq->pose.translation) << " m, rotation "
       << formatVector(rotationDegrees) << " deg (extrinsic X, Y, Z)\n";
  if (eq->startUnstable)
    text << "note: the start pose is an unstable equilibrium (GM transverse " << eq->startGmTransverse
         << " m, longitudinal " << eq->startGmLongitudinal << " m); the pose above is the nearest stable one found\n";
  if (!eq->converged)
    text << "note: the iteration limit was met with " << eq->residualMoment << " N m of moment left\n";
  printResult(options.json, out, text.str());
  return 0;
}
}  // namespace

void addEquilibriumVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<EquilibriumOptions>();
  CLI::App* verb = addVerb(app, action, "equilibrium",
                           "where a free body floats (draft, heel, trim) and its metacentric heights", options,
                           &runEquilibrium);
  addFloatingOptions(*verb, options->body);
  verb->add_option("--start-deg", options->startDegrees, "HEEL,TRIM the search starts from (degrees; default upright)")
      ->delimiter(',')
      ->expected(2);
}

}  // namespace hydrotex::tool
