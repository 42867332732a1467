// SPDX-License-Identifier: Zlib
#pragma once
/// @file SoftBodyDrag.hpp
/// The drag of a deforming body whose vertices move on their own (a soft body's nodes): the rigid
/// bodies' drag law (TexelDrag.hpp) texel by texel on the texels' own velocities, the forces
/// handed to the vertices as the pressure's are (TexelPressure.hpp), then taken semi-implicitly
/// so that drag never adds kinetic energy relative to the liquid, at any time step (derivation in
/// SoftBodyDrag.cpp). An engine's adapter (the Bullet plugin's SoftBodyBuoyancy) reads its nodes
/// into the input and adds the velocity changes to them; it holds no law of its own.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "hydrotex/bake/SurfaceBake.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex {

/// One deforming body's state for its drag in a step (world frame, SI units). Every span has one
/// entry per vertex of `mesh`, per triangle or per covered texel, as named.
struct SoftBodyDragInput {
  const Mesh* mesh = nullptr;                       ///< current vertex positions (m) and triangles
  const SurfaceBake* bake = nullptr;                ///< the texel pieces of `mesh`'s bake
  const SurfaceTextures* textures = nullptr;        ///< PT/VAT of the current vertices (world)
  std::span<const float> wetFraction;               ///< per texel, 0..1 (texelPressures)
  std::span<const Eigen::Vector3d> triangleAreaVectors;  ///< per triangle, m^2, current
  /// Per vertex: velocity (m/s) at the end of the last step, i.e. without any velocity the
  /// engine has already added for this step (Bullet's predictMotion adds g dt).
  std::span<const Eigen::Vector3d> vertexVelocity;
  std::span<const double> vertexMass;               ///< per vertex, kg; 0 for a pinned vertex (takes nothing)
  const LiquidSurface* surface = nullptr;           ///< the liquid at `time`
  Eigen::Vector3d current = Eigen::Vector3d::Zero();  ///< uniform current (m/s) added to the surface's velocity
  double viscosity = 1.0e-3;                        ///< Pa s; 0: no skin friction
  double time = 0.0;                                ///< s
  double dt = 0.0;                                  ///< s, > 0
  DragCoefficients coefficients;                    ///< the drag law's coefficients
};

/// What one step's drag did (world frame).
struct SoftBodyDragResult {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< N, sum of the texels' drag forces (before the energy limit)
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< N m about the vertices' centre of mass
  double power = 0.0;                                ///< W, rate of work on the vertices this step (<= 0)
  std::uint64_t texelsVisited = 0;                   ///< wet texels whose drag was evaluated
};

/// The drag step of one deforming body, with its per-vertex scratch kept between steps (no
/// allocation once grown). Not thread-safe; one per body (bodies run in parallel).
class SoftBodyDrag {
 public:
  /// Computes this step's change of every vertex's velocity (m/s; its position changes by that
  /// times dt, as a semi-implicit Euler step) into `velocityChange` (one per vertex: zero for a
  /// pinned vertex, non-finite for one whose change could not be computed: leave it as it is).
  /// Nothing is changed (all zero) when every vertex is pinned.
  SoftBodyDragResult step(const SoftBodyDragInput& input, std::span<Eigen::Vector3d> velocityChange);

 private:
  std::vector<Eigen::Vector3d> relative_;        ///< m/s, vertex velocity relative to the liquid
  std::vector<double> surfaceHeights_;           ///< m, the surface above each vertex (under a free surface in motion)
  std::vector<Eigen::Vector3d> vertexDrag_;      ///< N, the texels' drag handed to the vertices
  std::vector<Eigen::Vector3d> deformationChange_;  ///< m/s, drag's change of the vertex's deformation velocity
};

}  // namespace hydrotex
