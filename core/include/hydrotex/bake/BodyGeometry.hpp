// SPDX-License-Identifier: Zlib
#pragma once
/// @file BodyGeometry.hpp
/// Everything baked once for a body, in the order of the data flow (docs/design.md): mesh -> validate ->
/// physics atlas -> exact texel bake -> surface textures. The tool, the plugin and the demos all
/// prepare bodies through this one function.

#include <string>

#include "hydrotex/mesh/Atlas.hpp"
#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/MeshRepair.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// A body's baked geometry (read-only once prepared; per-step state lives elsewhere).
struct BodyGeometry {
  Mesh mesh;                 ///< as loaded (m) and repaired; artist UVs untouched unless a repair dropped them
  RepairReport repairs;      ///< what loadBodyGeometry repaired (empty from prepareBodyGeometry)
  MeshReport report;         ///< validation findings
  PhysicsAtlas atlas;        ///< the UV layout the physics bakes with (artist's or generated)
  SurfaceBake bake;          ///< exact texel pieces
  SurfaceTextures textures;  ///< PT, VAT, areas and texel edges (body frame)
};

/// What prepareBodyGeometry needs besides the mesh.
struct BodyGeometrySettings {
  BakeSettings bake;           ///< resolution and tile size
  bool requireClosed = true;   ///< volume and buoyancy need a closed mesh; drag or wetting alone do not
  MeshLoadSettings load;       ///< axes, units and repairs of loadBodyGeometry (repair on by default)
};

/// Validates `mesh`, picks or generates its physics atlas, bakes and evaluates the textures.
/// Errors: bake settings out of range, an empty mesh, degenerate-only meshes, an open mesh when
/// `requireClosed`, an inward-oriented mesh (the message says to flip it).
Expected<BodyGeometry> prepareBodyGeometry(Mesh mesh, const BodyGeometrySettings& settings);

/// loadMesh(path, settings.load) followed by prepareBodyGeometry; with `requireClosed`, a defect
/// the repair could not fix is refused first (RepairReport::requireRepaired). Every message
/// starts with the file name.
Expected<BodyGeometry> loadBodyGeometry(const std::string& path, const BodyGeometrySettings& settings);

}  // namespace hydrotex
