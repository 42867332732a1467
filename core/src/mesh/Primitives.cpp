// SPDX-License-Identifier: Zlib
// Closed primitives with physics-ready UV atlases. Every primitive is built as a few parametric
// grids ("charts") whose nodes share positions across seams by index (so the mesh is watertight
// with merged vertices) while each chart keeps its own UVs. Charts are laid out in layout units
// proportional to their 3D size, with gaps, and the layout is then stretched into [0,1]^2: one
// linear map for all charts, so the texel density per square metre is the same on every chart.
#include "hydrotex/mesh/Primitives.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <tuple>

namespace hydrotex::primitives {
namespace {

constexpr double kPi = std::numbers::pi;
// Margin kept free around the atlas, as a fraction of the UV square.
constexpr double kAtlasMargin = 0.01;

class MeshBuilder {
 public:
  explicit MeshBuilder(std::string name) { mesh_.sourceName = std::move(name); }

  int addPosition(const Eigen::Vector3d& p) {
    mesh_.positions.push_back(p);
    return static_cast<int>(mesh_.positions.size()) - 1;
  }
  /// A UV in layout units (metres of the chart's 3D size, charts already placed apart).
  int addUv(double u, double v) {
    mesh_.uv.uvs.emplace_back(u, v);
    return static_cast<int>(mesh_.uv.uvs.size()) - 1;
  }
  /// A triangle; one whose corners repeat a position (a collapsed grid cell at a pole, apex or
  /// bow) is dropped.
  void addTriangle(int p0, int p1, int p2, int t0, int t1, int t2) {
    if (p0 == p1 || p1 == p2 || p2 == p0) return;
    mesh_.triangles.emplace_back(p0, p1, p2);
    mesh_.uv.uvTriangles.emplace_back(t0, t1, t2);
  }
  /// A grid of (ns x nt) cells, nodes (i, j) for i in 0..ns, j in 0..nt, two triangles per cell,
  /// counter-clockwise in (i, j) (the surface normal is dP/di x dP/dj) unless `flip`. The cell's
  /// diagonal avoids triangles whose three corners all lie on `onCentre` nodes (the Wigley hull's
  /// centre plane, where both sides meet).
  void addGrid(int ns, int nt, const std::function<int(int, int)>& position, const std::function<int(int, int)>& uv,
               bool flip, const std::function<bool(int, int)>& onCentre = {}) {
    for (int j = 0; j < nt; ++j) {
      for (int i = 0; i < ns; ++i) {
        const int ai = i, aj = j, bi = i + 1, bj = j, ci = i + 1, cj = j + 1, di = i, dj = j + 1;
        auto shared = [&](int x, int y) { return onCentre && onCentre(x, y); };
        const bool acBad = (shared(ai, aj) && shared(bi, bj) && shared(ci, cj)) ||
                           (shared(ai, aj) && shared(ci, cj) && shared(di, dj));
        std::array<std::array<int, 2>, 6> corners;
        if (!acBad)
          corners = {{{ai, aj}, {bi, bj}, {ci, cj}, {ai, aj}, {ci, cj}, {di, dj}}};
        else
          corners = {{{ai, aj}, {bi, bj}, {di, dj}, {bi, bj}, {ci, cj}, {di, dj}}};
        for (int t = 0; t < 2; ++t) {
          std::array<int, 3> p{}, q{};
          for (int k = 0; k < 3; ++k) {
            const auto& c = corners[3 * t + k];
            p[k] = position(c[0], c[1]);
            q[k] = uv(c[0], c[1]);
          }
          if (flip)
            addTriangle(p[0], p[2], p[1], q[0], q[2], q[1]);
          else
            addTriangle(p[0], p[1], p[2], q[0], q[1], q[2]);
        }
      }
    }
  }
  /// Maps the layout's bounding box onto [margin, 1 - margin]^2 (one linear map for every chart).
  Mesh finish() {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY), hi = -lo;
    for (const auto& uv : mesh_.uv.uvs) {
      lo = lo.cwiseMin(uv);
      hi = hi.cwiseMax(uv);
    }
    const Eigen::Vector2d extent = (hi - lo).cwiseMax(1e-300);
    for (auto& uv : mesh_.uv.uvs)
      uv = Eigen::Vector2d::Constant(kAtlasMargin) + (1.0 - 2.0 * kAtlasMargin) * (uv - lo).cwiseQuotient(extent);
    return std::move(mesh_);
  }

