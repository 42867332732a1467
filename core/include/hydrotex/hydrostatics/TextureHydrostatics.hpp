// SPDX-License-Identifier: Zlib
#pragma once
/// @file TextureHydrostatics.hpp
/// The texture path (paper section 2.3; docs/design.md "Pressure integration", "The waterline inside a
/// texel", "Hierarchy"): hydrostatics as sums over the texels of a baked surface.
///
/// Built once per body from its bake and surface textures (refreshed in place by update() when
/// the mesh deforms);
/// queried once per step. A query neither throws nor allocates.

#include <cstdint>
#include <optional>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/hydrostatics/Hydrostatics.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// How a query walks the texels.
enum class TexelTraversal {
  /// Tiles wholly under or over the surface cost O(1). Flat surfaces: against the plane. Surfaces
  /// with jets and smoothness bounds (Gerstner waves): against a local quadratic model per tile,
  /// interpolated from a few surface samples, with a bounded error. Others (height grids, media):
  /// as BruteForce.
  Hierarchy,
  /// Every texel, every time, the surface asked at every texel that may be wet (reference and
  /// benchmark baseline).
  BruteForce,
};

/// Settings of the per-body texture hydrostatics. The hierarchy has two levels: groups of
/// groupSize x groupSize tiles of tileSize x tileSize texels. Groups keep the loop over wholly
/// wet or dry regions short; small tiles keep the texel work along the waterline short.
struct TextureHydrostaticsSettings {
  /// Texels per tile side; 0 picks 4 (bench_hydrostatics).
  int tileSize = 0;
  /// Tiles per group side; 0 picks one from the resolution so that a group spans about
  /// sqrt(width) texels (at least one tile).
  int groupSize = 0;
  /// Under waves: distance (m) between the surface samples that the local models interpolate;
  /// 0 picks it from the surface's smoothness so that the interpolation's error bound on the
  /// height is a thirtieth of surfaceModelTolerance (at most 40 samples per side).
  double surfaceSampleSpacing = 0.0;
  /// Under waves: the largest pointwise error bound (m) allowed to a local surface model. A group
  /// of tiles takes one model when its bound is within this, else each of its tiles takes its
  /// own, and a tile whose bound is still larger (steep or short waves, a coarse bake's large
  /// tiles) is summed texel by texel with the samples' interpolated heights (the surface's own
  /// where the interpolation's bound exceeds this). The bound only widens the band of tiles
  /// visited texel by texel; the sums' error is far smaller (it averages out over a tile). 0
  /// picks kDefaultSurfaceModelTolerance (3e-3 m), with which test_texture_hydrostatics_waves
  /// finds the submerged volume within 1e-5 of the body's volume of the per-texel answer (3e-5
  /// for its box).
  double surfaceModelTolerance = 0.0;
};

/// The default largest error bound (m) of a local surface model under waves
/// (TextureHydrostaticsSettings::surfaceModelTolerance = 0 picks it; the GL backend's chunks take
/// it too: GlBackendSettings::surfaceModels).
inline constexpr double kDefaultSurfaceModelTolerance = 3e-3;

/// Per-body texture hydrostatics: texel data packed for the query and per-tile moments.
class TextureHydrostatics {
 public:
  /// Packs the covered texels of `textures` (laid out by `bake`) into tiles and groups of tiles
  /// and precomputes each one's moments (sum A, sum p A^T, sum p p^T A_k, area) and body-frame bounds in double.
  /// Error when the two do not match in size or hold non-finite values.
  static Expected<TextureHydrostatics> build(const SurfaceBake& bake, const SurfaceTextures& textures,
                                             const TextureHydrostaticsSettings& settings = {});

  /// Hydrostatics of the body posed by `query` in `surface`. Errors (as values): invalid query or
  /// surface (see validateHydrostaticsQuery). For a flat surface the force is rho g V up and the
  /// torque that of this force at the centre of buoyancy (Archimedes, exact given the sums); for
  /// waves and grids, the sum of -p A over texels with p from the local surface height above each
  /// texel; for a medium without a free surface, -p A with the medium's pressure.
  Expected<HydrostaticsResult> query(const LiquidSurface& surface, const HydrostaticsQuery& query,
                                     TexelTraversal traversal = TexelTraversal::Hierarchy) const;

  /// Refreshes, in place, the packed texels and the moments and bounds of every tile, group and
  /// the body from moved `textures` of the same bake (a deforming body): no re-packing and no
  /// allocation; one pass over the texels. Error when the texel count or resolution differs from
  /// the build's, or a value is not finite; after an error every query answers that error until
  /// an update succeeds.
  Status update(const SurfaceTextures& textures);

