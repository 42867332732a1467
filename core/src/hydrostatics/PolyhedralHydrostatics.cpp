// SPDX-License-Identifier: Zlib
/// @file PolyhedralHydrostatics.cpp
/// Exact hydrostatics of a closed triangle mesh: each triangle is clipped against the water plane
/// (taken to the body frame, so vertices are never transformed) and the wetted part's moments
/// Sum A, Sum p A^T, Sum p p^T A_k are integrated exactly (the edge-midpoint rule is exact for
/// quadratics on a triangle: Strang and Fix 1973, table 4.1). HydrostaticSums turns the moments
/// into volume, centre of buoyancy and water plane (divergence theorem; Mirtich 1996, "Fast and
/// accurate computation of polyhedral mass properties", for the same idea on the whole body).

#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"

namespace hydrotex {

namespace {

using Moments = TextureHydrostatics::Moments;

struct Point {
  double x, y, z;
};

inline Point lerp(const Point& a, const Point& b, double t) {
  return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t};
}

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

/// Adds the part of triangle (a, b, c) where depth > 0; depths are linear over the triangle.
inline void addClippedTriangle(Moments& m, const Point p[3], const double depth[3]) {
  const bool under[3] = {depth[0] > 0.0, depth[1] > 0.0, depth[2] > 0.0};
  const int count = int(under[0]) + int(under[1]) + int(under[2]);
  if (count == 0) return;
  if (count == 3) {
    addTriangle(m, p[0], p[1], p[2]);
    return;
  }
  // Rotate the corners (keeping orientation) so that corner i is the odd one out.
  int i = 0;
  for (int k = 0; k < 3; ++k)
    if (under[k] == (count == 1)) i = k;
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  const Point qij = lerp(p[i], p[j], depth[i] / (depth[i] - depth[j]));
  const Point qik = lerp(p[i], p[k], depth[i] / (depth[i] - depth[k]));
  if (count == 1) {
    addTriangle(m, p[i], qij, qik);
  } else {
    // Corner i is over: the wetted part is the quad qij, p[j], p[k], qik.
    addTriangle(m, qij, p[j], p[k]);
    addTriangle(m, qij, p[k], qik);
  }
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
  if (!flat && surface.hasFreeSurface())
    return Error{"exact hydrostatics: the liquid surface is not flat; use the texture path for waves and grids"};
  if (mesh.triangles.empty()) return Error{"exact hydrostatics: the mesh has no triangles"};
  if (!indicesInRange(mesh)) return Error{"exact hydrostatics: a triangle index is out of range"};

  const Eigen::Matrix3d& rotation = query.pose.rotation;
  const Eigen::Vector3d& translation = query.pose.translation;
  const auto& positions = mesh.positions;
  Moments moments;
  detail::WettedSums sums;
  Eigen::Vector3d origin;

  if (flat) {
    // The water plane in the body frame: depth(p) = (h - t_y) - r . p with r the rotation's y row.
    const double level = *flat - translation.y();
    const double rx = rotation(1, 0), ry = rotation(1, 1), rz = rotation(1, 2);
    for (const Eigen::Vector3i& t : mesh.triangles) {
      Point p[3];
      double depth[3];
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector3d& v = positions[t[c]];
        p[c] = {v.x(), v.y(), v.z()};
        depth[c] = level - (rx * v.x() + ry * v.y() + rz * v.z());
      }
      addClippedTriangle(moments, p, depth);
    }
    origin = Eigen::Vector3d(translation.x(), *flat, translation.z());
    sums.addSubmergedMoments(moments, rotation, translation - origin);
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
      sums, origin, surface.density(), query, flat ? detail::ForceModel::Archimedes : detail::ForceModel::PressureSums,
      flat.has_value());
  if (!std::isfinite(result.submergedVolume) || !result.centerOfBuoyancy.allFinite() || !result.stiffness.allFinite())
    return Error{"exact hydrostatics: non-finite result (a vertex of the mesh is NaN or infinite)"};
  return result;
}

}  // namespace hydrotex
