// `hydrotex inspect MESH [--json]`

#include <sstream>

#include "ToolSupport.hpp"
#include "Verbs.hpp"
#include "hydrotex/MeshIO.hpp"
#include "hydrotex/MeshValidation.hpp"

namespace hydrotex::tool {

namespace {
struct InspectOptions {
  std::string meshPath;
  bool json = false;
};

int runInspect(const InspectOptions& options) {
  Expected<Mesh> mesh = loadMesh(options.meshPath);
  if (!mesh) return reportError(mesh.error());
  const MeshReport report = validateMesh(*mesh);

  nlohmann::json out;
  out["triangles"] = report.triangleCount;
  out["vertices"] = report.vertexCount;
  out["watertight"] = report.watertight;
  out["outward_oriented"] = report.outwardOriented;
  out["has_uv"] = report.hasUv;
  out["uv_overlap"] = report.uvOverlap;
  out["uv_usable_as_atlas"] = report.uvUsableAsAtlas();
  out["degenerate_triangles"] = report.degenerateTriangles;
  out["boundary_edges"] = report.boundaryEdges;
  out["non_manifold_edges"] = report.nonManifoldEdges;
  out["area"] = report.area;
  out["volume"] = report.volume ? nlohmann::json(*report.volume) : nlohmann::json(nullptr);
  out["bounds_min"] = toJson(report.boundsMin);
  out["bounds_max"] = toJson(report.boundsMax);

  std::ostringstream text;
  text << options.meshPath << "\n" << report.summary();
  if (!report.summary().empty() && report.summary().back() != '\n') text << "\n";
  printResult(options.json, out, text.str());
  return 0;
}
}  // namespace

void addInspectVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<InspectOptions>();
  CLI::App* verb = addVerb(app, action, "inspect", "counts, watertightness, UVs, area, volume and bounds of a mesh", options, &runInspect);
  verb->add_option("MESH", options->meshPath, "mesh file (any format assimp reads)")->required();
}

}  // namespace hydrotex::tool
