// SPDX-License-Identifier: Zlib
#include "hydrotex/flooding/LiquidGraph.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace hydrotex {
namespace {

enum NodeMode : int {
  kFree = 0,      // level follows the liquid: h = h0 + dl / area
  kFull = 1,      // held at capacity; its head may rise above the top (pressurized)
  kEmpty = 2,     // held at zero; its head may sit below the bottom
  kJunction = 3,  // holds nothing (zero capacity): passes liquid on, head free
};

bool finite(const Eigen::Vector3f& v) { return v.allFinite(); }

std::string nodeName(std::size_t i) { return "nodes[" + std::to_string(i) + "]"; }

/// The slope S_e (m^3/s per m of head) that makes a free node's implicit step follow the exact
/// exponential of A dh/dt = Q0 - S (h - h0): (Q0/S)(1 - exp(-S dt / A)) at any dt; S/2 as dt -> 0.
/// `slope`: S; `area`: the free-surface area A (m^2); `dt`: the step (s).
double fittedSlope(double slope, double area, double dt) {
  const double x = dt * slope / area;
  return x < 1e-6 ? slope * (0.5 + x / 12.0) : (area / dt) * (x / -std::expm1(-x) - 1.0);
}

}  // namespace

Expected<LiquidGraph> LiquidGraph::create(LiquidGraphDescription description) {
  const std::size_t n = description.nodes.size();
  if (n == 0) return Error{"liquid graph: no nodes"};
  if (description.spaces.size() != n) {
    return Error{"liquid graph: " + std::to_string(description.spaces.size()) + " spaces for " + std::to_string(n) +
                 " nodes"};
  }
  if (!description.cellSize.allFinite() || !(description.cellSize.minCoeff() > 0.0)) {
    return Error{"liquid graph: cellSize must be positive and finite"};
  }
  LiquidGraph graph;
  graph.cellSize_ = description.cellSize;
  graph.cellStart_.assign(1, 0);
  graph.porosity_.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const LiquidGraphNode& node = description.nodes[i];
    if (!node.position.allFinite()) return Error{nodeName(i) + ": position is not finite"};
    if (!(std::isfinite(node.capacity) && node.capacity >= 0.0)) {
      return Error{nodeName(i) + ": capacity " + std::to_string(node.capacity) + " m^3 must be >= 0 and finite"};
    }
    if (!(std::isfinite(node.liquid) && node.liquid >= 0.0 && node.liquid <= node.capacity)) {
      return Error{nodeName(i) + ": liquid " + std::to_string(node.liquid) + " m^3 is outside 0..capacity"};
    }
    const LiquidNodeSpace& space = description.spaces[i];
    if (space.centers.size() != space.volumes.size()) {
      return Error{"spaces[" + std::to_string(i) + "]: centers and volumes differ in size"};
    }
    double volume = 0.0;
    for (std::size_t c = 0; c < space.centers.size(); ++c) {
      if (!finite(space.centers[c]) || !(std::isfinite(space.volumes[c]) && space.volumes[c] > 0.0f)) {
        return Error{"spaces[" + std::to_string(i) + "]: cell " + std::to_string(c) +
                     " has a non-finite centre or a non-positive volume"};
      }
      volume += double(space.volumes[c]);
      graph.cellX_.push_back(space.centers[c].x());
      graph.cellY_.push_back(space.centers[c].y());
      graph.cellZ_.push_back(space.centers[c].z());
      graph.cellVolume_.push_back(space.volumes[c]);
    }
    graph.cellStart_.push_back(std::uint32_t(graph.cellX_.size()));
    if (node.capacity > volume * (1.0 + 1e-6)) {
      return Error{nodeName(i) + ": capacity " + std::to_string(node.capacity) + " m^3 exceeds its space of " +
                   std::to_string(volume) + " m^3"};
    }
    graph.porosity_[i] = volume > 0.0 ? std::min(1.0, node.capacity / volume) : 0.0;
  }
  for (std::size_t e = 0; e < description.edges.size(); ++e) {
    const LiquidGraphEdge& edge = description.edges[e];
    if (edge.first >= n || edge.second >= n || edge.first == edge.second) {
      return Error{"edges[" + std::to_string(e) + "]: names a missing node or joins a node to itself"};
    }
    if (!(std::isfinite(edge.transmissibility) && edge.transmissibility >= 0.0)) {
      return Error{"edges[" + std::to_string(e) + "]: transmissibility must be >= 0 and finite"};
    }
  }
  for (std::size_t t = 0; t < description.permeableTexels.size(); ++t) {
    const PermeableTexel& texel = description.permeableTexels[t];
    if (texel.node >= n) return Error{"permeableTexels[" + std::to_string(t) + "]: names a missing node"};
    if (!finite(texel.position) || !(std::isfinite(texel.transmissibility) && texel.transmissibility >= 0.0f)) {
      return Error{"permeableTexels[" + std::to_string(t) + "]: non-finite position or negative transmissibility"};
    }
  }
  // Texels node by node, so that the per-step pass reads one contiguous range per node.
  std::stable_sort(description.permeableTexels.begin(), description.permeableTexels.end(),
                   [](const PermeableTexel& a, const PermeableTexel& b) { return a.node < b.node; });
  graph.texelStart_.assign(n + 1, 0);
  for (const PermeableTexel& texel : description.permeableTexels) {
    ++graph.texelStart_[texel.node + 1];
    graph.texelX_.push_back(texel.position.x());
    graph.texelY_.push_back(texel.position.y());
    graph.texelZ_.push_back(texel.position.z());
    graph.texelT_.push_back(texel.transmissibility);
  }
  for (std::size_t i = 0; i < n; ++i) graph.texelStart_[i + 1] += graph.texelStart_[i];

  graph.nodes_ = std::move(description.nodes);
  graph.edges_ = std::move(description.edges);
  graph.texels_ = std::move(description.permeableTexels);
  graph.cellHeight_.assign(graph.cellX_.size(), 0.0);
  graph.cellOrder_.resize(graph.cellX_.size());
  for (std::size_t i = 0; i < n; ++i) {
    std::iota(graph.cellOrder_.begin() + graph.cellStart_[i], graph.cellOrder_.begin() + graph.cellStart_[i + 1],
              graph.cellStart_[i]);
  }
  graph.centroids_.assign(n, Eigen::Vector3d::Zero());
  for (auto* v : {&graph.levels_, &graph.exchange_, &graph.h0_, &graph.area_, &graph.q0_, &graph.pushedIn_, &graph.slopeAll_, &graph.slopeInside_,
                  &graph.slopeOutside_, &graph.bottom_, &graph.top_, &graph.delta_}) {
    v->assign(n, 0.0);
  }
  graph.mode_.assign(n, kFree);
  graph.matrix_.resize(Eigen::Index(n), Eigen::Index(n));
  graph.rhs_.resize(Eigen::Index(n));
  graph.head_.resize(Eigen::Index(n));
  graph.updateLiquidCentroids(Pose{});
  return graph;
}