 private:
  Mesh mesh_;
};

// A chart's UV nodes on a (ns + 1) x (nt + 1) grid over the layout rectangle [x, x + w] x
// [y, y + h]: columns evenly spaced, row j at the fraction rowFraction(j) of the height (0 at
// j = 0, 1 at j = nt), evenly spaced when none is given.
std::vector<int> gridUvs(MeshBuilder& builder, int ns, int nt, double x, double y, double w, double h,
                         const std::function<double(int)>* rowFraction = nullptr) {
  std::vector<int> index((ns + 1) * (nt + 1));
  for (int j = 0; j <= nt; ++j) {
    const double v = rowFraction ? (*rowFraction)(j) : double(j) / nt;
    for (int i = 0; i <= ns; ++i) index[j * (ns + 1) + i] = builder.addUv(x + w * i / ns, y + h * v);
  }
  return index;
}

// Flat disc fan (centre + rim) with its own chart: a disc of radius `radius` (layout units)
// centred at (cx, cy). `rim[k]` are the rim vertices at angles 2 pi k / n; `mirror` flips the
// UV disc so that the chart reads as seen from outside.
void addDisc(MeshBuilder& builder, int centre, const std::vector<int>& rim, bool reverse, double cx, double cy,
             double radius, bool mirror) {
  const int n = static_cast<int>(rim.size());
  const int centreUv = builder.addUv(cx, cy);
  std::vector<int> rimUv(n);
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    rimUv[k] = builder.addUv(cx + radius * std::cos(a), cy + (mirror ? -1.0 : 1.0) * radius * std::sin(a));
  }
  for (int k = 0; k < n; ++k) {
    const int k1 = (k + 1) % n;
    if (reverse)
      builder.addTriangle(centre, rim[k1], rim[k], centreUv, rimUv[k1], rimUv[k]);
    else
      builder.addTriangle(centre, rim[k], rim[k1], centreUv, rimUv[k], rimUv[k1]);
  }
}

}  // namespace

Mesh subdividedBox(const Eigen::Vector3d& extents, int divisions) {
  const int n = std::max(1, divisions);
  MeshBuilder builder(n == 1 ? "box" : "subdivided box");
  // Surface vertices are lattice points (i, j, k) in [0, n]^3; merging by lattice key keeps
  // the faces' shared edges exactly shared.
  std::map<std::tuple<int, int, int>, int> lattice;
  auto vertex = [&](int i, int j, int k) {
    auto [it, inserted] = lattice.try_emplace({i, j, k}, 0);
    if (inserted)
      it->second = builder.addPosition(Eigen::Vector3d(extents.x() * (double(i) / n - 0.5),
                                                       extents.y() * (double(j) / n - 0.5),
                                                       extents.z() * (double(k) / n - 0.5)));
    return it->second;
  };
  // Six faces in a 3 x 2 grid of equal cells (layout units: metres), each face at its own size.
  const double cell = extents.maxCoeff() * 1.08;
  for (int face = 0; face < 6; ++face) {
    const int axis = face % 3;
    const bool positive = face < 3;
    // Tangents a, b with a x b = outward normal: cyclic order for +, swapped for -.
    const int a = positive ? (axis + 1) % 3 : (axis + 2) % 3;
    const int b = positive ? (axis + 2) % 3 : (axis + 1) % 3;
    const double x = (face % 3) * cell, y = (face / 3) * cell;
    const std::vector<int> uv = gridUvs(builder, n, n, x, y, extents[a], extents[b]);
    builder.addGrid(
        n, n,
        [&](int s, int t) {
          std::array<int, 3> l{};
          l[axis] = positive ? n : 0;
          l[a] = s;
          l[b] = t;
          return vertex(l[0], l[1], l[2]);
        },
        [&](int s, int t) { return uv[t * (n + 1) + s]; }, false);
  }
  return builder.finish();
}

