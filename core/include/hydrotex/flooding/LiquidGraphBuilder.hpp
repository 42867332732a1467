// SPDX-License-Identifier: Zlib
#pragma once
/// @file LiquidGraphBuilder.hpp
/// Building a body's liquid graph (paper section 3.2): automatically (segment the surface into k
/// parts, a node per part at the centre of a least-squares sphere fit, edges between parts whose
/// spaces touch, capacities from each part's share of the enclosed volume times the porosity) or
/// from a manual description (nodes, capacities, edges; texels and space go to the nearest node).
/// Both map every permeable texel (permeability map, PMT) to the node it feeds.
///
/// The enclosed volume is cut into cells of a regular grid over the mesh's bounding box (a cell
/// belongs to the body when its centre is inside the mesh); each inside cell goes to one node, and
/// the cells' volumes are scaled so that they sum to the exact enclosed volume (texel cones).

#include <cstdint>
#include <optional>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/flooding/LiquidGraph.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// How the surface and the inside let liquid through.
struct LiquidGraphBuildSettings {
  /// Darcy permeability (m^2) where the permeability map is white (1); black (0) is watertight.
  /// 1e-9 m^2 is a coarse sand; a holed hull plate is modelled as a very permeable wall.
  double permeability = 1.0e-9;
  /// Wall thickness (m): Darcy's length L through the surface.
  double wallThickness = 0.01;
  /// Fraction (0..1) of the enclosed volume liquid can fill: 1 for a hollow hull; naval
  /// permeabilities 0.60 (stores), 0.85 (machinery), 0.95 (accommodation); a sponge's porosity.
  double porosity = 1.0;
  /// Darcy permeability (m^2) of the inside between automatic nodes (1e-6: nearly free flow in a
  /// hollow hull; lower for a porous material).
  double interiorPermeability = 1.0e-6;
  /// About this many cells in the bounding box carry the nodes' spaces (more: smoother levels).
  int cellBudget = 16384;
  /// Transmissibility per square metre of an opening (m: k / L), for the texels of lids over the
  /// openings of an open hull (SurfaceTextures::openingArea), which let liquid through as an
  /// open hole, whatever the wall's permeability, thickness or map. Default 1e-6 m: for water,
  /// the flow of an orifice (Torricelli, discharge coefficient 0.6, Cd sqrt(2 g h) per m^2) at
  /// h = 7 cm of head, the depth a gunwale goes under while a boat swamps; this linear law (the
  /// one Darcy law of the graph) passes more above that head and less below it.
  double openingConductance = 1.0e-6;
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// A node of a manual graph.
struct ManualLiquidNode {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< m, mesh frame
  /// m^3; empty: porosity times the volume of the space nearest to this node.
  std::optional<double> capacity;
};

/// An edge of a manual graph.
struct ManualLiquidEdge {
  std::uint32_t first = 0;         ///< node index
  std::uint32_t second = 0;        ///< node index
  double permeability = 1.0e-6;    ///< m^2, Darcy permeability of the passage
  std::optional<double> area;      ///< m^2; empty: the area where the two nodes' spaces touch (at least one cell face)
  std::optional<double> length;    ///< m; empty: the distance between the nodes
};

/// A manually made liquid graph (e.g. read from a JSON file by the plugin's scene loader).
struct ManualLiquidGraph {
  std::vector<ManualLiquidNode> nodes;  ///< at least one
  std::vector<ManualLiquidEdge> edges;  ///< may be empty
};

/// A default node count for a mesh: 4 times its longest over its shortest bounding-box extent,
/// clamped to 4..32 (elongated hulls get nodes along their length).
int defaultLiquidGraphNodeCount(const Mesh& mesh);

/// Automatic graph of `nodeCount` nodes (0: defaultLiquidGraphNodeCount) for a closed mesh and its
/// evaluated texels. `texelPermeability`: one value in [0,1] per covered texel (the permeability
/// map resampled with resampleToTexels), or empty for a wholly permeable surface; but the walls
/// of an open hull (textures with openingArea) are watertight without a map, so that liquid
/// enters through its openings only. The part of a texel on a lid over an opening is a
/// permeable texel of its own, at the lid's centroid in that texel, passing
/// settings.openingConductance times its area. Deterministic.
/// Errors: settings, a count outside 0..1024, a map of the wrong size or with values outside
/// [0,1], a mesh that encloses no cell.
Expected<LiquidGraph> buildAutomaticLiquidGraph(const Mesh& mesh, const SurfaceTextures& textures,
                                                const std::vector<float>& texelPermeability, int nodeCount,
                                                const LiquidGraphBuildSettings& settings);

/// Graph from a manual description: each inside cell and each permeable texel goes to the nearest
/// node. Errors: as the automatic builder, and nodes or edges that are unusable (naming them), a
/// capacity larger than its node's space.
Expected<LiquidGraph> buildManualLiquidGraph(const Mesh& mesh, const SurfaceTextures& textures,
                                             const std::vector<float>& texelPermeability,
                                             const ManualLiquidGraph& manual, const LiquidGraphBuildSettings& settings);

}  // namespace hydrotex