  /// Enclosed volume of the body from its texels (m^3): (1/3) the trace of sum p A^T plus the
  /// moment corrections (SurfaceTextures::momentCorrection), the pieces' (1/3) Int x . n dA.
  double enclosedVolume() const { return enclosedVolume_; }
  /// Number of tiles.
  std::size_t tileCount() const { return tiles_.size(); }
  /// Texels per tile side in use.
  int tileSize() const { return tileSize_; }
  /// Tiles per group side in use.
  int groupSize() const { return groupSize_; }
  /// Number of covered texels.
  std::size_t texelCount() const { return texels_.size(); }
  /// Number of texels that carry a moment correction (SurfaceTextures::momentTexel).
  std::size_t correctionCount() const { return corrections_.size(); }

  /// One covered texel, packed for the query (single precision, as baked).
  struct Texel {
    float position[3];    ///< PT (m, body frame)
    float areaVector[3];  ///< VAT (m^2, body frame)
    float area;           ///< m^2
    float edgeU[3];       ///< texel u edge on the surface (m, body frame)
    float edgeV[3];       ///< texel v edge on the surface (m, body frame)
  };

  /// The moment correction of a texel of several pieces (SurfaceTextures::momentCorrection),
  /// kept beside the packed texels for the tiles the waterline crosses.
  struct MomentCorrection {
    std::uint32_t texel = 0;  ///< index into the packed texels
    float moment[3][3] = {};  ///< Sum_k c_k A_k^T - p A^T (m^3, body frame), [i][k]
    float reach = 0.0f;       ///< largest distance from p to a piece's centroid (m)
  };

  /// Moments of a set of texels in the body frame, in double, sufficient to evaluate every
  /// hydrostatic sum of wholly submerged texels at any pose in O(1). The texels' moment
  /// corrections dM are included: sumPA gets dM, sumPPA the first-order p_i dM_jk + dM_ik p_j
  /// (detail::MomentCorrectionSums), so that a tile's moments equal its texels' sums.
  struct Moments {
    double sumArea = 0.0;                  ///< sum |A| (m^2)
    double sumA[3] = {0, 0, 0};            ///< sum A_k (m^2)
    double sumPA[3][3] = {};               ///< sum p_i A_k (m^3)
    double sumPPA[6][3] = {};              ///< sum p_i p_j A_k, (i,j) in xx, xy, xz, yy, yz, zz (m^4)
    /// Adds another set.
    void add(const Moments& other);
  };

  /// A tile (or a group of tiles): a contiguous range of texels (or tiles), its moments and the
  /// body-frame bounds of its texel patches.
  struct Tile {
    std::uint32_t begin = 0, end = 0;     ///< texel range (tile) or tile range (group)
    /// Range of its texels' entries in the moment corrections (tiles only; sorted by texel)
    std::uint32_t correctionBegin = 0, correctionEnd = 0;
    Moments moments;                      ///< of its texels
    Eigen::Vector3d boundsCenter = Eigen::Vector3d::Zero();       ///< m, body frame
    Eigen::Vector3d boundsHalfExtent = Eigen::Vector3d::Zero();   ///< m, body frame
    /// m: every texel patch lies within this distance of boundsCenter (at most the box's
    /// half-diagonal; the reach of a local surface model about the centre, waves)
    double boundsRadius = 0.0;
  };

 private:
  // The Hierarchy traversal under a surface with jets (TextureHydrostaticsWaves.cpp); empty when
  // the surface offers no smoothness bound (the caller then goes texel by texel).
  std::optional<HydrostaticsResult> queryWaves(const LiquidSurface& surface, const HydrostaticsQuery& query) const;
  void refresh();  // moments and bounds of tiles, groups and body from texels_ and corrections_
  void loadCorrections(const SurfaceTextures& textures);  // corrections_' moments from `textures`
  std::vector<Texel> texels_;
  std::vector<std::uint32_t> source_;  // per packed texel: its index in the SurfaceTextures
  std::vector<MomentCorrection> corrections_;    // sorted by packed texel
  std::vector<std::uint32_t> correctionSource_;  // per correction: its entry in SurfaceTextures::momentCorrection
  int width_ = 0, height_ = 0;         // resolution of the build's textures
  bool valid_ = true;                  // false after a failed update
  std::vector<Tile> tiles_;
  std::vector<Tile> groups_;
  std::vector<Tile> blocks_;                 // 2 x 2 tiles (Morton order within a group): tile ranges
  std::vector<std::uint32_t> groupBlocks_;   // per group, its first block; one past the last at the end
  Moments total_;
  Eigen::Vector3d boundsCenter_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d boundsHalfExtent_ = Eigen::Vector3d::Zero();
  double enclosedVolume_ = 0.0;
  int tileSize_ = 0;
  int groupSize_ = 0;
  double surfaceSampleSpacing_ = 0.0;   // m; 0: from the surface's smoothness
  double surfaceModelTolerance_ = 1e-4; // m
};

}  // namespace hydrotex
