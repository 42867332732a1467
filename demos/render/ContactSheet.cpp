// SPDX-License-Identifier: Zlib
#include "ContactSheet.hpp"

#include <algorithm>
#include <cmath>

namespace hydrotex::render {

RgbImage makeContactSheet(const std::vector<RgbImage>& frames, int columns, int tileWidth, int border) {
  if (frames.empty() || frames.front().width <= 0) return {};
  const int width = frames.front().width, height = frames.front().height;
  const int factor = std::max(1, (width + tileWidth - 1) / tileWidth);
  const int tw = width / factor, th = height / factor;
  columns = std::clamp(columns, 1, static_cast<int>(frames.size()));
  const int rows = (static_cast<int>(frames.size()) + columns - 1) / columns;
  RgbImage sheet{columns * tw + (columns + 1) * border, rows * th + (rows + 1) * border, {}};
  sheet.pixels.assign(std::size_t(sheet.width) * std::size_t(sheet.height) * 3, 255);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const RgbImage& frame = frames[f];
    if (frame.width != width || frame.height != height) continue;
    const int ox = border + static_cast<int>(f % std::size_t(columns)) * (tw + border);
    const int oy = border + static_cast<int>(f / std::size_t(columns)) * (th + border);
    for (int y = 0; y < th; ++y)
      for (int x = 0; x < tw; ++x)
        for (int c = 0; c < 3; ++c) {
          int sum = 0;
          for (int dy = 0; dy < factor; ++dy)
            for (int dx = 0; dx < factor; ++dx)
              sum += frame.pixels[(std::size_t(y * factor + dy) * std::size_t(width) + std::size_t(x * factor + dx)) * 3 + std::size_t(c)];
          sheet.pixels[(std::size_t(oy + y) * std::size_t(sheet.width) + std::size_t(ox + x)) * 3 + std::size_t(c)] =
              static_cast<std::uint8_t>(sum / (factor * factor));
        }
  }
  return sheet;
}

std::vector<int> chooseSheetFrames(int frameCount, int count) {
  std::vector<int> chosen;
  if (frameCount <= 0 || count <= 0) return chosen;
  count = std::min(count, frameCount);
  for (int k = 0; k < count; ++k)
    chosen.push_back(count == 1 ? frameCount - 1 : static_cast<int>(std::lround(double(k) * (frameCount - 1) / (count - 1))));
  return chosen;
}

}  // namespace hydrotex::render
