// SPDX-License-Identifier: Zlib
#pragma once
// An open-top box (five faces, no deck), the simplest open hull, for the open-hull suites: made
// here so that no test reads a file.

#include <Eigen/Core>

#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/mesh/Primitives.hpp"

namespace hydrotex::testing {

/// The box of full `extents` (m) centred at the origin, each face split into `divisions` x
/// `divisions` quads, without its top face (y = extents.y() / 2): one boundary loop of
/// 2 (x + z) m around the rim, 4 `divisions` edges. Its UVs are dropped (repair would drop them).
inline Mesh openTopBox(const Eigen::Vector3d& extents, int divisions) {
  Mesh mesh = primitives::subdividedBox(extents, divisions);
  mesh.uv = {};
  mesh.sourceName = "open box";
  const double rim = 0.5 * extents.y();
  std::vector<Eigen::Vector3i> walls;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    bool top = true;
    for (int c = 0; c < 3; ++c) top = top && mesh.positions[std::size_t(t[c])].y() == rim;
    if (!top) walls.push_back(t);
  }
  mesh.triangles = std::move(walls);
  return mesh;
}

}  // namespace hydrotex::testing
