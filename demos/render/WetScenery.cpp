// SPDX-License-Identifier: Zlib
#include "WetScenery.hpp"

#include "hydrotex/bake/TexelAdjacency.hpp"

namespace hydrotex::render {

WetScenery::WetScenery(BodyGeometry geometry, Wetting solver, LiquidTexture texture, Pose pose, std::vector<LiquidSource> sources)
    : geometry_(std::move(geometry)), solver_(std::move(solver)), texture_(std::move(texture)), pose_(pose), sources_(std::move(sources)) {}

Expected<std::unique_ptr<WetScenery>> WetScenery::create(const bullet::SceneBody& body, const Mesh& mesh, double initialSaturation,
                                                         bool pigment) {
  if (!(initialSaturation >= 0.0 && initialSaturation <= 1.0))
    return Error{"scenery " + body.name + ": initial_saturation " + std::to_string(initialSaturation) + " is outside 0..1"};
  if (Status valid = body.wetting.validate(); !valid) return Error{"scenery " + body.name + ": wetting." + valid.error().message};
  // The same preparation the plugin gives a wetting body (BuoyancyController::addBody).
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = body.wetting.resolution > 0 ? body.wetting.resolution : body.resolution;
  settings.requireClosed = false;
  Expected<BodyGeometry> geometry = prepareBodyGeometry(mesh, settings);
  if (!geometry) return Error{"scenery " + body.name + ": " + geometry.error().message};
  Expected<TexelAdjacency> graph = buildTexelAdjacency(geometry->bake, geometry->mesh, geometry->atlas.layout);
  if (!graph) return Error{"scenery " + body.name + ": " + graph.error().message};
  Expected<Wetting> solver = Wetting::create(std::move(graph).value(), geometry->textures, body.wetting.physics);
  if (!solver) return Error{"scenery " + body.name + ": wetting: " + solver.error().message};
  Expected<LiquidTexture> texture = makeLiquidTexture(geometry->textures.size(), body.wetting.material, {}, {}, pigment);
  if (!texture) return Error{"scenery " + body.name + ": wetting: " + texture.error().message};
  double held = 0.0;
  for (std::size_t i = 0; i < texture->size(); ++i) {
    texture->liquid[i] = static_cast<float>(initialSaturation) * texture->capacity[i];
    held += double(texture->liquid[i]) * solver->adjacency().area[i];
  }
  std::unique_ptr<WetScenery> scenery(new WetScenery(std::move(geometry).value(), std::move(solver).value(), std::move(texture).value(),
                                                     Pose::fromDegreesXYZ(body.rotationDegrees, body.position), body.wetting.sources));
  scenery->held_ = held;
  return scenery;
}

Status WetScenery::step(const LiquidSurface* liquid, double time, double dt) {
  WettingEnvironment environment;
  environment.liquid = liquid;
  environment.pose = pose_;
  environment.time = time;
  environment.sources = sources_;
  Expected<WettingStepReport> report = solver_.step(texture_, environment, dt);
  if (!report) return report.error();
  absorbed_ += report->absorbed;
  evaporated_ += report->evaporated;
  held_ += report->absorbed - report->evaporated;  // the step's balance is exact
  return Ok{};
}

}  // namespace hydrotex::render