Mesh box(const Eigen::Vector3d& extents) { return subdividedBox(extents, 1); }

namespace {

// Latitude-longitude surface of revolution around y: P(phi, lat) with phi in [0, 2 pi] and the
// chart's rows from `latitude(0)` to `latitude(stacks)`; rings of zero radius collapse to one
// vertex (pole). Returns the position indices of the rows, rows[j][i] for i in 0..slices-1.
struct RevolutionRows {
  std::vector<std::vector<int>> rows;
};

RevolutionRows addRevolution(MeshBuilder& builder, int slices, int stacks, const std::function<double(int)>& ringRadius,
                             const std::function<double(int)>& ringHeight, double chartX, double chartY, double chartW,
                             double chartH, const RevolutionRows* reuseFirstRow = nullptr,
                             const std::function<double(int)>* rowFraction = nullptr) {
  RevolutionRows result;
  result.rows.resize(stacks + 1);
  for (int j = 0; j <= stacks; ++j) {
    if (j == 0 && reuseFirstRow) {
      result.rows[0] = reuseFirstRow->rows.back();
      continue;
    }
    const double r = ringRadius(j), y = ringHeight(j);
    if (r == 0.0) {
      result.rows[j].assign(slices, builder.addPosition(Eigen::Vector3d(0.0, y, 0.0)));
      continue;
    }
    for (int i = 0; i < slices; ++i) {
      const double phi = 2.0 * kPi * i / slices;
      // (cos, -sin) in (x, z): with latitude growing upwards, dP/dphi x dP/dlat points outwards.
      result.rows[j].push_back(builder.addPosition(Eigen::Vector3d(r * std::cos(phi), y, -r * std::sin(phi))));
    }
  }
  const std::vector<int> uv = gridUvs(builder, slices, stacks, chartX, chartY, chartW, chartH, rowFraction);
  builder.addGrid(
      slices, stacks, [&](int i, int j) { return result.rows[j][i % slices]; },
      [&](int i, int j) { return uv[j * (slices + 1) + i]; }, false);
  return result;
}

}  // namespace

Mesh uvSphere(double radius, int slices, int stacks) {
  slices = std::max(3, slices);
  stacks = std::max(2, stacks);
  MeshBuilder builder("uv sphere");
  auto latitude = [&](int j) { return -0.5 * kPi + kPi * j / stacks; };
  addRevolution(
      builder, slices, stacks,
      [&](int j) { return (j == 0 || j == stacks) ? 0.0 : radius * std::cos(latitude(j)); },
      [&](int j) { return j == 0 ? -radius : j == stacks ? radius : radius * std::sin(latitude(j)); }, 0.0, 0.0,
      2.0 * kPi * radius, kPi * radius);
  return builder.finish();
}

