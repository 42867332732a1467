// SPDX-License-Identifier: Zlib
#pragma once
/// @file MeshValidation.hpp
/// What a mesh is fit for: closed (volume, buoyancy) or only a surface (drag, wetting), and whether
/// its UVs can serve as the physics atlas (bijective: no two UV triangles overlap).

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <string>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// A triangle is degenerate when its height is below this fraction of its longest edge
/// (twice its area <= kDegenerateRelativeTolerance * longest edge^2). Also used for UV triangles.
inline constexpr double kDegenerateRelativeTolerance = 1e-10;
/// UV overlap counting stops at this many pairs (the answer "overlaps" is known long before).
inline constexpr std::size_t kMaxCountedUvOverlaps = 100'000;

/// The findings of validateMesh.
struct MeshReport {
  std::size_t triangleCount = 0;            ///< triangles in the mesh
  std::size_t vertexCount = 0;              ///< unique positions
  std::size_t degenerateTriangles = 0;      ///< zero-area triangles (see kDegenerateRelativeTolerance)
  std::size_t boundaryEdges = 0;            ///< edges used by exactly one triangle (holes, open rims)
  std::size_t nonManifoldEdges = 0;         ///< edges used by more than two triangles
  std::size_t inconsistentEdges = 0;        ///< edges shared by two triangles that traverse it the same way
  bool watertight = false;                  ///< every edge shared by exactly two oppositely oriented triangles
  /// Watertight, and every part outward by its own signed volume (a part inside another part is a
  /// cavity and must point inwards; MeshParts.hpp): a closed mesh with one part inside out is not.
  bool outwardOriented = false;
  std::size_t parts = 0;                    ///< connected parts (across edges shared by two triangles)
  std::size_t insideOutParts = 0;           ///< closed parts whose sign disagrees with their nesting (MeshPart::insideOut)
  double insideOutVolume = 0.0;             ///< sum of |volume| of those parts (m^3)
  double area = 0.0;                        ///< total surface area (m^2)
  std::optional<double> volume;             ///< enclosed signed volume (m^3), only when watertight
  Eigen::Vector3d boundsMin = Eigen::Vector3d::Zero();  ///< axis-aligned bounds, lower corner (m)
  Eigen::Vector3d boundsMax = Eigen::Vector3d::Zero();  ///< axis-aligned bounds, upper corner (m)

  bool hasUv = false;                       ///< UVs cover every triangle
  bool uvOverlap = false;                   ///< two UV triangles overlap with positive area (stacked, mirrored, folded)
  std::size_t uvOverlapPairs = 0;           ///< overlapping pairs found (counting stops at kMaxCountedUvOverlaps)
  /// False when the overlap search ran out of its work budget (pathological UV layouts, e.g. a
  /// million slivers through one point); then uvOverlap may miss pairs and the UVs are not trusted.
  bool uvOverlapCheckComplete = true;
  std::size_t zeroUvAreaTriangles = 0;      ///< triangles with zero UV area but non-zero 3D area
  std::size_t uvsOutsideUnitSquare = 0;     ///< UV vertices (used by triangles) outside [0,1]^2

  /// True when the artist's UVs can be baked as they are: present, inside [0,1]^2, bijective.
  bool uvUsableAsAtlas() const {
    return hasUv && !uvOverlap && uvOverlapCheckComplete && zeroUvAreaTriangles == 0 && uvsOutsideUnitSquare == 0;
  }
  /// Multi-line human-readable text of every finding.
  std::string summary() const;
};

/// Validates topology, orientation, area, volume and UVs. O(n log n) in the triangle count;
/// a million triangles take about a second. Never fails: indices out of range count as
/// degenerate triangles. With `checkUvs` false the UV findings are left at their defaults (the
/// overlap search dominates the cost; paths that only need the topology skip it).
MeshReport validateMesh(const Mesh& mesh, bool checkUvs = true);

/// How the edges of a mesh are shared (each undirected edge counted once).
struct EdgeTopology {
  std::size_t boundaryEdges = 0;      ///< used by one triangle
  std::size_t nonManifoldEdges = 0;   ///< used by more than two triangles
  std::size_t inconsistentEdges = 0;  ///< used by two triangles walking it the same way
  /// Watertight, manifold and consistently oriented.
  bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0 && inconsistentEdges == 0; }
};

/// Counts boundary, non-manifold and inconsistently oriented edges. O(n log n); triangles with an
/// index out of range are skipped.
EdgeTopology countEdgeTopology(const Mesh& mesh);

/// The cheap closedness check alone (no UV work), for paths that need a closed volume: every edge
/// shared by exactly two triangles in opposite directions, indices in range. The message starts
/// with `what` (usually the file name). Orientation (inside out) is not checked here.
Status checkClosed(const Mesh& mesh, const std::string& what);

/// Ok when the mesh is closed and outward oriented (watertight, positive volume); otherwise the message used where a closed volume is required, e.g.
/// "ship.obj: mesh is open (12 boundary edges); volume and buoyancy need a closed mesh".
/// `what` names the mesh (usually its file name).
Status requireClosed(const MeshReport& report, const std::string& what);

/// Whether two UV triangles overlap with positive area (more than touching along an edge or at a
/// vertex). `tolerance` is the overlap length (UV units) below which contact counts as touching.
bool uvTrianglesOverlap(const Eigen::Vector2d a[3], const Eigen::Vector2d b[3], double tolerance);

}  // namespace hydrotex
