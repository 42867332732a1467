// SPDX-License-Identifier: Zlib
#include "DemoRunner.hpp"

#include <BulletSoftBody/btSoftBody.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <unistd.h>

#include "ContactSheet.hpp"
#include "DebugLineCollector.hpp"
#include "ImageFiles.hpp"
#include "VideoEncoder.hpp"
#include "WetScenery.hpp"
#include "WetnessImage.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bullet/Scene.hpp"
#include "hydrotex/gpu/EglContext.hpp"
#include "hydrotex/gpu/MakeBackend.hpp"

namespace hydrotex::render {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

Eigen::Matrix4f toMatrix(const btTransform& transform) {
  btScalar m[16];
  transform.getOpenGLMatrix(m);  // column-major, as Eigen stores it
  Eigen::Matrix4f out;
  for (int i = 0; i < 16; ++i) out.data()[i] = static_cast<float>(m[i]);
  return out;
}

/// What is measured on one body as the demo runs.
struct BodyFigures {
  std::string name;
  double volume = 0.0;                  // m^3, of the mesh
  std::optional<double> sinkTime;       // s, first time the submerged fraction reached demo.sinkFraction
  double submergedFraction = 0.0;       // at the end
  double listDegrees = 0.0, trimDegrees = 0.0, tiltDegrees = 0.0;  // at the end
  double mass = 0.0;                    // kg, at the end
  bool flooding = false, wetting = false;  // effects listed
  double liquidHeld = 0.0;              // m^3 in the liquid graph (flooding), at the end
  double surfaceHeld = 0.0, absorbed = 0.0, evaporated = 0.0;  // m^3 in the liquid texture (wetting)
};

/// A body whose liquid texture is drawn: where its texels sit in the physics atlas.
struct WetBody {
  std::size_t sceneIndex = 0;
  int rendererId = 0;
  WetnessImage image;
};

void printProgress(int done, int total, double simulated, double elapsed) {
  constexpr int width = 30;
  // Redrawn in place on a terminal; in a log (CI, a pipe) one line per tenth.
  static const bool terminal = isatty(fileno(stderr)) != 0;
  if (!terminal) {
    if (total > 0 && done != total && (done * 10) / total == ((done - 1) * 10) / total) return;
    std::fprintf(stderr, "  %3d%%  t = %6.2f s  (%5.1f s taken)\n", total > 0 ? done * 100 / total : 100, simulated, elapsed);
    return;
  }
  const int filled = total > 0 ? done * width / total : width;
  std::fprintf(stderr, "\r  [%.*s%*s] %3d%%  t = %6.2f s  (%5.1f s taken)", filled, "##############################",
               width - filled, "", total > 0 ? done * 100 / total : 100, simulated, elapsed);
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

/// The controller draws a body's weight as long as the body; a demo picks its own length. Every red
/// (weight) and green (buoyancy) line is scaled about its body's centre of mass or buoyancy by one
/// factor per body, the weight arrow's, so that weight and buoyancy keep their ratio.
void scaleForceArrows(DebugLineCollector& lines, bullet::SceneWorld& world, double weightLength) {
  std::vector<DebugLine> scaled = lines.lines();
  std::vector<bool> done(scaled.size(), false);
  auto near = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return (a - b).norm() < 1e-3f; };
  for (btRigidBody* body : world.bodies()) {
    const bullet::FloatingBodyReport* report = world.controller().report(body);
    if (report == nullptr) continue;
    const btVector3 c = body->getCenterOfMassPosition();
    const Eigen::Vector3f com(float(c.x()), float(c.y()), float(c.z()));
    const Eigen::Vector3f cob = report->hydrostatics.centerOfBuoyancy.cast<float>();
    // The weight arrow's shaft is the red line that starts at this body's centre of mass.
    float shaft = 0.0f;
    for (const DebugLine& line : scaled)
      if (line.colour.x() > 0.5f && line.colour.y() < 0.5f && near(line.from, com)) shaft = std::max(shaft, (line.to - line.from).norm());
    if (shaft <= 0.0f) continue;
    const float factor = float(weightLength) / shaft;
    // Each arrow's lines (shaft and head) lie within the shaft's length of its anchor.
    for (std::size_t k = 0; k < scaled.size(); ++k) {
      DebugLine& line = scaled[k];
      const bool red = line.colour.x() > 0.5f && line.colour.y() < 0.5f, green = line.colour.y() > 0.5f && line.colour.x() < 0.5f;
      const Eigen::Vector3f anchor = red ? com : cob;
      if (done[k] || !(red || green) || !near(line.from, anchor)) continue;
      done[k] = true;
      line.from = anchor + factor * (line.from - anchor);
      line.to = anchor + factor * (line.to - anchor);
    }
  }
  lines.clear();
  for (const DebugLine& line : scaled) lines.add(line.from, line.to, line.colour);
}

}  // namespace

