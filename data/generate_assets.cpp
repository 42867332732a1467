// SPDX-License-Identifier: Zlib
// Generates the bundled assets in data/: meshes (data/meshes/*.obj) built from the closed
// primitives of the core library and from a few shapes made here (surfaces of revolution, a height
// field slab), and their textures (data/textures/*.png): albedo, and for the ship the damage
// (permeability) maps of the paper's figures 10 and 11. Every mesh is closed, outward oriented and
// its UVs do not overlap; the program checks that before writing.
// Usage: hydrotex_generate_assets DATA_DIR   (writes DATA_DIR/meshes and DATA_DIR/textures)

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "hydrotex/mesh/ImageMap.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"
#include "hydrotex/mesh/Primitives.hpp"

namespace {

using hydrotex::Mesh;
using Eigen::Vector2d;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

/// Applies a rigid rotation and translation to every vertex (UVs untouched).
Mesh transformed(Mesh mesh, const Eigen::Matrix3d& rotation, const Vector3d& offset) {
  for (Vector3d& p : mesh.positions) p = rotation * p + offset;
  return mesh;
}

Mesh translated(Mesh mesh, const Vector3d& offset) { return transformed(std::move(mesh), Eigen::Matrix3d::Identity(), offset); }

Eigen::Matrix3d rotationAbout(const Vector3d& axis, double radians) {
  return Eigen::AngleAxisd(radians, axis.normalized()).toRotationMatrix();
}

/// Signed volume (m^3) by the divergence theorem; used to orient generated shapes outwards.
double signedVolume(const Mesh& mesh) {
  double sum = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles)
    sum += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]]));
  return sum / 6.0;
}

void orientOutwards(Mesh& mesh) {
  if (signedVolume(mesh) >= 0.0) return;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    std::swap(mesh.triangles[i][1], mesh.triangles[i][2]);
    std::swap(mesh.uv.uvTriangles[i][1], mesh.uv.uvTriangles[i][2]);
  }
}

/// A closed surface of revolution about the y axis. `profile` holds (radius, height) points (m).
/// With `loop` the profile is a closed loop of positive radii (a ring: the clay pot); otherwise it
/// starts and ends on the axis (radius 0: the poles of a buoy or a balloon). UVs: u around the
/// axis, v along the profile's arc length, inside [margin, 1 - margin].
Mesh lathe(const std::vector<Vector2d>& profile, int segments, bool loop, const std::string& name) {
  Mesh mesh;
  mesh.sourceName = name;
  const int n = static_cast<int>(profile.size());
  const int rows = loop ? n + 1 : n;  // a loop repeats its first point as the last UV row
  std::vector<double> arc(static_cast<std::size_t>(rows), 0.0);
  for (int j = 1; j < rows; ++j) arc[j] = arc[j - 1] + (profile[j % n] - profile[j - 1]).norm();
  constexpr double margin = 0.01;
  std::vector<std::vector<int>> ring(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    const bool pole = !loop && (j == 0 || j == n - 1);
    for (int s = 0; s < (pole ? 1 : segments); ++s) {
      const double a = 2.0 * kPi * s / segments;
      ring[j].push_back(static_cast<int>(mesh.positions.size()));
      mesh.positions.emplace_back(profile[j].x() * std::cos(a), profile[j].y(), -profile[j].x() * std::sin(a));
    }
  }
  auto uvIndex = [&](int s, int j) {
    mesh.uv.uvs.emplace_back(margin + (1.0 - 2.0 * margin) * s / segments, margin + (1.0 - 2.0 * margin) * arc[j] / arc[rows - 1]);
    return static_cast<int>(mesh.uv.uvs.size()) - 1;
  };
  auto at = [&](int j, int s) {
    const std::vector<int>& r = ring[j % n];
    return r.size() == 1 ? r[0] : r[s % segments];
  };
  for (int j = 0; j + 1 < rows; ++j)
    for (int s = 0; s < segments; ++s) {
      const int p00 = at(j, s), p10 = at(j, s + 1), p01 = at(j + 1, s), p11 = at(j + 1, s + 1);
      const int t00 = uvIndex(s, j), t10 = uvIndex(s + 1, j), t01 = uvIndex(s, j + 1), t11 = uvIndex(s + 1, j + 1);
      if (p00 != p10) {
        mesh.triangles.emplace_back(p00, p10, p11);
        mesh.uv.uvTriangles.emplace_back(t00, t10, t11);
      }
      if (p01 != p11) {
        mesh.triangles.emplace_back(p00, p11, p01);
        mesh.uv.uvTriangles.emplace_back(t00, t11, t01);
      }
    }
  orientOutwards(mesh);
  return mesh;
}

