// SPDX-License-Identifier: Zlib
// Per-texel maps from PNG: the row convention, 8/16-bit precision, luminance, errors, resampling.
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "TestPaths.hpp"
#include "hydrotex/mesh/ImageMap.hpp"

using hydrotex::test::outputPath;

namespace {

// --- A minimal 16-bit grayscale PNG writer (stb_image_write only writes 8 bit). ---------------
// PNG spec (ISO/IEC 15948): chunks with CRC-32; image data is a zlib stream (RFC 1950), here of
// uncompressed "stored" deflate blocks (RFC 1951 sec. 3.2.4), each row led by filter byte 0.

std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xFFFFFFFFu;
}

void appendBigEndian32(std::string& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((value >> shift) & 0xFF));
}

void appendChunk(std::string& png, const std::string& type, const std::string& data) {
  appendBigEndian32(png, static_cast<std::uint32_t>(data.size()));
  const std::string typed = type + data;
  png += typed;
  appendBigEndian32(png, crc32(typed));
}

std::string zlibStored(const std::string& raw) {
  std::string out = "\x78\x01";
  std::size_t offset = 0;
  do {
    const std::size_t length = std::min<std::size_t>(65535, raw.size() - offset);
    const bool last = offset + length == raw.size();
    out.push_back(last ? '\x01' : '\x00');
    out.push_back(static_cast<char>(length & 0xFF));
    out.push_back(static_cast<char>(length >> 8));
    out.push_back(static_cast<char>(~length & 0xFF));
    out.push_back(static_cast<char>((~length >> 8) & 0xFF));
    out += raw.substr(offset, length);
    offset += length;
  } while (offset < raw.size());
  std::uint32_t a = 1, b = 0;  // Adler-32
  for (unsigned char byte : raw) {
    a = (a + byte) % 65521;
    b = (b + a) % 65521;
  }
  appendBigEndian32(out, (b << 16) | a);
  return out;
}

