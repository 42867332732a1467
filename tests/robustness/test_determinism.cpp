// SPDX-License-Identifier: Zlib
// Determinism: the same scene run twice gives bit-identical results on the CPU backend, through
// the API (every body's state compared bit for bit after every step) and through
// `hydrotex simulate` (the CSV files compared byte for byte). A difference would come from
// uninitialised memory, iteration over pointer-keyed containers, or a thread race in a reduction.

#include <btBulletDynamicsCommon.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <vector>

#include "TestPaths.hpp"
#include "ToolRun.hpp"
#include "hydrotex/bullet/Scene.hpp"

using namespace hydrotex;
using hydrotex::test::outputPath;
using hydrotex::test::readFile;
using hydrotex::test::sourcePath;

namespace {

/// Every body's position, orientation and velocities after each step, as raw floats.
std::vector<btScalar> trajectory(const bullet::Scene& scene, long long steps) {
  auto created = bullet::SceneWorld::create(scene);
  INFO((created ? std::string() : created.error().message));
  REQUIRE(created.ok());
  bullet::SceneWorld& world = **created;
  std::vector<btScalar> states;
  for (long long i = 0; i < steps; ++i) {
    world.step();
    for (const btRigidBody* body : world.bodies()) {
      const btTransform& t = body->getCenterOfMassTransform();
      const btQuaternion q = t.getRotation();
      const btVector3 v = body->getLinearVelocity(), w = body->getAngularVelocity();
      for (btScalar value : {t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z(), q.x(), q.y(), q.z(), q.w(), v.x(),
                             v.y(), v.z(), w.x(), w.y(), w.z()})
        states.push_back(value);
    }
  }
  return states;
}

}  // namespace

TEST_CASE("the same scene twice gives bit-identical trajectories", "[robustness][determinism]") {
  const std::string file = GENERATE(as<std::string>{}, "log_waves.json", "log_cargo.json", "box_floating.json");
  CAPTURE(file);
  const Expected<bullet::Scene> scene = bullet::loadScene(sourcePath("data/scenes/" + file));
  INFO((scene ? std::string() : scene.error().message));
  REQUIRE(scene.ok());
  const long long steps = std::min<long long>(scene->stepCount(), 600);
  const std::vector<btScalar> first = trajectory(*scene, steps);
  const std::vector<btScalar> second = trajectory(*scene, steps);
  REQUIRE(first.size() == second.size());
  REQUIRE(!first.empty());
  // Bitwise, not ==: a NaN must compare equal to itself, and -0 must not pass for +0.
  CHECK(std::memcmp(first.data(), second.data(), first.size() * sizeof(btScalar)) == 0);
}

#ifdef HYDROTEX_TOOL_PATH
TEST_CASE("hydrotex simulate writes byte-identical CSV twice", "[robustness][determinism][tool]") {
  using hydrotex::test::runTool;
  for (const std::string file : {"log_waves.json", "log_cargo.json"}) {
    CAPTURE(file);
    const std::string scene = sourcePath("data/scenes/" + file);
    std::string csv[2];
    for (int run = 0; run < 2; ++run) {
      const std::string path = outputPath("robust_determinism_" + std::to_string(run) + "_" + file + ".csv");
      const test::ToolRun result = runTool("simulate " + scene + " --csv " + path, 300);
      INFO(result.err);
      REQUIRE(result.exitCode == 0);
      csv[run] = readFile(path);
    }
    REQUIRE(csv[0].size() > 1000);  // a real trajectory, not an empty file
    CHECK(csv[0] == csv[1]);
  }
}
#endif