double LiquidGraph::heldLiquid() const {
  double sum = 0.0;
  for (const LiquidGraphNode& node : nodes_) sum += node.liquid;
  return sum;
}

double LiquidGraph::totalCapacity() const {
  double sum = 0.0;
  for (const LiquidGraphNode& node : nodes_) sum += node.capacity;
  return sum;
}

Status LiquidGraph::setLiquid(std::size_t node, double volume) {
  if (node >= nodes_.size()) return Error{"liquid graph: node " + std::to_string(node) + " does not exist"};
  if (!(std::isfinite(volume) && volume >= 0.0 && volume <= nodes_[node].capacity)) {
    return Error{nodeName(node) + ": liquid " + std::to_string(volume) + " m^3 is outside 0..capacity"};
  }
  nodes_[node].liquid = volume;
  return Ok{};
}

void LiquidGraph::sortSpace(std::size_t node, const Eigen::Vector3d& up) {
  const std::uint32_t begin = cellStart_[node], end = cellStart_[node + 1];
  for (std::uint32_t c = begin; c < end; ++c) {
    cellHeight_[c] = up.x() * double(cellX_[c]) + up.y() * double(cellY_[c]) + up.z() * double(cellZ_[c]);
  }
  // Insertion sort from the last step's order: nearly linear while the body heels slowly; a
  // large turn (capsizing, the first step) falls back to a full sort once the moves pile up.
  std::uint32_t* order = cellOrder_.data();
  std::size_t moves = 0;
  const std::size_t budget = 8 * std::size_t(end - begin) + 64;
  for (std::uint32_t i = begin + 1; i < end && moves <= budget; ++i) {
    const std::uint32_t cell = order[i];
    const double key = cellHeight_[cell];
    std::uint32_t j = i;
    while (j > begin && cellHeight_[order[j - 1]] > key) {
      order[j] = order[j - 1];
      --j;
      ++moves;
    }
    order[j] = cell;
  }
  if (moves > budget) {
    std::sort(order + begin, order + end, [&](std::uint32_t a, std::uint32_t b) { return cellHeight_[a] < cellHeight_[b]; });
  }
}

