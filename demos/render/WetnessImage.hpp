// SPDX-License-Identifier: Zlib
#pragma once
/// @file WetnessImage.hpp
/// A body's liquid texture (per covered texel of its wetting bake, BuoyancyController::
/// liquidTexture) spread into a full image of its physics atlas, ready to upload as a texture the
/// renderer samples at RenderVertex::physicsUv. Covered texels' values are grown a few texels into
/// the uncovered gutter so that linear filtering at chart borders does not blend in dry texels.

#include <cstdint>
#include <vector>

#include "hydrotex/wetting/LiquidTexture.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex::render {

/// Where every pixel of the atlas image takes its value from.
class WetnessImage {
 public:
  /// From the wetting bake (the texel order of the liquid texture). Uncovered pixels within
  /// `gutter` texels (8-neighbourhood steps) of a covered one copy the nearest covered texel.
  explicit WetnessImage(const SurfaceBake& bake, int gutter = 2);

  /// Two values per pixel, row 0 at v = 1 (the bake's rows): the saturation (0..1, liquid /
  /// capacity) and the pigment's volume fraction in the held liquid (0..1; 0 for a clear liquid);
  /// zeros outside the charts. Empty when the texture's size is not the bake's covered count.
  std::vector<float> pixels(const LiquidTexture& texture) const;

  /// Pixels along u.
  int width() const { return width_; }
  /// Pixels along v.
  int height() const { return height_; }

 private:
  int width_ = 0, height_ = 0;
  std::size_t covered_ = 0;
  std::vector<std::int32_t> source_;  // per pixel: covered texel it copies, -1 for none
};

}  // namespace hydrotex::render
