// SPDX-License-Identifier: Zlib
#pragma once
/// @file MeshParts.hpp
/// The connected parts of a mesh (triangles joined across edges shared by exactly two of them),
/// each with its signed volume and how many other closed parts enclose it: what "outward
/// oriented" means for a multi-part mesh (a part inside another is a cavity and points inwards).

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// One connected part of a mesh.
struct MeshPart {
  std::vector<std::size_t> triangles;  ///< indices into Mesh::triangles
  bool closed = false;        ///< every edge of the part is shared by exactly two of its triangles, walked oppositely
  double signedVolume = 0.0;  ///< enclosed volume (m^3), positive for outward normals (meaningful when closed)
  int enclosingParts = 0;     ///< closed parts of the mesh that contain this one (0: an outer hull)
  /// A closed part whose sign disagrees with its nesting: an outer hull (even nesting) must have
  /// positive volume, a cavity (odd nesting) negative.
  bool insideOut() const { return closed && (signedVolume < 0.0) != (enclosingParts % 2 == 1); }
};

/// The parts of `mesh` in order of their first triangle. Triangles with an index out of range or
/// collapsed corners belong to no part. O(n log n) for the parts, plus one generalized winding
/// number per pair of closed parts whose bounding boxes nest (O(parts x triangles) at worst).
std::vector<MeshPart> findMeshParts(const Mesh& mesh);

/// Generalized winding number of the triangles `triangles` of `mesh` about `point` (m): the sum
/// of their signed solid angles over 4 pi; +1 inside a closed outward surface, -1 inside an
/// inward one, 0 outside (Jacobson et al., "Robust inside-outside segmentation using generalized
/// winding numbers", SIGGRAPH 2013; solid angle of Van Oosterom & Strackee 1983).
double windingNumber(const Mesh& mesh, const std::vector<std::size_t>& triangles, const Eigen::Vector3d& point);

}  // namespace hydrotex
