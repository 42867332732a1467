// SPDX-License-Identifier: Zlib
// Mass properties per triangle (issue 5; docs/design.md "Mass model"): the texel path's cone sums
// (TextureMassProperties.cpp) collapsed onto the triangles that the texel pieces belong to.
// Cone over a flat base B of area vector a B from apex c (Mirtich 1996, and the derivation at the
// top of TextureMassProperties.cpp): with q = c + s (x - c), s in [0, 1], dV = s^2 h ds dA and
//   volume v = h |B| / 3,   first moment about c  = 3/4 v E_B[x - c],
//   second moment about c  = 3/5 v E_B[(x - c)(x - c)^T],
// exact for any planar base. A piece k of triangle (V0, V1, V2) (area vector N = e1 x e2 / 2,
// e_i = V_i - V0, h = (V0 - c) . N over its plane) covering the fraction f_k of its UV area has
// v_k = f_k h / 3, and x - c = d0 + b1 e1 + b2 e2 (d0 = V0 - c) with b1, b2 the barycentrics,
// which the UV map carries over to the surface affinely. So per triangle only the density-weighted
// barycentric moments m = Sum rho_k f_k, w_i = Sum rho_k f_k E_k[b_i] and
// M_ij = Sum rho_k f_k E_k[b_i b_j] = Sum rho_k f_k (E_k[b_i] E_k[b_j] + Cov_k(b_i, b_j)) are needed:
//   mass   = h/3 m,   first = h/4 (m d0 + w1 e1 + w2 e2),
//   second = h/5 (m d0 d0^T + d0 u^T + u d0^T + M11 e1 e1^T + M12 (e1 e2^T + e2 e1^T) + M22 e2 e2^T),
// u = w1 e1 + w2 e2. A uniform density over the whole triangle has m = rho, w_i = rho/3,
// M_ij = rho (1 + delta_ij)/12 (in the symmetric form over d0, d1, d2: E[b_i b_j] = (1 + delta_ij)/12),
// and the sums become the exact polyhedral ones: with S = d0 + d1 + d2 and Q = Sum d_i d_i^T,
// mass h/3, first h S/12, second h (S S^T + Q)/60. The shell of unit areal density over a triangle
// of area |N|: |N|, |N| S/3, |N| (S S^T + Q)/12 (the degree-2 moments of a triangle, Eberly,
// "Polyhedral Mass Properties (Revisited)", 2002). Each piece's Cov_k comes from clipping its texel
// square against its UV triangle again (TexelClipping.hpp, as the bake) and the polygon's second
// moments (shoelace form: Steger, "On the calculation of arbitrary moments of polygons", 1996),
// mapped affinely from texel coordinates to barycentrics: Cov_k(b_i, b_j) = g_i^T C_k g_j with
// g_i the gradient of b_i in texel coordinates.
#include "hydrotex/mass/TriangleMassIntegrator.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "mass/MassMoments.hpp"
#include "bake/TexelClipping.hpp"

