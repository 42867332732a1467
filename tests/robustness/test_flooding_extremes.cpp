// SPDX-License-Identifier: Zlib
// Flooding hard cases (issue 11), on the liquid graph of a box with a hole in its floor: filling
// to full and draining to empty over thousands of steps; all the liquid entering or leaving in a
// single huge step; a zero-capacity junction and an all-white wall under huge steps. Every step:
// finite, 0 <= held <= capacity per node, and the liquid that crossed the surface equals the
// change of the liquid held. (Closed-form filling/draining curves, zero-capacity nodes at
// ordinary steps and all-black/all-white maps are in tests/core/test_liquid_graph.cpp.)

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "hydrotex/flooding/LiquidGraph.hpp"
#include "hydrotex/flooding/LiquidGraphBuilder.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"
#include "TestSurfaces.hpp"

using namespace hydrotex;
using hydrotex::test::floorHole;
using hydrotex::test::texturesOf;

namespace {

constexpr double kGravity = 9.81;
constexpr double kViscosity = 1.0e-3;

/// One compartment (the whole box) fed by the hole.
ManualLiquidGraph oneNode() {
  ManualLiquidGraph manual;
  manual.nodes.push_back({Eigen::Vector3d::Zero(), std::nullopt});
  return manual;
}

FloodingQuery queryAt(double height, double dt) {
  FloodingQuery query;
  query.pose = Pose::fromDegreesXYZ(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, height, 0));
  query.timeStep = dt;
  query.gravity = kGravity;
  query.viscosity = kViscosity;
  return query;
}

/// One step with every invariant checked, including that nothing enters a body wholly out of the
/// liquid and nothing leaves one wholly under it; returns the step's result.
FloodingStepResult checkedStep(LiquidGraph& graph, const LiquidSurface& water, const FloodingQuery& query) {
  const double before = graph.heldLiquid();
  const Expected<FloodingStepResult> step = graph.step(water, query);
  REQUIRE(step.ok());
  REQUIRE(std::isfinite(step->inflow));
  REQUIRE(std::isfinite(step->outflow));
  REQUIRE(step->inflow >= 0.0);
  REQUIRE(step->outflow >= 0.0);
  for (const LiquidGraphNode& node : graph.nodes()) {
    REQUIRE(std::isfinite(node.liquid));
    REQUIRE(node.liquid >= 0.0);
    REQUIRE(node.liquid <= node.capacity);
  }
  // Mass: what crossed the surface is the change held, to the double rounding of a few sums of
  // volumes of order 1 m^3 (the documented contract says float rounding: 1e-6 of the capacity).
  REQUIRE(step->inflow - step->outflow == Approx(graph.heldLiquid() - before).margin(1e-6 * graph.totalCapacity()));
  // Wholly out of the liquid nothing can enter; wholly under it (the top 1 m deep, every node's
  // level below the outside's) nothing can leave.
  // 1e-12 of the capacity: rounding of the per-node surface terms.
  const double height = query.pose.translation.y();
  if (height > 0.5) REQUIRE(step->inflow <= 1e-12 * graph.totalCapacity());
  if (height < -0.5) REQUIRE(step->outflow <= 1e-12 * graph.totalCapacity());
  return *step;
}

}  // namespace

