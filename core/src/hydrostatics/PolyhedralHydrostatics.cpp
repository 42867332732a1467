// SPDX-License-Identifier: Zlib
/// @file PolyhedralHydrostatics.cpp
/// Exact hydrostatics of a closed triangle mesh. Under a flat surface (flatPolyhedralHydrostatics)
/// the water plane is taken to the body frame (vertices are never transformed), each vertex's depth
/// is found once, wholly dry triangles are skipped, wholly wet ones add their constant moments
/// weighted by the upward component of their area vector, and cut ones are clipped first; the
/// moments are exact (the edge-midpoint rule is exact for quadratics on a triangle: Strang and Fix
/// 1973, table 4.1) and HydrostaticSums turns them into volume, centre of buoyancy and water plane
/// (divergence theorem with fields that vanish on the water plane, so the cap is never built: the
/// classic scheme of signed tetrahedra with their apex on the plane; Mirtich 1996, "Fast and
/// accurate computation of polyhedral mass properties", for the same idea on the whole body).
/// Under waves and height grids (issue 19 item 2) the depth below the local surface is taken at
/// each vertex and linear over each triangle, the triangle is clipped where it changes sign, and
/// the linear pressure is integrated exactly over the wetted part (addWetTriangle), as boat
/// models that clip hull triangles against a wave surface do (Kerner, "Water interaction model
/// for boats in video games", Game Developer 2015; Stonefish's hydrodynamics).

#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "hydrostatics/CutCornerLanes.hpp"
#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrostatics/PolyhedralFlatSums.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrostatics/WetTriangleClipping.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"

namespace hydrotex {

namespace {

using detail::SurfaceVertex;
using detail::addClippedWetTriangle;
using Moments = TextureHydrostatics::Moments;

struct Point {
  double x, y, z;
};

/// Exact moments of one triangle (counter-clockwise seen from outside).
inline void addTriangle(Moments& m, const Point& a, const Point& b, const Point& c) {
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const double ax = 0.5 * (uy * vz - uz * vy), ay = 0.5 * (uz * vx - ux * vz), az = 0.5 * (ux * vy - uy * vx);
  const double area = std::sqrt(ax * ax + ay * ay + az * az);
  // Edge midpoints: Int_T f dA = |T| / 3 * sum f(midpoints) for quadratic f.
  const double m0x = 0.5 * (a.x + b.x), m0y = 0.5 * (a.y + b.y), m0z = 0.5 * (a.z + b.z);
  const double m1x = 0.5 * (b.x + c.x), m1y = 0.5 * (b.y + c.y), m1z = 0.5 * (b.z + c.z);
  const double m2x = 0.5 * (c.x + a.x), m2y = 0.5 * (c.y + a.y), m2z = 0.5 * (c.z + a.z);
  const double third = 1.0 / 3.0;
  const double cx = (a.x + b.x + c.x) * third, cy = (a.y + b.y + c.y) * third, cz = (a.z + b.z + c.z) * third;
  const double sxx = (m0x * m0x + m1x * m1x + m2x * m2x) * third;
  const double sxy = (m0x * m0y + m1x * m1y + m2x * m2y) * third;
  const double sxz = (m0x * m0z + m1x * m1z + m2x * m2z) * third;
  const double syy = (m0y * m0y + m1y * m1y + m2y * m2y) * third;
  const double syz = (m0y * m0z + m1y * m1z + m2y * m2z) * third;
  const double szz = (m0z * m0z + m1z * m1z + m2z * m2z) * third;
  const double av[3] = {ax, ay, az};
  const double cv[3] = {cx, cy, cz};
  const double sv[6] = {sxx, sxy, sxz, syy, syz, szz};
  m.sumArea += area;
  for (int k = 0; k < 3; ++k) {
    m.sumA[k] += av[k];
    for (int i = 0; i < 3; ++i) m.sumPA[i][k] += cv[i] * av[k];
    for (int pair = 0; pair < 6; ++pair) m.sumPPA[pair][k] += sv[pair] * av[k];
  }
}

/// The 10 upward-weighted body moments of a wetted surface (CutCornerLanes.hpp), with what adds
/// to them: wholly wet triangles and nodes here, cut triangles through a batch for the lanes.
struct UpwardMoments : detail::UpwardSums<double> {
  /// Adds a wholly wet piece of the surface given by its constants; `up` is r1 in the body frame.
  inline void add(const double up[3], const detail::TriangleConstants& k) {
    const double aUp = up[0] * k.areaVector[0] + up[1] * k.areaVector[1] + up[2] * k.areaVector[2];
    sumArea += k.area;
    sumAUp += aUp;
    for (int i = 0; i < 3; ++i) sumPAUp[i] += k.centroid[i] * aUp;
    for (int pair = 0; pair < 6; ++pair) sumPPAUp[pair] += k.secondMoments[pair] * aUp;
  }