/// A closed slab whose top is the height field y = height(x, z) over [-sx/2, sx/2] x [-sz/2, sz/2]
/// and whose bottom is the plane y = bottom. UV charts: top (upper 3/4), bottom and four sides
/// (strips in the lowest quarter).
Mesh heightFieldSlab(double sx, double sz, int n, double bottom, const std::function<double(double, double)>& height) {
  Mesh mesh;
  mesh.sourceName = "height field slab";
  auto x = [&](int i) { return sx * (double(i) / n - 0.5); };
  auto z = [&](int j) { return sz * (double(j) / n - 0.5); };
  std::vector<int> top((n + 1) * (n + 1)), low((n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      top[j * (n + 1) + i] = static_cast<int>(mesh.positions.size());
      mesh.positions.emplace_back(x(i), height(x(i), z(j)), z(j));
    }
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      low[j * (n + 1) + i] = static_cast<int>(mesh.positions.size());
      mesh.positions.emplace_back(x(i), bottom, z(j));
    }
  auto addUv = [&](double u, double v) {
    mesh.uv.uvs.emplace_back(u, v);
    return static_cast<int>(mesh.uv.uvs.size()) - 1;
  };
  auto quad = [&](int a, int b, int c, int d, int ua, int ub, int uc, int ud) {
    mesh.triangles.emplace_back(a, b, c);
    mesh.uv.uvTriangles.emplace_back(ua, ub, uc);
    mesh.triangles.emplace_back(a, c, d);
    mesh.uv.uvTriangles.emplace_back(ua, uc, ud);
  };
  // Top: (i, j) -> u = i/n, v = 0.26 + 0.73 (1 - j/n); seen from above, +z is "down" in the image.
  // Bottom: u in [0.01, 0.49], v in [0.01, 0.24].
  std::vector<int> topUv((n + 1) * (n + 1)), lowUv((n + 1) * (n + 1));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      topUv[j * (n + 1) + i] = addUv(0.01 + 0.98 * i / n, 0.26 + 0.73 * (1.0 - double(j) / n));
      lowUv[j * (n + 1) + i] = addUv(0.01 + 0.48 * i / n, 0.01 + 0.23 * double(j) / n);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      auto k = [&](int a, int b) { return b * (n + 1) + a; };
      quad(top[k(i, j)], top[k(i, j + 1)], top[k(i + 1, j + 1)], top[k(i + 1, j)], topUv[k(i, j)], topUv[k(i, j + 1)],
           topUv[k(i + 1, j + 1)], topUv[k(i + 1, j)]);
      quad(low[k(i, j)], low[k(i + 1, j)], low[k(i + 1, j + 1)], low[k(i, j + 1)], lowUv[k(i, j)], lowUv[k(i + 1, j)],
           lowUv[k(i + 1, j + 1)], lowUv[k(i, j + 1)]);
    }
  // Four sides, each a strip of n quads along the rim.
  std::vector<std::pair<int, int>> rim;
  for (int i = 0; i < n; ++i) rim.emplace_back(i, 0);
  for (int j = 0; j < n; ++j) rim.emplace_back(n, j);
  for (int i = n; i > 0; --i) rim.emplace_back(i, n);
  for (int j = n; j > 0; --j) rim.emplace_back(0, j);
  for (int side = 0; side < 4; ++side) {
    const double u0 = 0.51, u1 = 0.99, v0 = 0.01 + 0.06 * side, v1 = v0 + 0.05;
    for (int q = 0; q < n; ++q) {
      const auto [ia, ja] = rim[side * n + q];
      const auto [ib, jb] = rim[(side * n + q + 1) % (4 * n)];
      const int a = ja * (n + 1) + ia, b = jb * (n + 1) + ib;
      const double ua = u0 + (u1 - u0) * q / n, ub = u0 + (u1 - u0) * (q + 1) / n;
      quad(top[a], top[b], low[b], low[a], addUv(ua, v1), addUv(ub, v1), addUv(ub, v0), addUv(ua, v0));
    }
  }
  orientOutwards(mesh);
  return mesh;
}