namespace hydrotex {
namespace {

// a += s b for the six entries xx yy zz xy xz yz of symmetric matrices.
inline void addSymmetric(double* a, double s, const double* b) {
  for (int m = 0; m < 6; ++m) a[m] += s * b[m];
}

// The six entries of p q^T + q p^T (xx yy zz xy xz yz).
inline void symmetricProduct(const double* p, const double* q, double* out) {
  out[0] = 2.0 * p[0] * q[0];
  out[1] = 2.0 * p[1] * q[1];
  out[2] = 2.0 * p[2] * q[2];
  out[3] = p[0] * q[1] + q[0] * p[1];
  out[4] = p[0] * q[2] + q[0] * p[2];
  out[5] = p[1] * q[2] + q[1] * p[2];
}

Eigen::Matrix3d symmetric(const double* s) {
  Eigen::Matrix3d m;
  m << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
  return m;
}

bool finiteNonNegative(double value) { return std::isfinite(value) && value >= 0.0; }

}  // namespace

Expected<TriangleMassIntegrator> TriangleMassIntegrator::create(const SurfaceBake& bake, const UvLayout& layout,
                                                                const Eigen::Vector3d& referencePoint) {
  if (!referencePoint.allFinite()) return Error{"triangle mass integrator: reference point is not finite"};
  const std::size_t triangles = layout.uvTriangles.size();
  if (triangles == 0) return Error{"triangle mass integrator: the UV layout has no triangles"};
  if (triangles > 0xFFFFFFFFull) return Error{"triangle mass integrator: too many triangles"};
  const std::size_t covered = bake.coveredCount();
  if (bake.pieceStart.size() != covered + 1 || bake.pieceStart.back() != bake.pieces.size())
    return Error{"triangle mass integrator: the bake's piece ranges do not match its pieces"};
  if (bake.width <= 0 || bake.height <= 0) return Error{"triangle mass integrator: the bake has no texels"};

  // Per triangle: its corners in texel coordinates (as the bake: x = u width, y = (1 - v) height).
  struct UvTriangle {
    std::array<double, 3> x{}, y{};
    double twiceSigned = 0.0;
  };
  std::vector<UvTriangle> uv(triangles);
  const int uvCount = static_cast<int>(layout.uvs.size());
  for (std::size_t t = 0; t < triangles; ++t) {
    const Eigen::Vector3i& corners = layout.uvTriangles[t];
    for (int k = 0; k < 3; ++k) {
      if (corners[k] < 0 || corners[k] >= uvCount)
        return Error{"triangle mass integrator: UV triangle " + std::to_string(t) + " has UV index " +
                     std::to_string(corners[k]) + " out of range"};
      uv[t].x[std::size_t(k)] = layout.uvs[std::size_t(corners[k])].x() * bake.width;
      uv[t].y[std::size_t(k)] = (1.0 - layout.uvs[std::size_t(corners[k])].y()) * bake.height;
    }
    const UvTriangle& p = uv[t];
    uv[t].twiceSigned = (p.x[1] - p.x[0]) * (p.y[2] - p.y[0]) - (p.x[2] - p.x[0]) * (p.y[1] - p.y[0]);
  }

  TriangleMassIntegrator result;
  result.referencePoint_ = referencePoint;
  result.texelCount_ = covered;
  // Counting sort of the pieces by triangle (stable: texel order within a triangle).
  result.triangleStart_.assign(triangles + 1, 0);
  const std::size_t texels = std::size_t(bake.width) * std::size_t(bake.height);
  for (std::size_t i = 0; i < covered; ++i) {
    if (bake.texelIndex[i] >= texels)
      return Error{"triangle mass integrator: covered texel " + std::to_string(i) + " lies outside the bake"};
    for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k) {
      const std::uint32_t t = bake.pieces[k].triangle;
      if (t >= triangles)
        return Error{"triangle mass integrator: a piece names triangle " + std::to_string(t) + ", the layout has " +
                     std::to_string(triangles)};
      ++result.triangleStart_[t + 1];
    }
  }
  for (std::size_t t = 0; t < triangles; ++t) result.triangleStart_[t + 1] += result.triangleStart_[t];
  std::vector<std::uint32_t> next(result.triangleStart_.begin(), result.triangleStart_.end() - 1);
  result.pieces_.resize(bake.pieces.size());

