// SPDX-License-Identifier: Zlib
#pragma once
/// @file LiquidGraph.hpp
/// The liquid graph of a permeable body (paper section 3.1; docs/design.md "LiquidGraph"): nodes are
/// spaces that can hold liquid (hollow compartments, or the pores of a material), edges connect
/// spaces that liquid can pass between. Each step, liquid enters or leaves through the submerged
/// permeable texels by Darcy's law (paper eq. 9), driven by the outside pressure at the texel's
/// depth minus the pressure of the liquid inside the node at that depth, and moves between nodes
/// along edges, driven by their level difference. The liquid in a node sits at the bottom of its
/// space as seen from the current "up" direction, so its centroid moves when the body heels.
///
/// The read-only model (nodes' capacities and spaces, edges, permeable texels) is built once by
/// LiquidGraphBuilder.hpp; the state that changes per step is the liquid in each node.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/Pose.hpp"

namespace hydrotex {

/// A space that can hold liquid (paper's N_i = <x_i, c_i, l_i>).
struct LiquidGraphNode {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< m, body frame (paper's x_i)
  double capacity = 0.0;  ///< m^3 it holds when full (paper's c_i): porosity times its space's volume
  double liquid = 0.0;    ///< m^3 held now (paper's l_i), 0..capacity
};

/// Two connected spaces (paper's <N_i, N_k, p_ik>).
struct LiquidGraphEdge {
  std::uint32_t first = 0;   ///< node index
  std::uint32_t second = 0;  ///< node index (!= first)
  /// k A / L (m^3): Darcy permeability (m^2) times the area of the passage (m^2) over its length
  /// (m). The flow from first to second is transmissibility / viscosity * rho g (h_first - h_second).
  double transmissibility = 0.0;
};

/// The space of one node, as volume cells of one common size (LiquidGraphDescription::cellSize):
/// cell centres (m, body frame) and the volume of the space inside each cell (m^3).
struct LiquidNodeSpace {
  std::vector<Eigen::Vector3f> centers;  ///< m, body frame
  std::vector<float> volumes;            ///< m^3 per cell (> 0), same order as centers
};

/// A texel of the surface that lets liquid through, and the node it feeds (a texel holding
/// pieces of a wall and of a lid over an opening gives one for each).
struct PermeableTexel {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();  ///< m, body frame (PT)
  /// k A / L (m^3): the texel's Darcy permeability (m^2, the permeability map's value times the
  /// body's permeability) times its area (m^2) over the wall thickness (m).
  float transmissibility = 0.0f;
  std::uint32_t node = 0;   ///< node it feeds
  std::uint32_t texel = 0;  ///< covered texel index (SurfaceTextures order), for maps and overlays
};

/// Everything a liquid graph is made of; LiquidGraph::create checks and arranges it.
struct LiquidGraphDescription {
  std::vector<LiquidGraphNode> nodes;          ///< the nodes, with their starting liquid
  std::vector<LiquidGraphEdge> edges;          ///< connections between nodes
  std::vector<LiquidNodeSpace> spaces;         ///< one per node (a node without cells holds nothing)
  Eigen::Vector3d cellSize = Eigen::Vector3d::Ones();  ///< m, edge lengths of the space cells (> 0)
  std::vector<PermeableTexel> permeableTexels; ///< the texels with a non-zero transmissibility
};

/// One flooding step's inputs.
struct FloodingQuery {
  Pose pose;                 ///< body frame (the frame the graph was built in) to world
  double time = 0.0;         ///< s, passed to the liquid surface
  double timeStep = 1.0 / 60.0;  ///< s (> 0); any size: the update is implicit
  double gravity = 9.81;     ///< m/s^2 (> 0), magnitude along -y
  double viscosity = 1.0e-3; ///< Pa s (> 0): 1.0e-3 for water at 20 C
};

/// What one flooding step did (volumes in m^3).
struct FloodingStepResult {
  double inflow = 0.0;       ///< liquid that entered through the surface
  double outflow = 0.0;      ///< liquid that left through the surface (drained)
  double held = 0.0;         ///< liquid held in all nodes after the step
  int activeSetRounds = 0;   ///< solves needed to keep every node within 0..capacity
  std::size_t texelsVisited = 0;  ///< permeable texels evaluated
};

/// One node's sums over its permeable texels in a step (Darcy through the surface): the pass
/// LiquidGraph::step makes over the texels, whoever makes it. T is a texel's transmissibility
/// (m^3), heads are heights of liquid (m) above the texel, outside (the surface's) and inside
/// (the node's level).
struct FloodingNodeSums {
  double netHead = 0.0;     ///< Sum T (outside head - inside head) (m^4)
  double pushedHead = 0.0;  ///< Sum T outside head (m^4)
  double all = 0.0;         ///< Sum T (m^3)
  double inside = 0.0;      ///< Sum T over the texels the node's liquid reaches (m^3)
  double either = 0.0;      ///< Sum T over the texels wet inside or outside (m^3)
};

/// The levels a pass over the permeable texels needs under a flat surface, as heights along `up`
/// in the body frame measured from the body origin (a texel at p is at height up . p).
struct FloodingTexelLevels {
  Eigen::Vector3f up = Eigen::Vector3f::UnitY();  ///< the world's up in the body frame
  float outsideLevel = 0.0f;                      ///< m, the surface
  std::span<const float> insideLevel;             ///< m, per node: its liquid's level
  std::span<const float> wetLevel;                ///< m, per node: texels at or below it count as wet inside
};

/// The per-node texel sums of a step under a flat surface, made elsewhere than LiquidGraph's own
/// loop (a GPU: ComputeBackend::makeFloodingPass), in float as that loop, for the texels of the
/// graph it was made for (LiquidGraph::permeableTexels, grouped by node).
class FloodingTexelPass {
 public:
  virtual ~FloodingTexelPass() = default;
  /// One FloodingNodeSums per node into `sums`. Errors leave `sums` undefined (the step fails).
  virtual Status sums(const FloodingTexelLevels& levels, std::span<FloodingNodeSums> sums) = 0;
};

/// A body's liquid graph and the liquid in it. Not thread-safe; one per body.
class LiquidGraph {
 public:
  /// Checks and arranges `description`. Errors (naming the value): non-finite or negative
  /// capacity or liquid, liquid above capacity, an edge naming a missing node or itself, a
  /// negative transmissibility, a non-positive cell size, a space whose sizes disagree or whose
  /// volume is smaller than the node's capacity, a permeable texel naming a missing node, a
  /// space count that is not the node count.
  static Expected<LiquidGraph> create(LiquidGraphDescription description);