// Volume below height z of a node's space, with each cell spread uniformly over its projected
// height `width` (|up| weighted by the cell's edges): a piecewise linear, non-decreasing function
// of z, exact for a prism standing on the cells' layers. Swept in sorted order: the cells' lower
// ends and upper ends come in the same order.
LiquidGraph::Level LiquidGraph::levelOf(std::size_t node, double liquid, double width) const {
  const std::uint32_t begin = cellStart_[node], end = cellStart_[node + 1];
  if (begin == end || !(porosity_[node] > 0.0)) return {levels_[node], 0.0};
  const std::uint32_t* order = cellOrder_.data();
  const double half = 0.5 * width;
  const double target = liquid / porosity_[node];
  std::uint32_t a = begin, b = begin;
  double filled = 0.0, slope = 0.0, lastSlope = 0.0;
  double z = cellHeight_[order[begin]] - half;
  while (b < end) {
    const double nextStart = a < end ? cellHeight_[order[a]] - half : std::numeric_limits<double>::infinity();
    const double nextEnd = cellHeight_[order[b]] + half;
    const double next = std::min(nextStart, nextEnd);
    if (slope > 0.0 && next > z) {  // zero-length steps (cells of one layer) gather the layer's slope first
      const double gained = slope * (next - z);
      if (filled + gained >= target) return {z + (target - filled) / slope, slope * porosity_[node]};
      filled += gained;
      lastSlope = slope;
    }
    z = next;
    if (nextStart <= nextEnd) {
      slope += double(cellVolume_[order[a]]) / width;
      ++a;
    } else {
      slope -= double(cellVolume_[order[b]]) / width;
      ++b;
    }
    if (a == b) slope = 0.0;  // no cell spans z: drop the rounding left by the additions
  }
  return {z, lastSlope * porosity_[node]};
}

Eigen::Vector3d LiquidGraph::centroidBelow(std::size_t node, double height, double width,
                                           const Eigen::Vector3d& up) const {
  const std::uint32_t begin = cellStart_[node], end = cellStart_[node + 1];
  const double half = 0.5 * width;
  double volume = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (std::uint32_t i = begin; i < end; ++i) {
    const std::uint32_t cell = cellOrder_[i];
    const double start = cellHeight_[cell] - half;
    if (start >= height) break;
    const double fraction = std::min(1.0, (height - start) / width);
    const double v = fraction * double(cellVolume_[cell]);
    // The filled lower part of the cell's slab has its centre (1 - fraction) half-widths below the cell's.
    const Eigen::Vector3d centre = Eigen::Vector3d(cellX_[cell], cellY_[cell], cellZ_[cell]) + up * ((fraction - 1.0) * half);
    moment += v * centre;
    volume += v;
  }
  return volume > 0.0 ? Eigen::Vector3d(moment / volume) : nodes_[node].position;
}

