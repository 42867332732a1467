// SPDX-License-Identifier: Zlib
// `hydrotex inspect MESH [--up y|z] [--scale S] [--no-repair] [--max-hole-fraction F] [--open-hull] [--json]`

#include <sstream>

#include "ToolSupport.hpp"
#include "Verbs.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"

namespace hydrotex::tool {

namespace {
struct InspectOptions {
  std::string meshPath;
  MeshLoadSettings load;
  bool json = false;
};

int runInspect(const InspectOptions& options) {
  RepairReport repairs;
  Expected<Mesh> mesh = loadMesh(options.meshPath, options.load, &repairs);
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
  out["parts"] = report.parts;
  out["inside_out_parts"] = report.insideOutParts;
  out["up"] = options.load.up == UpAxis::Z ? "z" : "y";
  out["scale"] = options.load.scale;
  out["file_unit_scale"] = mesh->fileUnitScale;
  nlohmann::json repaired;
  repaired["enabled"] = options.load.repair.enabled;
  repaired["vertices_welded"] = repairs.verticesWelded;
  repaired["triangles_dropped"] = repairs.trianglesDropped;
  repaired["triangles_flipped"] = repairs.trianglesReoriented;
  repaired["parts_flipped"] = repairs.partsFlipped;
  repaired["flipped_volume"] = repairs.flippedVolume;
  repaired["uvs_dropped"] = repairs.uvsDropped;
  repaired["holes_closed"] = nlohmann::json::array();
  for (const ClosedHole& hole : repairs.holesClosed)
    repaired["holes_closed"].push_back({{"edges", hole.edges}, {"perimeter", hole.perimeter}, {"area", hole.area}});
  // Openings of an open hull (--open-hull): each capped by a lid with no mass, open to liquid.
  repaired["lids"] = nlohmann::json::array();
  for (const ClosedHole& lid : repairs.lids)
    repaired["lids"].push_back({{"edges", lid.edges}, {"loop_length", lid.perimeter}, {"area", lid.area}});
  repaired["not_repaired"] = repairs.unrepaired;
  out["repairs"] = repaired;

  std::ostringstream text;
  text << options.meshPath << "\n" << (options.load.repair.enabled ? repairs.summary() : "repairs: off (--no-repair)\n")
       << report.summary();
  if (!report.summary().empty() && report.summary().back() != '\n') text << "\n";
  if (std::abs(mesh->fileUnitScale - 1.0) > 1e-12)
    text << "units: the file declares " << mesh->fileUnitScale << " m per unit (applied)\n";
  printResult(options.json, out, text.str());
  return 0;
}
}  // namespace

void addInspectVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<InspectOptions>();
  CLI::App* verb = addVerb(app, action, "inspect", "counts, watertightness, UVs, area, volume and bounds of a mesh", options, &runInspect);
  verb->add_option("MESH", options->meshPath, "mesh file (any format assimp reads)")->required();
  addMeshLoadOptions(*verb, options->load);
}

}  // namespace hydrotex::tool
