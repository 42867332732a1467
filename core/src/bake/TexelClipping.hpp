// SPDX-License-Identifier: Zlib
#pragma once
/// @file TexelClipping.hpp
/// Private to core: clipping a texel square against a UV triangle (Sutherland-Hodgman against the
/// triangle's three half-planes, in double), shared by the bake (SurfaceBake.cpp), which keeps the
/// pieces' areas and centroids, and TriangleMassIntegrator.cpp, which clips the same pieces again
/// for their second moments. Coordinates are texel coordinates: x = u * width, y = (1 - v) * height,
/// so that texel (column, row) is [column, column + 1] x [row, row + 1] (row 0 is v = 1, Mesh.hpp).

#include <array>

namespace hydrotex::detail {

/// A convex polygon in texel coordinates; the square (4) clipped by 3 half-planes has at most 7
/// corners.
struct Polygon {
  std::array<double, 8> x{};  ///< corner x (texels)
  std::array<double, 8> y{};  ///< corner y (texels)
  int count = 0;              ///< corners in use
};

/// Edge function of one triangle edge, positive inside: e(x, y) = a x + b y + c.
struct HalfPlane {
  double a = 0.0, b = 0.0, c = 0.0;  ///< coefficients (texel coordinates)
  /// The edge function at (x, y).
  double at(double x, double y) const { return a * x + b * y + c; }
};

/// The three edge functions of the triangle with corners (px[k], py[k]) (texel coordinates),
/// oriented so that the inside is positive whatever the winding; `twiceSigned` is its signed
/// doubled area (px1 - px0)(py2 - py0) - (px2 - px0)(py1 - py0), not zero.
inline std::array<HalfPlane, 3> triangleHalfPlanes(const std::array<double, 3>& px, const std::array<double, 3>& py,
                                                   double twiceSigned) {
  const double orientation = twiceSigned > 0.0 ? 1.0 : -1.0;
  std::array<HalfPlane, 3> planes;
  for (int k = 0; k < 3; ++k) {
    const int a = k, b = (k + 1) % 3;
    // cross(b - a, p - a) = (bx-ax)(py-ay) - (by-ay)(px-ax)
    planes[k].a = -(py[b] - py[a]) * orientation;
    planes[k].b = (px[b] - px[a]) * orientation;
    planes[k].c = ((py[b] - py[a]) * px[a] - (px[b] - px[a]) * py[a]) * orientation;
  }
  return planes;
}

/// The square of texel (column, row), counter-clockwise in texel coordinates.
inline Polygon texelSquare(int column, int row) {
  const double x0 = column, x1 = column + 1.0, y0 = row, y1 = row + 1.0;
  Polygon square;
  square.count = 4;
  square.x = {x0, x1, x1, x0};
  square.y = {y0, y0, y1, y1};
  return square;
}

/// Sutherland-Hodgman step: keeps the part of `in` where the edge function is >= 0.
inline void clipAgainst(const Polygon& in, const HalfPlane& plane, Polygon& out) {
  out.count = 0;
  for (int i = 0; i < in.count; ++i) {
    const int j = (i + 1 == in.count) ? 0 : i + 1;
    const double ei = plane.at(in.x[i], in.y[i]);
    const double ej = plane.at(in.x[j], in.y[j]);
    if (ei >= 0.0) {
      out.x[out.count] = in.x[i];
      out.y[out.count] = in.y[i];
      ++out.count;
    }
    if ((ei >= 0.0) != (ej >= 0.0)) {
      const double t = ei / (ei - ej);
      out.x[out.count] = in.x[i] + t * (in.x[j] - in.x[i]);
      out.y[out.count] = in.y[i] + t * (in.y[j] - in.y[i]);
      ++out.count;
    }
  }
}

}  // namespace hydrotex::detail
