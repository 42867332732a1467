// SPDX-License-Identifier: Zlib
#include "WetnessImage.hpp"

#include <algorithm>

namespace hydrotex::render {

WetnessImage::WetnessImage(const SurfaceBake& bake, int gutter) : width_(bake.width), height_(bake.height), covered_(bake.coveredCount()) {
  const std::size_t pixels = std::size_t(width_) * std::size_t(height_);
  source_.assign(pixels, -1);
  for (std::size_t i = 0; i < bake.texelIndex.size(); ++i)
    if (bake.texelIndex[i] < pixels) source_[bake.texelIndex[i]] = static_cast<std::int32_t>(i);
  // Grow ring by ring: a pixel takes a neighbour's source only from rings already placed, so the
  // copy comes from (one of) the nearest covered texels.
  for (int ring = 0; ring < gutter; ++ring) {
    std::vector<std::int32_t> next = source_;
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x) {
        const std::size_t at = std::size_t(y) * std::size_t(width_) + std::size_t(x);
        if (source_[at] >= 0) continue;
        for (int dy = -1; dy <= 1 && next[at] < 0; ++dy)
          for (int dx = -1; dx <= 1 && next[at] < 0; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
            const std::int32_t from = source_[std::size_t(ny) * std::size_t(width_) + std::size_t(nx)];
            if (from >= 0) next[at] = from;
          }
      }
    source_ = std::move(next);
  }
}

std::vector<float> WetnessImage::pixels(const LiquidTexture& texture) const {
  if (texture.size() != covered_ || texture.capacity.size() != covered_) return {};
  const bool pigment = texture.pigment.size() == covered_;
  std::vector<float> image(2 * source_.size(), 0.0f);
  for (std::size_t p = 0; p < source_.size(); ++p) {
    if (source_[p] < 0) continue;
    const std::size_t i = std::size_t(source_[p]);
    image[2 * p] = std::clamp(texture.saturation(i), 0.0f, 1.0f);
    if (pigment && texture.liquid[i] > 0.0f) image[2 * p + 1] = std::clamp(texture.pigment[i] / texture.liquid[i], 0.0f, 1.0f);
  }
  return image;
}

}  // namespace hydrotex::render
