// SPDX-License-Identifier: Zlib
#include "hydrotex/flooding/LiquidGraphBuilder.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <string>
#include <utility>

namespace hydrotex {
namespace {

constexpr std::int32_t kOutside = -2;
constexpr std::int32_t kUnlabelled = -1;

/// Regular cells over the mesh's bounding box; inside cells carry a node label.
struct CellGrid {
  Eigen::Vector3d lower = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  // m, cell edges
  std::array<int, 3> count{1, 1, 1};
  std::vector<std::int32_t> label;  // kOutside, kUnlabelled or a node index
  double cellVolume = 0.0;          // m^3 of one inside cell after scaling to the exact volume

  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * std::size_t(count[1]) + std::size_t(j)) * std::size_t(count[0]) + std::size_t(i);
  }
  Eigen::Vector3d centre(int i, int j, int k) const {
    return lower + Eigen::Vector3d((i + 0.5) * size.x(), (j + 0.5) * size.y(), (k + 0.5) * size.z());
  }
  std::array<int, 3> cellOf(const Eigen::Vector3d& p) const {
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[std::size_t(a)] = std::clamp(int(std::floor((p[a] - lower[a]) / size[a])), 0, count[std::size_t(a)] - 1);
    return c;
  }
  double faceArea(int axis) const { return axis == 0 ? size.y() * size.z() : axis == 1 ? size.x() * size.z() : size.x() * size.y(); }
};

/// Exact enclosed volume from the texels (sum of cones p . A / 3, divergence theorem).
double enclosedVolume(const SurfaceTextures& textures) {
  double volume = 0.0;
  for (std::size_t t = 0; t < textures.size(); ++t) {
    volume += double(textures.position[t].dot(textures.areaVector[t])) / 3.0;
  }
  return volume;
}

