/// @file ImageMap.cpp
/// PNG maps through stb_image / stb_image_write (implementations live in libstb).

#include "hydrotex/ImageMap.hpp"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

namespace hydrotex {
namespace {

/// THE row convention (Mesh.hpp): continuous pixel coordinates of texture point (u, v), where
/// integer values are pixel centres. Column x = u * width - 0.5; row y = (1 - v) * height - 0.5,
/// so v = 0 is the last row and v = 1 the top of the first.
struct PixelCoordinates {
  double column;
  double row;
};
PixelCoordinates pixelCoordinates(double u, double v, int width, int height) {
  return {u * width - 0.5, (1.0 - v) * height - 0.5};
}

/// Rec. 709 / sRGB luma weights (ITU-R BT.709-6, item 3.2); they sum to 1, so gray stays gray.
constexpr double kLumaRed = 0.2126, kLumaGreen = 0.7152, kLumaBlue = 0.0722;

template <class Sample>
ImageMap toSingleChannel(const Sample* data, int width, int height, int channels, double fullScale) {
  ImageMap image;
  image.width = width;
  image.height = height;
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  image.values.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Sample* pixel = data + i * static_cast<std::size_t>(channels);
    double value = pixel[0];
    if (channels >= 3) value = kLumaRed * pixel[0] + kLumaGreen * pixel[1] + kLumaBlue * pixel[2];
    image.values[i] = static_cast<float>(std::clamp(value / fullScale, 0.0, 1.0));
  }
  return image;
}

struct StbFree {
  void operator()(void* data) const { stbi_image_free(data); }
};

}  // namespace

Expected<ImageMap> loadImageMap(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) return Error{path + ": file not found"};
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) return Error{path + ": cannot read the file (" + error.message() + ")"};
  if (size == 0) return Error{path + ": file is empty"};
  int width = 0, height = 0, channels = 0;
  if (stbi_info(path.c_str(), &width, &height, &channels) == 0)
    return Error{path + ": not a readable image (" + std::string(stbi_failure_reason()) + ")"};
  if (width <= 0 || height <= 0) return Error{path + ": image has zero size"};
  if (channels < 1 || channels > 4)
    return Error{path + ": unsupported channel count " + std::to_string(channels) + " (expected 1 to 4)"};
  ImageMap image;
  if (stbi_is_16_bit(path.c_str()) != 0) {
    std::unique_ptr<stbi_us, StbFree> data(stbi_load_16(path.c_str(), &width, &height, &channels, 0));
    if (!data) return Error{path + ": corrupt image (" + std::string(stbi_failure_reason()) + ")"};
    image = toSingleChannel(data.get(), width, height, channels, 65535.0);
  } else {
    std::unique_ptr<stbi_uc, StbFree> data(stbi_load(path.c_str(), &width, &height, &channels, 0));
    if (!data) return Error{path + ": corrupt image (" + std::string(stbi_failure_reason()) + ")"};
    image = toSingleChannel(data.get(), width, height, channels, 255.0);
  }
  if (image.width <= 0 || image.height <= 0) return Error{path + ": image has zero size"};
  return image;
}

float sampleImageMap(const ImageMap& image, double u, double v) {
  if (image.width <= 0 || image.height <= 0 || image.values.empty()) return 0.0f;
  const PixelCoordinates p = pixelCoordinates(u, v, image.width, image.height);
  // Clamp to the outermost pixel centres (edge extension); NaN goes to the first pixel.
  const double column = std::isnan(p.column) ? 0.0 : std::clamp(p.column, 0.0, image.width - 1.0);
  const double row = std::isnan(p.row) ? 0.0 : std::clamp(p.row, 0.0, image.height - 1.0);
  const int c0 = static_cast<int>(column), r0 = static_cast<int>(row);
  const int c1 = std::min(c0 + 1, image.width - 1), r1 = std::min(r0 + 1, image.height - 1);
  const double fc = column - c0, fr = row - r0;
  const double top = (1.0 - fc) * image.at(r0, c0) + fc * image.at(r0, c1);
  const double bottom = (1.0 - fc) * image.at(r1, c0) + fc * image.at(r1, c1);
  return static_cast<float>((1.0 - fr) * top + fr * bottom);
}

std::vector<float> resampleToTexels(const ImageMap& image, const SurfaceBake& bake) {
  std::vector<float> values(bake.texelIndex.size(), 0.0f);
  if (bake.width <= 0 || bake.height <= 0) return values;
  for (std::size_t i = 0; i < bake.texelIndex.size(); ++i) {
    const std::uint32_t row = bake.texelIndex[i] / static_cast<std::uint32_t>(bake.width);
    const std::uint32_t column = bake.texelIndex[i] % static_cast<std::uint32_t>(bake.width);
    // Texel centre in UV, by the same convention as image pixels (texel row 0 is v = 1).
    const double u = (column + 0.5) / bake.width;
    const double v = 1.0 - (row + 0.5) / bake.height;
    values[i] = sampleImageMap(image, u, v);
  }
  return values;
}

Status writePng(const std::string& path, int width, int height, int channels, const std::vector<std::uint8_t>& pixels) {
  if (width <= 0 || height <= 0) return Error{path + ": image size " + std::to_string(width) + "x" + std::to_string(height) + " is empty"};
  if (channels < 1 || channels > 4) return Error{path + ": channel count " + std::to_string(channels) + " is not 1 to 4"};
  const std::size_t expected = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels);
  if (pixels.size() != expected)
    return Error{path + ": " + std::to_string(pixels.size()) + " bytes given, " + std::to_string(expected) + " expected"};
  if (stbi_write_png(path.c_str(), width, height, channels, pixels.data(), width * channels) == 0)
    return Error{path + ": cannot write the PNG file"};
  return Ok{};
}

}  // namespace hydrotex
