// SPDX-License-Identifier: Zlib
/// @file ImageMap.cpp
/// PNG maps through stb_image / stb_image_write (implementations live in libstb).

#include "hydrotex/mesh/ImageMap.hpp"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

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

/// Largest image file read (bytes), below stb's int sizes; an image map is a few MB.
constexpr std::uintmax_t kMaxImageFileBytes = std::uintmax_t{1} << 30;
/// Largest pixel count decoded: 2^28 (16384^2, 1 GiB of floats), far above the 4096^2 bake. A
/// guard against a small compressed file that claims a huge image (a decompression bomb).
constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 28;

/// CRC-32 of the PNG specification (ISO/IEC 15948, Annex D: polynomial 0xEDB88320, reflected).
std::uint32_t pngCrc(const unsigned char* data, std::size_t size) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFFu] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

std::uint32_t bigEndian32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

/// For a PNG, checks every chunk's bounds and CRC up to IEND. stb_image checks neither, so a
/// flipped bit in the pixel data would otherwise load as a silently wrong density. Other formats
/// pass unchecked.
Status checkPngChunks(const std::vector<unsigned char>& bytes) {
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (bytes.size() < 8 || !std::equal(kSignature, kSignature + 8, bytes.begin())) return Ok{};
  std::size_t at = 8;
  while (true) {
    if (bytes.size() - at < 12) return Error{"corrupt PNG (truncated at byte " + std::to_string(at) + ")"};
    const std::uint32_t length = bigEndian32(&bytes[at]);
    const std::string type(reinterpret_cast<const char*>(&bytes[at + 4]), 4);
    if (length > bytes.size() - at - 12)
      return Error{"corrupt PNG (chunk '" + type + "' at byte " + std::to_string(at) + " runs past the end)"};
    const std::uint32_t stored = bigEndian32(&bytes[at + 8 + length]);
    if (pngCrc(&bytes[at + 4], std::size_t{length} + 4) != stored)
      return Error{"corrupt PNG (CRC mismatch in chunk '" + type + "' at byte " + std::to_string(at) + ")"};
    at += std::size_t{length} + 12;
    if (type == "IEND") return Ok{};
  }
}

}  // namespace

Expected<ImageMap> loadImageMap(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) return Error{path + ": file not found"};
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) return Error{path + ": cannot read the file (" + error.message() + ")"};
  if (size == 0) return Error{path + ": file is empty"};
  if (size > kMaxImageFileBytes) return Error{path + ": file of " + std::to_string(size) + " bytes is too large for an image map"};
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  {
    std::ifstream file(path, std::ios::binary);
    if (!file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
      return Error{path + ": cannot read the file"};
  }
  if (Status chunks = checkPngChunks(bytes); !chunks) return Error{path + ": " + chunks.error().message};
  const int length = static_cast<int>(bytes.size());
  int width = 0, height = 0, channels = 0;
  if (stbi_info_from_memory(bytes.data(), length, &width, &height, &channels) == 0)
    return Error{path + ": not a readable image (" + std::string(stbi_failure_reason()) + ")"};
  if (width <= 0 || height <= 0) return Error{path + ": image has zero size"};
  if (static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) > kMaxImagePixels)
    return Error{path + ": image of " + std::to_string(width) + " x " + std::to_string(height) +
                 " pixels exceeds the limit of 2^28 pixels"};
  if (channels < 1 || channels > 4)
    return Error{path + ": unsupported channel count " + std::to_string(channels) + " (expected 1 to 4)"};
  ImageMap image;
  if (stbi_is_16_bit_from_memory(bytes.data(), length) != 0) {
    std::unique_ptr<stbi_us, StbFree> data(stbi_load_16_from_memory(bytes.data(), length, &width, &height, &channels, 0));
    if (!data) return Error{path + ": corrupt image (" + std::string(stbi_failure_reason()) + ")"};
    image = toSingleChannel(data.get(), width, height, channels, 65535.0);
  } else {
    std::unique_ptr<stbi_uc, StbFree> data(stbi_load_from_memory(bytes.data(), length, &width, &height, &channels, 0));
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