  /// Adds a wholly wet node of triangles: its summed constants contracted with `up`.
  inline void add(const double up[3], const detail::NodeSums& c) {
    sumArea += c.area;
    sumAUp += up[0] * c.areaVector[0] + up[1] * c.areaVector[1] + up[2] * c.areaVector[2];
    for (int i = 0; i < 3; ++i)
      sumPAUp[i] += up[0] * c.firstMoments[i][0] + up[1] * c.firstMoments[i][1] + up[2] * c.firstMoments[i][2];
    for (int pair = 0; pair < 6; ++pair)
      sumPPAUp[pair] +=
          up[0] * c.secondMoments[pair][0] + up[1] * c.secondMoments[pair][1] + up[2] * c.secondMoments[pair][2];
  }

  /// Adds the part of the triangle with corners p[0..2] (counter-clockwise from outside) and
  /// constants `whole` where the depth, linear over it and given at the corners, is positive: the
  /// triangle or quadrilateral under the water line. `under` corners of the three have depth > 0
  /// (1 or 2: it is cut). Only the odd corner's triangle is formed (addCutCorner, in `batch`,
  /// which is summed when full): it is the wetted part (one corner under), or what the dry
  /// corner takes from the whole (two under).
  inline void addCut(const double up[3], const double* p[3], const double depth[3], int under,
                     const detail::TriangleConstants& whole, detail::CutCornerBatch& batch) {
    // Turn the corners (keeping orientation) so that corner i is the odd one out.
    int i = 0;
    for (int k = 0; k < 3; ++k)
      if ((depth[k] > 0.0) == (under == 1)) i = k;
    const int corners[3] = {i, (i + 1) % 3, (i + 2) % 3};
    const double sign = under == 1 ? 1.0 : -1.0;
    if (under != 1) add(up, whole);
    const unsigned e = batch.count++;
    for (int c = 0; c < 3; ++c) {
      for (int axis = 0; axis < 3; ++axis) batch.corner[3 * c + axis][e] = p[corners[c]][axis];
      batch.depth[c][e] = depth[corners[c]];
    }
    batch.area[e] = sign * whole.area;
    batch.aUp[e] = sign * (up[0] * whole.areaVector[0] + up[1] * whole.areaVector[1] + up[2] * whole.areaVector[2]);
    if (batch.count == detail::CutCornerBatch::kCapacity) addCuts(batch);
  }