/// Marks the cells whose centre is inside the mesh by the parity of crossings along vertical rays.
/// The rays are shifted by an irrational fraction of a cell so that none runs exactly through a
/// vertex or an edge of an axis-aligned mesh (where a crossing would count twice).
Expected<CellGrid> cellsInside(const Mesh& mesh, const SurfaceTextures& textures, int budget) {
  if (mesh.positions.empty() || mesh.triangles.empty()) return Error{mesh.sourceName + ": the mesh is empty"};
  Eigen::Vector3d lower = mesh.positions.front(), upper = lower;
  for (const Eigen::Vector3d& p : mesh.positions) {
    if (!p.allFinite()) return Error{mesh.sourceName + ": a vertex is not finite"};
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  const Eigen::Vector3d extent = upper - lower;
  if (!(extent.minCoeff() > 0.0)) return Error{mesh.sourceName + ": the mesh is flat (encloses no volume)"};
  CellGrid grid;
  grid.lower = lower;
  const double side = std::cbrt(extent.prod() / double(budget));
  for (int a = 0; a < 3; ++a) {
    grid.count[std::size_t(a)] = std::max(1, int(std::lround(extent[a] / side)));
    grid.size[a] = extent[a] / grid.count[std::size_t(a)];
  }
  const int nx = grid.count[0], ny = grid.count[1], nz = grid.count[2];
  grid.label.assign(std::size_t(nx) * std::size_t(ny) * std::size_t(nz), kOutside);
  const double shiftX = 0.41421356237 * 1e-4 * grid.size.x(), shiftZ = 0.73205080757 * 1e-4 * grid.size.z();
  std::vector<std::vector<double>> crossings(std::size_t(nx) * std::size_t(nz));
  for (const Eigen::Vector3i& tri : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.positions[std::size_t(tri[0])];
    const Eigen::Vector3d& b = mesh.positions[std::size_t(tri[1])];
    const Eigen::Vector3d& c = mesh.positions[std::size_t(tri[2])];
    const double det = (b.x() - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (b.z() - a.z());
    if (std::abs(det) <= 1e-300) continue;  // vertical: parallel to the rays
    const double minX = std::min({a.x(), b.x(), c.x()}), maxX = std::max({a.x(), b.x(), c.x()});
    const double minZ = std::min({a.z(), b.z(), c.z()}), maxZ = std::max({a.z(), b.z(), c.z()});
    const int i0 = std::max(0, int(std::ceil((minX - lower.x() - shiftX) / grid.size.x() - 0.5)));
    const int i1 = std::min(nx - 1, int(std::floor((maxX - lower.x() - shiftX) / grid.size.x() - 0.5)));
    const int k0 = std::max(0, int(std::ceil((minZ - lower.z() - shiftZ) / grid.size.z() - 0.5)));
    const int k1 = std::min(nz - 1, int(std::floor((maxZ - lower.z() - shiftZ) / grid.size.z() - 0.5)));
    for (int k = k0; k <= k1; ++k) {
      const double z = lower.z() + (k + 0.5) * grid.size.z() + shiftZ;
      for (int i = i0; i <= i1; ++i) {
        const double x = lower.x() + (i + 0.5) * grid.size.x() + shiftX;
        const double wb = ((x - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (z - a.z())) / det;
        const double wc = ((b.x() - a.x()) * (z - a.z()) - (x - a.x()) * (b.z() - a.z())) / det;
        const double wa = 1.0 - wb - wc;
        if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
        crossings[std::size_t(k) * std::size_t(nx) + std::size_t(i)].push_back(wa * a.y() + wb * b.y() + wc * c.y());
      }
    }
  }
  std::size_t inside = 0;
  for (int k = 0; k < nz; ++k) {
    for (int i = 0; i < nx; ++i) {
      std::vector<double>& ys = crossings[std::size_t(k) * std::size_t(nx) + std::size_t(i)];
      std::sort(ys.begin(), ys.end());
      for (int j = 0; j < ny; ++j) {
        const double y = lower.y() + (j + 0.5) * grid.size.y();
        const auto below = std::lower_bound(ys.begin(), ys.end(), y) - ys.begin();
        if (below % 2 == 1) {
          grid.label[grid.index(i, j, k)] = kUnlabelled;
          ++inside;
        }
      }
    }
  }
  if (inside == 0) return Error{mesh.sourceName + ": no space cell lies inside the mesh (raise cellBudget)"};
  grid.cellVolume = enclosedVolume(textures) / double(inside);
  if (!(grid.cellVolume > 0.0)) return Error{mesh.sourceName + ": encloses no volume (is it inside out?)"};
  return grid;
}

Status checkPermeability(const std::vector<float>& values, std::size_t texels) {
  if (!values.empty() && values.size() != texels) {
    return Error{"permeability map: " + std::to_string(values.size()) + " values for " + std::to_string(texels) +
                 " texels"};
  }
  for (std::size_t t = 0; t < values.size(); ++t) {
    if (!(values[t] >= 0.0f && values[t] <= 1.0f)) {
      return Error{"permeability map: texel " + std::to_string(t) + " has a value outside [0, 1]"};
    }
  }
  return Ok{};
}

/// Nodes' spaces from the labelled cells, and the face area where each pair of spaces touches.
struct Spaces {
  std::vector<LiquidNodeSpace> spaces;
  std::vector<Eigen::Vector3d> centroids;
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> touching;  // m^2
};

Spaces collectSpaces(const CellGrid& grid, std::size_t nodeCount) {
  Spaces out;
  out.spaces.resize(nodeCount);
  out.centroids.assign(nodeCount, Eigen::Vector3d::Zero());
  for (int k = 0; k < grid.count[2]; ++k)
    for (int j = 0; j < grid.count[1]; ++j)
      for (int i = 0; i < grid.count[0]; ++i) {
        const std::int32_t label = grid.label[grid.index(i, j, k)];
        if (label < 0) continue;
        const Eigen::Vector3d centre = grid.centre(i, j, k);
        out.spaces[std::size_t(label)].centers.push_back(centre.cast<float>());
        out.spaces[std::size_t(label)].volumes.push_back(float(grid.cellVolume));
        out.centroids[std::size_t(label)] += centre;
        const std::array<int, 3> here{i, j, k};
        for (int axis = 0; axis < 3; ++axis) {
          std::array<int, 3> next = here;
          if (++next[std::size_t(axis)] >= grid.count[std::size_t(axis)]) continue;
          const std::int32_t other = grid.label[grid.index(next[0], next[1], next[2])];
          if (other < 0 || other == label) continue;
          const std::uint32_t a = std::uint32_t(std::min(label, other)), b = std::uint32_t(std::max(label, other));
          out.touching[{a, b}] += grid.faceArea(axis);
        }
      }
  for (std::size_t n = 0; n < nodeCount; ++n) {
    if (!out.spaces[n].centers.empty()) out.centroids[n] /= double(out.spaces[n].centers.size());
  }
  return out;
}

std::vector<PermeableTexel> permeableTexels(const SurfaceTextures& textures, const std::vector<float>& values,
                                            const std::vector<std::uint32_t>& texelNode,
                                            const LiquidGraphBuildSettings& settings) {
  std::vector<PermeableTexel> out;
  // An open hull (Mesh::openingTriangles) takes liquid in through its openings; its walls are
  // watertight unless a map says otherwise.
  const bool openHull = !textures.openingArea.empty() && textures.openingArea.size() == textures.size() &&
                        textures.openingPosition.size() == textures.size();
  const auto add = [&](std::size_t t, const Eigen::Vector3f& position, double transmissibility) {
    if (!(transmissibility > 0.0)) return;
    PermeableTexel texel;
    texel.position = position;
    texel.transmissibility = float(transmissibility);
    texel.node = texelNode[t];
    texel.texel = std::uint32_t(t);
    out.push_back(texel);
  };
  for (std::size_t t = 0; t < textures.size(); ++t) {
    if (!(textures.area[t] > 0.0f)) continue;
    const double lidArea = openHull ? double(textures.openingArea[t]) : 0.0;
    const double wallArea = std::max(double(textures.area[t]) - lidArea, 0.0);
    const double value = values.empty() ? (openHull ? 0.0 : 1.0) : double(values[t]);
    // Darcy's k A / L per texel (paper eq. 9): the map scales the permeability of white.
    add(t, textures.position[t], value * settings.permeability * wallArea / settings.wallThickness);
    // The texel's part on a lid is an opening, with no wall to pass, where the lid is (a texel
    // may hold pieces of a lid and of the bottom: its own position is neither's).
    if (lidArea > 0.0) add(t, textures.openingPosition[t], settings.openingConductance * lidArea);
  }
  return out;
}

/// Centre of the least-squares sphere through weighted points (algebraic fit: |p|^2 = 2 c.p + d,
/// linear in c and d). Empty when the fit is singular (a flat or tiny part).
std::optional<Eigen::Vector3d> sphereCentre(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& weights) {
  if (points.size() < 4) return std::nullopt;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    mean += weights[i] * points[i];
    total += weights[i];
  }
  if (!(total > 0.0)) return std::nullopt;
  mean /= total;
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = points[i] - mean;  // centred for conditioning
    const Eigen::Vector4d row(2.0 * p.x(), 2.0 * p.y(), 2.0 * p.z(), 1.0);
    normal += weights[i] * row * row.transpose();
    rhs += weights[i] * p.squaredNorm() * row;
  }
  Eigen::LDLT<Eigen::Matrix4d> solver(normal);
  if (solver.info() != Eigen::Success || !(solver.vectorD().cwiseAbs().minCoeff() > 1e-12 * solver.vectorD().cwiseAbs().maxCoeff())) {
    return std::nullopt;
  }
  const Eigen::Vector4d solution = solver.solve(rhs);
  if (!solution.allFinite()) return std::nullopt;
  return Eigen::Vector3d(mean + solution.head<3>());
}

std::size_t nearest(const std::vector<Eigen::Vector3d>& centres, const Eigen::Vector3d& p) {
  std::size_t best = 0;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < centres.size(); ++c) {
    const double d = (centres[c] - p).squaredNorm();
    if (d < bestDistance) {
      bestDistance = d;
      best = c;
    }
  }
  return best;
}

}  // namespace

