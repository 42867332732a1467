#pragma once
/// @file MassProperties.hpp
/// Mass, centre of mass and inertia: the exact polyhedral reference (Mirtich 1996 / Eberly,
/// divergence theorem on triangles) and the texture path (paper section 2.1-2.3).

#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/Mesh.hpp"
#include "hydrotex/SurfaceBake.hpp"

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

/// What a body is made of, for the texture path (DESIGN.md "Mass model").
struct TextureMassModel {
  double solidDensity = 1000.0;    ///< kg/m^3 filling the enclosed volume (0: hollow)
  double shellDensity = 0.0;       ///< kg/m^2 over the surface (hulls, buoys)
  /// Optional per covered texel density (kg/m^3), replacing solidDensity: a texel's density fills
  /// the cone from `referencePoint` to that texel. Empty: uniform solidDensity.
  std::vector<float> texelDensity;
  Eigen::Vector3d referencePoint = Eigen::Vector3d::Zero();   ///< cone apex (m, mesh frame)
};

/// Mass properties from texel sums. Uniform solids: volume exact, centre and inertia converge
/// with resolution. One pass over the covered texels.
MassProperties textureMassProperties(const SurfaceTextures& textures, const TextureMassModel& model);

}  // namespace hydrotex