  /// Adds the batch's cut corners and empties it: four at a time in AVX2, else two in SSE2, else
  /// one by one.
  inline void addCuts(detail::CutCornerBatch& batch) {
    batch.pad();
#ifdef HYDROTEX_DOUBLE_LANES
    if (!detail::sumCutCornersAvx2(batch, *this)) detail::sumCutCornerLanes<detail::DoubleLanes>(batch, *this);
#else
    detail::sumCutCornersOneByOne(batch, *this);
#endif
    batch.count = 0;
  }
};

/// Per-thread scratch of one depth per vertex under a flat surface (grows to the largest mesh the
/// thread has seen and is reused: a step allocates nothing).
std::vector<double>& vertexDepthScratch() {
  thread_local std::vector<double> scratch;
  return scratch;
}

/// Per-thread scratch for the vertices under a free surface that is not flat: it grows to the
/// largest mesh a thread has seen and is reused, so that a step allocates nothing.
/// A query's scratch under a free surface (per thread, grown once): the posed vertices, those
/// whose surface height is asked (index, world x and z, the height), and the triangles that may be
/// wet. Columns of fixed size filled by a count, so that a vertex costs a few stores.
struct SurfaceScratch {
  std::vector<SurfaceVertex> vertices;
  std::vector<std::uint32_t> asked, wetTriangles;
  std::vector<double> x, z, height;
};

SurfaceScratch& surfaceScratch() {
  thread_local SurfaceScratch scratch;
  return scratch;
}

bool indicesInRange(const Mesh& mesh) {
  const auto count = static_cast<unsigned>(mesh.positions.size());
  for (const Eigen::Vector3i& t : mesh.triangles)
    if (static_cast<unsigned>(t[0]) >= count || static_cast<unsigned>(t[1]) >= count ||
        static_cast<unsigned>(t[2]) >= count)
      return false;
  return true;
}

}  // namespace

Expected<HydrostaticsResult> detail::flatPolyhedralHydrostatics(const Mesh& mesh, const PreparedTriangles* prepared,
                                                                double level, double density,
                                                                const HydrostaticsQuery& query,
                                                                std::size_t* nodesVisited) {
  // The water plane in the body frame: depth(p) = (h - t_y) - r1 . p, once per vertex; a triangle
  // with no corner under it costs three loads and compares, a wholly wet one its constants' 13
  // multiply-adds, and only the cut ones are clipped (as Jolt's and Kerner's buoyancy do). A
  // prepared mesh's nodes wholly under or over the plane cost O(1) (TriangleNode).
  const Eigen::Matrix3d& rotation = query.pose.rotation;
  const Eigen::Vector3d& translation = query.pose.translation;
  const double up[3] = {rotation(1, 0), rotation(1, 1), rotation(1, 2)};
  const double bodyLevel = level - translation.y();
  const auto& positions = mesh.positions;
  // The depth of a vertex: a prepared mesh takes it per corner of the leaves its walk opens (the
  // same expression, so the same bits), the plain path once per vertex into the thread's scratch
  // (a prepared 17,160-face sphere spent 4 of its 12 us on the 8,582 vertices' depths).
  const auto depthOf = [&](const Eigen::Vector3d& p) { return bodyLevel - (up[0] * p.x() + up[1] * p.y() + up[2] * p.z()); };
  std::vector<double>& depths = vertexDepthScratch();
  if (!prepared) {
    depths.resize(positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) depths[v] = depthOf(positions[v]);
  }
  UpwardMoments m;
  detail::CutCornerBatch cuts;  // the cut triangles, summed 32 at a time
  // Triangles [begin, end) of `triangles` one by one (`constants` aligned with them, or null).
  const auto addTriangles = [&](const Eigen::Vector3i* triangles, const TriangleConstants* constants, std::size_t begin,
                                std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const Eigen::Vector3i& tri = triangles[t];
      double depth[3];
      for (int c = 0; c < 3; ++c)
        depth[c] = constants ? depthOf(positions[std::size_t(tri[c])]) : depths[std::size_t(tri[c])];
      const int under = int(depth[0] > 0.0) + int(depth[1] > 0.0) + int(depth[2] > 0.0);
      if (under == 0) continue;
      const double* p[3] = {positions[std::size_t(tri[0])].data(), positions[std::size_t(tri[1])].data(),
                            positions[std::size_t(tri[2])].data()};
      if (under != 3)
        m.addCut(up, p, depth, under, constants ? constants[t] : triangleConstants(p[0], p[1], p[2]), cuts);
      else if (constants)
        m.add(up, constants[t]);  // by reference: no copy of the 104 bytes
      else
        m.add(up, triangleConstants(p[0], p[1], p[2]));
    }
  };
  if (prepared) {
    // A node's corners lie within its half extents of its centre, so their depths lie within
    // Sum |r1_i| h_i of the centre's; the margin, 1e-12 of the terms a depth sums, keeps the
    // classification conservative through the depths' rounding: all under (> 0) or none (<= 0)
    // exactly as the triangles one by one would find. Depth first: an opened node's first child
    // is the next node, a closed one's subtree is skipped to its `next`.
    const double reach[3] = {std::abs(up[0]) * (1.0 + 1e-12), std::abs(up[1]) * (1.0 + 1e-12),
                             std::abs(up[2]) * (1.0 + 1e-12)};
    const std::vector<TriangleNode>& nodes = prepared->nodes;
    std::size_t visited = 0;
    for (std::size_t i = 0; i < nodes.size(); ++visited) {
      const TriangleNode& node = nodes[i];
      const double height = up[0] * node.center[0] + up[1] * node.center[1] + up[2] * node.center[2];
      const double depth = bodyLevel - height;
      const double spread =
          reach[0] * (node.halfExtent[0] + 1e-12 * std::abs(node.center[0])) +
          reach[1] * (node.halfExtent[1] + 1e-12 * std::abs(node.center[1])) +
          reach[2] * (node.halfExtent[2] + 1e-12 * std::abs(node.center[2])) + 1e-12 * std::abs(bodyLevel);
      if (depth < -spread) {
        i = node.next;
      } else if (depth > spread) {
        m.add(up, prepared->sums[i]);
        i = node.next;
      } else {
        if (node.next == i + 1)  // a leaf the water line may cross
          addTriangles(prepared->triangles.data(), prepared->constants.data(), node.begin, node.end);
        ++i;
      }
    }
    if (nodesVisited) *nodesVisited = visited;
  } else {
    addTriangles(mesh.triangles.data(), nullptr, 0, mesh.triangles.size());
  }
  m.addCuts(cuts);