  for (std::size_t i = 0; i < covered; ++i) {
    const int column = static_cast<int>(bake.texelIndex[i] % std::uint32_t(bake.width));
    const int row = static_cast<int>(bake.texelIndex[i] / std::uint32_t(bake.width));
    const double x0 = column, y0 = row;
    for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k) {
      const std::uint32_t t = bake.pieces[k].triangle;
      Piece& piece = result.pieces_[next[t]++];
      piece.texel = static_cast<std::uint32_t>(i);
      const UvTriangle& p = uv[t];
      if (p.twiceSigned == 0.0) continue;  // no UV area: the bake gave it no pieces; carries nothing
      // The piece again: the texel square clipped by the triangle's three half-planes (a plane
      // that does not cut the square keeps it as it is, so this is the bake's polygon).
      const std::array<detail::HalfPlane, 3> planes = detail::triangleHalfPlanes(p.x, p.y, p.twiceSigned);
      detail::Polygon a = detail::texelSquare(column, row), b;
      detail::Polygon* current = &a;
      detail::Polygon* clipped = &b;
      for (int plane = 0; plane < 3 && current->count > 0; ++plane) {
        detail::clipAgainst(*current, planes[std::size_t(plane)], *clipped);
        std::swap(current, clipped);
      }
      // Area, first and second moments of the polygon relative to the texel corner (shoelace
      // forms; counter-clockwise, so `twice` > 0).
      double twice = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0;
      for (int c = 0; c < current->count; ++c) {
        const int d = (c + 1 == current->count) ? 0 : c + 1;
        const double xi = current->x[std::size_t(c)] - x0, yi = current->y[std::size_t(c)] - y0;
        const double xj = current->x[std::size_t(d)] - x0, yj = current->y[std::size_t(d)] - y0;
        const double cross = xi * yj - xj * yi;
        twice += cross;
        sx += (xi + xj) * cross;
        sy += (yi + yj) * cross;
        sxx += (xi * xi + xi * xj + xj * xj) * cross;
        syy += (yi * yi + yi * yj + yj * yj) * cross;
        sxy += (xi * yj + 2.0 * xi * yi + 2.0 * xj * yj + xj * yi) * cross;
      }
      if (!(twice > 0.0)) continue;  // nothing left (the bake dropped such slivers too)
      // Centroid (relative to the corner) and covariance about it (texel^2).
      const double cx = sx / (3.0 * twice), cy = sy / (3.0 * twice);
      const double cxx = sxx / (6.0 * twice) - cx * cx;
      const double cyy = syy / (6.0 * twice) - cy * cy;
      const double cxy = sxy / (12.0 * twice) - cx * cy;
      // Barycentrics b1, b2 (affine in x, y) at the centroid, and their gradients.
      const double inverseTwice = 1.0 / p.twiceSigned;
      const double x = x0 + cx, y = y0 + cy;
      const double b1 = ((x - p.x[0]) * (p.y[2] - p.y[0]) - (p.x[2] - p.x[0]) * (y - p.y[0])) * inverseTwice;
      const double b2 = ((p.x[1] - p.x[0]) * (y - p.y[0]) - (x - p.x[0]) * (p.y[1] - p.y[0])) * inverseTwice;
      const double g1x = (p.y[2] - p.y[0]) * inverseTwice, g1y = -(p.x[2] - p.x[0]) * inverseTwice;
      const double g2x = -(p.y[1] - p.y[0]) * inverseTwice, g2y = (p.x[1] - p.x[0]) * inverseTwice;
      const auto covariance = [&](double gx, double gy, double hx, double hy) {
        return gx * cxx * hx + (gx * hy + gy * hx) * cxy + gy * cyy * hy;
      };
      const double fraction = 0.5 * twice / (0.5 * std::abs(p.twiceSigned));
      piece.moments[0] = float(fraction);
      piece.moments[1] = float(fraction * b1);
      piece.moments[2] = float(fraction * b2);
      piece.moments[3] = float(fraction * (b1 * b1 + covariance(g1x, g1y, g1x, g1y)));
      piece.moments[4] = float(fraction * (b1 * b2 + covariance(g1x, g1y, g2x, g2y)));
      piece.moments[5] = float(fraction * (b2 * b2 + covariance(g2x, g2y, g2x, g2y)));
    }
  }
  return result;
}

Status TriangleMassIntegrator::setTexelDensity(const std::vector<float>& density) {
  if (density.empty()) {
    if (mapped_) {
      mapped_ = false;
      mappedMass_ = 0.0;
      std::fill(std::begin(mappedFirst_), std::end(mappedFirst_), 0.0);
      std::fill(std::begin(mappedSecond_), std::end(mappedSecond_), 0.0);
    }
    return Ok{};
  }
  if (density.size() != texelCount_)
    return Error{"density map has " + std::to_string(density.size()) + " texels, the bake has " +
                 std::to_string(texelCount_)};
  const std::size_t triangles = triangleCount();
  spareDensity_.resize(triangles);  // keeps its capacity: no allocation after the first map
  // Every covered texel has at least one piece, so this pass sees every density.
  bool valid = true;
  const float* rho = density.data();
  for (std::size_t t = 0; t < triangles; ++t) {
    double m = 0.0, w1 = 0.0, w2 = 0.0, m11 = 0.0, m12 = 0.0, m22 = 0.0;
    for (std::uint32_t k = triangleStart_[t]; k < triangleStart_[t + 1]; ++k) {
      const Piece& piece = pieces_[k];
      const float value = rho[piece.texel];
      valid &= (value >= 0.0f) & (value <= std::numeric_limits<float>::max());  // NaN fails both; no branch
      const double r = value;
      m += r * piece.moments[0];
      w1 += r * piece.moments[1];
      w2 += r * piece.moments[2];
      m11 += r * piece.moments[3];
      m12 += r * piece.moments[4];
      m22 += r * piece.moments[5];
    }
    spareDensity_[t] = {m, w1, w2, m11, m12, m22};
  }
  if (!valid) return Error{"density map has a negative or non-finite density"};
  density_.swap(spareDensity_);
  mapped_ = true;
  if (updated_) sumMappedCones();
  return Ok{};
}