/// One piece of a multi-part asset and the UV rectangle {u0, v0, u1, v1} its [0,1]^2 atlas goes to.
struct Part {
  Mesh mesh;
  Eigen::Vector4d rect;
};

/// Joins closed parts into one mesh (parts must not touch, so that the mesh stays closed after
/// vertex merging), each part's atlas scaled into its rectangle so that no UVs overlap.
Mesh combine(const std::vector<Part>& parts, const std::string& name) {
  Mesh mesh;
  mesh.sourceName = name;
  for (const Part& part : parts) {
    const int p0 = static_cast<int>(mesh.positions.size()), t0 = static_cast<int>(mesh.uv.uvs.size());
    mesh.positions.insert(mesh.positions.end(), part.mesh.positions.begin(), part.mesh.positions.end());
    for (const Vector2d& uv : part.mesh.uv.uvs)
      mesh.uv.uvs.emplace_back(part.rect[0] + (part.rect[2] - part.rect[0]) * uv.x(), part.rect[1] + (part.rect[3] - part.rect[1]) * uv.y());
    for (std::size_t i = 0; i < part.mesh.triangles.size(); ++i) {
      mesh.triangles.push_back(part.mesh.triangles[i] + Eigen::Vector3i::Constant(p0));
      mesh.uv.uvTriangles.push_back(part.mesh.uv.uvTriangles[i] + Eigen::Vector3i::Constant(t0));
    }
  }
  return mesh;
}

/// An RGB image in the ImageMap convention (row 0 is v = 1).
struct Image {
  int size = 0;
  std::vector<Vector3d> rgb;
  std::vector<bool> painted;
};

/// Paints a texture by the 3D position and normal of the surface point under each texel centre
/// (rasterising the UV triangles), then grows the painted texels a few texels outwards so that
/// bilinear filtering at chart borders does not pick up the background.
using Painter = std::function<Vector3d(const Vector3d& position, const Vector3d& normal)>;
Image paint(const Mesh& mesh, int size, const Painter& painter) {
  Image image{size, std::vector<Vector3d>(static_cast<std::size_t>(size) * size, Vector3d::Zero()),
              std::vector<bool>(static_cast<std::size_t>(size) * size, false)};
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vector3d p[3] = {mesh.positions[mesh.triangles[t][0]], mesh.positions[mesh.triangles[t][1]], mesh.positions[mesh.triangles[t][2]]};
    const Vector3d normal = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
    Vector2d q[3];
    for (int k = 0; k < 3; ++k) {
      const Vector2d uv = mesh.uv.uvs[mesh.uv.uvTriangles[t][k]];
      q[k] = Vector2d(uv.x() * size, (1.0 - uv.y()) * size);
    }
    const double area = (q[1] - q[0]).x() * (q[2] - q[0]).y() - (q[1] - q[0]).y() * (q[2] - q[0]).x();
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, int(std::floor(std::min({q[0].x(), q[1].x(), q[2].x()}))));
    const int x1 = std::min(size - 1, int(std::ceil(std::max({q[0].x(), q[1].x(), q[2].x()}))));
    const int y0 = std::max(0, int(std::floor(std::min({q[0].y(), q[1].y(), q[2].y()}))));
    const int y1 = std::min(size - 1, int(std::ceil(std::max({q[0].y(), q[1].y(), q[2].y()}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Vector2d c(x + 0.5, y + 0.5);
        auto edge = [&](const Vector2d& a, const Vector2d& b) { return ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x()) / area; };
        const double w0 = edge(q[1], q[2]), w1 = edge(q[2], q[0]), w2 = edge(q[0], q[1]);
        if (w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9) continue;
        const std::size_t index = static_cast<std::size_t>(y) * size + x;
        image.rgb[index] = painter(w0 * p[0] + w1 * p[1] + w2 * p[2], normal);
        image.painted[index] = true;
      }
  }
  for (int pass = 0; pass < 4; ++pass) {
    std::vector<bool> painted = image.painted;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const std::size_t index = static_cast<std::size_t>(y) * size + x;
        if (image.painted[index]) continue;
        for (int d = 0; d < 4 && !painted[index]; ++d) {
          const int nx = x + (d == 0) - (d == 1), ny = y + (d == 2) - (d == 3);
          if (nx < 0 || ny < 0 || nx >= size || ny >= size) continue;
          const std::size_t other = static_cast<std::size_t>(ny) * size + nx;
          if (image.painted[other]) {
            image.rgb[index] = image.rgb[other];
            painted[index] = true;
          }
        }
      }
    image.painted = painted;
  }
  return image;
}

