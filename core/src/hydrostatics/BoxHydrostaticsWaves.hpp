// SPDX-License-Identifier: Zlib
#pragma once
/// @file BoxHydrostaticsWaves.hpp
/// Private to core: a box under waves by a quadrature rule on its wetted faces
/// (BoxHydrostaticsWaves.cpp), for the controller's bodies that are boxes (RigidBodiesStep.cpp),
/// which keep its surface jets for their drag.

#include <Eigen/Core>
#include <optional>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"

namespace hydrotex::detail {

class SurfaceJetGrid;  // SurfaceJetGrid.hpp

/// Nodes of the box's quadrature on each face (BoxHydrostaticsWaves.cpp).
struct BoxQuadrature {
  int across = 0;  ///< Gauss-Legendre nodes across a face (its less steep side)
  int along = 0;   ///< Gauss-Legendre nodes on each line's wet part (up its steeper side)
};

/// The hydrostatics of a solid box of half extents `halfExtents` (m, along the body axes) centred
/// at `center` (m, body frame) under a surface that is not flat and offers smoothness bounds
/// (Gerstner waves): the exact path's sums (HydrostaticSums.hpp) integrated over the wetted part
/// of each face by a product rule (BoxHydrostaticsWaves.cpp). Empty where the rule does not apply
/// (no bounds; a face the water line crosses that is not steep enough against the surface's
/// slope, or where the rule cannot prove where the water line meets its sides; the jet grid cannot
/// meet its error or give a height, as for a box so small that its cells' scale underflows): the
/// caller takes the exact path on the box's mesh. Errors: an invalid query
/// (validateHydrostaticsQuery), a surface height above the centre of mass that is not finite. `keep`, when given, receives
/// the grid of surface jets the heights were interpolated from. `rule`: the nodes (zeros: from the
/// box's size against the waves); `used`, when given, receives them.
std::optional<Expected<HydrostaticsResult>> waveBoxHydrostatics(const Eigen::Vector3d& halfExtents,
                                                                const Eigen::Vector3d& center,
                                                                const LiquidSurface& surface,
                                                                const HydrostaticsQuery& query,
                                                                std::optional<SurfaceJetGrid>* keep = nullptr,
                                                                BoxQuadrature rule = {}, BoxQuadrature* used = nullptr);

}  // namespace hydrotex::detail