Status LiquidGraphBuildSettings::validate() const {
  if (!(std::isfinite(permeability) && permeability >= 0.0)) return Error{"permeability: must be >= 0 m^2 and finite"};
  if (!(std::isfinite(wallThickness) && wallThickness > 0.0)) return Error{"wall_thickness: must be > 0 m and finite"};
  if (!(porosity >= 0.0 && porosity <= 1.0)) return Error{"porosity: must lie in [0, 1]"};
  if (!(std::isfinite(interiorPermeability) && interiorPermeability >= 0.0)) {
    return Error{"interior_permeability: must be >= 0 m^2 and finite"};
  }
  if (cellBudget < 8 || cellBudget > 4000000) return Error{"cellBudget: must lie in 8..4000000"};
  if (!(std::isfinite(openingConductance) && openingConductance >= 0.0))
    return Error{"opening_conductance: must be >= 0 m and finite"};
  return Ok{};
}

int defaultLiquidGraphNodeCount(const Mesh& mesh) {
  if (mesh.positions.empty()) return 4;
  Eigen::Vector3d lower = mesh.positions.front(), upper = lower;
  for (const Eigen::Vector3d& p : mesh.positions) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  const Eigen::Vector3d extent = upper - lower;
  if (!(extent.minCoeff() > 0.0)) return 4;
  return std::clamp(int(std::lround(4.0 * extent.maxCoeff() / extent.minCoeff())), 4, 32);
}