hydrotex::Status writeImage(const Image& image, const std::string& path, bool gray) {
  const int channels = gray ? 1 : 3;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(image.size) * image.size * channels);
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    for (int c = 0; c < channels; ++c)
      pixels[i * channels + c] = static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(image.rgb[i][c], 0.0, 1.0)));
  return hydrotex::writePng(path, image.size, image.size, channels, pixels);
}

/// Cheap deterministic value noise in [0, 1] (texture grain, rock bumps).
double hashNoise(const Vector3d& p, double scale) {
  const Eigen::Vector3i cell = (p * scale).array().floor().cast<int>();
  auto h = [](int x, int y, int z) {
    std::uint32_t n = static_cast<std::uint32_t>(x) * 73856093u ^ static_cast<std::uint32_t>(y) * 19349663u ^ static_cast<std::uint32_t>(z) * 83492791u;
    n = (n ^ (n >> 13)) * 1274126177u;
    return double(n & 0xffffu) / 65535.0;
  };
  const Vector3d f = p * scale - cell.cast<double>();
  double sum = 0.0;
  for (int k = 0; k < 8; ++k) {
    const int dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1;
    const double w = (dx ? f.x() : 1 - f.x()) * (dy ? f.y() : 1 - f.y()) * (dz ? f.z() : 1 - f.z());
    sum += w * h(cell.x() + dx, cell.y() + dy, cell.z() + dz);
  }
  return sum;
}

Vector3d rgb(int r, int g, int b) { return Vector3d(r, g, b) / 255.0; }

// ---- the assets -----------------------------------------------------------------------------

// Ship: a Wigley hull 8 m long, 1.6 m wide, 1.2 m deep (deck at y = 0), with a deckhouse, a bridge
// and a funnel on top (separate closed parts 5 mm apart: the mesh stays closed, the gap does not
// matter to the physics). Bow at +x, stern at -x.
constexpr double kShipLength = 8.0, kShipBreadth = 1.6, kShipDepth = 1.2;

Mesh makeShip() {
  namespace prim = hydrotex::primitives;
  const double gap = 0.005;
  const Eigen::Matrix3d upright = rotationAbout(Vector3d::UnitX(), -kPi / 2);
  return combine({{prim::wigleyHull(kShipLength, kShipBreadth, kShipDepth, 80, 20), {0.0, 0.25, 1.0, 1.0}},
                  {translated(prim::box(Vector3d(2.4, 0.7, 1.0)), Vector3d(-1.4, 0.35 + gap, 0)), {0.0, 0.0, 0.33, 0.25}},
                  {translated(prim::box(Vector3d(1.2, 0.5, 0.8)), Vector3d(-1.7, 0.95 + 2 * gap, 0)), {0.33, 0.0, 0.66, 0.25}},
                  {transformed(prim::cylinder(0.18, 0.8, 24), upright, Vector3d(-0.7, 1.1 + 2 * gap, 0)), {0.66, 0.0, 1.0, 0.25}}},
                 "ship");
}

