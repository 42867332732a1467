// SPDX-License-Identifier: Zlib
/// @file PreparedPolyhedron.cpp
/// Preparing a closed mesh for the exact path: the per-call checks made once and the triangles'
/// constants kept (PolyhedralFlatSums.hpp), which the flat-surface sums then read instead of
/// computing them for every wholly wet triangle.

#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"

#include <span>
#include <string>

#include "hydrostatics/PolyhedralFlatSums.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex {

Expected<PreparedPolyhedron> PreparedPolyhedron::prepare(std::shared_ptr<const Mesh> mesh) {
  if (!mesh) return Error{"exact hydrostatics: no mesh to prepare"};
  if (mesh->triangles.empty()) return Error{"exact hydrostatics: the mesh has no triangles"};
  const std::string name = mesh->sourceName.empty() ? std::string("mesh") : mesh->sourceName;
  const auto count = static_cast<unsigned>(mesh->positions.size());
  for (const Eigen::Vector3i& t : mesh->triangles)
    for (int c = 0; c < 3; ++c)
      if (static_cast<unsigned>(t[c]) >= count) return Error{name + ": a triangle index is out of range"};
  for (std::size_t v = 0; v < mesh->positions.size(); ++v)
    if (!mesh->positions[v].allFinite()) return Error{name + ": vertex " + std::to_string(v) + " is not finite"};
  if (Status closed = checkClosedMesh(*mesh); !closed) return closed.error();

  std::shared_ptr<detail::TriangleConstants[]> constants(new detail::TriangleConstants[mesh->triangles.size()]);
  for (std::size_t t = 0; t < mesh->triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh->triangles[t];
    constants[t] = detail::triangleConstants(mesh->positions[std::size_t(tri[0])].data(),
                                             mesh->positions[std::size_t(tri[1])].data(),
                                             mesh->positions[std::size_t(tri[2])].data());
  }
  PreparedPolyhedron body;
  body.constants_ = std::move(constants);
  body.mesh_ = std::move(mesh);
  return body;
}

std::size_t PreparedPolyhedron::memoryBytes() const {
  return mesh_ ? mesh_->triangles.size() * sizeof(detail::TriangleConstants) : 0;
}

Expected<HydrostaticsResult> polyhedralHydrostatics(const PreparedPolyhedron& body, const LiquidSurface& surface,
                                                    const HydrostaticsQuery& query) {
  const std::optional<double> flat = surface.flatHeight();
  if (!flat) return polyhedralHydrostaticsUnchecked(*body.mesh_, surface, query);
  if (Status valid = validateHydrostaticsQuery(surface, query); !valid) return valid.error();
  const std::span<const detail::TriangleConstants> constants(body.constants_.get(), body.mesh_->triangles.size());
  return detail::flatPolyhedralHydrostatics(*body.mesh_, constants, *flat, surface.density(), query);
}

}  // namespace hydrotex
