// SPDX-License-Identifier: Zlib
// Liquid graph (paper section 3): Darcy filling and draining of a compartment against closed
// forms, the free surface moving with heel, conservation and bounds over 10,000 steps, zero
// capacity nodes, all-black and all-white permeability maps, and the builders' checks.
#include <catch2/catch.hpp>

#include <cmath>

#include "hydrotex/flooding/LiquidGraph.hpp"
#include "hydrotex/flooding/LiquidGraphBuilder.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "TestSurfaces.hpp"

using namespace hydrotex;
using hydrotex::test::floorHole;
using hydrotex::test::texturesOf;
namespace prim = hydrotex::primitives;

namespace {

constexpr double kGravity = 9.81;
constexpr double kViscosity = 1.0e-3;

double holeArea(const SurfaceTextures& tex, const std::vector<float>& values) {
  double area = 0.0;
  for (std::size_t t = 0; t < tex.size(); ++t) area += double(values[t]) * double(tex.area[t]);
  return area;
}

FloodingQuery queryAt(const Pose& pose, double dt) {
  FloodingQuery query;
  query.pose = pose;
  query.timeStep = dt;
  query.gravity = kGravity;
  query.viscosity = kViscosity;
  return query;
}

ManualLiquidGraph oneNode() {
  ManualLiquidGraph manual;
  manual.nodes.push_back({Eigen::Vector3d::Zero(), std::nullopt});
  return manual;
}

}  // namespace

TEST_CASE("liquid graph: a compartment under a constant head fills as 1 - exp(-t/tau) at any step") {
  // Unit box, bottom at y = -1, top at the outside level y = 0: the hole in the floor sees the
  // head P0 = rho g H (H = 1 m) less the inside level's pressure rho g h, so with V = A_floor h,
  // S = h / H obeys dS/dt = (1 - S) / tau, tau = mu L V_cap / (k A P0) (docs/references.md).
  const Mesh box = prim::box(Eigen::Vector3d(1, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 64);
  const std::vector<float> hole = floorHole(tex, 0.1);
  LiquidGraphBuildSettings settings;
  settings.permeability = 1.0e-9;
  settings.wallThickness = 0.01;
  const FlatSurface water(0.0, 1000.0);
  const Pose pose = Pose::fromDegreesXYZ(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, -0.5, 0));
  const double area = holeArea(tex, hole);
  REQUIRE(area > 0.01);
  const double tau = kViscosity * settings.wallThickness * 1.0 / (settings.permeability * area * 1000.0 * kGravity * 1.0);
  for (double stepsPerTau : {100.0, 10.0, 2.0}) {
    auto graph = buildManualLiquidGraph(box, tex, hole, oneNode(), settings);
    REQUIRE(graph.ok());
    // The cells fill the box exactly (grid aligned with its bounds), so V_cap is the exact volume.
    REQUIRE(graph->nodes()[0].capacity == Approx(1.0).epsilon(1e-6));
    const double dt = tau / stepsPerTau;
    double worst = 0.0;
    for (int i = 1; i <= int(3 * stepsPerTau); ++i) {
      REQUIRE(graph->step(water, queryAt(pose, dt)).ok());
      const double expected = 1.0 - std::exp(-i * dt / tau);
      worst = std::max(worst, std::abs(graph->heldLiquid() / graph->nodes()[0].capacity - expected));
    }
    INFO("steps per tau " << stepsPerTau);
    // The update is the exact solution of the linear level equation (exponential fitting), so only
    // float rounding remains: texel transmissibilities and heights are floats (1e-6 relative).
    CHECK(worst < 2e-5);
  }
}

