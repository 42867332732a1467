// SPDX-License-Identifier: Zlib
#pragma once
/// @file MeshRepair.hpp
/// Repairs of the defects real meshes bring (near-coincident vertices, collapsed triangles,
/// flipped faces, inside-out parts, small holes), each reported with its size; what cannot be
/// repaired is named so that a closed body can be refused with one line.

#include <cstddef>
#include <string>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// What repairMesh may do.
struct RepairSettings {
  /// False: nothing is repaired (tool `--no-repair`, scene `"repair": false`); a defective mesh is
  /// then refused by the closed-mesh checks (MeshValidation.hpp).
  bool enabled = true;
  /// Vertices closer than this fraction of the bounding-box diagonal are welded (default 1e-7:
  /// float rounding of exported coordinates is about 1e-7 relative, a real feature is far larger).
  double weldFraction = 1e-7;
  /// A boundary loop is closed when its perimeter is at most this fraction of the bounding-box
  /// diagonal (default 0.1: the WAM-V's pontoon-end holes, 0.07 of its diagonal, close; the
  /// DTMB 5512's open transom, 0.26, and a dinghy's open top, 2.3, do not). 0 closes no hole
  /// by its perimeter.
  double maxHoleFraction = 0.1;
  /// ... or when its cap's area is at most this fraction of the mesh's surface area (default 1e-4:
  /// long thin slits between panels, whose perimeter is large but which enclose next to nothing).
  double maxHoleAreaFraction = 1e-4;
  /// True: a boundary loop too large to be a hole (beyond both limits above) is taken as the
  /// opening of an open hull by design (a dinghy's gunwale, an open transom) and capped by a lid
  /// that closes the volume but is no material: its triangles are listed in
  /// Mesh::openingTriangles, carry no shell mass and let liquid in as an open hole (tool
  /// `--open-hull`, scene key `"open_hull": true`). False (default): such a loop is refused.
  bool openHull = false;
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// One hole closed (or one opening capped by a lid) by a triangle fan from its loop's centroid.
struct ClosedHole {
  std::size_t edges = 0;   ///< boundary edges of the loop
  double perimeter = 0.0;  ///< length of the loop (m)
  double area = 0.0;       ///< area of the cap (m^2)
};

/// What repairMesh did and what it could not do.
struct RepairReport {
  std::size_t verticesWelded = 0;         ///< vertices merged into a nearby one
  std::size_t trianglesDropped = 0;       ///< collapsed (repeated corner) or loose zero-area triangles removed
  std::size_t trianglesReoriented = 0;    ///< triangles flipped to agree with their part's neighbours
  std::size_t partsFlipped = 0;           ///< closed parts turned right side out (or to a cavity inside another part)
  double flippedVolume = 0.0;             ///< sum of |volume| of the flipped parts (m^3)
  std::vector<ClosedHole> holesClosed;    ///< holes capped
  std::vector<ClosedHole> lids;           ///< openings capped by a lid (RepairSettings::openHull): no mass, open to liquid
  bool uvsDropped = false;                ///< the artist's UVs were dropped (caps have none): the physics atlas is generated
  /// Defects left, one line each naming the defect, its size and what to do. Empty: the mesh is
  /// closed, manifold and outward oriented per part.
  std::vector<std::string> unrepaired;

  /// True when any repair changed the mesh.
  bool changed() const {
    return verticesWelded + trianglesDropped + trianglesReoriented + partsFlipped + holesClosed.size() + lids.size() > 0;
  }
  /// Multi-line readable list of the repairs and of what is left ("none" when nothing was done).
  std::string summary() const;
  /// Ok, or the first unrepaired defect as "`what`: <defect>" (one line).
  Status requireRepaired(const std::string& what) const;
};

/// Repairs `mesh` in place, in this order: weld vertices closer than settings.weldFraction of the
/// diagonal; drop triangles with repeated corners and zero-area triangles whose removal opens no
/// edge; orient each part consistently (breadth-first over shared edges, keeping its majority);
/// cap boundary loops whose perimeter is at most settings.maxHoleFraction of the diagonal, or
/// whose cap area is at most settings.maxHoleAreaFraction of the surface area (fan
/// from the loop's centroid, one per simple loop where a loop passes a vertex twice; the
/// artist's UVs are then dropped); with settings.openHull, cap the
/// larger loops the same way as lids listed in Mesh::openingTriangles; turn each closed part outward
/// by its signed volume, except that a part inside another keeps the sign of a cavity
/// (MeshParts.hpp). Never touches a file. With settings.enabled false, the mesh is left as it is
/// and the report lists nothing. Errors: invalid settings only; defects left are in `unrepaired`.
Expected<RepairReport> repairMesh(Mesh& mesh, const RepairSettings& settings);

}  // namespace hydrotex