  /// Advances the liquid by one step at `query.pose` in `surface`'s liquid. Implicit in the node
  /// levels (backward Euler between nodes, exponentially fitted through the surface, so that a
  /// single compartment follows 1 - exp(-t/tau) at any step), with an active set that holds every
  /// node within 0..capacity; the volume that crossed the surface is, to float rounding, the
  /// change of the held liquid. A surface without a free surface (a gas) moves nothing. Errors:
  /// a non-finite pose, a non-positive time step, gravity or viscosity.
  /// `pass`, when given, makes the texel sums under a flat surface (a GPU); under any other
  /// surface, and without it, the graph's own loop makes them.
  Expected<FloodingStepResult> step(const LiquidSurface& surface, const FloodingQuery& query,
                                    FloodingTexelPass* pass = nullptr);

  /// Nodes (positions, capacities and the liquid they hold).
  const std::vector<LiquidGraphNode>& nodes() const { return nodes_; }
  /// Edges.
  const std::vector<LiquidGraphEdge>& edges() const { return edges_; }
  /// Permeable texels, grouped by node.
  const std::vector<PermeableTexel>& permeableTexels() const { return texels_; }
  /// Per node: centroid (m, body frame) of the liquid it holds, at the bottom of its space as seen
  /// at the pose of the last step or updateLiquidCentroids(); the node's position when empty.
  const std::vector<Eigen::Vector3d>& liquidCentroids() const { return centroids_; }
  /// Per node: world height (m) of its liquid level at the last step (its space's bottom when empty).
  const std::vector<double>& levels() const { return levels_; }
  /// Per node: volume (m^3) that crossed the surface into it at the last step (negative: out).
  const std::vector<double>& lastExchange() const { return exchange_; }
  /// Liquid held in all nodes (m^3).
  double heldLiquid() const;
  /// Sum of the capacities (m^3).
  double totalCapacity() const;

  /// Sets the liquid (m^3) in `node`; error when the node is missing or the volume is outside
  /// 0..capacity or not finite. Centroids follow at the next step or updateLiquidCentroids().
  Status setLiquid(std::size_t node, double volume);
  /// Recomputes the liquid centroids and levels for the body's orientation `pose` (e.g. after setLiquid).
  void updateLiquidCentroids(const Pose& pose);

 private:
  struct Level {
    double height = 0.0;  // m, along up in the body frame
    double area = 0.0;    // m^2, free-surface area: capacity per unit height at that level
  };
  void sortSpace(std::size_t node, const Eigen::Vector3d& up);
  FloodingNodeSums flatNodeSums(std::size_t node, const FloodingTexelLevels& levels) const;
  Level levelOf(std::size_t node, double liquid, double width) const;
  Eigen::Vector3d centroidBelow(std::size_t node, double height, double width, const Eigen::Vector3d& up) const;
  void refreshLevelsAndCentroids(const Eigen::Vector3d& up, double translationY, double width);

  std::vector<LiquidGraphNode> nodes_;
  std::vector<LiquidGraphEdge> edges_;
  std::vector<PermeableTexel> texels_;
  Eigen::Vector3d cellSize_ = Eigen::Vector3d::Ones();
  // Space cells of all nodes, node by node (SoA); per node its range and porosity.
  std::vector<float> cellX_, cellY_, cellZ_, cellVolume_;
  std::vector<std::uint32_t> cellStart_;   // size nodes + 1
  std::vector<double> porosity_;           // capacity / space volume (0 for junction nodes)
  // Per cell: height along up (m), and per node the cells sorted by it (kept between steps, so
  // that a slowly heeling body re-sorts in nearly linear time).
  std::vector<double> cellHeight_;
  std::vector<std::uint32_t> cellOrder_;
  // Permeable texels, node by node (SoA floats for the per-step pass).
  std::vector<float> texelX_, texelY_, texelZ_, texelT_;
  std::vector<std::uint32_t> texelStart_;  // size nodes + 1
  // Per-step state and scratch.
  std::vector<float> passInside_, passWet_;
  std::vector<FloodingNodeSums> passSums_;
  std::vector<Eigen::Vector3d> centroids_;
  std::vector<double> levels_, exchange_;
  std::vector<double> h0_, area_, q0_, pushedIn_, slopeAll_, slopeInside_, slopeOutside_, bottom_, top_, delta_;
  std::vector<int> mode_;
  Eigen::MatrixXd matrix_;
  Eigen::VectorXd rhs_, head_;
};

}  // namespace hydrotex
