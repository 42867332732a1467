// SPDX-License-Identifier: Zlib
#include "hydrotex/bake/BodyGeometry.hpp"

#include "hydrotex/mesh/MeshIO.hpp"

#include <algorithm>

namespace hydrotex {

Expected<BodyGeometry> prepareBodyGeometry(Mesh mesh, const BodyGeometrySettings& settings) {
  if (Status valid = settings.bake.validate(); !valid) return valid.error();
  const std::string name = mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName;
  if (mesh.triangles.empty()) return Error{name + ": mesh has no triangles"};

  BodyGeometry body;
  body.report = validateMesh(mesh);
  if (body.report.degenerateTriangles == body.report.triangleCount)
    return Error{name + ": every triangle is degenerate (zero area)"};
  if (settings.requireClosed) {
    if (Status closed = requireClosed(body.report, name); !closed) return closed.error();
    if (!body.report.outwardOriented)
      return Error{name + ": mesh is closed but oriented inwards (negative volume); flip its triangles"};
  }
  body.atlas = physicsAtlas(mesh, body.report, std::max(settings.bake.width, settings.bake.height));
  Expected<SurfaceBake> bake = bakeSurface(mesh, body.atlas.layout, settings.bake);
  if (!bake) return Error{name + ": " + bake.error().message};
  body.bake = std::move(bake).value();
  body.textures = evaluateSurface(body.bake, mesh, body.atlas.layout);
  body.mesh = std::move(mesh);
  return body;
}

Expected<BodyGeometry> loadBodyGeometry(const std::string& path, const BodyGeometrySettings& settings) {
  RepairReport repairs;
  Expected<Mesh> mesh = loadMesh(path, settings.load, &repairs);
  if (!mesh) return mesh.error();
  if (settings.requireClosed)
    if (Status repaired = repairs.requireRepaired(mesh->sourceName); !repaired) return repaired.error();
  Expected<BodyGeometry> body = prepareBodyGeometry(std::move(mesh).value(), settings);
  if (body) body->repairs = std::move(repairs);
  return body;
}

}  // namespace hydrotex