std::optional<std::string> missingRequirement(const DemoDescription& demo) {
  for (const std::string& name : demo.requires_) {
    const std::optional<bullet::Effect> effect = bullet::effectFromName(name);
    if (!effect) return "effect '" + name + "' is unknown to this build";
    // Ask the plugin itself whether it accepts the effect on a plain body: reserved effects are
    // refused by FloatingBodySettings::validate() until their issue lands.
    bullet::FloatingBodySettings settings;
    settings.mesh = std::make_shared<Mesh>(primitives::box(Eigen::Vector3d::Ones()));
    settings.resolution = 16;
    settings.density = 500.0;
    settings.effects = {bullet::Effect::Buoyancy, *effect};
    if (*effect == bullet::Effect::Deformation) settings.scaleKeyframes = {{0.0, Eigen::Vector3d::Ones()}};
    if (const Status valid = settings.validate(); !valid) return "effect '" + name + "' is not available yet: " + valid.error().message;
  }
  if (!demo.waitingFor.empty()) return demo.waitingFor;
  return std::nullopt;
}

PictureSize pictureSize(const DemoDescription& demo, const DemoOptions& options) {
  return PictureSize{options.width.value_or(options.smoke ? 160 : demo.width), options.height.value_or(options.smoke ? 90 : demo.height)};
}

