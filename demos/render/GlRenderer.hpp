// SPDX-License-Identifier: Zlib
#pragma once
/// @file GlRenderer.hpp
/// Draws one frame of a floating scene offscreen with OpenGL 4.3 core (in a headless EGL context:
/// hydrotex::gpu::EglContext): a sky, the liquid's surface (flat or waves) as transparent water
/// with a Fresnel tint, the bodies with their albedo textures, sun shadows (a shadow map) and
/// overlays (force lines, pseudo-colour maps over a body's surface). Returns the pixels.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "Camera.hpp"
#include "DebugLineCollector.hpp"
#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mesh/Mesh.hpp"

namespace hydrotex::render {

/// An 8-bit RGB image, row 0 at the top.
struct RgbImage {
  int width = 0;                    ///< pixels
  int height = 0;                   ///< pixels
  std::vector<std::uint8_t> pixels; ///< width * height * 3 bytes
};

/// Colour maps for the pseudo-colour views of a surface map (figures 10, 13, 18).
enum class Palette {
  Heat,     ///< black-red-yellow-white: permeability (holes glow)
  Viridis,  ///< dark blue to yellow: density
  Wetness,  ///< white to deep blue: saturation
};

/// Fixed settings of a renderer.
struct RendererSettings {
  int width = 640;                 ///< pixels
  int height = 360;                ///< pixels
  int samples = 4;                 ///< multisampling (0 or 1: none)
  int shadowMapSize = 2048;        ///< texels per side
  double waterHalfExtent = 40.0;   ///< m: the water grid spans this much around the camera target
  int waterGridCells = 160;        ///< cells per side of the water grid
};

/// How one body is drawn this frame.
struct BodyInstance {
  int body = 0;                                            ///< id from GlRenderer::addBody
  Eigen::Matrix4f model = Eigen::Matrix4f::Identity();     ///< mesh frame to world (scale included)
  float overlayOpacity = 0.0f;                             ///< 0: albedo only; 1: the pseudo-colour map only
  float wetnessViewOpacity = 0.0f;                         ///< 0: wet shading only; 1: the saturation in pseudo-colour (Palette::Wetness) only
};

/// Everything that changes per frame.
struct FrameInput {
  Camera camera;                                  ///< view
  std::vector<BodyInstance> bodies;               ///< bodies to draw
  const LiquidSurface* surface = nullptr;         ///< liquid (null or no free surface: no water drawn)
  double time = 0.0;                              ///< s, passed to the surface
  std::vector<DebugLine> lines;                   ///< overlays drawn on top of everything
  Eigen::Vector3d sunDirection{-0.4, -1.0, -0.3}; ///< towards the scene
  Eigen::Vector3d shadowCentre{0, 0, 0};          ///< m: centre of the shadowed region
  double shadowRadius = 10.0;                     ///< m: its radius
};

/// The renderer. Needs a current GL 4.3 core context for its whole life.
class GlRenderer {
 public:
  /// Compiles the shaders and makes the framebuffers. Errors: a shader that does not compile (with
  /// the driver's log), an incomplete framebuffer, a size out of range.
  static Expected<std::unique_ptr<GlRenderer>> create(const RendererSettings& settings);
  ~GlRenderer();
  GlRenderer(const GlRenderer&) = delete;
  GlRenderer& operator=(const GlRenderer&) = delete;

  /// Uploads a body's mesh (mesh frame, m) and its albedo (null: light gray); `overlay` (gray
  /// levels, null: none) is drawn through `palette`. `physicsLayout` is the UV layout its wetness
  /// (setWetness) is in, when that is not the mesh's own (a generated physics atlas). Returns the
  /// body's id.
  Expected<int> addBody(const Mesh& mesh, const RgbImage* albedo, const RgbImage* overlay, Palette palette,
                        const UvLayout* physicsLayout = nullptr);
  /// Sets a body's wetness per texel of its physics atlas, `width` x `height`, row 0 at v = 1
  /// (SurfaceBake rows), two values per texel: saturation (0..1, liquid / capacity) and pigment
  /// fraction of the liquid (0..1), as WetnessImage::pixels gives them. Drawn with the Lekner
  /// and Dorf wet appearance (gpu/shaders/wet_shading.glsl): darker and glossier where wet,
  /// tinted by the film's transmittance where the liquid is coloured (`pigmentTransmittance`:
  /// per crossing of a film of pure pigment, per channel). Errors: unknown body, a size that does not match.
  Status setWetness(int body, int width, int height, const std::vector<float>& wetness,
                    const Eigen::Vector3f& pigmentTransmittance = Eigen::Vector3f(0.75f, 0.12f, 0.2f));
  /// Replaces a body's mesh (same triangles and UVs, moved vertices: a soft body's nodes, m, in
  /// the frame its BodyInstance::model maps from). Errors: unknown body, a mesh without triangles.
  Status setBodyMesh(int body, const Mesh& mesh);
  /// Replaces a body's albedo (e.g. with its wet-shaded colour as the liquid texture changes).
  Status setAlbedo(int body, const RgbImage& albedo);

  /// Draws a frame and reads it back.
  Expected<RgbImage> render(const FrameInput& frame);

  /// The settings it was made with.
  const RendererSettings& settings() const { return settings_; }

 private:
  struct Impl;
  explicit GlRenderer(const RendererSettings& settings);
  RendererSettings settings_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydrotex::render
