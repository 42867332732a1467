// SPDX-License-Identifier: Zlib
#pragma once
/// @file BoxHydrostaticsWaves.hpp
/// Private to core: a box under waves by a quadrature rule on its wetted faces
/// (BoxHydrostaticsWaves.cpp), for the controller's bodies that are boxes (RigidBodiesStep.cpp),
/// which keep its surface jets for their drag; and the same kind of rule's nodes on the wetted faces
/// under a flat surface, for a box's drag.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrostatics/WettedNode.hpp"
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
/// box's size against the waves); `used`, when given, receives them. `nodes`, when given, receives
/// the drag's nodes (WettedNode, world frame): the same pieces of the same faces under `dragRule`
/// (Gauss-Legendre lines across each piece, nodes on each line's wet part up to its own water
/// line), as flatBoxDragNodes' in flat water; emptied where no answer comes.
std::optional<Expected<HydrostaticsResult>> waveBoxHydrostatics(const Eigen::Vector3d& halfExtents,
                                                                const Eigen::Vector3d& center,
                                                                const LiquidSurface& surface,
                                                                const HydrostaticsQuery& query,
                                                                std::optional<SurfaceJetGrid>* keep = nullptr,
                                                                BoxQuadrature rule = {}, BoxQuadrature* used = nullptr,
                                                                std::vector<WettedNode>* nodes = nullptr,
                                                                BoxQuadrature dragRule = {2, 2});

/// The drag's nodes (WettedNode) on the wetted faces of a box of half extents `halfExtents` (m,
/// along the columns of `rotation`) centred at `center` (m, world) under a flat surface at `level`
/// (m): on each face the water line is straight, so the wet part is cut into pieces where that line
/// meets the face's sides, and each piece takes `rule.across` Gauss-Legendre lines across it and
/// `rule.along` nodes on each line's wet part (waveBoxHydrostatics' product rule, its outline
/// exact here). A level face (top or bottom) is wholly wet below the level. Into `nodes` (emptied
/// first; none for a dry box). The default, 2 x 2 nodes a piece (20 for a level box half under),
/// is within 4.1e-3 of the law's integral in force (test_rigid_body_step), where the controller's
/// 64 patches of bench_peers' box were up to 35 % off.
void flatBoxDragNodes(const Eigen::Vector3d& halfExtents, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& center,
                      double level, std::vector<WettedNode>& nodes, BoxQuadrature rule = {2, 2});

}  // namespace hydrotex::detail