Expected<LiquidGraph> buildAutomaticLiquidGraph(const Mesh& mesh, const SurfaceTextures& textures,
                                                const std::vector<float>& texelPermeability, int nodeCount,
                                                const LiquidGraphBuildSettings& settings) {
  if (Status s = settings.validate(); !s) return s.error();
  if (nodeCount < 0 || nodeCount > 1024) return Error{"liquid_graph_nodes: " + std::to_string(nodeCount) + " is outside 0..1024"};
  if (textures.size() == 0) return Error{"liquid graph: the surface has no texels"};
  if (Status s = checkPermeability(texelPermeability, textures.size()); !s) return s.error();
  const std::size_t texels = textures.size();
  const std::size_t k = std::min<std::size_t>(std::size_t(nodeCount == 0 ? defaultLiquidGraphNodeCount(mesh) : nodeCount), texels);

  // Segmentation (paper 3.2, step 1): k-means of the surface (area-weighted texel positions),
  // seeded by farthest points so that the result does not depend on a random draw.
  const std::size_t stride = std::max<std::size_t>(1, texels / 32768);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (std::size_t t = 0; t < texels; t += stride) {
    points.push_back(textures.position[t].cast<double>());
    weights.push_back(std::max(double(textures.area[t]), 1e-30));
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) mean += p;
  mean /= double(points.size());
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> distance(points.size(), std::numeric_limits<double>::infinity());
  std::size_t seed = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if ((points[i] - mean).squaredNorm() > (points[seed] - mean).squaredNorm()) seed = i;
  }
  while (centres.size() < k) {
    centres.push_back(points[seed]);
    std::size_t farthest = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      distance[i] = std::min(distance[i], (points[i] - centres.back()).squaredNorm());
      if (distance[i] > distance[farthest]) farthest = i;
    }
    if (!(distance[farthest] > 0.0)) break;  // fewer distinct points than k
    seed = farthest;
  }
  std::vector<std::size_t> assignment(points.size(), 0);
  for (int iteration = 0; iteration < 20; ++iteration) {
    bool moved = false;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::size_t c = nearest(centres, points[i]);
      moved = moved || c != assignment[i];
      assignment[i] = c;
    }
    std::vector<Eigen::Vector3d> sums(centres.size(), Eigen::Vector3d::Zero());
    std::vector<double> mass(centres.size(), 0.0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      sums[assignment[i]] += weights[i] * points[i];
      mass[assignment[i]] += weights[i];
    }
    for (std::size_t c = 0; c < centres.size(); ++c) {
      if (mass[c] > 0.0) centres[c] = sums[c] / mass[c];
    }
    if (!moved && iteration > 0) break;
  }
  std::vector<std::uint32_t> part(texels);
  for (std::size_t t = 0; t < texels; ++t) part[t] = std::uint32_t(nearest(centres, textures.position[t].cast<double>()));

  // Each inside cell goes to the part of the nearest texels around it, then the labels grow
  // through the inside (6-neighbour flood), so a part's space is the volume behind its surface.
  Expected<CellGrid> built = cellsInside(mesh, textures, settings.cellBudget);
  if (!built) return built.error();
  CellGrid& grid = *built;
  std::vector<double> best(grid.label.size(), std::numeric_limits<double>::infinity());
  for (std::size_t t = 0; t < texels; ++t) {
    const Eigen::Vector3d p = textures.position[t].cast<double>();
    const std::array<int, 3> c = grid.cellOf(p);
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int i = c[0] + di, j = c[1] + dj, kk = c[2] + dk;
          if (i < 0 || j < 0 || kk < 0 || i >= grid.count[0] || j >= grid.count[1] || kk >= grid.count[2]) continue;
          const std::size_t cell = grid.index(i, j, kk);
          if (grid.label[cell] == kOutside) continue;
          const double d = (grid.centre(i, j, kk) - p).squaredNorm();
          if (d < best[cell]) {
            best[cell] = d;
            grid.label[cell] = std::int32_t(part[t]);
          }
        }
  }
  std::deque<std::array<int, 3>> queue;
  for (int kk = 0; kk < grid.count[2]; ++kk)
    for (int j = 0; j < grid.count[1]; ++j)
      for (int i = 0; i < grid.count[0]; ++i)
        if (grid.label[grid.index(i, j, kk)] >= 0) queue.push_back({i, j, kk});
  while (!queue.empty()) {
    const std::array<int, 3> c = queue.front();
    queue.pop_front();
    const std::int32_t label = grid.label[grid.index(c[0], c[1], c[2])];
    for (int axis = 0; axis < 3; ++axis)
      for (int step : {-1, 1}) {
        std::array<int, 3> next = c;
        next[std::size_t(axis)] += step;
        if (next[std::size_t(axis)] < 0 || next[std::size_t(axis)] >= grid.count[std::size_t(axis)]) continue;
        std::int32_t& other = grid.label[grid.index(next[0], next[1], next[2])];
        if (other != kUnlabelled) continue;
        other = label;
        queue.push_back(next);
      }
  }
  for (int kk = 0; kk < grid.count[2]; ++kk)
    for (int j = 0; j < grid.count[1]; ++j)
      for (int i = 0; i < grid.count[0]; ++i) {
        std::int32_t& label = grid.label[grid.index(i, j, kk)];
        if (label == kUnlabelled) label = std::int32_t(nearest(centres, grid.centre(i, j, kk)));
      }

  // Parts without space (thinner than a cell) hand their texels to the nearest part with space.
  Spaces spaces = collectSpaces(grid, centres.size());
  std::vector<std::uint32_t> renumber(centres.size(), 0);
  std::vector<Eigen::Vector3d> keptCentres;
  std::vector<std::size_t> kept;
  for (std::size_t c = 0; c < centres.size(); ++c) {
    if (spaces.spaces[c].centers.empty()) continue;
    renumber[c] = std::uint32_t(kept.size());
    kept.push_back(c);
    keptCentres.push_back(spaces.centroids[c]);
  }
  for (std::size_t c = 0; c < centres.size(); ++c) {
    if (spaces.spaces[c].centers.empty()) renumber[c] = std::uint32_t(nearest(keptCentres, centres[c]));
  }
  for (std::uint32_t& p : part) p = renumber[p];

  LiquidGraphDescription description;
  description.cellSize = grid.size;
  Eigen::Vector3d lower = mesh.positions.front(), upper = lower;
  for (const Eigen::Vector3d& p : mesh.positions) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  std::vector<std::vector<Eigen::Vector3d>> partPoints(kept.size());
  std::vector<std::vector<double>> partWeights(kept.size());
  for (std::size_t t = 0; t < texels; t += stride) {
    partPoints[part[t]].push_back(textures.position[t].cast<double>());
    partWeights[part[t]].push_back(std::max(double(textures.area[t]), 1e-30));
  }
  for (std::size_t n = 0; n < kept.size(); ++n) {
    LiquidGraphNode node;
    // Paper 3.2 step 2: the node sits at the centre of the part's least-squares sphere; a flat
    // part's sphere centre runs off to infinity, so one outside the bounding box falls back to
    // the centroid of the part's space.
    const std::optional<Eigen::Vector3d> centre = sphereCentre(partPoints[n], partWeights[n]);
    const bool usable = centre && (centre->array() >= lower.array()).all() && (centre->array() <= upper.array()).all();
    node.position = usable ? *centre : spaces.centroids[kept[n]];
    double volume = 0.0;
    for (float v : spaces.spaces[kept[n]].volumes) volume += double(v);
    node.capacity = settings.porosity * volume;
    description.nodes.push_back(node);
    description.spaces.push_back(std::move(spaces.spaces[kept[n]]));
  }
  // Paper 3.2 step 3: an edge where two parts' spaces touch; T = k A / L with the touching area.
  for (const auto& [pair, area] : spaces.touching) {
    const std::uint32_t a = renumber[pair.first], b = renumber[pair.second];
    if (a == b) continue;
    const double length = std::max((spaces.centroids[pair.first] - spaces.centroids[pair.second]).norm(), 1e-9);
    description.edges.push_back({a, b, settings.interiorPermeability * area / length});
  }
  description.permeableTexels = permeableTexels(textures, texelPermeability, part, settings);
  return LiquidGraph::create(std::move(description));
}