void LiquidGraph::refreshLevelsAndCentroids(const Eigen::Vector3d& up, double translationY, double width) {
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (cellStart_[i] == cellStart_[i + 1] || !(porosity_[i] > 0.0)) {
      levels_[i] = up.dot(nodes_[i].position) + translationY;
      centroids_[i] = nodes_[i].position;
      continue;
    }
    const Level level = levelOf(i, nodes_[i].liquid, width);
    levels_[i] = level.height + translationY;
    centroids_[i] = nodes_[i].liquid > 0.0 ? centroidBelow(i, level.height, width, up) : nodes_[i].position;
  }
}

void LiquidGraph::updateLiquidCentroids(const Pose& pose) {
  const Eigen::Vector3d up = pose.rotation.row(1).transpose();
  const double width = up.cwiseAbs().dot(cellSize_);
  for (std::size_t i = 0; i < nodes_.size(); ++i) sortSpace(i, up);
  refreshLevelsAndCentroids(up, pose.translation.y(), width);
}

FloodingNodeSums LiquidGraph::flatNodeSums(std::size_t node, const FloodingTexelLevels& levels) const {
  // Float, in eight independent lanes so that the compiler can vectorize the pass (a GPU's pass,
  // FloodingTexelPass, makes the same float sums in its own order).
  const std::uint32_t begin = texelStart_[node], end = texelStart_[node + 1];
  const float ux = levels.up.x(), uy = levels.up.y(), uz = levels.up.z();
  const float outsideLevel = levels.outsideLevel, insideLevel = levels.insideLevel[node], wetLevel = levels.wetLevel[node];
  constexpr int kLanes = 8;
  float laneQ[kLanes] = {}, lanePushed[kLanes] = {}, laneAll[kLanes] = {}, laneIn[kLanes] = {}, laneEither[kLanes] = {};
  std::uint32_t t = begin;
  for (; t + kLanes <= end; t += kLanes) {
    for (int l = 0; l < kLanes; ++l) {
      const std::uint32_t k = t + std::uint32_t(l);
      const float y = ux * texelX_[k] + uy * texelY_[k] + uz * texelZ_[k];
      const float outsideHead = std::max(outsideLevel - y, 0.0f);
      const float insideHead = std::max(insideLevel - y, 0.0f);
      const float c = texelT_[k];
      laneQ[l] += c * (outsideHead - insideHead);
      lanePushed[l] += c * outsideHead;
      laneAll[l] += c;
      laneIn[l] += y <= wetLevel ? c : 0.0f;
      laneEither[l] += (y <= wetLevel || outsideHead > 0.0f) ? c : 0.0f;
    }
  }
  FloodingNodeSums sums;
  for (int l = 0; l < kLanes; ++l) {
    sums.netHead += double(laneQ[l]);
    sums.pushedHead += double(lanePushed[l]);
    sums.all += double(laneAll[l]);
    sums.inside += double(laneIn[l]);
    sums.either += double(laneEither[l]);
  }
  for (; t < end; ++t) {
    const double y = double(ux * texelX_[t] + uy * texelY_[t] + uz * texelZ_[t]);
    const double outsideHead = std::max(double(outsideLevel) - y, 0.0);
    const double insideHead = std::max(double(insideLevel) - y, 0.0);
    const double c = double(texelT_[t]);
    sums.netHead += c * (outsideHead - insideHead);
    sums.pushedHead += c * outsideHead;
    sums.all += c;
    if (y <= double(wetLevel)) sums.inside += c;
    if (y <= double(wetLevel) || outsideHead > 0.0) sums.either += c;
  }
  return sums;
}