Status TriangleMassIntegrator::update(const Mesh& mesh) {
  const std::size_t triangles = triangleCount();
  updated_ = false;
  if (mesh.triangles.size() != triangles)
    return Error{"triangle mass integrator: the mesh has " + std::to_string(mesh.triangles.size()) +
                 " triangles, the bake's layout " + std::to_string(triangles)};
  frames_.resize(triangles);  // keeps its capacity: no allocation after the first update
  const std::size_t vertices = mesh.positions.size();
  const double cx = referencePoint_.x(), cy = referencePoint_.y(), cz = referencePoint_.z();
  double volume = 0.0, area = 0.0;
  double volumeFirst[3] = {}, volumeSecond[6] = {}, shellFirst[3] = {}, shellSecond[6] = {};
  // Lids over openings (ascending, Mesh.hpp) close the volume but carry no shell.
  std::size_t nextOpening = 0;
  for (std::size_t t = 0; t < triangles; ++t) {
    while (nextOpening < mesh.openingTriangles.size() && mesh.openingTriangles[nextOpening] < t) ++nextOpening;
    const bool lid = nextOpening < mesh.openingTriangles.size() && mesh.openingTriangles[nextOpening] == t;
    const Eigen::Vector3i& corners = mesh.triangles[t];
    if (std::size_t(unsigned(corners[0])) >= vertices || std::size_t(unsigned(corners[1])) >= vertices ||
        std::size_t(unsigned(corners[2])) >= vertices)
      return Error{"triangle mass integrator: triangle " + std::to_string(t) + " has a vertex index out of range"};
    const Eigen::Vector3d& v0 = mesh.positions[std::size_t(corners[0])];
    const Eigen::Vector3d& v1 = mesh.positions[std::size_t(corners[1])];
    const Eigen::Vector3d& v2 = mesh.positions[std::size_t(corners[2])];
    Frame& frame = frames_[t];
    const double d0[3] = {v0.x() - cx, v0.y() - cy, v0.z() - cz};
    const double d1[3] = {v1.x() - cx, v1.y() - cy, v1.z() - cz};
    const double d2[3] = {v2.x() - cx, v2.y() - cy, v2.z() - cz};
    for (int c = 0; c < 3; ++c) {
      frame.d0[c] = d0[c];
      frame.e1[c] = d1[c] - d0[c];
      frame.e2[c] = d2[c] - d0[c];
    }
    const double* e1 = frame.e1;
    const double* e2 = frame.e2;
    // Area vector N = e1 x e2 / 2; h = d0 . N (the cone's volume is h / 3).
    const double n[3] = {0.5 * (e1[1] * e2[2] - e1[2] * e2[1]), 0.5 * (e1[2] * e2[0] - e1[0] * e2[2]),
                         0.5 * (e1[0] * e2[1] - e1[1] * e2[0])};
    const double h = d0[0] * n[0] + d0[1] * n[1] + d0[2] * n[2];
    const double a = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double s[3], q[6];  // S and S S^T + Sum d_i d_i^T
    detail::triangleCornerSums(d0, d1, d2, s, q);
    const double shell = lid ? 0.0 : a;
    volume += h;
    area += shell;
    for (int c = 0; c < 3; ++c) {
      volumeFirst[c] += h * s[c];
      shellFirst[c] += shell * s[c];
    }
    addSymmetric(volumeSecond, h, q);
    addSymmetric(shellSecond, shell, q);
  }
  // The common factors: volume h/3, first h S/12, second h (S S^T + Q)/60; shell |N|, |N| S/3,
  // |N| (S S^T + Q)/12.
  volume_ = volume / 3.0;
  area_ = area;
  for (int c = 0; c < 3; ++c) {
    volumeFirst_[c] = volumeFirst[c] / 12.0;
    shellFirst_[c] = shellFirst[c] / 3.0;
  }
  for (int m = 0; m < 6; ++m) {
    volumeSecond_[m] = volumeSecond[m] / 60.0;
    shellSecond_[m] = shellSecond[m] / 12.0;
  }
  bool finite = std::isfinite(volume_) && std::isfinite(area_);
  for (int m = 0; m < 6; ++m) finite = finite && std::isfinite(volumeSecond_[m]) && std::isfinite(shellSecond_[m]);
  if (!finite) {
    volume_ = 0.0;
    return Error{"triangle mass integrator: a vertex of the mesh is not finite"};
  }
  updated_ = true;
  if (mapped_) sumMappedCones();
  return Ok{};
}