  // To the world sums about o = (t_x, h, t_z), with x' = R p + b, b = t - o: Sum x' a_up =
  // R P + b W and Sum x' x'^T a_up = R S R^T + b (R P)^T + (R P) b^T + b b^T W (W = Sum a_up,
  // P = Sum p a_up, S = Sum p p^T a_up); on the wetted surface D = -y', Q = y'^2, h' = 0
  // (HydrostaticSums.hpp): the y column of WettedSums::addSubmergedMoments, all a flat surface reads.
  const Eigen::Vector3d origin(translation.x(), level, translation.z());
  const Eigen::Vector3d b = translation - origin;
  const Eigen::Vector3d rp = rotation * Eigen::Vector3d(m.sumPAUp[0], m.sumPAUp[1], m.sumPAUp[2]);
  Eigen::Matrix3d s;
  s << m.sumPPAUp[0], m.sumPPAUp[1], m.sumPPAUp[2], m.sumPPAUp[1], m.sumPPAUp[3], m.sumPPAUp[4], m.sumPPAUp[2],
      m.sumPPAUp[4], m.sumPPAUp[5];
  const double w = m.sumAUp;
  const Eigen::Vector3d w1 = rp + b * w;
  const Eigen::Matrix3d w2 =
      rotation * s * rotation.transpose() + b * rp.transpose() + rp * b.transpose() + (b * b.transpose()) * w;
  WettedSums sums;
  sums.sumDA[1] = -w1.y();
  sums.sumDXAy = -w2(0, 1);
  sums.sumDZAy = -w2(2, 1);
  sums.sumYB = 0.5 * w2(1, 1);
  sums.sumAy = w;
  sums.sumXAy = w1.x();
  sums.sumZAy = w1.z();
  sums.sumXXAy = w2(0, 0);
  sums.sumXZAy = w2(0, 2);
  sums.sumZZAy = w2(2, 2);
  sums.wettedArea = m.sumArea;
  HydrostaticsResult result = finishHydrostatics(sums, origin, density, query, ForceModel::Archimedes, true);
  if (!std::isfinite(result.submergedVolume) || !result.centerOfBuoyancy.allFinite() || !result.stiffness.allFinite())
    return Error{"exact hydrostatics: non-finite result (a vertex of the mesh is NaN or infinite)"};
  return result;
}