TEST_CASE("liquid graph: a full compartment lifted out of the water drains as exp(-t/tau)") {
  // Out of the water the hole sees no outside pressure: A dh/dt = -c (h - y_floor), the same tau.
  const Mesh box = prim::box(Eigen::Vector3d(1, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 64);
  const std::vector<float> hole = floorHole(tex, 0.1);
  LiquidGraphBuildSettings settings;
  auto graph = buildManualLiquidGraph(box, tex, hole, oneNode(), settings);
  REQUIRE(graph.ok());
  REQUIRE(graph->setLiquid(0, graph->nodes()[0].capacity).ok());
  const FlatSurface water(-10.0, 1000.0);
  const double tau = kViscosity * settings.wallThickness / (settings.permeability * holeArea(tex, hole) * 1000.0 * kGravity);
  const double dt = tau / 10.0;
  double worst = 0.0, drained = 0.0;
  for (int i = 1; i <= 30; ++i) {
    auto step = graph->step(water, queryAt(Pose::fromDegreesXYZ(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 2, 0)), dt));
    REQUIRE(step.ok());
    CHECK(step->inflow == 0.0);
    drained += step->outflow;
    worst = std::max(worst, std::abs(graph->heldLiquid() / graph->nodes()[0].capacity - std::exp(-i * dt / tau)));
  }
  CHECK(worst < 2e-5);  // float rounding, as above
  CHECK(drained == Approx(graph->nodes()[0].capacity - graph->heldLiquid()).epsilon(1e-12));
}

