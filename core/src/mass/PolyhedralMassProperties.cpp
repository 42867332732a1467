// SPDX-License-Identifier: Zlib
// Exact mass properties of a closed triangle mesh.
// Source: D. Eberly, "Polyhedral Mass Properties (Revisited)", Geometric Tools (2002), which
// simplifies B. Mirtich, "Fast and Accurate Computation of Polyhedral Mass Properties",
// Journal of Graphics Tools 1(2), 1996: the divergence theorem turns the volume integrals of
// 1, x, y, z, x^2, y^2, z^2, xy, yz, zx into sums over the triangles.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "hydrotex/mass/MassProperties.hpp"
#include "mass/MassMoments.hpp"
#include "hydrotex/mesh/MeshParts.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"

namespace hydrotex {
namespace {

// Eberly's subexpressions for one coordinate of a triangle's three vertices.
struct Subexpressions {
  double f1, f2, f3, g0, g1, g2;
};

Subexpressions subexpressions(double w0, double w1, double w2) {
  Subexpressions s{};
  const double temp0 = w0 + w1;
  s.f1 = temp0 + w2;
  const double temp1 = w0 * w0;
  const double temp2 = temp1 + w1 * temp0;
  s.f2 = temp2 + w2 * s.f1;
  s.f3 = w0 * temp1 + w1 * temp2 + w2 * s.f2;
  s.g0 = s.f2 + w0 * (s.f1 + w0);
  s.g1 = s.f2 + w1 * (s.f1 + w1);
  s.g2 = s.f2 + w2 * (s.f1 + w2);
  return s;
}

/// Every vertex finite and every index in range (messages start with `name`): what both the solid
/// and the shell integrals need before they sum.
Status checkVerticesAndIndices(const Mesh& mesh, const std::string& name) {
  const int vertexCount = static_cast<int>(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i)
    if (!mesh.positions[i].allFinite()) return Error{name + ": vertex " + std::to_string(i) + " is not finite"};
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles[t][k] < 0 || mesh.triangles[t][k] >= vertexCount)
        return Error{name + ": triangle " + std::to_string(t) + " has a vertex index out of range"};
  return Ok{};
}

}  // namespace

Expected<MassProperties> polyhedralMassProperties(const Mesh& mesh, double density) {
  const std::string name = mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName;
  if (!(density > 0.0) || !std::isfinite(density))
    return Error{name + ": density " + std::to_string(density) + " kg/m^3 must be positive and finite"};
  if (mesh.triangles.empty()) return Error{name + ": no triangles, no volume"};
  if (Status usable = checkVerticesAndIndices(mesh, name); !usable) return usable.error();
  if (Status closed = checkClosed(mesh, name); !closed) return closed.error();
  // A closed mesh with one part inside out sums to a plausible positive volume but a centre of
  // mass and inertia that are wrong (negative diagonal terms): refuse it (repairMesh turns it).
  std::size_t insideOut = 0;
  for (const MeshPart& part : findMeshParts(mesh)) insideOut += part.insideOut() ? 1 : 0;
  if (insideOut > 0)
    return Error{name + ": " + std::to_string(insideOut) +
                 " closed parts are inside out (negative volume outside any other part); repair the mesh "
                 "(repairMesh, or drop --no-repair) or flip those parts"};

  // Integrate about the bounding-box centre: the products below lose fewer digits there.
  Eigen::Vector3d lo = mesh.positions[0], hi = lo;
  for (const auto& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d origin = 0.5 * (lo + hi);

  // intg: 1, x, y, z, x^2, y^2, z^2, xy, yz, zx (Eberly's order).
  double intg[10] = {};
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d p0 = mesh.positions[t[0]] - origin;
    const Eigen::Vector3d p1 = mesh.positions[t[1]] - origin;
    const Eigen::Vector3d p2 = mesh.positions[t[2]] - origin;
    const Eigen::Vector3d d = (p1 - p0).cross(p2 - p0);
    const Subexpressions x = subexpressions(p0.x(), p1.x(), p2.x());
    const Subexpressions y = subexpressions(p0.y(), p1.y(), p2.y());
    const Subexpressions z = subexpressions(p0.z(), p1.z(), p2.z());
    intg[0] += d.x() * x.f1;
    intg[1] += d.x() * x.f2;
    intg[2] += d.y() * y.f2;
    intg[3] += d.z() * z.f2;
    intg[4] += d.x() * x.f3;
    intg[5] += d.y() * y.f3;
    intg[6] += d.z() * z.f3;
    intg[7] += d.x() * (p0.y() * x.g0 + p1.y() * x.g1 + p2.y() * x.g2);
    intg[8] += d.y() * (p0.z() * y.g0 + p1.z() * y.g1 + p2.z() * y.g2);
    intg[9] += d.z() * (p0.x() * z.g0 + p1.x() * z.g1 + p2.x() * z.g2);
  }
  intg[0] /= 6.0;
  for (int i = 1; i <= 3; ++i) intg[i] /= 24.0;
  for (int i = 4; i <= 6; ++i) intg[i] /= 60.0;
  for (int i = 7; i <= 9; ++i) intg[i] /= 120.0;

  const double volume = intg[0];
  if (!(volume > 0.0))
    return Error{name + ": enclosed volume " + std::to_string(volume) +
                 " m^3 is not positive (triangles facing inwards?)"};
  const Eigen::Vector3d c(intg[1] / volume, intg[2] / volume, intg[3] / volume);  // about `origin`

  // Second moments about the centre of mass (per unit density), then I = trace(S) Id - S.
  Eigen::Matrix3d central;
  central(0, 0) = intg[4] - volume * c.x() * c.x();
  central(1, 1) = intg[5] - volume * c.y() * c.y();
  central(2, 2) = intg[6] - volume * c.z() * c.z();
  central(0, 1) = central(1, 0) = intg[7] - volume * c.x() * c.y();
  central(1, 2) = central(2, 1) = intg[8] - volume * c.y() * c.z();
  central(0, 2) = central(2, 0) = intg[9] - volume * c.z() * c.x();

  MassProperties result;
  result.volume = volume;
  result.mass = density * volume;
  result.centerOfMass = origin + c;
  result.inertia = density * (central.trace() * Eigen::Matrix3d::Identity() - central);
  return result;
}