Mesh capsule(double radius, double cylinderLength, int slices, int stacksPerCap) {
  slices = std::max(3, slices);
  const int m = std::max(1, stacksPerCap);
  // Rows: the lower cap from its pole to its equator (m + 1 rows), the cylinder's inner rows, the
  // upper cap from above its equator to its pole; one chart, each row at its arc length from the
  // lower pole, so that texel density is uniform however tall the rows. The cylinder's side is
  // ruled (exact with one row); it gets rows about as tall as the caps', as many as `slices` at
  // most: a 110 m capsule of 0.25 m radius took 5,882 rows of 19 mm (a million triangles, 6.3 s
  // to simulate its scene, 60 s under the sanitizers: fuzz_scene's timeout), which its volume
  // does not need.
  const double capRow = 0.5 * kPi * radius / m;
  const int c = cylinderLength > 0.0 ? std::clamp(int(std::lround(cylinderLength / capRow)), 1, slices) : 0;
  const int stacks = 2 * m + c;
  const double half = 0.5 * cylinderLength;
  const double capArc = 0.5 * kPi * radius, arc = 2.0 * capArc + cylinderLength;
  MeshBuilder builder("capsule");
  auto row = [&](int j, bool height) {
    double latitude = 0.0, y = 0.0;
    if (j <= m) {
      latitude = -0.5 * kPi + 0.5 * kPi * j / m;
      y = -half;
    } else if (j < m + c) {
      y = -half + cylinderLength * (j - m) / c;
    } else {
      latitude = 0.5 * kPi * (j - m - c) / m;
      y = half;
    }
    if (j == 0 || j == stacks) return height ? y + (j == 0 ? -radius : radius) : 0.0;
    return height ? y + radius * std::sin(latitude) : radius * std::cos(latitude);
  };
  const std::function<double(int)> rowFraction = [&](int j) {
    if (j <= m) return capArc * j / m / arc;
    if (j < m + c) return (capArc + cylinderLength * (j - m) / c) / arc;
    return j == stacks ? 1.0 : (capArc + cylinderLength + capArc * (j - m - c) / m) / arc;
  };
  addRevolution(
      builder, slices, stacks, [&](int j) { return row(j, false); }, [&](int j) { return row(j, true); }, 0.0, 0.0,
      2.0 * kPi * radius, arc, nullptr, &rowFraction);
  return builder.finish();
}

Mesh hemisphere(double radius, int slices, int stacks, bool up) {
  slices = std::max(3, slices);
  stacks = std::max(1, stacks);
  MeshBuilder builder(up ? "hemisphere (up)" : "hemisphere (down)");
  auto latitude = [&](int j) { return 0.5 * kPi * j / stacks; };
  const RevolutionRows dome = addRevolution(
      builder, slices, stacks, [&](int j) { return j == stacks ? 0.0 : radius * std::cos(latitude(j)); },
      [&](int j) { return j == 0 ? 0.0 : j == stacks ? radius : radius * std::sin(latitude(j)); }, 0.0, 0.0,
      2.0 * kPi * radius, 0.5 * kPi * radius);
  // Flat face at y = 0 looking down (-y): reversed fan over the equator ring.
  const int centre = builder.addPosition(Eigen::Vector3d::Zero());
  const double gap = 0.2 * radius;
  addDisc(builder, centre, dome.rows[0], true, radius, 0.5 * kPi * radius + gap + radius, radius, true);
  Mesh mesh = builder.finish();
  if (!up) {
    // Mirror in y; a mirror turns the winding inside out, so swap two corners (UVs alike).
    for (auto& p : mesh.positions) p.y() = -p.y();
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    for (auto& t : mesh.uv.uvTriangles) std::swap(t[1], t[2]);
  }
  return mesh;
}

Mesh cylinder(double radius, double length, int segments) {
  segments = std::max(3, segments);
  MeshBuilder builder("cylinder");
  // Side: P(phi, z) = (r cos phi, r sin phi, z); dP/dphi x dP/dz points outwards.
  std::array<std::vector<int>, 2> rims;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < segments; ++i) {
      const double phi = 2.0 * kPi * i / segments;
      rims[j].push_back(builder.addPosition(
          Eigen::Vector3d(radius * std::cos(phi), radius * std::sin(phi), (j - 0.5) * length)));
    }
  const double sideW = 2.0 * kPi * radius;
  const std::vector<int> uv = gridUvs(builder, segments, 1, 0.0, 0.0, sideW, length);
  builder.addGrid(
      segments, 1, [&](int i, int j) { return rims[j][i % segments]; },
      [&](int i, int j) { return uv[j * (segments + 1) + i]; }, false);
  // Caps below the side chart: the +z cap counter-clockwise about +z, the -z cap reversed.
  const double gap = 0.2 * radius;
  const int back = builder.addPosition(Eigen::Vector3d(0.0, 0.0, -0.5 * length));
  const int front = builder.addPosition(Eigen::Vector3d(0.0, 0.0, 0.5 * length));
  addDisc(builder, back, rims[0], true, radius, length + gap + radius, radius, true);
  addDisc(builder, front, rims[1], false, 3.0 * radius + gap, length + gap + radius, radius, false);
  return builder.finish();
}

