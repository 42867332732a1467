// SPDX-License-Identifier: Zlib
// libFuzzer target: scene parsing (hydrotex::bullet::parseScene on arbitrary text), then, for
// small valid scenes, building the Bullet world and stepping it a few times. Mesh paths resolve
// against data/scenes relative to the working directory (the fuzz scripts run from the repository
// root), so the corpus' "../meshes/box.obj" works and no clone's own path reaches the target: two
// clones then fuzz the same inputs. Anything may fail with an Error; nothing may crash, leak, hang
// or trip a sanitizer.

#include <cstddef>
#include <cstdint>
#include <string>

#include "hydrotex/bullet/Scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string base = "data/scenes";
  hydrotex::Expected<hydrotex::bullet::Scene> scene = hydrotex::bullet::parseScene(text, base, "fuzz.json");
  if (!scene) return 0;
  (void)scene->validate();
  (void)scene->stepCount();
  const auto surface = hydrotex::bullet::makeSceneSurface(*scene);
  (void)surface->surfaceHeight(0.5, -0.5, 0.25);
  // Building a world bakes every body: keep that to small bakes and few bodies, so that each input
  // costs milliseconds.
  if (scene->bodies.size() > 3) return 0;
  for (const hydrotex::bullet::SceneBody& body : scene->bodies)
    if (body.resolution > 32 || body.pointMasses.size() > 8 || body.scaleKeyframes.size() > 8) return 0;
  // One thread: the controller's worker threads would make the coverage libFuzzer sees depend on
  // scheduling (two clones of one commit gave different fuzz_scene counts with threads = 0); the
  // results of every thread count are the same bits (test_determinism), so one loses nothing.
  scene->threads = 1;
  auto world = hydrotex::bullet::SceneWorld::create(*scene);
  if (!world) return 0;
  for (int i = 0; i < 3; ++i) (*world)->step();
  return 0;
}
