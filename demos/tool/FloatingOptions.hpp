// SPDX-License-Identifier: Zlib
#pragma once
// What `hydrotex equilibrium` and `hydrotex stability` share: the floating body's options (mesh,
// up axis, mass, centre of mass, point masses, liquid, method) and their loading.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ToolSupport.hpp"
#include "hydrotex/hydrostatics/FloatingEquilibrium.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::tool {

/// The command line of a floating body (file coordinates, before the up axis is applied).
struct FloatingOptions {
  std::string meshPath;
  MeshLoadSettings load;                       ///< --up, --scale, --no-repair, --max-hole-fraction, --open-hull
  std::optional<double> mass;                  ///< kg, the hull's
  std::optional<double> density;               ///< kg/m^3, a uniform hull
  std::optional<double> shellDensity;          ///< kg/m^2, a hull that is a shell (an open hull's walls, lids left out)
  std::optional<double> displacement;          ///< m^3, the whole body's
  std::optional<Eigen::Vector3d> centerOfMass; ///< m, the hull's
  std::vector<std::string> pointMasses;        ///< "KG@X,Y,Z"
  double fluidDensity = 1000.0;                ///< kg/m^3
  std::string method = "auto";                 ///< exact, texture or auto (= exact)
  int resolution = 256;                        ///< texels per side (texture)
  std::string backend = "cpu";                 ///< texture path's backend
};

/// Adds MESH and the options above to `verb`.
void addFloatingOptions(CLI::App& verb, FloatingOptions& options);

/// A loaded floating body, ready for findFloatingEquilibrium / rightingLeverCurve.
struct FloatingSetup {
  Mesh mesh;                          ///< y up (rotated from the file's z up with --up z)
  Eigen::Matrix3d fromFile = Eigen::Matrix3d::Identity();  ///< file axes to `mesh`'s (a rotation: --up)
  double fileScale = 1.0;  ///< metres per file unit (--scale)
  FloatingBody body;                  ///< total mass and centre of mass (mesh frame, y up)
  FloatingSettings settings;          ///< liquid density
  MethodOptions method;               ///< what ran ("auto" resolved)
  std::unique_ptr<FlatSurface> water; ///< the texture path's liquid (surface y = 0)
  std::unique_ptr<ComputeBackend> backend;  ///< texture path
  FloatingHydrostatics answer;        ///< empty: exact
};

/// Loads the mesh, applies the up axis, resolves mass and centre of mass and, for the texture
/// path, bakes and registers the body. Errors name the option or file at fault.
Expected<std::unique_ptr<FloatingSetup>> loadFloatingBody(const FloatingOptions& options);

/// Extrinsic X, Y, Z angles (degrees) of a rotation R = Rz Ry Rx.
Eigen::Vector3d extrinsicDegreesXYZ(const Eigen::Matrix3d& rotation);

/// The method and body keys shared by both verbs' JSON.
void addFloatingJson(nlohmann::json& out, const FloatingSetup& setup);

}  // namespace hydrotex::tool
