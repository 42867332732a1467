// SPDX-License-Identifier: Zlib
#pragma once
/// @file PolyhedralFlatSums.hpp
/// Private to core: the exact path under a flat surface, shared by polyhedralHydrostatics (a plain
/// Mesh) and PreparedPolyhedron (the same mesh with its per-triangle constants made once). Under a
/// flat surface every sum HydrostaticSums.hpp needs is a field along y, so the wetted surface
/// enters only through a_up = r1 . A, the upward (world y) component of each element's area
/// vector (r1: the rotation's second row): Sum |A|, Sum a_up, Sum p a_up and Sum p p^T a_up in the
/// body frame (10 sums, where the full body moments take 30), turned into the world sums once.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::detail {

class SurfaceJetGrid;  // SurfaceJetGrid.hpp

/// What a triangle (counter-clockwise seen from outside, body frame) brings to the sums when it is
/// wholly wet, independent of the pose: area vector A = (b - a) x (c - a) / 2 (m^2), area |A|
/// (m^2), centroid (m) and Int p p^T dA / |T| (m^2; xx, xy, xz, yy, yz, zz: the mean over the edge
/// midpoints, exact for quadratics: Strang and Fix 1973, table 4.1).
struct TriangleConstants {
  double areaVector[3];
  double area;
  double centroid[3];
  double secondMoments[6];
};
static_assert(sizeof(TriangleConstants) == 13 * sizeof(double));