Status checkClosedMesh(const Mesh& mesh) {
  // One closedness check in the project: MeshValidation's, without its UV work.
  return requireClosed(validateMesh(mesh, false), mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName);
}

Expected<HydrostaticsResult> polyhedralHydrostatics(const Mesh& mesh, const LiquidSurface& surface,
                                                    const HydrostaticsQuery& query) {
  if (Status closed = checkClosedMesh(mesh); !closed) return closed.error();
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    if (!mesh.positions[v].allFinite())
      return Error{(mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName) + ": vertex " + std::to_string(v) +
                   " is not finite"};
  return polyhedralHydrostaticsUnchecked(mesh, surface, query);
}

Expected<HydrostaticsResult> polyhedralHydrostaticsUnchecked(const Mesh& mesh, const LiquidSurface& surface,
                                                             const HydrostaticsQuery& query) {
  if (Status valid = validateHydrostaticsQuery(surface, query); !valid) return valid.error();
  const std::optional<double> flat = surface.flatHeight();
  if (mesh.triangles.empty()) return Error{"exact hydrostatics: the mesh has no triangles"};
  if (!indicesInRange(mesh)) return Error{"exact hydrostatics: a triangle index is out of range"};
  if (flat) return detail::flatPolyhedralHydrostatics(mesh, nullptr, *flat, surface.density(), query);

  const Eigen::Matrix3d& rotation = query.pose.rotation;
  const Eigen::Vector3d& translation = query.pose.translation;
  const auto& positions = mesh.positions;
  Moments moments;
  detail::WettedSums sums;
  Eigen::Vector3d origin;

  if (surface.hasFreeSurface()) {
    // Waves, height grids: the surface asked once per vertex (of the triangles that may be wet),
    // the depth taken linear over each triangle between its vertices (so the surface is
    // linearized between vertices: an O(edge^2 curvature) difference from the true surface), and
    // the wetted part integrated exactly for that depth (addWetTriangle). The frame origin, the
    // force model and the water plane are the texture path's under waves
    // (TextureHydrostatics.cpp): o = (t_x, h(x_G, z_G), t_z), pressure sums, and the stiffness
    // from the cap's projection onto the horizontal, about the plane y = h(x_G, z_G) through o,
    // i.e. the flat-water formulas applied to the local mean plane at the centre of mass.
    const Eigen::Vector3d centerOfMass = query.pose.apply(query.centerOfMass);
    const double originHeight = surface.surfaceHeight(centerOfMass.x(), centerOfMass.z(), query.time);
    if (!std::isfinite(originHeight))
      return Error{"exact hydrostatics: the liquid surface height is not finite (" + std::to_string(originHeight) +
                   " m) above the centre of mass"};
    origin = Eigen::Vector3d(translation.x(), originHeight, translation.z());
    const Eigen::Vector3d offset = translation - origin;
    // Triangles wholly above the surface's highest point are dry without asking the surface
    // (Gerstner waves: a Newton search per call).
    const double highest = surface.heightRange(query.time).second - origin.y();
    SurfaceScratch& scratch = surfaceScratch();
    std::vector<SurfaceVertex>& vertices = scratch.vertices;
    vertices.resize(positions.size());
    detail::Footprint footprint;
    for (std::size_t v = 0; v < positions.size(); ++v) {
      const Eigen::Vector3d w = rotation * positions[v] + offset;
      vertices[v] = {w.x(), w.y(), w.z(), std::numeric_limits<double>::quiet_NaN()};
      footprint.add(w.x() + origin.x(), w.z() + origin.z());
    }
    // The triangles that may be wet (one under the highest crest), and their vertices in the
    // mesh's order, asked the surface at once: a surface may start each search from the last
    // vertex's answer (waves), and the mesh's order keeps most neighbours near each other.
    scratch.asked.resize(positions.size());
    scratch.x.resize(positions.size());
    scratch.z.resize(positions.size());
    scratch.height.resize(positions.size());
    scratch.wetTriangles.resize(mesh.triangles.size());
    std::size_t askedCount = 0, wetCount = 0;
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
      const Eigen::Vector3i& t = mesh.triangles[k];
      if (std::min({vertices[t[0]].y, vertices[t[1]].y, vertices[t[2]].y}) >= highest) continue;
      scratch.wetTriangles[wetCount++] = std::uint32_t(k);
      for (int c = 0; c < 3; ++c) {
        SurfaceVertex& vertex = vertices[t[c]];
        if (vertex.depth == 0.0) continue;  // already asked (NaN until then)
        if (!std::isfinite(vertex.x) || !std::isfinite(vertex.y) || !std::isfinite(vertex.z))
          return Error{"exact hydrostatics: vertex " + std::to_string(t[c]) + " of the mesh is not finite"};
        vertex.depth = 0.0;
        scratch.asked[askedCount] = std::uint32_t(t[c]);
        scratch.x[askedCount] = vertex.x + origin.x();
        scratch.z[askedCount] = vertex.z + origin.z();
        ++askedCount;
      }
    }
    // The heights from jets over the footprint where that takes fewer surface samples than the
    // vertices would (a Gerstner height is a Newton search; the Wigley hull has 2,113 vertices).
    detail::SurfaceHeights heights(surface, query.time, footprint, kExactWaveHeightError, double(askedCount));
    heights.at(std::span(scratch.x.data(), askedCount), std::span(scratch.z.data(), askedCount),
               std::span(scratch.height.data(), askedCount));
    for (std::size_t r = 0; r < askedCount; ++r) {
      const double height = scratch.height[r];
      if (!std::isfinite(height))
        return Error{"exact hydrostatics: the liquid surface height is not finite (" + std::to_string(height) +
                     " m) at (x, z) = (" + std::to_string(scratch.x[r]) + ", " + std::to_string(scratch.z[r]) +
                     ") m, above vertex " + std::to_string(scratch.asked[r])};
      SurfaceVertex& vertex = vertices[scratch.asked[r]];
      vertex.depth = (height - origin.y()) - vertex.y;
    }
    for (std::size_t k = 0; k < wetCount; ++k) {
      const Eigen::Vector3i& t = mesh.triangles[scratch.wetTriangles[k]];
      const SurfaceVertex* p[3] = {&vertices[t[0]], &vertices[t[1]], &vertices[t[2]]};
      addClippedWetTriangle(sums, p);
    }
    sums.setHydrostaticPressure(surface.density() * query.gravity);
  } else {
    // No free surface: all of the body is submerged; the medium's pressure is integrated per
    // triangle at its centroid (exact when the density is constant: p is then linear).
    origin = translation;
    for (const Eigen::Vector3i& t : mesh.triangles) {
      const Point p[3] = {{positions[t[0]].x(), positions[t[0]].y(), positions[t[0]].z()},
                          {positions[t[1]].x(), positions[t[1]].y(), positions[t[1]].z()},
                          {positions[t[2]].x(), positions[t[2]].y(), positions[t[2]].z()}};
      addTriangle(moments, p[0], p[1], p[2]);
      const Eigen::Vector3d bodyArea = 0.5 * (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
      const Eigen::Vector3d centroid = query.pose.apply((positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0);
      const Eigen::Vector3d force = -surface.pressure(centroid, query.time, query.gravity) * (rotation * bodyArea);
      const Eigen::Vector3d torque = (centroid - origin).cross(force);
      for (int k = 0; k < 3; ++k) {
        sums.pressureForce[k] += force[k];
        sums.pressureTorque[k] += torque[k];
      }
    }
    sums.addSubmergedMoments(moments, rotation, Eigen::Vector3d::Zero());
  }

  HydrostaticsResult result = detail::finishHydrostatics(
      sums, origin, surface.density(), query, detail::ForceModel::PressureSums, surface.hasFreeSurface());
  if (!std::isfinite(result.submergedVolume) || !result.centerOfBuoyancy.allFinite() || !result.stiffness.allFinite())
    return Error{"exact hydrostatics: non-finite result (a vertex of the mesh is NaN or infinite)"};
  return result;
}

}  // namespace hydrotex