Vector3d shipAlbedo(const Vector3d& p, const Vector3d& n) {
  const double grain = 0.9 + 0.1 * hashNoise(p, 12.0);
  if (p.y() > 0.002) {  // superstructure
    if (std::abs(p.x() + 0.7) < 0.19 && std::abs(p.z()) < 0.19)  // funnel
      return p.y() > 1.35 ? rgb(30, 30, 30) : rgb(200, 40, 30);
    if (n.y() > 0.9) return rgb(150, 150, 145) * grain;  // roofs
    const bool window = p.y() > 0.95 && p.y() < 1.1 && std::fmod(std::abs(p.x()) + std::abs(p.z()), 0.3) < 0.18;
    return window ? rgb(40, 60, 80) : rgb(235, 235, 228) * grain;
  }
  if (n.y() > 0.9 && p.y() > -0.01) {  // deck planks
    const double plank = std::fmod(std::abs(p.z()) * 10.0, 1.0) < 0.08 ? 0.75 : 1.0;
    return rgb(176, 132, 84) * grain * plank;
  }
  // A mid-gray hull from the keel to the deck: wetness darkens mid tones most (Lekner and Dorf:
  // linear albedo 0.4 falls to 0.26 under water), so the wet band stays readable at a glance, and
  // no paint line sits near the waterline to be mistaken for it.
  if (p.y() < -1.05) return rgb(150, 40, 35) * grain;   // antifouling along the keel
  return rgb(150, 160, 170) * grain;                      // topsides
}

/// Damage (permeability) map of the ship: white where the hull is holed. Holes are smooth blobs
/// on the hull below the waterline: at the bow on the starboard side (paper figure 10), or at
/// the stern on both sides (figure 11).
Vector3d shipDamage(const Vector3d& p, const Vector3d& n, bool bow) {
  if (p.y() > 0.002 || n.y() > 0.9) return Vector3d::Zero();  // superstructure and deck stay intact
  auto blob = [&](const Vector3d& centre, double radius) {
    const double d = (p - centre).norm() / radius;
    return std::clamp(1.5 * (1.0 - d * d), 0.0, 1.0);
  };
  double level = 0.0;
  if (bow) {
    level = p.z() >= 0 ? blob(Vector3d(3.0, -0.9, 0.15), 0.55) : 0.0;
  } else {
    level = std::max(blob(Vector3d(-3.1, -0.9, 0.15), 0.5), blob(Vector3d(-3.1, -0.9, -0.15), 0.5));
  }
  return Vector3d::Constant(level);
}

// Navigation buoy: a float with a cone on top and a short keel, 1.6 m tall, radius 0.5 m.
Mesh makeBuoy() {
  return lathe({{0.0, -0.9}, {0.15, -0.9}, {0.2, -0.5}, {0.5, -0.4}, {0.5, 0.3}, {0.3, 0.4}, {0.12, 0.9}, {0.0, 0.95}}, 48, false,
               "buoy");
}
Vector3d buoyAlbedo(const Vector3d& p, const Vector3d&) {
  const double band = std::floor((p.y() + 1.0) / 0.35);
  return (static_cast<int>(band) % 2 == 0) ? rgb(215, 40, 30) : rgb(240, 240, 235);
}

// Ball of radius 0.5 m (the unstable uniform-shell ball of figure 12), beach-ball colours.
Mesh makeBall() { return hydrotex::primitives::uvSphere(0.5, 48, 24); }
Vector3d ballAlbedo(const Vector3d& p, const Vector3d&) {
  if (std::abs(p.y()) > 0.46) return rgb(245, 245, 240);
  const double azimuth = std::atan2(p.z(), p.x()) + kPi;
  const Vector3d colours[6] = {rgb(230, 50, 40), rgb(250, 250, 245), rgb(40, 110, 220), rgb(250, 250, 245), rgb(250, 200, 40), rgb(250, 250, 245)};
  return colours[static_cast<int>(azimuth / (2 * kPi) * 6) % 6];
}

