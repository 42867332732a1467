// SPDX-License-Identifier: Zlib
#include "ImageFiles.hpp"

#include <stb_image.h>

#include <cmath>

#include "hydrotex/mesh/ImageMap.hpp"

namespace hydrotex::render {

Expected<RgbImage> loadRgbImage(const std::string& path) {
  int width = 0, height = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
  if (data == nullptr) return Error{path + ": cannot read image (" + (stbi_failure_reason() ? stbi_failure_reason() : "unknown") + ")"};
  RgbImage image{width, height, std::vector<std::uint8_t>(data, data + std::size_t(width) * std::size_t(height) * 3)};
  stbi_image_free(data);
  return image;
}

Status saveRgbImage(const RgbImage& image, const std::string& path) {
  return writePng(path, image.width, image.height, 3, image.pixels);
}

double pixelStandardDeviation(const RgbImage& image) {
  if (image.pixels.empty()) return 0.0;
  double sum = 0.0, squares = 0.0;
  for (std::uint8_t v : image.pixels) {
    sum += v;
    squares += double(v) * v;
  }
  const double n = double(image.pixels.size()), mean = sum / n;
  return std::sqrt(std::max(0.0, squares / n - mean * mean));
}

}  // namespace hydrotex::render
