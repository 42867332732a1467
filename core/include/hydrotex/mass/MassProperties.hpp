// SPDX-License-Identifier: Zlib
#pragma once
/// @file MassProperties.hpp
/// Mass, centre of mass and inertia: the exact polyhedral reference (Mirtich 1996 / Eberly,
/// divergence theorem on triangles) and the texture path (paper section 2.1-2.3).

#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// Mass properties of a body, in the mesh's frame.
struct MassProperties {
  double mass = 0.0;                                          ///< kg
  double volume = 0.0;                                        ///< enclosed volume (m^3)
  Eigen::Vector3d centerOfMass = Eigen::Vector3d::Zero();     ///< m, mesh frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();          ///< kg m^2 about the centre of mass, mesh axes
};

/// Exact mass properties of a closed triangle mesh of uniform `density` (kg/m^3), in double
/// precision. Error when the mesh is open, empty, or has non-finite vertices, or density <= 0.
Expected<MassProperties> polyhedralMassProperties(const Mesh& mesh, double density);

/// Exact mass properties of a shell of uniform `arealDensity` (kg/m^2) over the triangles of
/// `mesh`, lids over openings (Mesh::openingTriangles) left out: an open hull's own mass. The
/// mesh need not be closed; `volume` is 0 (a shell encloses nothing of its own). Error when the
/// density is not positive and finite, the mesh has no triangles or no area outside its lids,
/// a vertex is not finite or an index is out of range.
Expected<MassProperties> polyhedralShellMassProperties(const Mesh& mesh, double arealDensity);

/// What a body is made of, for the texture path (docs/design.md "Mass model").
struct TextureMassModel {
  double solidDensity = 1000.0;    ///< kg/m^3 filling the enclosed volume (0: hollow)
  double shellDensity = 0.0;       ///< kg/m^2 over the surface (hulls, buoys), lids over openings excluded
  /// Optional per covered texel density (kg/m^3), replacing solidDensity: a texel's density fills
  /// the cone from `referencePoint` to that texel. Empty: uniform solidDensity.
  std::vector<float> texelDensity;
  Eigen::Vector3d referencePoint = Eigen::Vector3d::Zero();   ///< cone apex (m, mesh frame)
};

/// Mass properties from texel sums. Uniform solids: volume exact, centre and inertia converge
/// with resolution. One pass over the covered texels. A `texelDensity` whose size is not the
/// texel count gives NaN mass properties (TextureMassIntegrator::evaluate says why instead).
/// A body of zero mass gets its centre at the reference point and zero inertia.
MassProperties textureMassProperties(const SurfaceTextures& textures, const TextureMassModel& model);

/// The texture path split in two for bodies evaluated again and again (density maps that change
/// per step): what depends only on the geometry and the reference point is prepared once, in
/// compact float arrays (per texel: the cone's apex-to-base vector p - c and volume
/// (p - c) . A / 3) and geometry-only sums; an evaluation with a density map is one memory-bound
/// pass accumulating in double per block of texels, one of a uniform solid scales the sums (no
/// pass over the texels). Cone i (apex c, base texel at p, volume v) has its centroid at
/// c + 3/4 (p - c) and second moment about c of 3/5 v ((p - c)(p - c)^T + C_i), C_i the texel's
/// in-plane covariance from its edges (exact for a flat parallelogram texel).
class TextureMassIntegrator {
 public:
  /// Prepares the per-texel arrays for `textures` with cone apex `referencePoint` (m).
  TextureMassIntegrator(const SurfaceTextures& textures, const Eigen::Vector3d& referencePoint);

  /// Prepares again, in place, for moved `textures` (a deforming body), keeping the reference
  /// point: allocates nothing when the texel count is unchanged, and costs one pass over the
  /// texels in float, block by block (the cone terms of a texel are single precision; the sums
  /// are float within a block of 256 texels, double across blocks).
  void update(const SurfaceTextures& textures);

  /// Mass properties for `model` (its referencePoint is ignored: the prepared one is used).
  /// Error when model.texelDensity is neither empty nor one value per covered texel, or a
  /// density is negative or not finite.
  Expected<MassProperties> evaluate(const TextureMassModel& model) const;

  /// Number of covered texels prepared.
  std::size_t size() const { return count_; }
  /// Enclosed volume (m^3): the sum of the cone volumes (exact up to float rounding).
  double volume() const { return totalVolume_; }
  /// Surface area (m^2) that carries the shell: the sum of the texel areas, less the lids over
  /// openings (SurfaceTextures::openings, subtracted exactly).
  double area() const { return shellArea_; }

 private:
  struct Moments;  // mass, first and second moments about the reference point, in double
  MassProperties finish(const Moments& moments) const;

  Eigen::Vector3d referencePoint_;
  std::size_t count_ = 0;
  // Per texel (SoA, padded with zeros to a multiple of the block size).
  std::vector<float> dx_, dy_, dz_, volume_;
  // Per block of texels: sum of 3/5 v_i C_i (cone covariance terms) and sum |v_i|.
  std::vector<double> blockCovariance_;  // 6 per block: xx yy zz xy xz yz
  std::vector<double> blockAbsVolume_;
  // Geometry-only sums for the shell (area density is uniform): sum a, a d, a (d d^T + C).
  double shellArea_ = 0.0;
  Eigen::Vector3d shellFirst_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d shellSecond_ = Eigen::Matrix3d::Zero();
  // Geometry-only sums of the cones about the reference point: sum v d, sum v d d^T and sum of the
  // covariance terms 3/5 v C. A uniform solid's moments are these times its density.
  Eigen::Vector3d volumeFirst_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d volumeSecond_ = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d coneCovariance_ = Eigen::Matrix3d::Zero();
  double totalVolume_ = 0.0;
};

}  // namespace hydrotex
