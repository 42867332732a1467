// SPDX-License-Identifier: Zlib
// bench_controller: 100 floating boxes at 256^2 with buoyancy and drag in flat water, in a Bullet
// world stepped at 60 Hz; the split between Bullet's own work and the BuoyancyController, on 1
// thread and on 2 (ControllerSettings::threads), and the whole step's speed-up. Prints a table
// and writes CSV (argv[1], default bench_controller.csv). Medians of several runs.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "hydrotex/Primitives.hpp"
#include "hydrotex/bullet/Scene.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using Clock = std::chrono::steady_clock;

namespace {

/// Wraps the controller to time its updateAction separately from the rest of the step.
class TimedAction : public btActionInterface {
 public:
  explicit TimedAction(btActionInterface& inner) : inner_(inner) {}
  void updateAction(btCollisionWorld* world, btScalar dt) override {
    const auto start = Clock::now();
    inner_.updateAction(world, dt);
    seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }
  void debugDraw(btIDebugDraw* drawer) override { inner_.debugDraw(drawer); }
  double seconds = 0.0;

 private:
  btActionInterface& inner_;
};

struct Run {
  double totalMs, controllerMs;
};

Run runOnce(EffectSet effects, int resolution, int bodies, int steps, int threads) {
  Scene scene;
  scene.sourceName = "bench";
  scene.dt = 1.0 / 60.0;
  scene.threads = threads;
  auto box = std::make_shared<const Mesh>(primitives::box({1.0, 0.6, 0.8}));
  for (int i = 0; i < bodies; ++i) {
    SceneBody body;
    body.name = "box" + std::to_string(i);
    body.mesh = box;
    body.density = 400.0 + 4.0 * i;
    body.position = Eigen::Vector3d(2.0 * (i % 10), 0.5 + 0.05 * (i % 7), 2.0 * (i / 10));
    body.rotationDegrees = Eigen::Vector3d(3.0 * (i % 5), 10.0 * i, 0.0);
    body.resolution = resolution;
    body.effects = effects;
    scene.bodies.push_back(body);
  }
  auto created = SceneWorld::create(scene);
  if (!created) {
    std::fprintf(stderr, "bench_controller: %s\n", created.error().message.c_str());
    std::exit(1);
  }
  SceneWorld& world = **created;
  // Time the controller from inside the world: swap the action for a timed wrapper.
  TimedAction timed(world.controller());
  world.world().removeAction(&world.controller());
  world.world().addAction(&timed);
  for (int i = 0; i < 30; ++i) world.step();  // warm-up: bodies enter the water
  timed.seconds = 0.0;
  const auto start = Clock::now();
  for (int i = 0; i < steps; ++i) world.step();
  const double total = std::chrono::duration<double>(Clock::now() - start).count();
  world.world().removeAction(&timed);
  world.world().addAction(&world.controller());
  return {1000.0 * total / steps, 1000.0 * timed.seconds / steps};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::string csvPath = argc > 1 ? argv[1] : "bench_controller.csv";
  struct Case {
    const char* name;
    EffectSet effects;
  };
  const Case cases[] = {
      {"none", EffectSet{}},
      {"buoyancy", EffectSet{Effect::Buoyancy}},
      {"buoyancy+drag", EffectSet{Effect::Buoyancy, Effect::Drag}},
      {"buoyancy+drag+added_mass", EffectSet{Effect::Buoyancy, Effect::Drag, Effect::AddedMass}},
  };
  const int bodies = 100, resolution = 256, steps = 120, runs = 5;
  std::ofstream csv(csvPath);
  csv << "effects,bodies,resolution,threads,runs,total_ms_per_step,bullet_ms_per_step,controller_ms_per_step\n";
  std::printf("%-26s %7s %5s %7s %12s %12s %15s\n", "effects", "bodies", "res", "threads", "total ms", "bullet ms",
              "controller ms");
  double speedUp = 0.0, controllerSpeedUp = 0.0;
  const int threadCounts[2] = {1, 2};
  for (const Case& c : cases) {
    // The runs alternate between the counts, so that a neighbour's load on a shared machine falls
    // on both alike.
    std::vector<double> totals[2], controllers[2], bullets[2];
    for (int r = 0; r < runs; ++r) {
      for (int k = 0; k < 2; ++k) {
        const Run run = runOnce(c.effects, resolution, bodies, steps, threadCounts[k]);
        totals[k].push_back(run.totalMs);
        controllers[k].push_back(run.controllerMs);
        bullets[k].push_back(run.totalMs - run.controllerMs);
      }
    }
    double serialTotal = 0.0, serialController = 0.0;
    for (int k = 0; k < 2; ++k) {
      const int threads = threadCounts[k];
      const std::vector<double>& total = totals[k];
      const std::vector<double>& controller = controllers[k];
      const std::vector<double>& bullet = bullets[k];
      std::printf("%-26s %7d %5d %7d %12.3f %12.3f %15.3f\n", c.name, bodies, resolution, threads, median(total),
                  median(bullet), median(controller));
      csv << c.name << ',' << bodies << ',' << resolution << ',' << threads << ',' << runs << ',' << median(total) << ','
          << median(bullet) << ',' << median(controller) << '\n';
      if (threads == 1) {
        serialTotal = median(total);
        serialController = median(controller);
      } else if (std::string(c.name) == "buoyancy+drag") {
        speedUp = serialTotal / median(total);
        controllerSpeedUp = serialController / median(controller);
      }
    }
  }
  std::printf("buoyancy+drag, 2 threads against 1: whole step %.2fx, controller %.2fx (goal 1.8x)\n", speedUp,
              controllerSpeedUp);
  std::printf("target: buoyancy+drag under 8 ms per step (60 Hz, 100 bodies, 256^2)\n");
  return 0;
}
