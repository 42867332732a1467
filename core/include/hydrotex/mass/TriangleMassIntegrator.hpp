// SPDX-License-Identifier: Zlib
#pragma once
/// @file TriangleMassIntegrator.hpp
/// Mass properties of a deforming body in O(triangles) per step (issue 5 "Deforming bodies";
/// docs/design.md "Mass model"), with the same meaning as the texel path (TextureMassIntegrator): a
/// solid of uniform density or a per-texel density map (a texel's density fills the cones from the
/// reference point to its pieces), plus a shell of uniform areal density. A texel piece is a fixed
/// polygon of one triangle in barycentric coordinates, so every sum over texels collapses to a
/// sum over triangles of the triangle's moved vertices times density-weighted barycentric moments
/// that depend on the map alone. Exact: a uniform solid or shell gives the polyhedral mass
/// properties (polyhedralMassProperties) to double rounding; a density map is exact per piece.

#include <cstdint>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// The triangle path of the mass properties. Prepared once from a bake (the texel pieces clipped
/// again for their exact second moments); a density map costs one pass over the pieces when it is
/// set; each moved mesh (update) costs one pass over the triangles in double, allocation-free.
/// Not thread-safe.
class TriangleMassIntegrator {
 public:
  /// Prepares for `bake` of a mesh with UV layout `layout` (the layout the bake was made from),
  /// cones from `referencePoint` (m, mesh frame). Error when the reference point is not finite,
  /// the layout has no triangles or a UV index out of range, or a piece names a triangle the
  /// layout lacks or a texel outside the bake. One clip per piece (as the bake, ~the bake's time).
  static Expected<TriangleMassIntegrator> create(const SurfaceBake& bake, const UvLayout& layout,
                                                 const Eigen::Vector3d& referencePoint);

  /// Replaces the density map: one density (kg/m^3) per covered texel, SurfaceTextures order
  /// (as TextureMassModel::texelDensity), replacing the uniform solid density. Empty: back to
  /// the uniform solid. One pass over the pieces (the map's density-weighted barycentric moments
  /// per triangle), allocation-free after the first map. Error, keeping the previous map, when the
  /// size is not the texel count or a density is negative or not finite.
  Status setTexelDensity(const std::vector<float>& density);
  /// True while a density map is set.
  bool hasTexelDensity() const { return mapped_; }

  /// Takes the vertices of `mesh` (the baked mesh's topology, vertices moved: a deforming body)
  /// and sums the cones and the shell over its triangles, in double: O(triangles), no allocation
  /// after the first call. Error when the triangle count is not the layout's, a vertex index is
  /// out of range or a vertex used is not finite; evaluate() is then an error until the next
  /// successful update.
  Status update(const Mesh& mesh);

  /// Mass properties (mesh frame) of the last updated mesh: the density map's solid if one is
  /// set, else a uniform solid of `solidDensity` (kg/m^3), plus a shell of `shellDensity`
  /// (kg/m^2). O(1): the sums of update() scaled. Error when a density is negative or not finite
  /// or no mesh was updated. A body of zero mass gets its centre at the reference point.
  Expected<MassProperties> evaluate(double solidDensity, double shellDensity) const;
  /// update(mesh), then evaluate(solidDensity, shellDensity).
  Expected<MassProperties> evaluate(const Mesh& mesh, double solidDensity, double shellDensity);

  /// Enclosed volume (m^3) of the last updated mesh (exact polyhedral volume; 0 before any).
  double volume() const { return volume_; }
  /// Surface area (m^2) of the last updated mesh that carries the shell: lids over openings
  /// (Mesh::openingTriangles) excluded (exact; 0 before any).
  double area() const { return area_; }
  /// Number of covered texels (the size a density map must have).
  std::size_t texelCount() const { return texelCount_; }
  /// Number of triangles (the mesh's, the layout's).
  std::size_t triangleCount() const { return triangleStart_.empty() ? 0 : triangleStart_.size() - 1; }
  /// Number of texel pieces (the density pass's length).
  std::size_t pieceCount() const { return pieces_.size(); }
  /// Cone apex (m, mesh frame).
  const Eigen::Vector3d& referencePoint() const { return referencePoint_; }

 private:
  /// One piece of one triangle in one texel, as the density pass reads it: its texel and its
  /// barycentric moments f, f E[b1], f E[b2], f E[b1^2], f E[b1 b2], f E[b2^2] (f the piece's
  /// share of the triangle's UV area, E over the piece), single precision.
  struct Piece {
    std::uint32_t texel = 0;
    float moments[6] = {};
  };
  /// Per triangle: the density-weighted sums of its pieces' moments (kg/m^3), in the order above.
  struct DensityMoments {
    double m = 0.0, w1 = 0.0, w2 = 0.0, m11 = 0.0, m12 = 0.0, m22 = 0.0;
  };
  /// Per triangle, from the last update: vertex 0 relative to the reference point and the edges
  /// from vertex 0 (m).
  struct Frame {
    double d0[3] = {}, e1[3] = {}, e2[3] = {};
  };
  /// The density map's cone sums over the frames (mappedMass_, mappedFirst_, mappedSecond_).
  void sumMappedCones();

  Eigen::Vector3d referencePoint_ = Eigen::Vector3d::Zero();
  std::size_t texelCount_ = 0;
  std::vector<std::uint32_t> triangleStart_;   // per triangle: first piece; size triangles + 1
  std::vector<Piece> pieces_;                  // grouped by triangle
  std::vector<DensityMoments> density_;        // per triangle, the current map's
  std::vector<DensityMoments> spareDensity_;   // the next map's, swapped in when it is valid
  bool mapped_ = false;
  std::vector<Frame> frames_;                  // per triangle, the last updated mesh's
  bool updated_ = false;
  // Geometry-only sums of the last update, about the reference point (6 = xx yy zz xy xz yz):
  // unit-density cones (volume, first, second) and the unit shell (area, first, second).
  double volume_ = 0.0, area_ = 0.0;
  double volumeFirst_[3] = {}, volumeSecond_[6] = {};
  double shellFirst_[3] = {}, shellSecond_[6] = {};
  // The density map's cones over the last update: mass (kg), first (kg m), second (kg m^2).
  double mappedMass_ = 0.0, mappedFirst_[3] = {}, mappedSecond_[6] = {};
};

}  // namespace hydrotex