Expected<MassProperties> polyhedralShellMassProperties(const Mesh& mesh, double arealDensity) {
  const std::string name = mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName;
  if (!(arealDensity > 0.0) || !std::isfinite(arealDensity))
    return Error{name + ": shell density " + std::to_string(arealDensity) + " kg/m^2 must be positive and finite"};
  if (mesh.triangles.empty()) return Error{name + ": no triangles, no shell"};
  if (Status usable = checkVerticesAndIndices(mesh, name); !usable) return usable.error();
  // About the bounding-box centre, as above; a triangle's area moments a s / 3, a q / 12.
  Eigen::Vector3d lo = mesh.positions[0], hi = lo;
  for (const auto& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d origin = 0.5 * (lo + hi);
  std::vector<bool> lid(mesh.triangles.size(), false);
  for (std::uint32_t t : mesh.openingTriangles)
    if (t < lid.size()) lid[t] = true;
  double area = 0.0, first[3] = {}, second[6] = {};
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (lid[t]) continue;
    const Eigen::Vector3d p0 = mesh.positions[std::size_t(mesh.triangles[t][0])] - origin;
    const Eigen::Vector3d p1 = mesh.positions[std::size_t(mesh.triangles[t][1])] - origin;
    const Eigen::Vector3d p2 = mesh.positions[std::size_t(mesh.triangles[t][2])] - origin;
    const double a = 0.5 * (p1 - p0).cross(p2 - p0).norm();
    double s[3], q[6];
    detail::triangleCornerSums(p0.data(), p1.data(), p2.data(), s, q);
    area += a;
    for (int c = 0; c < 3; ++c) first[c] += a * s[c] / 3.0;
    for (int m = 0; m < 6; ++m) second[m] += a * q[m] / 12.0;
  }
  if (!(area > 0.0)) return Error{name + ": no area outside its lids, no shell"};
  detail::MassMoments moments;
  moments.mass = arealDensity * area;
  moments.first = arealDensity * Eigen::Vector3d(first[0], first[1], first[2]);
  moments.second << second[0], second[3], second[4], second[3], second[1], second[5], second[4], second[5], second[2];
  moments.second *= arealDensity;
  return detail::massPropertiesFromMoments(moments, origin);
}

}  // namespace hydrotex
