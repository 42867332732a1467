// SPDX-License-Identifier: Zlib
#pragma once
/// @file SphereHydrostaticsWaves.hpp
/// Private to core: a true sphere under waves (SphereHydrostaticsWaves.cpp), for sphereHydrostatics
/// and for the controller's bodies that are spheres (RigidBodiesStep.cpp), which keep its surface
/// jets and its nodes for their drag; and the same nodes on a sphere's cap under a flat surface.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrostatics/WettedNode.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"

namespace hydrotex::detail {

class SurfaceJetGrid;  // SurfaceJetGrid.hpp

/// Azimuths and polar nodes of the sphere's quadrature (SphereHydrostaticsWaves.cpp).
struct SphereQuadrature {
  int azimuths = 0;     ///< M, equally spaced (the trapezoidal rule, periodic)
  int polarNodes = 0;   ///< K, Gauss-Legendre nodes on each meridian's wet arc
};

/// The hydrostatics of a solid sphere of `radius` (m) centred at `center` (m, body frame) under a
/// surface that is not flat and offers smoothness bounds (Gerstner waves):
/// the exact path's sums (HydrostaticSums.hpp) integrated over the sphere's wetted surface by a
/// product rule (SphereHydrostaticsWaves.cpp). Empty where the rule does not apply (the surface
/// offers no bounds, the water line may pass within a few degrees of a pole or cross a meridian
/// twice, the jet grid cannot meet its error over the sphere): the caller takes the exact path on
/// the sphere's mesh. Errors: an invalid query (validateHydrostaticsQuery), a surface height that is
/// not finite. `keep`, when given, receives the
/// grid of surface jets the heights were interpolated from (the body's drag reads it after, as
/// polyhedralHydrostaticsKeepingJets'). `rule`: the nodes to use (zeros: chosen from the sphere's
/// size against the waves', SphereHydrostaticsWaves.cpp); `used`, when given, receives them;
/// `nodes`, when given, the rule's nodes on the wetted surface (emptied where no answer comes).
std::optional<Expected<HydrostaticsResult>> waveSphereHydrostatics(double radius, const Eigen::Vector3d& center,
                                                                   const LiquidSurface& surface,
                                                                   const HydrostaticsQuery& query,
                                                                   std::optional<SurfaceJetGrid>* keep = nullptr,
                                                                   SphereQuadrature rule = {},
                                                                   SphereQuadrature* used = nullptr,
                                                                   std::vector<WettedNode>* nodes = nullptr);

/// The drag's nodes (WettedNode) on the wetted cap of a sphere of `radius` (m) centred at `center`
/// (m, world) under a flat surface at `level` (m): the sphere rule's (`rule.azimuths` meridians
/// equally spaced, `rule.polarNodes` Gauss-Legendre nodes on each one's wet arc, about the
/// vertical), the same as its drag takes under waves (every other meridian of the 16 x 8 rule:
/// 8 x 4, the default). Into `nodes` (emptied first; none for a dry sphere).
void flatSphereDragNodes(double radius, const Eigen::Vector3d& center, double level, std::vector<WettedNode>& nodes,
                         SphereQuadrature rule = {8, 4});

}  // namespace hydrotex::detail