Expected<FloodingStepResult> LiquidGraph::step(const LiquidSurface& surface, const FloodingQuery& query,
                                               FloodingTexelPass* pass) {
  if (!query.pose.isFinite()) return Error{"flooding: pose is not finite"};
  if (!(std::isfinite(query.timeStep) && query.timeStep > 0.0)) return Error{"flooding: timeStep must be > 0"};
  if (!(std::isfinite(query.gravity) && query.gravity > 0.0)) return Error{"flooding: gravity must be > 0"};
  if (!(std::isfinite(query.viscosity) && query.viscosity > 0.0)) return Error{"flooding: viscosity must be > 0"};
  const std::size_t n = nodes_.size();
  const double dt = query.timeStep;
  // World height of a body point p is up . p + t_y, up = R^T e_y (the rotation's second row).
  const Eigen::Vector3d up = query.pose.rotation.row(1).transpose();
  const double ty = query.pose.translation.y();
  const double width = up.cwiseAbs().dot(cellSize_);
  FloodingStepResult result;
  std::fill(exchange_.begin(), exchange_.end(), 0.0);
  for (std::size_t i = 0; i < n; ++i) sortSpace(i, up);
  if (!surface.hasFreeSurface()) {  // a gas: nothing to take on
    refreshLevelsAndCentroids(up, ty, width);
    result.held = heldLiquid();
    return result;
  }
  const double rhoG = surface.density() * query.gravity;
  // Darcy (paper eq. 9; docs/references.md): Q = k A dp / (mu L) = T dp / mu, dp = rho g (head difference).
  const double conductancePerT = rhoG / query.viscosity;  // (m^3/s per m of head) per m^3 of T

  // Levels, free-surface areas and bounds of every node at this pose.
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t begin = cellStart_[i], end = cellStart_[i + 1];
    const LiquidGraphNode& node = nodes_[i];
    if (begin == end || !(node.capacity > 0.0)) {
      mode_[i] = kJunction;
      h0_[i] = bottom_[i] = top_[i] = up.dot(node.position) + ty;
      area_[i] = 0.0;
      continue;
    }
    const Level level = levelOf(i, node.liquid, width);
    bottom_[i] = cellHeight_[cellOrder_[begin]] - 0.5 * width + ty;
    top_[i] = cellHeight_[cellOrder_[end - 1]] + 0.5 * width + ty;
    h0_[i] = level.height + ty;
    // A floor on the area keeps a nearly full, heeled node's level finite (its top is a point).
    const double meanArea = node.capacity / std::max(top_[i] - bottom_[i], 1e-12);
    area_[i] = std::max(level.area, 1e-3 * meanArea);
    mode_[i] = node.liquid >= node.capacity ? kFull : (node.liquid <= 0.0 ? kEmpty : kFree);
  }

  // Through the surface, per node: Q(h) = sum_t c_t (max(H_out - y_t, 0) - max(h - y_t, 0)) at
  // h = h0, and its slopes: -dQ/dh over the texels wet inside (a free level) or wet on either
  // side (a pressurized node, whose head may pass the texels).
  const std::optional<double> flat = surface.flatHeight();
  passSums_.resize(n);
  if (flat) {
    // A texel that the level reaches within a thousandth of a cell counts as wet inside (an
    // empty node's level sits exactly on its floor's texels, up to float rounding).
    passInside_.resize(n);
    passWet_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      passInside_[i] = float(h0_[i] - ty);
      passWet_[i] = passInside_[i] + float(1e-3 * width);
    }
    FloodingTexelLevels levels;
    levels.up = up.cast<float>();
    levels.outsideLevel = float(*flat - ty);
    levels.insideLevel = passInside_;
    levels.wetLevel = passWet_;
    if (pass != nullptr) {
      if (Status s = pass->sums(levels, passSums_); !s) return Error{"flooding: " + s.error().message};
    } else {
      for (std::size_t i = 0; i < n; ++i) passSums_[i] = flatNodeSums(i, levels);
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      FloodingNodeSums& sums = passSums_[i];
      sums = FloodingNodeSums{};
      for (std::uint32_t t = texelStart_[i]; t < texelStart_[i + 1]; ++t) {
        const Eigen::Vector3d world = query.pose.apply(Eigen::Vector3d(texelX_[t], texelY_[t], texelZ_[t]));
        const double outsideHead = surface.pressure(world, query.time, query.gravity) / rhoG;
        const double insideHead = std::max(h0_[i] - world.y(), 0.0);
        const double c = double(texelT_[t]);
        sums.netHead += c * (outsideHead - insideHead);
        sums.pushedHead += c * outsideHead;
        sums.all += c;
        const bool wet = world.y() <= h0_[i] + 1e-3 * width;
        if (wet) sums.inside += c;
        if (wet || outsideHead > 0.0) sums.either += c;
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const FloodingNodeSums& sums = passSums_[i];
    result.texelsVisited += texelStart_[i + 1] - texelStart_[i];
    q0_[i] = sums.netHead * conductancePerT;
    pushedIn_[i] = sums.pushedHead * conductancePerT;
    slopeAll_[i] = sums.all * conductancePerT;
    slopeInside_[i] = sums.inside * conductancePerT;
    slopeOutside_[i] = sums.either * conductancePerT;
  }

  // Implicit level solve with an active set (each node free, full, empty or a junction):
  //   free:   A (x - h0) = dt [Q0 - S_e (x - h0) + sum_j g_ij (x_j - x)]
  //   fixed:  d          = dt [Q0 - S   (x - h0) + sum_j g_ij (x_j - x)],  d = c - l, -l or 0
  // S_e fits the exponential: a lone node with S (x - h0) moves by (Q0/S)(1 - exp(-S dt / A)),
  // the exact solution of A dh/dt = Q0 - S (h - h0), at any dt (S_e -> S/2 as dt -> 0).
  double scale = 0.0;
  for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, area_[i] + dt * slopeOutside_[i]);
  for (const LiquidGraphEdge& edge : edges_) scale = std::max(scale, dt * edge.transmissibility * conductancePerT);
  // A node held full or empty has no storage term; where a group of such nodes has nothing else
  // to anchor its heads, a faint pull towards one common height per kind keeps the system regular
  // without driving any flow between them (equal heads): low for empty nodes (they stay empty),
  // high for full ones (they stay full). Its effect elsewhere is at the level of rounding.
  const double pin = 1e-13 * std::max(scale, 1e-300);
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
  for (std::size_t i = 0; i < n; ++i) {
    lowest = std::min(lowest, bottom_[i]);
    highest = std::max(highest, top_[i]);
  }
  const double emptyReference = lowest - (highest - lowest) - 1.0;
  const double fullReference = highest + (highest - lowest) + 1.0;
  const int maxRounds = int(2 * n + 4);
  int round = 0;
  for (; round < maxRounds; ++round) {
    matrix_.setZero();
    rhs_.setZero();
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Index r = Eigen::Index(i);
      const LiquidGraphNode& node = nodes_[i];
      switch (mode_[i]) {
        case kFree: {
          const double diagonal = area_[i] + dt * fittedSlope(slopeInside_[i], area_[i], dt);
          matrix_(r, r) += diagonal;
          rhs_(r) += dt * q0_[i] + diagonal * h0_[i];
          break;
        }
        case kFull:
          matrix_(r, r) += dt * slopeOutside_[i] + pin;
          rhs_(r) += dt * q0_[i] + dt * slopeOutside_[i] * h0_[i] - (node.capacity - node.liquid) + pin * fullReference;
          break;
        case kEmpty:  // nothing inside pushes back
          matrix_(r, r) += pin;
          rhs_(r) += dt * q0_[i] + node.liquid + pin * emptyReference;
          break;
        default:  // junction
          matrix_(r, r) += dt * slopeOutside_[i] + pin;
          rhs_(r) += dt * q0_[i] + dt * slopeOutside_[i] * h0_[i] + pin * h0_[i];
          break;
      }
    }
    for (const LiquidGraphEdge& edge : edges_) {
      const double g = dt * edge.transmissibility * conductancePerT;
      const Eigen::Index a = Eigen::Index(edge.first), b = Eigen::Index(edge.second);
      matrix_(a, a) += g;
      matrix_(b, b) += g;
      matrix_(a, b) -= g;
      matrix_(b, a) -= g;
    }
    // Factorised in place over matrix_ (rebuilt above every pass): no allocation per step, and no
    // solver object kept in the graph, whose copy would read Eigen's never-set ComputationInfo
    // (UBSan flagged that load when a graph built by create() was moved).
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> solver(matrix_);
    if (solver.info() != Eigen::Success) return Error{"flooding: the level system is not positive definite"};
    head_ = solver.solve(rhs_);
    if (!head_.allFinite()) return Error{"flooding: the level solve gave a non-finite head"};
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      const double x = head_(Eigen::Index(i));
      const double capacity = nodes_[i].capacity;
      const double heightTolerance = 1e-9 * (top_[i] - bottom_[i] + 1e-9);
      if (mode_[i] == kFree) {
        const double next = nodes_[i].liquid + area_[i] * (x - h0_[i]);
        if (next > capacity * (1.0 + 1e-12)) {
          mode_[i] = kFull;
          changed = true;
        } else if (next < -1e-12 * capacity) {
          mode_[i] = kEmpty;
          changed = true;
        }
      } else if (mode_[i] == kFull && x < top_[i] - heightTolerance) {
        mode_[i] = kFree;
        changed = true;
      } else if (mode_[i] == kEmpty && x > bottom_[i] + heightTolerance) {
        mode_[i] = kFree;
        changed = true;
      }
    }
    if (!changed) break;
  }
  result.activeSetRounds = std::min(round + 1, maxRounds);

  // Apply, clamped to 0..capacity (rounding only, once the active set settled).
  double netChange = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    LiquidGraphNode& node = nodes_[i];
    double change = 0.0;
    switch (mode_[i]) {
      case kFree: change = area_[i] * (head_(Eigen::Index(i)) - h0_[i]); break;
      case kFull: change = node.capacity - node.liquid; break;
      case kEmpty: change = -node.liquid; break;
      default: break;
    }
    const double next = std::clamp(node.liquid + change, 0.0, node.capacity);
    netChange += next - node.liquid;
    node.liquid = next;
  }
  // Account what crossed the surface from each node's own Darcy term (its row's surface part), not
  // as its change less what it passed along edges: edge flows are huge conductances times head
  // differences that, between nodes held full or empty, only the faint pin decides, so at long
  // steps they are rounding magnified by dt (a dry, drained graph reported 5e5 m^3 of inflow at
  // dt = 1e6 s). The linearized term can still claim inflow where the level fell below texels
  // that it linearized around. The true flow bounds it: no node takes in more than the outside
  // pushes into it empty (pushedIn_: nothing out of the liquid), and under a flat surface at
  // height H none loses more than its head above H drives out through all its texels,
  // Q >= -slopeAll (x - H)+ (nothing from a node wholly under the liquid with its head below H).
  // Edges cancel in the sum, so the net is the held liquid's change, and inflow - outflow is made
  // to balance it exactly.
  for (std::size_t i = 0; i < n; ++i) {
    const double x = head_(Eigen::Index(i));
    switch (mode_[i]) {
      case kFree: exchange_[i] = dt * (q0_[i] - fittedSlope(slopeInside_[i], area_[i], dt) * (x - h0_[i])); break;
      case kEmpty: exchange_[i] = dt * q0_[i]; break;
      default: exchange_[i] = dt * (q0_[i] - slopeOutside_[i] * (x - h0_[i])); break;  // full, junction
    }
    exchange_[i] = std::min(exchange_[i], dt * pushedIn_[i]);
    if (flat) exchange_[i] = std::max(exchange_[i], -dt * slopeAll_[i] * std::max(x - *flat, 0.0));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (exchange_[i] > 0.0) {
      result.inflow += exchange_[i];
    } else {
      result.outflow -= exchange_[i];
    }
  }
  // The rest shrinks the side that claims too much before it grows the other.
  const double residual = netChange - (result.inflow - result.outflow);
  if (residual > 0.0) {
    result.outflow -= residual;
  } else {
    result.inflow += residual;
  }
  if (result.outflow < 0.0) {
    result.inflow -= result.outflow;
    result.outflow = 0.0;
  }
  if (result.inflow < 0.0) {
    result.outflow -= result.inflow;
    result.inflow = 0.0;
  }
  refreshLevelsAndCentroids(up, ty, width);
  result.held = heldLiquid();
  return result;
}

}  // namespace hydrotex