// Plush doll (a teddy): body, head, two ears, two arms and two legs, 1 m tall.
Mesh makeDoll() {
  namespace prim = hydrotex::primitives;
  auto ellipsoid = [](double rx, double ry, double rz) {
    Mesh m = prim::uvSphere(1.0, 24, 12);
    for (Vector3d& p : m.positions) p = p.cwiseProduct(Vector3d(rx, ry, rz));
    return m;
  };
  auto limb = [&](const Vector3d& at, const Vector3d& axis, double radius, double length) {
    Mesh m = ellipsoid(radius, 0.5 * length, radius);
    return transformed(std::move(m), Eigen::Quaterniond::FromTwoVectors(Vector3d::UnitY(), axis).toRotationMatrix(), at);
  };
  return combine({{ellipsoid(0.22, 0.28, 0.18), {0.0, 0.5, 0.5, 1.0}},
                  {translated(prim::uvSphere(0.18, 32, 16), Vector3d(0, 0.47, 0)), {0.5, 0.5, 1.0, 1.0}},
                  {translated(ellipsoid(0.06, 0.06, 0.03), Vector3d(-0.14, 0.67, 0)), {0.0, 0.25, 0.25, 0.5}},
                  {translated(ellipsoid(0.06, 0.06, 0.03), Vector3d(0.14, 0.67, 0)), {0.25, 0.25, 0.5, 0.5}},
                  {limb(Vector3d(-0.31, 0.08, 0.0), Vector3d(-0.6, -1, 0.3), 0.07, 0.34), {0.5, 0.25, 0.75, 0.5}},
                  {limb(Vector3d(0.31, 0.08, 0.0), Vector3d(0.6, -1, 0.3), 0.07, 0.34), {0.75, 0.25, 1.0, 0.5}},
                  {limb(Vector3d(-0.12, -0.43, 0.05), Vector3d(-0.2, -1, 0.4), 0.08, 0.34), {0.0, 0.0, 0.5, 0.25}},
                  {limb(Vector3d(0.12, -0.43, 0.05), Vector3d(0.2, -1, 0.4), 0.08, 0.34), {0.5, 0.0, 1.0, 0.25}}},
                 "plush doll");
}
Vector3d dollAlbedo(const Vector3d& p, const Vector3d&) {
  const double fur = 0.85 + 0.15 * hashNoise(p, 60.0);
  if (p.z() > 0.12 && p.y() > -0.15 && p.y() < 0.2) return rgb(225, 195, 150) * fur;  // belly
  if (p.y() > 0.4 && p.z() > 0.15) return rgb(225, 195, 150) * fur;                   // muzzle
  return rgb(150, 100, 60) * fur;
}

// Hot-air balloon: envelope 2 m across (deflated it is still this shape; the scene scales it) and
// a wicker basket hanging below. The mesh origin is the basket's floor, so that a scale animation
// about the origin inflates the balloon upwards from the ground.
Mesh makeBalloon() {
  namespace prim = hydrotex::primitives;
  std::vector<Vector2d> envelope;
  for (int k = 0; k <= 24; ++k) {
    const double t = kPi * (1.0 - double(k) / 24.0);  // from the bottom (pi) to the top (0)
    const double r = std::sin(t) * (t > kPi / 2 ? 0.55 + 0.45 * std::sin(t) : 1.0);
    envelope.emplace_back(k == 0 || k == 24 ? 0.0 : r, std::cos(t) * (t > kPi / 2 ? 1.25 : 1.0));
  }
  envelope.front() = {0.0, -1.25};
  envelope.insert(envelope.begin() + 1, Vector2d(0.18, -1.25));  // the mouth's flat ring
  return translated(combine({{lathe(envelope, 48, false, "envelope"), {0.0, 0.2, 1.0, 1.0}},
                             {translated(prim::box(Vector3d(0.5, 0.4, 0.5)), Vector3d(0, -1.75, 0)), {0.0, 0.0, 0.4, 0.2}}},
                            "hot-air balloon"),
                    Vector3d(0, 1.95, 0));
}
Vector3d balloonAlbedo(const Vector3d& position, const Vector3d&) {
  const Vector3d p = position - Vector3d(0, 1.95, 0);  // envelope-centred
  if (p.y() < -1.4) return rgb(150, 110, 60) * (0.8 + 0.2 * hashNoise(p, 40.0));  // basket
  const double azimuth = std::atan2(p.z(), p.x()) + kPi;
  const int gore = static_cast<int>(azimuth / (2 * kPi) * 12);
  if (p.y() < -0.9) return rgb(60, 60, 70);
  return gore % 2 == 0 ? rgb(240, 190, 30) : rgb(200, 40, 50);
}