Expected<LiquidGraph> buildManualLiquidGraph(const Mesh& mesh, const SurfaceTextures& textures,
                                             const std::vector<float>& texelPermeability,
                                             const ManualLiquidGraph& manual, const LiquidGraphBuildSettings& settings) {
  if (Status s = settings.validate(); !s) return s.error();
  if (manual.nodes.empty()) return Error{"liquid graph: no nodes"};
  if (Status s = checkPermeability(texelPermeability, textures.size()); !s) return s.error();
  std::vector<Eigen::Vector3d> positions;
  for (std::size_t i = 0; i < manual.nodes.size(); ++i) {
    const ManualLiquidNode& node = manual.nodes[i];
    if (!node.position.allFinite()) return Error{"nodes[" + std::to_string(i) + "]: position is not finite"};
    if (node.capacity && !(std::isfinite(*node.capacity) && *node.capacity >= 0.0)) {
      return Error{"nodes[" + std::to_string(i) + "]: capacity must be >= 0 m^3 and finite"};
    }
    positions.push_back(node.position);
  }
  for (std::size_t e = 0; e < manual.edges.size(); ++e) {
    const ManualLiquidEdge& edge = manual.edges[e];
    const std::string name = "edges[" + std::to_string(e) + "]";
    if (edge.first >= manual.nodes.size() || edge.second >= manual.nodes.size() || edge.first == edge.second) {
      return Error{name + ": names a missing node or joins a node to itself"};
    }
    if (!(std::isfinite(edge.permeability) && edge.permeability >= 0.0)) return Error{name + ": permeability must be >= 0 m^2"};
    if (edge.area && !(std::isfinite(*edge.area) && *edge.area > 0.0)) return Error{name + ": area must be > 0 m^2"};
    if (edge.length && !(std::isfinite(*edge.length) && *edge.length > 0.0)) return Error{name + ": length must be > 0 m"};
  }
  Expected<CellGrid> built = cellsInside(mesh, textures, settings.cellBudget);
  if (!built) return built.error();
  CellGrid& grid = *built;
  for (int k = 0; k < grid.count[2]; ++k)
    for (int j = 0; j < grid.count[1]; ++j)
      for (int i = 0; i < grid.count[0]; ++i) {
        std::int32_t& label = grid.label[grid.index(i, j, k)];
        if (label == kUnlabelled) label = std::int32_t(nearest(positions, grid.centre(i, j, k)));
      }
  Spaces spaces = collectSpaces(grid, positions.size());
  LiquidGraphDescription description;
  description.cellSize = grid.size;
  for (std::size_t i = 0; i < manual.nodes.size(); ++i) {
    double volume = 0.0;
    for (float v : spaces.spaces[i].volumes) volume += double(v);
    LiquidGraphNode node;
    node.position = positions[i];
    node.capacity = manual.nodes[i].capacity.value_or(settings.porosity * volume);
    if (node.capacity > volume * (1.0 + 1e-6)) {
      return Error{"nodes[" + std::to_string(i) + "]: capacity " + std::to_string(node.capacity) +
                   " m^3 exceeds the " + std::to_string(volume) + " m^3 of space nearest to it"};
    }
    description.nodes.push_back(node);
    description.spaces.push_back(std::move(spaces.spaces[i]));
  }
  const double smallestFace = std::min({grid.faceArea(0), grid.faceArea(1), grid.faceArea(2)});
  for (const ManualLiquidEdge& edge : manual.edges) {
    const auto touching = spaces.touching.find({std::min(edge.first, edge.second), std::max(edge.first, edge.second)});
    const double area = edge.area.value_or(touching != spaces.touching.end() ? touching->second : smallestFace);
    const double length = edge.length.value_or(std::max((positions[edge.first] - positions[edge.second]).norm(), 1e-9));
    description.edges.push_back({edge.first, edge.second, edge.permeability * area / length});
  }
  std::vector<std::uint32_t> texelNode(textures.size());
  for (std::size_t t = 0; t < textures.size(); ++t) {
    texelNode[t] = std::uint32_t(nearest(positions, textures.position[t].cast<double>()));
  }
  description.permeableTexels = permeableTexels(textures, texelPermeability, texelNode, settings);
  return LiquidGraph::create(std::move(description));
}

}  // namespace hydrotex