int runDemo(const DemoDescription& demo, const DemoOptions& options) {
  std::printf("%s\n", demo.title.c_str());
  if (!demo.figure.empty()) std::printf("  reproduces %s\n", demo.figure.c_str());
  if (const std::optional<std::string> missing = missingRequirement(demo)) {
    std::printf("  WAITING: demo '%s' cannot run in this build: %s\n", demo.name.c_str(), missing->c_str());
    return kDemoWaitingExitCode;
  }
  Expected<bullet::Scene> scene = bullet::parseScene(demo.sceneText, demo.baseDirectory, "demo_" + demo.name + ".json: scene");
  if (!scene) {
    std::fprintf(stderr, "hydrotex_demo: %s\n", scene.error().message.c_str());
    return 1;
  }
  if (options.threads) scene->threads = *options.threads;
  if (options.backend) scene->backend = *options.backend;
  const auto wallStart = std::chrono::steady_clock::now();
  Expected<std::unique_ptr<bullet::SceneWorld>> world = bullet::SceneWorld::create(*scene, gpu::makeControllerBackend);
  if (!world) {
    std::fprintf(stderr, "hydrotex_demo: %s\n", world.error().message.c_str());
    return 1;
  }
  bullet::SceneWorld& sceneWorld = **world;

  Expected<std::unique_ptr<gpu::EglContext>> context = gpu::EglContext::create();
  if (!context) {
    std::fprintf(stderr, "hydrotex_demo: no headless OpenGL 4.3 context: %s\n", context.error().message.c_str());
    return 1;
  }
  if (const Status current = (*context)->makeCurrent(); !current) {
    std::fprintf(stderr, "hydrotex_demo: %s\n", current.error().message.c_str());
    return 1;
  }
  RendererSettings rendererSettings;
  const PictureSize size = pictureSize(demo, options);
  rendererSettings.width = size.width;
  rendererSettings.height = size.height;
  Expected<std::unique_ptr<GlRenderer>> renderer = GlRenderer::create(rendererSettings);
  if (!renderer) {
    std::fprintf(stderr, "hydrotex_demo: %s\n", renderer.error().message.c_str());
    return 1;
  }
  std::printf("  renderer: %s (%s), %dx%d\n", (*context)->renderer().c_str(), (*context)->platform().c_str(), rendererSettings.width,
              rendererSettings.height);
  std::printf("  physics: %s backend (%s), %d threads\n", sceneWorld.controller().backend().name().c_str(),
              sceneWorld.controller().backend().renderer().c_str(), sceneWorld.controller().threads());

  // Bodies: meshes and looks.
  std::vector<int> rendererIds;
  std::vector<BodyFigures> figures;
  std::vector<double> overlayOpacity;
  std::vector<WetBody> wetBodies;
  std::vector<double> wetnessView;
  // A body's mesh and look (albedo, overlay); false after printing what is wrong.
  auto loadBody = [&](const bullet::SceneBody& body, Mesh& mesh, BodyLook& look, std::optional<RgbImage>& albedo,
                      std::optional<RgbImage>& overlay) {
    if (body.mesh) {
      mesh = *body.mesh;
    } else {
      Expected<Mesh> loaded = loadMesh(body.meshPath);
      if (!loaded) {
        std::fprintf(stderr, "hydrotex_demo: %s\n", loaded.error().message.c_str());
        return false;
      }
      mesh = std::move(*loaded);
    }
    const auto lookIt = demo.looks.find(body.name);
    look = lookIt != demo.looks.end() ? lookIt->second : BodyLook{};
    for (auto [path, image] : {std::pair{&look.albedoPath, &albedo}, std::pair{&look.overlayPath, &overlay}}) {
      if (path->empty()) continue;
      Expected<RgbImage> loaded = loadRgbImage(*path);
      if (!loaded) {
        std::fprintf(stderr, "hydrotex_demo: body %s: %s\n", body.name.c_str(), loaded.error().message.c_str());
        return false;
      }
      *image = std::move(*loaded);
    }
    return true;
  };
  for (const bullet::SceneBody& body : scene->bodies) {
    Mesh mesh;
    BodyLook look;
    std::optional<RgbImage> albedo, overlay;
    if (!loadBody(body, mesh, look, albedo, overlay)) return 1;
    // The liquid texture lives in the wetting bake's physics atlas: the same bake the controller
    // made (same mesh, resolution, settings), so its texel order is the texture's. The atlas is
    // the artist's UVs when they are usable, else a generated one: either way the renderer gets
    // its layout as a second UV set, so no resampling between the two is needed.
    std::optional<BodyGeometry> wettingGeometry;
    if (body.effects.has(bullet::Effect::Wetting)) {
      BodyGeometrySettings geometrySettings;
      geometrySettings.bake.width = geometrySettings.bake.height = body.wetting.resolution > 0 ? body.wetting.resolution : body.resolution;
      geometrySettings.requireClosed = false;
      Expected<BodyGeometry> geometry = prepareBodyGeometry(mesh, geometrySettings);
      if (!geometry) {
        std::fprintf(stderr, "hydrotex_demo: body %s: wetting bake: %s\n", body.name.c_str(), geometry.error().message.c_str());
        return 1;
      }
      wettingGeometry = std::move(*geometry);
    }
    Expected<int> id = (*renderer)->addBody(mesh, albedo ? &*albedo : nullptr, overlay ? &*overlay : nullptr, look.palette,
                                            wettingGeometry ? &wettingGeometry->atlas.layout : nullptr);
    if (!id) {
      std::fprintf(stderr, "hydrotex_demo: %s\n", id.error().message.c_str());
      return 1;
    }
    rendererIds.push_back(*id);
    if (wettingGeometry) wetBodies.push_back(WetBody{rendererIds.size() - 1, *id, WetnessImage(wettingGeometry->bake)});
    overlayOpacity.push_back(overlay ? look.overlayOpacity : 0.0);
    wetnessView.push_back(look.wetnessViewOpacity);
    BodyFigures bodyFigures;
    bodyFigures.name = body.name;
    figures.push_back(bodyFigures);
  }

  // Soft bodies (`soft: true`): drawn from their nodes, which are the mesh's vertices one for one
  // (btSoftBodyHelpers::CreateFromTriMesh), so the mesh's triangles and UVs carry the body's look.
  struct SoftInstance {
    std::size_t sceneIndex = 0;
    int rendererId = 0;
    Mesh mesh;  // nodes copied into its positions each frame (world frame, m)
    float overlayOpacity = 0.0f;
  };
  std::vector<SoftInstance> softBodies;
  for (std::size_t i = 0; i < scene->softBodies.size(); ++i) {
    Mesh mesh;
    BodyLook look;
    std::optional<RgbImage> albedo, overlay;
    if (!loadBody(scene->softBodies[i], mesh, look, albedo, overlay)) return 1;
    Expected<int> id = (*renderer)->addBody(mesh, albedo ? &*albedo : nullptr, overlay ? &*overlay : nullptr, look.palette);
    if (!id) {
      std::fprintf(stderr, "hydrotex_demo: %s\n", id.error().message.c_str());
      return 1;
    }
    softBodies.push_back(SoftInstance{i, *id, std::move(mesh), overlay ? float(look.overlayOpacity) : 0.0f});
  }

  // The ground (a scene's seabed, or the field a balloon stands on): a wide flat box whose top is
  // the floor Bullet collides with.
  std::optional<BodyInstance> ground;
  if (scene->seabed) {
    const bool underWater = scene->surface.type != bullet::SceneSurface::Type::None;
    const RgbImage colour = underWater ? RgbImage{1, 1, {150, 135, 100}} : RgbImage{1, 1, {95, 135, 70}};
    Expected<int> id = (*renderer)->addBody(primitives::box(Eigen::Vector3d(400.0, 0.2, 400.0)), &colour, nullptr, Palette::Heat);
    if (!id) {
      std::fprintf(stderr, "hydrotex_demo: %s\n", id.error().message.c_str());
      return 1;
    }
    Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
    model(1, 3) = static_cast<float>(*scene->seabed - 0.1);
    ground = BodyInstance{*id, model, 0.0f};
  }

  // Static wet scenery: each item is parsed as a scene body (the plugin's keys and checks) and
  // wetted here through the core API (WetScenery says why).
  struct SceneryInstance {
    std::string name;
    std::unique_ptr<WetScenery> wet;
    int rendererId = 0;
    WetnessImage image;
    BodyInstance instance;
  };
  std::vector<SceneryInstance> scenery;
  for (const SceneryItem& item : demo.scenery) {
    nlohmann::json wrapped = nlohmann::json::parse(demo.sceneText);
    wrapped["bodies"] = nlohmann::json::array({nlohmann::json::parse(item.bodyText)});
    Expected<bullet::Scene> parsed = bullet::parseScene(wrapped.dump(), demo.baseDirectory, "demo_" + demo.name + ".json: scenery");
    if (!parsed) {
      std::fprintf(stderr, "hydrotex_demo: %s\n", parsed.error().message.c_str());
      return 1;
    }
    const bullet::SceneBody& body = parsed->bodies.front();
    Mesh mesh;
    BodyLook look;
    std::optional<RgbImage> albedo, overlay;
    if (!loadBody(body, mesh, look, albedo, overlay)) return 1;
    Expected<std::unique_ptr<WetScenery>> wet = WetScenery::create(body, mesh, item.initialSaturation, item.pigment);
    if (!wet) {
      std::fprintf(stderr, "hydrotex_demo: %s\n", wet.error().message.c_str());
      return 1;
    }
    Expected<int> id = (*renderer)->addBody(mesh, albedo ? &*albedo : nullptr, overlay ? &*overlay : nullptr, look.palette,
                                            &(*wet)->geometry().atlas.layout);
    if (!id) {
      std::fprintf(stderr, "hydrotex_demo: %s\n", id.error().message.c_str());
      return 1;
    }
    Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
    model.topLeftCorner<3, 3>() = (*wet)->pose().rotation.cast<float>();
    model.topRightCorner<3, 1>() = (*wet)->pose().translation.cast<float>();
    WetnessImage image((*wet)->geometry().bake);
    const BodyInstance instance{*id, model, overlay ? float(look.overlayOpacity) : 0.0f, float(look.wetnessViewOpacity)};
    scenery.push_back(SceneryInstance{body.name, std::move(*wet), *id, std::move(image), instance});
  }

  // Frames and the steps between them.
  const long long totalSteps = scene->stepCount();
  const int defaultFrames = std::max(1, static_cast<int>(std::lround(scene->duration * demo.fps)));
  const int frameCount = options.frames.value_or(options.smoke ? 4 : defaultFrames);
  const long long stepsPerFrame = std::max<long long>(1, std::llround(double(totalSteps) / defaultFrames));
  const std::filesystem::path outDir(options.outputDirectory);
  std::error_code ec;
  std::filesystem::create_directories(outDir / "frames", ec);
  for (const auto& entry : std::filesystem::directory_iterator(outDir / "frames", ec))
    if (entry.path().extension() == ".png") std::filesystem::remove(entry.path(), ec);
  const std::vector<int> sheetChoice = chooseSheetFrames(frameCount, demo.sheetFrames);
  std::vector<RgbImage> sheetFrames;

  const int followIndex = [&] {
    for (std::size_t i = 0; i < scene->bodies.size(); ++i)
      if (scene->bodies[i].name == demo.followBody) return static_cast<int>(i);
    return -1;
  }();
  const std::optional<btTransform> followStart =
      followIndex >= 0 ? sceneWorld.controller().meshTransform(sceneWorld.bodies()[std::size_t(followIndex)]) : std::nullopt;
  DebugLineCollector lines;
  double renderSeconds = 0.0;
  int framesDone = 0;

  for (int frame = 0; frame < frameCount; ++frame) {
    if (frame > 0) {
      for (long long s = 0; s < stepsPerFrame; ++s) sceneWorld.step();
      // A GL backend makes its own context current for its passes: the renderer's again.
      if (sceneWorld.controller().backend().name() != "cpu") {
        if (const Status current = (*context)->makeCurrent(); !current) {
          std::fprintf(stderr, "hydrotex_demo: %s\n", current.error().message.c_str());
          return 1;
        }
      }
      // Scenery is wetted once per frame: the wetting step is stable at any time step, and the
      // sea moves little within one frame.
      for (SceneryInstance& item : scenery)
        if (const Status stepped = item.wet->step(sceneWorld.controller().liquid().surface.get(), sceneWorld.controller().time(),
                                                  double(stepsPerFrame) * scene->dt);
            !stepped) {
          std::fprintf(stderr, "\nhydrotex_demo: scenery %s: %s\n", item.name.c_str(), stepped.error().message.c_str());
          return 1;
        }
    }
    const double time = sceneWorld.time();
    FrameInput input;
    input.camera = demo.camera;
    if (followStart) {
      const btVector3 moved = sceneWorld.controller().meshTransform(sceneWorld.bodies()[std::size_t(followIndex)])->getOrigin() - followStart->getOrigin();
      // Horizontally only unless asked: the water level stays put in the picture.
      const Eigen::Vector3d shift(moved.x(), demo.followVertical ? moved.y() : 0.0, moved.z());
      input.camera.eye += shift;
      input.camera.target += shift;
    }
    input.surface = sceneWorld.controller().liquid().surface.get();
    input.time = sceneWorld.controller().time();
    input.shadowCentre = input.camera.target;
    input.shadowRadius = std::max(6.0, 0.6 * (input.camera.eye - input.camera.target).norm());
    lines.clear();
    if (demo.drawForces) {
      sceneWorld.controller().debugDraw(&lines);
      scaleForceArrows(lines, sceneWorld, demo.forceArrowLength);
    }
    for (std::size_t i = 0; i < scene->bodies.size(); ++i) {
      btRigidBody* body = sceneWorld.bodies()[i];
      const std::optional<btTransform> meshTransform = sceneWorld.controller().meshTransform(body);
      if (!meshTransform) continue;
      Eigen::Matrix4f model = toMatrix(*meshTransform);
      if (!scene->bodies[i].scaleKeyframes.empty())
        model = model * Eigen::Affine3f(Eigen::Scaling(bullet::scaleAt(scene->bodies[i].scaleKeyframes, time).cast<float>())).matrix();
      input.bodies.push_back({rendererIds[i], model, static_cast<float>(overlayOpacity[i]), static_cast<float>(wetnessView[i])});
      if (demo.drawPointMasses)
        if (const MassModel* massModel = sceneWorld.controller().massModel(body))
          for (const PointMass& point : massModel->pointMasses()) {
            const Eigen::Vector3d local = point.path.empty() ? point.position : pathPosition(point.path, time);
            const Eigen::Vector3f at = (model * local.cast<float>().homogeneous()).head<3>();
            const float arm = 0.15f;
            const Eigen::Vector3f orange(1.0f, 0.55f, 0.0f);
            for (int axis = 0; axis < 3; ++axis)
              lines.add(at - arm * Eigen::Vector3f::Unit(axis), at + arm * Eigen::Vector3f::Unit(axis), orange);
          }
      // Figures.
      if (const bullet::FloatingBodyReport* report = sceneWorld.controller().report(body)) {
        BodyFigures& f = figures[i];
        f.volume = report->massProperties.volume;
        f.mass = report->massProperties.mass;
        f.flooding = scene->bodies[i].effects.has(bullet::Effect::Flooding);
        f.wetting = scene->bodies[i].effects.has(bullet::Effect::Wetting);
        f.liquidHeld = report->liquidVolume;
        f.surfaceHeld = report->liquidHeld;
        f.absorbed = report->liquidAbsorbed;
        f.evaporated = report->liquidEvaporated;
        f.submergedFraction = f.volume > 0.0 ? report->hydrostatics.submergedVolume / f.volume : 0.0;
        if (!f.sinkTime && f.submergedFraction >= demo.sinkFraction && input.surface->hasFreeSurface()) f.sinkTime = time;
        const btMatrix3x3& basis = meshTransform->getBasis();
        const btVector3 lengthAxis = basis.getColumn(0), upAxis = basis.getColumn(1), beamAxis = basis.getColumn(2);
        f.listDegrees = std::asin(std::clamp(double(beamAxis.y()), -1.0, 1.0)) * kDegreesPerRadian;
        f.trimDegrees = std::asin(std::clamp(double(lengthAxis.y()), -1.0, 1.0)) * kDegreesPerRadian;
        f.tiltDegrees = std::acos(std::clamp(double(upAxis.y()), -1.0, 1.0)) * kDegreesPerRadian;
      }
    }
    for (const WetBody& wet : wetBodies)
      if (const LiquidTexture* texture = sceneWorld.controller().liquidTexture(sceneWorld.bodies()[wet.sceneIndex])) {
        const std::vector<float> pixels = wet.image.pixels(*texture);
        if (pixels.empty()) continue;  // not the bake the controller made: drawn dry rather than wrong
        if (const Status set = (*renderer)->setWetness(wet.rendererId, wet.image.width(), wet.image.height(), pixels); !set) {
          std::fprintf(stderr, "\nhydrotex_demo: %s\n", set.error().message.c_str());
          return 1;
        }
      }
    for (SoftInstance& soft : softBodies) {
      const btSoftBody& body = *sceneWorld.softBodies()[soft.sceneIndex];
      const std::size_t nodes = std::min(std::size_t(body.m_nodes.size()), soft.mesh.positions.size());
      for (std::size_t k = 0; k < nodes; ++k) {
        const btVector3& x = body.m_nodes[int(k)].m_x;
        soft.mesh.positions[k] = Eigen::Vector3d(x.x(), x.y(), x.z());
      }
      if (const Status set = (*renderer)->setBodyMesh(soft.rendererId, soft.mesh); !set) {
        std::fprintf(stderr, "\nhydrotex_demo: %s\n", set.error().message.c_str());
        return 1;
      }
      input.bodies.push_back({soft.rendererId, Eigen::Matrix4f::Identity(), soft.overlayOpacity, 0.0f});
    }
    for (const SceneryInstance& item : scenery) {
      const std::vector<float> pixels = item.image.pixels(item.wet->texture());
      if (const Status set = (*renderer)->setWetness(item.rendererId, item.image.width(), item.image.height(), pixels); !set) {
        std::fprintf(stderr, "\nhydrotex_demo: %s\n", set.error().message.c_str());
        return 1;
      }
      input.bodies.push_back(item.instance);
    }
    if (ground) input.bodies.push_back(*ground);
    input.lines = lines.lines();
    const auto renderStart = std::chrono::steady_clock::now();
    Expected<RgbImage> picture = (*renderer)->render(input);
    if (!picture) {
      std::fprintf(stderr, "\nhydrotex_demo: %s\n", picture.error().message.c_str());
      return 1;
    }
    char name[64];
    std::snprintf(name, sizeof name, "frame_%04d.png", frame);
    if (const Status saved = saveRgbImage(*picture, (outDir / "frames" / name).string()); !saved) {
      std::fprintf(stderr, "\nhydrotex_demo: %s\n", saved.error().message.c_str());
      return 1;
    }
    renderSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - renderStart).count();
    framesDone = frame + 1;
    bool goOn = true;
    if (options.showFrame) {
      // The viewer draws in its own context (a window's GLX one), which cannot be made current
      // while this EGL context is (libglvnd: X error BadAccess, which ends the process); the
      // renderer's context is made current again afterwards.
      if (const Status released = (*context)->release(); !released) {
        std::fprintf(stderr, "\nhydrotex_demo: %s\n", released.error().message.c_str());
        return 1;
      }
      goOn = options.showFrame(*picture, time);
      if (const Status current = (*context)->makeCurrent(); !current) {
        std::fprintf(stderr, "\nhydrotex_demo: %s\n", current.error().message.c_str());
        return 1;
      }
    }
    if (std::find(sheetChoice.begin(), sheetChoice.end(), frame) != sheetChoice.end()) sheetFrames.push_back(std::move(*picture));
    printProgress(frame + 1, frameCount, time, std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count());
    if (!goOn) break;
  }
  if (framesDone < frameCount) {
    if (isatty(fileno(stderr)) != 0) std::fprintf(stderr, "\n");  // end the progress bar's line
    std::printf("  stopped after %d of %d frames\n", framesDone, frameCount);
    // The sheet's frames are chosen again over the frames there are, read back from disk.
    sheetFrames.clear();
    for (const int frame : chooseSheetFrames(framesDone, demo.sheetFrames)) {
      char name[64];
      std::snprintf(name, sizeof name, "frame_%04d.png", frame);
      Expected<RgbImage> written = loadRgbImage((outDir / "frames" / name).string());
      if (!written) {
        std::fprintf(stderr, "hydrotex_demo: %s\n", written.error().message.c_str());
        return 1;
      }
      sheetFrames.push_back(std::move(*written));
    }
  }

  // Contact sheet and video.
  const std::string sheetPath = (outDir / (demo.name + "_contact.png")).string();
  const RgbImage sheet = makeContactSheet(sheetFrames, demo.sheetColumns, options.smoke ? 160 : 320);
  if (const Status saved = saveRgbImage(sheet, sheetPath); !saved) {
    std::fprintf(stderr, "hydrotex_demo: %s\n", saved.error().message.c_str());
    return 1;
  }
  std::string videoPath;
  int status = 0;
  if (options.video && !options.smoke) {
    videoPath = (outDir / (demo.name + ".mp4")).string();
    if (const Status encoded = encodeVideo((outDir / "frames" / "frame_%04d.png").string(), demo.fps, videoPath); !encoded) {
      std::fprintf(stderr, "hydrotex_demo: %s\n", encoded.error().message.c_str());
      videoPath.clear();
      status = 1;
    }
  }
  const double wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();

  // The figures a viewer wants.
  std::ostringstream text;
  char line[256];
  std::snprintf(line, sizeof line, "  time simulated   %.2f s (%d frames, %lld steps of %.4f s)\n", sceneWorld.time(), framesDone,
                static_cast<long long>(std::llround(sceneWorld.time() / scene->dt)), scene->dt);
  text << line;
  std::snprintf(line, sizeof line, "  time taken       %.1f s (rendering and writing frames %.1f s)\n", wallSeconds, renderSeconds);
  text << line;
  for (const BodyFigures& f : figures) {
    std::snprintf(line, sizeof line, "  %-14s  mass %.1f kg, submerged %.1f %% of %.3f m^3, list %+.1f deg, trim %+.1f deg, tilt %.1f deg\n",
                  f.name.c_str(), f.mass, 100.0 * f.submergedFraction, f.volume, f.listDegrees, f.trimDegrees, f.tiltDegrees);
    text << line;
    if (f.sinkTime)
      std::snprintf(line, sizeof line, "  %-14s  sank (%.0f %% submerged) at t = %.2f s\n", "", 100.0 * demo.sinkFraction, *f.sinkTime);
    else
      std::snprintf(line, sizeof line, "  %-14s  did not sink\n", "");
    text << line;
    if (f.flooding) {
      std::snprintf(line, sizeof line, "  %-14s  liquid held %.3f m^3 (%.0f kg), %.1f %% of its volume\n", "", f.liquidHeld,
                    f.liquidHeld * scene->fluidDensity, f.volume > 0.0 ? 100.0 * f.liquidHeld / f.volume : 0.0);
      text << line;
    }
    if (f.wetting) {
      std::snprintf(line, sizeof line, "  %-14s  surface layer holds %.3g L (absorbed %.3g L, evaporated %.3g L)\n", "",
                    1000.0 * f.surfaceHeld, 1000.0 * f.absorbed, 1000.0 * f.evaporated);
      text << line;
    }
  }
  for (const SceneryInstance& item : scenery) {
    std::snprintf(line, sizeof line, "  %-14s  (scenery) surface layer holds %.3g L (absorbed %.3g L, evaporated %.3g L)\n", item.name.c_str(),
                  1000.0 * item.wet->held(), 1000.0 * item.wet->absorbed(), 1000.0 * item.wet->evaporated());
    text << line;
  }
  text << "  contact sheet    " << sheetPath << "\n";
  text << "  frames           " << (outDir / "frames").string() << "/frame_NNNN.png\n";
  if (!videoPath.empty()) text << "  video            " << videoPath << "\n";
  std::printf("%s", text.str().c_str());
  std::ofstream((outDir / (demo.name + "_figures.txt")).string()) << demo.title << "\n" << text.str();

  if (options.smoke) {
    // Read the sheet back from disk: the check sees what a viewer would open.
    Expected<RgbImage> written = loadRgbImage(sheetPath);
    if (!written) {
      std::fprintf(stderr, "hydrotex_demo: smoke check: %s\n", written.error().message.c_str());
      return 1;
    }
    const double spread = pixelStandardDeviation(*written);
    // A blank (single-colour) render has spread 0; sky, water and a body give tens of levels.
    if (spread < 5.0) {
      std::fprintf(stderr, "hydrotex_demo: smoke check: %s looks blank (pixel spread %.2f < 5)\n", sheetPath.c_str(), spread);
      return 1;
    }
    std::printf("  smoke check      passed (pixel spread %.1f)\n", spread);
  }
  return status;
}

}  // namespace hydrotex::render
