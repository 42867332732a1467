// SPDX-License-Identifier: Zlib
#pragma once
/// @file RigidBodyDragWithJets.hpp
/// Private to core: rigidBodyDrag (RigidBodyStep.hpp) that reads the surface's heights above its
/// patches from a grid of surface jets another query of the same body sampled at the same time
/// (the exact path's under waves, RigidBodiesStep.cpp), instead of sampling a grid of its own.

#include "hydrotex/step/RigidBodyStep.hpp"

namespace hydrotex::detail {

class SurfaceJetGrid;  // hydrostatics/SurfaceJetGrid.hpp

/// rigidBodyDrag with `jets` (may be null: a grid of its own) as SurfaceHeights' shared grid: taken
/// where it is of the liquid's surface and time and its spacing meets kDragSurfaceHeightError.
DragLoads rigidBodyDrag(const DragBody& body, const RigidBodyMotion& motion, const DragLiquid& liquid, double dt,
                        SurfaceJetGrid* jets);

}  // namespace hydrotex::detail