void writeGray16Png(const std::string& path, int width, int height, const std::vector<std::uint16_t>& values) {
  std::string png = "\x89PNG\r\n\x1a\n";
  std::string header;
  appendBigEndian32(header, static_cast<std::uint32_t>(width));
  appendBigEndian32(header, static_cast<std::uint32_t>(height));
  header += std::string("\x10\x00\x00\x00\x00", 5);  // 16 bit, grayscale, deflate, filter 0, no interlace
  appendChunk(png, "IHDR", header);
  std::string raw;
  for (int row = 0; row < height; ++row) {
    raw.push_back('\0');
    for (int column = 0; column < width; ++column) {
      const std::uint16_t value = values[static_cast<std::size_t>(row * width + column)];
      raw.push_back(static_cast<char>(value >> 8));
      raw.push_back(static_cast<char>(value & 0xFF));
    }
  }
  appendChunk(png, "IDAT", zlibStored(raw));
  appendChunk(png, "IEND", "");
  std::ofstream(path, std::ios::binary) << png;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_CASE("Image rows: column 0 is u = 0, the last row is v = 0", "[image]") {
  // 2 columns x 3 rows, every pixel distinct.
  const int width = 2, height = 3;
  const std::vector<std::uint8_t> pixels = {10, 20, 30, 40, 50, 60};  // row 0 (top) first
  const std::string path = outputPath("rows_2x3.png");
  REQUIRE(hydrotex::writePng(path, width, height, 1, pixels).ok());
  const auto image = hydrotex::loadImageMap(path);
  REQUIRE(image.ok());
  REQUIRE(image->width == width);
  REQUIRE(image->height == height);
  for (int row = 0; row < height; ++row)
    for (int column = 0; column < width; ++column) {
      const float expected = pixels[static_cast<std::size_t>(row * width + column)] / 255.0f;
      CHECK(image->at(row, column) == expected);
      // Pixel centre in UV: u = (c + 0.5) / W, v = 1 - (r + 0.5) / H. Bilinear weights are then
      // exactly 0/1 up to double rounding of the centre (1e-15), so the value comes back to 1e-6.
      const double u = (column + 0.5) / width, v = 1.0 - (row + 0.5) / height;
      INFO("row " << row << " column " << column);
      CHECK(hydrotex::sampleImageMap(*image, u, v) == Approx(expected).margin(1e-6));
    }
  // v = 0 is the bottom edge: the last row (50, 60); v = 1 the first row (10, 20).
  CHECK(hydrotex::sampleImageMap(*image, 0.0, 0.0) == Approx(50 / 255.0).margin(1e-6));
  CHECK(hydrotex::sampleImageMap(*image, 1.0, 1.0) == Approx(20 / 255.0).margin(1e-6));
  // Halfway between the centres of rows 0 and 1 in column 0: the mean of 10 and 30.
  CHECK(hydrotex::sampleImageMap(*image, 0.25, 1.0 - 1.0 / 3.0) == Approx(20 / 255.0).margin(1e-6));
}

TEST_CASE("16-bit PNGs keep 16-bit precision", "[image]") {
  const std::vector<std::uint16_t> values = {1000, 1001, 65535, 0, 32768, 12345};
  const std::string path = outputPath("gray16.png");
  writeGray16Png(path, 3, 2, values);
  const auto image = hydrotex::loadImageMap(path);
  INFO((image.ok() ? std::string() : image.error().message));
  REQUIRE(image.ok());
  REQUIRE(image->values.size() == values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    // Float holds value / 65535 to 6e-8 relative; neighbouring 16-bit codes differ by 1.5e-5.
    CHECK(image->values[i] == Approx(values[i] / 65535.0).margin(1e-7));
  CHECK(image->values[1] - image->values[0] == Approx(1.0 / 65535.0).margin(1e-7));
}

TEST_CASE("RGB and RGBA become Rec. 709 luminance; gray stays gray", "[image]") {
  const std::vector<std::uint8_t> rgba = {255, 0, 0, 255, 0, 255, 0, 0, 0, 0, 255, 128, 77, 77, 77, 255};
  const std::string path = outputPath("colours.png");
  REQUIRE(hydrotex::writePng(path, 4, 1, 4, rgba).ok());
  const auto image = hydrotex::loadImageMap(path);
  REQUIRE(image.ok());
  // Weights 0.2126, 0.7152, 0.0722 (sum 1); float storage: 1e-6.
  CHECK(image->values[0] == Approx(0.2126).margin(1e-6));
  CHECK(image->values[1] == Approx(0.7152).margin(1e-6));
  CHECK(image->values[2] == Approx(0.0722).margin(1e-6));
  CHECK(image->values[3] == Approx(77 / 255.0).margin(1e-6));
  const std::vector<std::uint8_t> rgb = {0, 0, 255, 255, 255, 255};
  REQUIRE(hydrotex::writePng(outputPath("rgb.png"), 2, 1, 3, rgb).ok());
  const auto fromRgb = hydrotex::loadImageMap(outputPath("rgb.png"));
  REQUIRE(fromRgb.ok());
  CHECK(fromRgb->values[0] == Approx(0.0722).margin(1e-6));
  CHECK(fromRgb->values[1] == Approx(1.0).margin(1e-6));
}

TEST_CASE("Resampling to a bake: same size gives texel (row, column) = pixel (row, column)", "[image]") {
  const int width = 4, height = 3;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width * height));
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(17 * i + 3);
  const std::string path = outputPath("bake_sized.png");
  REQUIRE(hydrotex::writePng(path, width, height, 1, pixels).ok());
  const auto image = hydrotex::loadImageMap(path);
  REQUIRE(image.ok());
  hydrotex::SurfaceBake bake;
  bake.width = width;
  bake.height = height;
  bake.texelIndex = {0, 5, 11, 8, 3};  // covered texels, any order
  const std::vector<float> values = hydrotex::resampleToTexels(*image, bake);
  REQUIRE(values.size() == bake.texelIndex.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    CHECK(values[i] == Approx(pixels[bake.texelIndex[i]] / 255.0).margin(1e-6));

  // A bake of twice the resolution: its corner texels' centres lie a quarter pixel outside the
  // outermost pixel centres, where sampling clamps to the corner pixels.
  hydrotex::SurfaceBake fine;
  fine.width = 2 * width;
  fine.height = 2 * height;
  fine.texelIndex = {0, static_cast<std::uint32_t>(fine.width * fine.height - 1)};
  const std::vector<float> corners = hydrotex::resampleToTexels(*image, fine);
  CHECK(corners[0] == Approx(pixels[0] / 255.0).margin(1e-6));
  CHECK(corners[1] == Approx(pixels.back() / 255.0).margin(1e-6));
}

TEST_CASE("Bad images give a one-line error naming the file", "[image]") {
  auto expectError = [](const std::string& path) {
    const auto image = hydrotex::loadImageMap(path);
    REQUIRE_FALSE(image.ok());
    INFO(image.error().message);
    CHECK(image.error().message.rfind(path, 0) == 0);
    CHECK(image.error().message.find('\n') == std::string::npos);
  };
  expectError(outputPath("no_such_image.png"));
  std::ofstream(outputPath("empty.png"), std::ios::binary).flush();
  expectError(outputPath("empty.png"));
  std::ofstream(outputPath("garbage.png"), std::ios::binary) << "definitely not an image at all";
  expectError(outputPath("garbage.png"));
  // A real PNG cut in half: header intact, image data missing.
  const std::vector<std::uint8_t> pixels(64 * 64, 200);
  REQUIRE(hydrotex::writePng(outputPath("whole.png"), 64, 64, 1, pixels).ok());
  const std::string bytes = readBytes(outputPath("whole.png"));
  std::ofstream(outputPath("truncated.png"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expectError(outputPath("truncated.png"));
  // A PNG whose IHDR claims zero width.
  std::string zeroSize = "\x89PNG\r\n\x1a\n";
  std::string header;
  appendBigEndian32(header, 0);
  appendBigEndian32(header, 4);
  header += std::string("\x08\x00\x00\x00\x00", 5);
  appendChunk(zeroSize, "IHDR", header);
  appendChunk(zeroSize, "IEND", "");
  std::ofstream(outputPath("zero_size.png"), std::ios::binary) << zeroSize;
  expectError(outputPath("zero_size.png"));

  CHECK_FALSE(hydrotex::writePng(outputPath("bad.png"), 2, 2, 1, {1, 2, 3}).ok());
  CHECK_FALSE(hydrotex::writePng(outputPath("bad.png"), 0, 2, 1, {}).ok());
  CHECK_FALSE(hydrotex::writePng(outputPath("bad.png"), 1, 1, 5, {1, 2, 3, 4, 5}).ok());
  CHECK(hydrotex::sampleImageMap(hydrotex::ImageMap{}, 0.5, 0.5) == 0.0f);
}