void TriangleMassIntegrator::sumMappedCones() {
  double mass = 0.0, first[3] = {}, second[6] = {};
  const std::size_t triangles = frames_.size();
  for (std::size_t t = 0; t < triangles; ++t) {
    const Frame& f = frames_[t];
    const DensityMoments& g = density_[t];
    const double n[3] = {0.5 * (f.e1[1] * f.e2[2] - f.e1[2] * f.e2[1]), 0.5 * (f.e1[2] * f.e2[0] - f.e1[0] * f.e2[2]),
                         0.5 * (f.e1[0] * f.e2[1] - f.e1[1] * f.e2[0])};
    const double h = f.d0[0] * n[0] + f.d0[1] * n[1] + f.d0[2] * n[2];
    const double u[3] = {g.w1 * f.e1[0] + g.w2 * f.e2[0], g.w1 * f.e1[1] + g.w2 * f.e2[1],
                         g.w1 * f.e1[2] + g.w2 * f.e2[2]};
    double term[6];
    double sum[6] = {};
    // m d0 d0^T (as half of the symmetric product d0 d0^T + d0 d0^T).
    symmetricProduct(f.d0, f.d0, term);
    addSymmetric(sum, 0.5 * g.m, term);
    symmetricProduct(f.d0, u, term);
    addSymmetric(sum, 1.0, term);
    symmetricProduct(f.e1, f.e1, term);
    addSymmetric(sum, 0.5 * g.m11, term);
    symmetricProduct(f.e1, f.e2, term);
    addSymmetric(sum, g.m12, term);
    symmetricProduct(f.e2, f.e2, term);
    addSymmetric(sum, 0.5 * g.m22, term);
    mass += h * g.m;
    for (int c = 0; c < 3; ++c) first[c] += h * (g.m * f.d0[c] + u[c]);
    addSymmetric(second, h, sum);
  }
  mappedMass_ = mass / 3.0;
  for (int c = 0; c < 3; ++c) mappedFirst_[c] = first[c] / 4.0;
  for (int m = 0; m < 6; ++m) mappedSecond_[m] = second[m] / 5.0;
}

Expected<MassProperties> TriangleMassIntegrator::evaluate(double solidDensity, double shellDensity) const {
  if (!finiteNonNegative(solidDensity))
    return Error{"solid density " + std::to_string(solidDensity) + " kg/m^3 is negative or not finite"};
  if (!finiteNonNegative(shellDensity))
    return Error{"shell density " + std::to_string(shellDensity) + " kg/m^2 is negative or not finite"};
  if (!updated_) return Error{"triangle mass integrator: no mesh (update failed or was not called)"};
  detail::MassMoments moments;
  if (mapped_) {
    moments.mass = mappedMass_;
    moments.first = Eigen::Vector3d(mappedFirst_[0], mappedFirst_[1], mappedFirst_[2]);
    moments.second = symmetric(mappedSecond_);
  } else {
    moments.mass = solidDensity * volume_;
    moments.first = solidDensity * Eigen::Vector3d(volumeFirst_[0], volumeFirst_[1], volumeFirst_[2]);
    moments.second = solidDensity * symmetric(volumeSecond_);
  }
  moments.mass += shellDensity * area_;
  moments.first += shellDensity * Eigen::Vector3d(shellFirst_[0], shellFirst_[1], shellFirst_[2]);
  moments.second += shellDensity * symmetric(shellSecond_);
  moments.volume = volume_;
  return detail::massPropertiesFromMoments(moments, referencePoint_);
}

Expected<MassProperties> TriangleMassIntegrator::evaluate(const Mesh& mesh, double solidDensity, double shellDensity) {
  if (Status s = update(mesh); !s) return s.error();
  return evaluate(solidDensity, shellDensity);
}

}  // namespace hydrotex