TEST_CASE("flooding: filled to full under water, drained to empty above it", "[robustness][hard][flooding]") {
  const Mesh box = primitives::box(Eigen::Vector3d(1, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 64);
  auto graph = buildManualLiquidGraph(box, tex, floorHole(tex, 0.1), oneNode(), LiquidGraphBuildSettings{});
  REQUIRE(graph.ok());
  const double capacity = graph->totalCapacity();
  REQUIRE(capacity > 0.0);
  const FlatSurface water(0.0, 1000.0);
  // Wholly under water (top 1 m below the surface): it fills until every node is full.
  for (int i = 0; i < 3000; ++i) checkedStep(*graph, water, queryAt(-1.5, 0.05));
  // Full to float rounding of the node levels: the last head is what is left, 1e-6 relative.
  CHECK(graph->heldLiquid() == Approx(capacity).epsilon(1e-6));
  // Lifted wholly out (floor 1 m above the surface): it drains until every node is empty.
  for (int i = 0; i < 3000; ++i) checkedStep(*graph, water, queryAt(1.5, 0.5));
  CHECK(graph->heldLiquid() == Approx(0.0).margin(1e-6 * capacity));
}

TEST_CASE("flooding: all the liquid enters or leaves in one huge step", "[robustness][hard][flooding]") {
  const Mesh box = primitives::box(Eigen::Vector3d(1, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 64);
  auto graph = buildManualLiquidGraph(box, tex, floorHole(tex, 0.1), oneNode(), LiquidGraphBuildSettings{});
  REQUIRE(graph.ok());
  const double capacity = graph->totalCapacity();
  const FlatSurface water(0.0, 1000.0);
  // 1e6 s is many thousand filling time constants: a single compartment follows its exponential
  // at any step (LiquidGraph.hpp), so one step lands on the end state, neither overshooting
  // capacity nor going below empty.
  const FloodingStepResult in = checkedStep(*graph, water, queryAt(-1.5, 1e6));
  CHECK(in.inflow == Approx(capacity).epsilon(1e-6));
  CHECK(graph->heldLiquid() == Approx(capacity).epsilon(1e-6));
  const FloodingStepResult out = checkedStep(*graph, water, queryAt(1.5, 1e6));
  CHECK(out.outflow == Approx(capacity).epsilon(1e-6));
  CHECK(graph->heldLiquid() == Approx(0.0).margin(1e-6 * capacity));
}

// Found here and fixed in LiquidGraph::step: multi-node graphs once reported their inflow and
// outflow as each node's change less its edge flows, which between nodes held full or empty are
// rounding times huge conductances at long steps: a dry, drained all-white box reported 5e5 m^3 of
// inflow at dt = 1e6 s (capacity 1.2 m^3). Now every step here is checked for direction too.
TEST_CASE("flooding: a zero-capacity junction and an all-white wall under huge steps", "[robustness][hard][flooding]") {
  const Mesh box = primitives::box(Eigen::Vector3d(1.2, 1, 1));
  const SurfaceTextures tex = texturesOf(box, 64);
  const FlatSurface water(0.0, 1000.0);
  SECTION("zero-capacity junction between two compartments") {
    ManualLiquidGraph manual;
    manual.nodes.push_back({Eigen::Vector3d(-0.4, 0, 0), std::nullopt});
    manual.nodes.push_back({Eigen::Vector3d(0.0, 0, 0), 0.0});
    manual.nodes.push_back({Eigen::Vector3d(0.4, 0, 0), std::nullopt});
    manual.edges.push_back({0, 1, 1e-6, std::nullopt, std::nullopt});
    manual.edges.push_back({1, 2, 1e-6, std::nullopt, std::nullopt});
    auto graph = buildManualLiquidGraph(box, tex, floorHole(tex, 0.1, -0.45), manual, LiquidGraphBuildSettings{});
    REQUIRE(graph.ok());
    for (const double dt : {1e-4, 1.0, 1e3, 1e6}) {
      CAPTURE(dt);
      for (int i = 0; i < 50; ++i) checkedStep(*graph, water, queryAt(i % 2 == 0 ? -1.5 : 1.5, dt));
      CHECK(graph->nodes()[1].liquid == 0.0);  // it can hold nothing, whatever the step
    }
  }
  SECTION("all-white wall: every texel permeable") {
    auto graph = buildAutomaticLiquidGraph(box, tex, std::vector<float>(tex.size(), 1.0f), 4, LiquidGraphBuildSettings{});
    REQUIRE(graph.ok());
    for (const double dt : {1e-4, 1.0, 1e3, 1e6}) {
      CAPTURE(dt);
      for (int i = 0; i < 50; ++i) checkedStep(*graph, water, queryAt(i % 2 == 0 ? -1.5 : 1.5, dt));
    }
  }
}