// Clay pot: a flower pot 0.3 m tall with 2 cm walls and a drainage hole (a ring-shaped lathe).
Mesh makePot() {
  return lathe({{0.02, 0.0}, {0.12, 0.0}, {0.16, 0.26}, {0.18, 0.27}, {0.18, 0.3}, {0.14, 0.3}, {0.14, 0.27}, {0.10, 0.02}, {0.02, 0.02}},
               64, true, "clay pot");
}
Vector3d potAlbedo(const Vector3d& p, const Vector3d&) { return rgb(190, 100, 60) * (0.85 + 0.15 * hashNoise(p, 80.0)); }

// Beach: a 16 m x 8 m sand slab sloping into the sea along +x, with rocks (separate parts).
double beachHeight(double x, double z) { return 0.4 - 0.1 * x + 0.05 * std::sin(1.3 * z) * std::cos(0.7 * x); }
Mesh makeBeach() {
  namespace prim = hydrotex::primitives;
  std::vector<Part> parts = {{heightFieldSlab(16.0, 8.0, 64, -1.5, beachHeight), {0.0, 0.3, 1.0, 1.0}}};
  const Vector3d rocks[3] = {{-3.0, 0.0, 1.5}, {-1.0, 0.0, -2.0}, {1.5, 0.0, 2.2}};
  for (int r = 0; r < 3; ++r) {
    Mesh rock = prim::icosphere(0.5 + 0.15 * r, 2);
    for (Vector3d& p : rock.positions) p *= 0.75 + 0.5 * hashNoise(p + Vector3d::Constant(r), 2.5);
    // Sit the rock on the sand, above it by a gap so that the parts do not touch.
    double lowest = 1e9;
    for (const Vector3d& p : rock.positions) lowest = std::min(lowest, p.y());
    const Vector3d at = rocks[r] + Vector3d(0, beachHeight(rocks[r].x(), rocks[r].z()) + 0.12 - lowest, 0);
    parts.push_back({translated(std::move(rock), at), {0.33 * r, 0.0, 0.33 * r + 0.32, 0.29}});
  }
  return combine(parts, "beach");
}
Vector3d beachAlbedo(const Vector3d& p, const Vector3d& n) {
  const double grain = 0.85 + 0.15 * hashNoise(p, 30.0);
  const double sand = p.y() - beachHeight(p.x(), p.z());
  if (std::abs(sand) < 0.01 && n.y() > 0.5) return rgb(225, 200, 150) * grain;
  if (sand > 0.05) return rgb(120, 118, 112) * (0.7 + 0.3 * hashNoise(p, 6.0));  // rocks
  return rgb(170, 145, 100) * grain;                                               // slab sides
}