Mesh cone(double radius, double height, int segments) {
  segments = std::max(3, segments);
  MeshBuilder builder("cone");
  const double slant = std::hypot(radius, height);
  const RevolutionRows side = addRevolution(
      builder, segments, 1, [&](int j) { return j == 0 ? radius : 0.0; }, [&](int j) { return j == 0 ? 0.0 : height; },
      0.0, 0.0, 2.0 * kPi * radius, slant);
  const int centre = builder.addPosition(Eigen::Vector3d::Zero());
  const double gap = 0.2 * radius;
  addDisc(builder, centre, side.rows[0], true, radius, slant + gap + radius, radius, true);
  return builder.finish();
}

Mesh torus(double majorRadius, double minorRadius, int majorSegments, int minorSegments) {
  majorSegments = std::max(3, majorSegments);
  minorSegments = std::max(3, minorSegments);
  MeshBuilder builder("torus");
  // P(phi, theta) = ((R + r cos theta) cos phi, r sin theta, -(R + r cos theta) sin phi): one
  // periodic chart, seams duplicated in UV only.
  std::vector<int> index(majorSegments * minorSegments);
  for (int j = 0; j < minorSegments; ++j)
    for (int i = 0; i < majorSegments; ++i) {
      const double phi = 2.0 * kPi * i / majorSegments, theta = 2.0 * kPi * j / minorSegments;
      const double ring = majorRadius + minorRadius * std::cos(theta);
      index[j * majorSegments + i] = builder.addPosition(
          Eigen::Vector3d(ring * std::cos(phi), minorRadius * std::sin(theta), -ring * std::sin(phi)));
    }
  const std::vector<int> uv =
      gridUvs(builder, majorSegments, minorSegments, 0.0, 0.0, 2.0 * kPi * majorRadius, 2.0 * kPi * minorRadius);
  builder.addGrid(
      majorSegments, minorSegments,
      [&](int i, int j) { return index[(j % minorSegments) * majorSegments + i % majorSegments]; },
      [&](int i, int j) { return uv[j * (majorSegments + 1) + i]; }, false);
  return builder.finish();
}

Mesh icosphere(double radius, int subdivisions) {
  subdivisions = std::clamp(subdivisions, 0, 8);
  MeshBuilder builder("icosphere");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  const std::array<Eigen::Vector3d, 12> corners = {{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}}};
  const std::array<Eigen::Vector3i, 20> faces = {{{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                                  {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                  {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                                  {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}}};
  // A vertex is identified by its position on the icosahedron as integer barycentric weights
  // (denominator n) over the base corners; shared edges then give the same key from both faces.
  const int n = 1 << subdivisions;
  std::map<std::array<int, 6>, int> vertexOf;
  auto vertex = [&](const Eigen::Vector3i& face, int wa, int wb, int wc) {
    std::array<std::pair<int, int>, 3> parts = {{{face[0], wa}, {face[1], wb}, {face[2], wc}}};
    std::sort(parts.begin(), parts.end());
    std::array<int, 6> key{};
    int used = 0;
    for (const auto& [corner, weight] : parts)
      if (weight != 0) {
        key[2 * used] = corner;
        key[2 * used + 1] = weight;
        ++used;
      }
    for (int k = used; k < 3; ++k) key[2 * k] = key[2 * k + 1] = -1;
    auto [it, inserted] = vertexOf.try_emplace(key, 0);
    if (inserted) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (const auto& [corner, weight] : parts) p += weight * corners[corner];
      it->second = builder.addPosition(radius * p.normalized());
    }
    return it->second;
  };
  // Twenty equilateral charts in a 5 x 4 grid (layout units: the base edge).
  const double edge = 1.0, cellW = 1.1, cellH = 0.866 * edge + 0.1;
  for (int f = 0; f < 20; ++f) {
    const double x0 = (f % 5) * cellW, y0 = (f / 5) * cellH;
    const Eigen::Vector2d ua(x0, y0), ub(x0 + edge, y0), uc(x0 + 0.5 * edge, y0 + 0.8660254037844386 * edge);
    std::vector<int> pos((n + 1) * (n + 1), -1), tex((n + 1) * (n + 1), -1);
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i + j <= n; ++i) {
        const int k = n - i - j;  // weights: corner a gets k, b gets i, c gets j
        pos[j * (n + 1) + i] = vertex(faces[f], k, i, j);
        const Eigen::Vector2d uv = (k * ua + i * ub + j * uc) / n;
        tex[j * (n + 1) + i] = builder.addUv(uv.x(), uv.y());
      }
    auto at = [&](int i, int j) { return j * (n + 1) + i; };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        builder.addTriangle(pos[at(i, j)], pos[at(i + 1, j)], pos[at(i, j + 1)], tex[at(i, j)], tex[at(i + 1, j)],
                            tex[at(i, j + 1)]);
        if (i + j + 1 < n)
          builder.addTriangle(pos[at(i + 1, j)], pos[at(i + 1, j + 1)], pos[at(i, j + 1)], tex[at(i + 1, j)],
                              tex[at(i + 1, j + 1)], tex[at(i, j + 1)]);
      }
  }
  return builder.finish();
}