TEST_CASE("liquid graph: the held liquid's centroid moves to the low side when the body heels") {
  // Half-full rectangular tank (breadth B = 1, depth h = 0.5) heeled by theta: the liquid's
  // centroid moves B^2 tan(theta) / (12 h) towards the low side and rises B^2 tan^2(theta) / (24 h)
  // (free-surface effect, the wedge moved across the tank), while the surface stays inside the walls.
  const Mesh box = prim::box(Eigen::Vector3d(1, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 32);
  auto graph = buildManualLiquidGraph(box, tex, {}, oneNode(), LiquidGraphBuildSettings{});
  REQUIRE(graph.ok());
  REQUIRE(graph->setLiquid(0, 0.5).ok());
  graph->updateLiquidCentroids(Pose{});
  const Eigen::Vector3d upright = graph->liquidCentroids()[0];
  CHECK(upright.y() == Approx(-0.25).margin(1e-6));
  const double theta = 10.0 * 3.14159265358979323846 / 180.0;
  graph->updateLiquidCentroids(Pose::fromDegreesXYZ(Eigen::Vector3d(0, 0, 10), Eigen::Vector3d::Zero()));
  const Eigen::Vector3d heeled = graph->liquidCentroids()[0];
  // Rz(+10 deg) lifts the body's +x side: the liquid gathers at -x.
  const double shift = std::tan(theta) / (12.0 * 0.5);
  const double rise = std::tan(theta) * std::tan(theta) / (24.0 * 0.5);
  // Each cell's volume is spread evenly over its projected height, where a tilted cube's is
  // trapezoidal: the error is a fraction of a cell (s = 0.04 m) times sin(theta): 5e-3 s covers it.
  CHECK(heeled.x() == Approx(-shift).margin(2e-4));
  CHECK(heeled.y() == Approx(-0.25 + rise).margin(2e-4));
  CHECK(std::abs(heeled.z()) < 1e-6);
}

TEST_CASE("liquid graph: conservation and bounds over 10,000 steps of a rocking, heaving body") {
  // Automatic graph of 8 nodes; holes on one side of the floor; the body rolls and heaves through
  // the surface, so liquid enters, spreads, and drains again. Every step: what crossed the surface
  // equals the change of the held liquid, and every node stays within 0..capacity.
  const Mesh box = prim::subdividedBox(Eigen::Vector3d(2, 1, 1), 4);
  const SurfaceTextures tex = texturesOf(box, 64);
  std::vector<float> pmt(tex.size(), 0.0f);
  for (std::size_t t = 0; t < tex.size(); ++t) {
    if (tex.position[t].x() > 0.5f && tex.position[t].y() < -0.3f) pmt[t] = 1.0f;
  }
  LiquidGraphBuildSettings settings;
  settings.permeability = 1.0e-8;
  settings.porosity = 0.85;  // machinery spaces (docs/references.md)
  auto graph = buildAutomaticLiquidGraph(box, tex, pmt, 8, settings);
  REQUIRE(graph.ok());
  REQUIRE(graph->nodes().size() >= 2);
  REQUIRE_FALSE(graph->edges().empty());
  double totalVolume = 0.0;
  for (const LiquidGraphNode& node : graph->nodes()) totalVolume += node.capacity;
  // Capacities: porosity times the exact enclosed volume, up to the float cell volumes.
  CHECK(totalVolume == Approx(0.85 * 2.0).epsilon(1e-5));
  std::vector<bool> fed(graph->nodes().size(), false);
  for (const PermeableTexel& texel : graph->permeableTexels()) fed[texel.node] = true;

  const FlatSurface water(0.0, 1025.0);
  double crossed = 0.0, worstStep = 0.0, worstUnfed = 0.0, maxHeld = 0.0;
  const double held0 = graph->heldLiquid();
  bool withinBounds = true;
  for (int i = 0; i < 10000; ++i) {
    const double t = i * 0.01;
    const Pose pose = Pose::fromDegreesXYZ(Eigen::Vector3d(10.0 * std::sin(0.7 * t), 0.0, 25.0 * std::sin(0.3 * t)),
                                           Eigen::Vector3d(0.0, 0.6 * std::sin(0.05 * t), 0.0));
    const double before = graph->heldLiquid();
    auto step = graph->step(water, queryAt(pose, 0.01));
    REQUIRE(step.ok());
    const double change = graph->heldLiquid() - before;
    worstStep = std::max(worstStep, std::abs(step->inflow - step->outflow - change));
    crossed += step->inflow - step->outflow;
    maxHeld = std::max(maxHeld, graph->heldLiquid());
    for (std::size_t n = 0; n < graph->nodes().size(); ++n) {
      const LiquidGraphNode& node = graph->nodes()[n];
      withinBounds = withinBounds && node.liquid >= 0.0 && node.liquid <= node.capacity;
      if (!fed[n]) worstUnfed = std::max(worstUnfed, std::abs(graph->lastExchange()[n]));
    }
  }
  CHECK(withinBounds);
  CHECK(maxHeld > 0.05);  // liquid did enter (the test is not vacuous)
  // Rounding of sums of a few terms of size <= the capacity (1e-16 relative), and the solve's
  // residual: 1e-10 of the capacity per step is far above both and far below any real leak.
  CHECK(worstStep < 1e-10 * totalVolume);
  CHECK(std::abs(crossed - (graph->heldLiquid() - held0)) < 1e-8 * totalVolume);
  // A node without permeable texels exchanges nothing with the outside (its balance holds).
  CHECK(worstUnfed < 1e-8 * totalVolume);
}

TEST_CASE("liquid graph: a zero-capacity node passes liquid on and never holds any") {
  const Mesh box = prim::box(Eigen::Vector3d(1.2, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 64);
  const std::vector<float> hole = floorHole(tex, 0.1, -0.45);
  ManualLiquidGraph manual;
  manual.nodes.push_back({Eigen::Vector3d(-0.4, 0, 0), std::nullopt});
  manual.nodes.push_back({Eigen::Vector3d(0.0, 0, 0), 0.0});
  manual.nodes.push_back({Eigen::Vector3d(0.4, 0, 0), std::nullopt});
  manual.edges.push_back({0, 1, 1e-6, std::nullopt, std::nullopt});
  manual.edges.push_back({1, 2, 1e-6, std::nullopt, std::nullopt});
  auto graph = buildManualLiquidGraph(box, tex, hole, manual, LiquidGraphBuildSettings{});
  REQUIRE(graph.ok());
  const FlatSurface water(0.0, 1000.0);
  const Pose pose = Pose::fromDegreesXYZ(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, -0.2, 0));
  bool junctionEmpty = true;
  for (int i = 0; i < 2000; ++i) {
    REQUIRE(graph->step(water, queryAt(pose, 0.05)).ok());
    junctionEmpty = junctionEmpty && graph->nodes()[1].liquid == 0.0;
  }
  CHECK(junctionEmpty);
  CHECK(graph->nodes()[2].liquid > 0.01);  // reached through the junction only
}

TEST_CASE("liquid graph: all-black map takes on nothing, all-white fills to the outside level") {
  const Mesh box = prim::box(Eigen::Vector3d(1, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 32);
  const FlatSurface water(-0.25, 1000.0);
  const Pose pose = Pose::fromDegreesXYZ(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, -0.5, 0));
  LiquidGraphBuildSettings settings;
  settings.permeability = 1e-7;
  auto black = buildAutomaticLiquidGraph(box, tex, std::vector<float>(tex.size(), 0.0f), 4, settings);
  REQUIRE(black.ok());
  CHECK(black->permeableTexels().empty());
  auto white = buildAutomaticLiquidGraph(box, tex, std::vector<float>(tex.size(), 1.0f), 4, settings);
  REQUIRE(white.ok());
  for (int i = 0; i < 400; ++i) {
    REQUIRE(black->step(water, queryAt(pose, 0.5)).ok());
    REQUIRE(white->step(water, queryAt(pose, 0.5)).ok());
  }
  CHECK(black->heldLiquid() == 0.0);
  // Equilibrium: the inside level meets the outside one, 0.75 m above the floor of a 1 m^2 box;
  // the nodes' cell layers are 0.04 m, and levels between nodes settle within 1e-3 m.
  CHECK(white->heldLiquid() == Approx(0.75).margin(2e-3));
}

TEST_CASE("liquid graph: unusable descriptions, maps and queries are refused with a reason") {
  LiquidGraphDescription description;
  CHECK_FALSE(LiquidGraph::create(description).ok());
  description.nodes.push_back({Eigen::Vector3d::Zero(), 1.0, 0.0});
  description.spaces.push_back({{Eigen::Vector3f::Zero()}, {0.5f}});
  auto overfull = LiquidGraph::create(description);
  REQUIRE_FALSE(overfull.ok());
  CHECK(overfull.error().message.find("capacity") != std::string::npos);
  description.nodes[0].capacity = 0.5;
  description.edges.push_back({0, 0, 1.0});
  CHECK_FALSE(LiquidGraph::create(description).ok());
  description.edges.clear();
  description.nodes[0].liquid = std::nan("");
  CHECK_FALSE(LiquidGraph::create(description).ok());
  description.nodes[0].liquid = 0.0;
  auto graph = LiquidGraph::create(description);
  REQUIRE(graph.ok());
  const FlatSurface water;
  FloodingQuery query;
  query.timeStep = 0.0;
  CHECK_FALSE(graph->step(water, query).ok());
  query.timeStep = 0.01;
  query.pose.translation.x() = std::nan("");
  CHECK_FALSE(graph->step(water, query).ok());
  CHECK_FALSE(graph->setLiquid(0, 0.6).ok());
  CHECK_FALSE(graph->setLiquid(3, 0.1).ok());

  const Mesh box = prim::box(Eigen::Vector3d(1, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 32);
  auto wrongSize = buildAutomaticLiquidGraph(box, tex, std::vector<float>(3, 1.0f), 4, {});
  REQUIRE_FALSE(wrongSize.ok());
  CHECK(wrongSize.error().message.find("permeability map") != std::string::npos);
  CHECK_FALSE(buildAutomaticLiquidGraph(box, tex, std::vector<float>(tex.size(), 2.0f), 4, {}).ok());
  CHECK_FALSE(buildAutomaticLiquidGraph(box, tex, {}, -1, {}).ok());
  LiquidGraphBuildSettings badWall;
  badWall.wallThickness = 0.0;
  CHECK_FALSE(buildAutomaticLiquidGraph(box, tex, {}, 4, badWall).ok());
  ManualLiquidGraph tooBig = oneNode();
  tooBig.nodes[0].capacity = 2.0;
  auto big = buildManualLiquidGraph(box, tex, {}, tooBig, {});
  REQUIRE_FALSE(big.ok());
  CHECK(big.error().message.find("nodes[0]") != std::string::npos);
}
