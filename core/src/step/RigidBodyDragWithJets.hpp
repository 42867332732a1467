// SPDX-License-Identifier: Zlib
#pragma once
/// @file RigidBodyDragWithJets.hpp
/// Private to core: rigidBodyDrag (RigidBodyStep.hpp) that reads the surface's heights above its
/// patches from a grid of surface jets another query of the same body sampled at the same time
/// (the exact path's under waves, RigidBodiesStep.cpp), instead of sampling a grid of its own; and
/// the same law summed on the nodes of a quadrature rule over the wetted surface instead of on
/// patches (a true sphere's under waves, SphereHydrostaticsWaves.hpp).

#include <span>

#include "hydrotex/step/RigidBodyStep.hpp"

namespace hydrotex::detail {

class SurfaceJetGrid;  // hydrostatics/SurfaceJetGrid.hpp
struct WettedNode;     // hydrostatics/WettedNode.hpp

/// rigidBodyDrag with `jets` (may be null: a grid of its own) as SurfaceHeights' shared grid: taken
/// where it is of the liquid's surface and time and its spacing meets kDragSurfaceHeightError.
DragLoads rigidBodyDrag(const DragBody& body, const RigidBodyMotion& motion, const DragLiquid& liquid, double dt,
                        SurfaceJetGrid* jets);

/// rigidBodyDrag with the wetted surface given by a quadrature rule's `nodes` (world frame, each
/// wholly wet, with the surface's height above it) in place of the body's patches, for a liquid
/// with a free surface: the same law (texelDragForceWithFriction) on each node's area vector at
/// its velocity relative to the liquid there, the same rotational damping (the wetted fraction
/// from body.totalPatchArea) and damping. DragLoads::patchesVisited counts the nodes.
DragLoads rigidBodyDragOnNodes(const DragBody& body, const RigidBodyMotion& motion, const DragLiquid& liquid, double dt,
                               std::span<const WettedNode> nodes);

}  // namespace hydrotex::detail