Mesh wigleyHull(double length, double breadth, double draft, int lengthSegments, int depthSegments) {
  const int nx = std::max(2, lengthSegments), ny = std::max(2, depthSegments);
  MeshBuilder builder("wigley hull");
  auto xAt = [&](int i) { return length * (double(i) / nx - 0.5); };
  auto yAt = [&](int j) { return draft * (double(j) / ny - 1.0); };  // j = 0 keel (-T), j = ny deck (0)
  auto halfBreadth = [&](int i, int j) {
    const double a = 2.0 * xAt(i) / length, b = yAt(j) / draft;
    return 0.5 * breadth * (1.0 - a * a) * (1.0 - b * b);
  };
  // Nodes on the centre plane (stem, stern, keel) are shared by both sides.
  auto onCentre = [&](int i, int j) { return i == 0 || i == nx || j == 0; };
  std::vector<int> centre((nx + 1) * (ny + 1), -1);
  std::array<std::vector<int>, 2> sides;
  for (int s = 0; s < 2; ++s) {
    sides[s].assign((nx + 1) * (ny + 1), -1);
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        int& slot = onCentre(i, j) ? centre[j * (nx + 1) + i] : sides[s][j * (nx + 1) + i];
        if (slot < 0)
          slot = builder.addPosition(Eigen::Vector3d(xAt(i), yAt(j), (s == 0 ? 1.0 : -1.0) * halfBreadth(i, j)));
        sides[s][j * (nx + 1) + i] = slot;
      }
  }
  // Charts: starboard (+z) side, port (-z) side, deck, stacked with gaps (layout units: metres).
  const double gap = 0.1 * std::max(draft, breadth);
  for (int s = 0; s < 2; ++s) {
    const std::vector<int> uv = gridUvs(builder, nx, ny, 0.0, s * (draft + gap), length, draft);
    // dP/dx x dP/dy is +z: right for the +z side, reversed for the -z side.
    builder.addGrid(
        nx, ny, [&](int i, int j) { return sides[s][j * (nx + 1) + i]; },
        [&](int i, int j) { return uv[j * (nx + 1) + i]; }, s == 1, onCentre);
  }
  // Deck at y = 0 between the two rims, row t = 0 on the -z rim, t = 1 on the +z rim;
  // dP/dx x dP/dt is -y, reversed to look up.
  const std::vector<int> deckUv = gridUvs(builder, nx, 1, 0.0, 2.0 * (draft + gap), length, breadth);
  builder.addGrid(
      nx, 1, [&](int i, int t) { return sides[t == 0 ? 1 : 0][ny * (nx + 1) + i]; },
      [&](int i, int t) { return deckUv[t * (nx + 1) + i]; }, true);
  return builder.finish();
}

}  // namespace hydrotex::primitives