struct Asset {
  std::string name;  ///< mesh file stem
  Mesh mesh;
  Painter albedo;    ///< empty: no texture
  int textureSize = 256;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: hydrotex_generate_assets DATA_DIR\n");
    return 2;
  }
  const std::string meshDir = std::string(argv[1]) + "/meshes/", textureDir = std::string(argv[1]) + "/textures/";
  std::error_code ec;
  std::filesystem::create_directories(meshDir, ec);
  std::filesystem::create_directories(textureDir, ec);
  namespace prim = hydrotex::primitives;
  const Eigen::Matrix3d upright = rotationAbout(Vector3d::UnitX(), -kPi / 2);

  std::vector<Asset> assets;
  // 1 m cube: the box of the closed-form tests.
  assets.push_back({"box", prim::box(Vector3d(1.0, 1.0, 1.0)), {}, 0});
  // Sphere of radius 0.5 m.
  assets.push_back({"sphere", prim::uvSphere(0.5, 48, 24), {}, 0});
  // A 162-vertex, 320-face convex hull (icosphere of subdivision 2, radius 0.5 m): the hull of the
  // peer figures (docs/references.md "Peers": Jolt's 162-vertex hull; data/scenes/peers_*.json).
  assets.push_back({"hull162", prim::icosphere(0.5, 2), {}, 0});
  // Spar buoy: a vertical cylinder, radius 0.4 m, 2 m tall, centred at the origin.
  assets.push_back({"buoy", transformed(prim::cylinder(0.4, 2.0, 48), upright, Vector3d::Zero()), buoyAlbedo, 256});
  // Log: a horizontal cylinder (axis along z), radius 0.25 m, 3 m long.
  assets.push_back({"log", prim::cylinder(0.25, 3.0, 48), {}, 0});
  // Torus (non-convex): major radius 1 m, tube radius 0.25 m.
  assets.push_back({"torus", prim::torus(1.0, 0.25, 64, 24), {}, 0});
  // Wigley hull: L = 4 m, B = 0.4 m, T = 0.25 m, deck at y = 0.
  assets.push_back({"wigley", prim::wigleyHull(4.0, 0.4, 0.25, 64, 16), {}, 0});
  // The demos' assets.
  assets.push_back({"ship", makeShip(), shipAlbedo, 512});
  assets.push_back({"nav_buoy", makeBuoy(), buoyAlbedo, 256});
  assets.push_back({"ball", makeBall(), ballAlbedo, 256});
  assets.push_back({"plush_doll", makeDoll(), dollAlbedo, 256});
  assets.push_back({"balloon", makeBalloon(), balloonAlbedo, 256});
  assets.push_back({"clay_pot", makePot(), potAlbedo, 256});
  assets.push_back({"beach", makeBeach(), beachAlbedo, 512});

  int failures = 0;
  for (const Asset& asset : assets) {
    const hydrotex::MeshReport report = hydrotex::validateMesh(asset.mesh);
    if (!report.outwardOriented || !report.uvUsableAsAtlas() || report.degenerateTriangles != 0) {
      std::fprintf(stderr, "hydrotex_generate_assets: %s is not a closed mesh with a usable atlas:\n%s\n", asset.name.c_str(),
                   report.summary().c_str());
      ++failures;
      continue;
    }
    hydrotex::Status saved = hydrotex::saveMesh(asset.mesh, meshDir + asset.name + ".obj");
    if (saved && asset.albedo) saved = writeImage(paint(asset.mesh, asset.textureSize, asset.albedo), textureDir + asset.name + "_albedo.png", false);
    if (!saved) {
      std::fprintf(stderr, "hydrotex_generate_assets: %s\n", saved.error().message.c_str());
      return 1;
    }
    std::printf("%-12s %6zu triangles, volume %.4f m^3, area %.3f m^2\n", asset.name.c_str(), asset.mesh.triangles.size(),
                report.volume.value_or(0.0), report.area);
  }
  // Damage maps of the ship (gray: 0 intact, 1 open), 256 texels square: enough for blobs.
  const Mesh ship = makeShip();
  for (const bool bow : {true, false}) {
    const std::string path = textureDir + (bow ? "ship_damage_bow.png" : "ship_damage_stern.png");
    const hydrotex::Status saved = writeImage(paint(ship, 256, [bow](const Vector3d& p, const Vector3d& n) { return shipDamage(p, n, bow); }), path, true);
    if (!saved) {
      std::fprintf(stderr, "hydrotex_generate_assets: %s\n", saved.error().message.c_str());
      return 1;
    }
  }
  return failures == 0 ? 0 : 1;
}