/// The centroid and second moments per area of triangle (a, b, c) into `k` (its area fields are
/// the caller's).
inline void addTriangleShape(TriangleConstants& k, const double a[3], const double b[3], const double c[3]) {
  const double third = 1.0 / 3.0;
  double m[3][3];  // edge midpoints
  for (int i = 0; i < 3; ++i) {
    k.centroid[i] = (a[i] + b[i] + c[i]) * third;
    m[0][i] = 0.5 * (a[i] + b[i]);
    m[1][i] = 0.5 * (b[i] + c[i]);
    m[2][i] = 0.5 * (c[i] + a[i]);
  }
  static constexpr int kPair[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  for (int pair = 0; pair < 6; ++pair) {
    const int i = kPair[pair][0], j = kPair[pair][1];
    k.secondMoments[pair] = (m[0][i] * m[0][j] + m[1][i] * m[1][j] + m[2][i] * m[2][j]) * third;
  }
}

/// The constants of triangle (a, b, c). Inline (out of line it cost the exact path 10 %: the
/// 162-vertex hull 6.3 -> 6.9 us plain, 4.8 -> 5.4 us prepared, same machine and load): the
/// prepared and the plain path get the same bits as long as the build does not contract their
/// multiply-adds differently (no -march with FMA here; test_prepared_polyhedron checks the bits).
inline TriangleConstants triangleConstants(const double a[3], const double b[3], const double c[3]) {
  TriangleConstants k;
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  k.areaVector[0] = 0.5 * (u[1] * v[2] - u[2] * v[1]);
  k.areaVector[1] = 0.5 * (u[2] * v[0] - u[0] * v[2]);
  k.areaVector[2] = 0.5 * (u[0] * v[1] - u[1] * v[0]);
  k.area = std::sqrt(k.areaVector[0] * k.areaVector[0] + k.areaVector[1] * k.areaVector[1] +
                     k.areaVector[2] * k.areaVector[2]);
  addTriangleShape(k, a, b, c);
  return k;
}

/// Most triangles in a leaf of a prepared mesh's hierarchy: the cost of a leaf the water line
/// crosses (its triangles one by one) against the nodes opened above it (bench_peers, Wigley hull
/// of 4,222 triangles: commit e045bbd). The walks under waves list a leaf's triangles on the stack.
inline constexpr std::size_t kMaxLeafTriangles = 8;
/// Most distinct vertices in a leaf (three corners a triangle).
inline constexpr std::size_t kMaxLeafVertices = 3 * kMaxLeafTriangles;

/// A node of a prepared mesh's bounding-volume hierarchy (PreparedPolyhedron): a box around nearby
/// triangles, with their constants summed (NodeSums, alongside). The sums are linear in the up
/// row r1, so a node wholly under a flat surface adds its 31 numbers contracted with r1 (O(1),
/// where its triangles one by one take 13 multiply-adds each and a classification), one wholly
/// above it is skipped, and only the nodes the water line crosses are opened, down to leaves of a
/// few triangles, as the texture path's tiles are. Nodes are stored depth first: a node's first
/// child follows it, and `next` is the node after its subtree (a leaf's is its own index + 1), so
/// the walk needs no stack. What the walk reads of every node it visits (one cache line) is kept
/// apart from the sums, which it reads only for a node wholly under (Wigley hull, the 100 states
/// of bench_peers' buoyancy-only pass: about 700 nodes visited a query, 90 of them wholly under).
struct alignas(64) TriangleNode {
  double center[3];          ///< m, body frame: the centre of its triangles' corners' bounds
  double halfExtent[3];      ///< m: every corner lies within these of `center` on each axis
  std::uint32_t begin, end;  ///< its triangles [begin, end) in the prepared order
  std::uint32_t next;        ///< the node after its subtree
};

/// A node's triangles' constants summed (TriangleConstants times their area vectors).
struct NodeSums {
  double area;                 ///< Sum |A| (m^2)
  double areaVector[3];        ///< Sum A_k (m^2)
  double firstMoments[3][3];   ///< Sum centroid_i A_k (m^3)
  double secondMoments[6][3];  ///< Sum secondMoments_pair A_k (m^4)
};

/// A mesh's triangles laid out for the hierarchy (PreparedPolyhedron::prepare): the index triples
/// and constants in the leaves' order, and the nodes, depth first (the root first), with their
/// sums in the same order. A second layout of the same mesh may keep no constants of its own and
/// read another's (`constantsOf`) through `constantIndex`: the 104 bytes a triangle once.
struct PreparedTriangles {
  std::vector<Eigen::Vector3i> triangles;
  std::vector<TriangleConstants> constants;  ///< in this layout's order; empty when read from `constantsOf`
  std::shared_ptr<const PreparedTriangles> constantsOf;
  std::vector<std::uint32_t> constantIndex;  ///< triangle k's constants are constantsOf->constants[constantIndex[k]]
  std::vector<TriangleNode> nodes;
  std::vector<NodeSums> sums;
  /// Each leaf's distinct vertices, so that a walk under waves poses a vertex that several of the
  /// leaf's triangles share, and asks a model its height, once (a fine mesh's leaf of 8 triangles
  /// has about 8 vertices to its 24 corners): the leaves' vertices (mesh indices) leaf after leaf,
  /// node i's being leafVertices[vertexBegin[i], vertexBegin[i + 1]) (none for an inner node),
  /// and for triangle k (this layout's order) its corners' places in its leaf's list.
  std::vector<std::uint32_t> leafVertices;
  std::vector<std::uint32_t> vertexBegin;                  ///< nodes.size() + 1 entries
  std::vector<std::array<std::uint8_t, 3>> leafCorners;    ///< triangles.size() entries
  /// The constants of triangle k (this layout's order).
  const TriangleConstants& constant(std::size_t k) const {
    return constantsOf ? constantsOf->constants[constantIndex[k]] : constants[k];
  }
};

/// The exact hydrostatics of a closed mesh (body frame) under a flat surface at `level` (m) of
/// `density` (kg/m^3), the query already validated and the mesh's indices known to be in range.
/// `prepared`: the mesh's triangles in a hierarchy (their constants made once), or null to visit
/// the mesh's triangles one by one and compute the constants of those that need them. The two
/// add the same terms in another order: they agree to rounding (test_prepared_polyhedron).
/// Error: a non-finite result (a vertex that is NaN or infinite). `nodesVisited`, when given with a
/// hierarchy, receives the nodes its walk visited.
Expected<HydrostaticsResult> flatPolyhedralHydrostatics(const Mesh& mesh, const PreparedTriangles* prepared,
                                                        double level, double density, const HydrostaticsQuery& query,
                                                        std::size_t* nodesVisited = nullptr);

/// The exact hydrostatics of a prepared closed mesh under a surface that is not flat and offers
/// smoothness bounds (Gerstner waves): its triangle nodes against local surface models
/// (PolyhedralHydrostaticsWaves.cpp), the query already validated. Empty when the surface offers
/// no bounds (height grids: the caller takes the plain path). Errors: a surface height that is
/// not finite, a non-finite result. `work`, when given, receives what it did; `keep`, when given,
/// the grid of surface jets its models were interpolated from (SurfaceJetGrid.hpp), for the same
/// body's drag after it.
std::optional<Expected<HydrostaticsResult>> wavePolyhedralHydrostatics(const Mesh& mesh,
                                                                       const PreparedTriangles& prepared,
                                                                       const LiquidSurface& surface,
                                                                       const HydrostaticsQuery& query,
                                                                       ExactWaveWork* work = nullptr,
                                                                       std::optional<SurfaceJetGrid>* keep = nullptr);

}  // namespace hydrotex::detail
