// SPDX-License-Identifier: Zlib
// Image maps that are not what the bake expects, through the API (loadImageMap) and the tool
// (`hydrotex mass --density-map`): a size other than the bake's, grey+alpha, 16-bit, and corrupt
// files. Usable images give the right mass; corrupt ones one line naming the file, never a crash
// or silently wrong values.

#include <catch2/catch.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "TestPaths.hpp"
#include "ToolRun.hpp"
#include "hydrotex/mesh/ImageMap.hpp"

using namespace hydrotex;
using hydrotex::test::outputPath;
using hydrotex::test::readFile;
using hydrotex::test::writeScratch;

namespace {

// A minimal PNG encoder (PNG specification, ISO/IEC 15948: chunks with CRC-32, zlib stream of
// stored blocks with Adler-32), for what stb_image_write cannot write: 16-bit samples.
std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xFFFFFFFFu;
}
void appendBigEndian(std::string& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((value >> shift) & 0xFFu));
}
void appendChunk(std::string& png, const std::string& type, const std::string& data) {
  appendBigEndian(png, static_cast<std::uint32_t>(data.size()));
  const std::string typed = type + data;
  png += typed;
  appendBigEndian(png, crc32(typed));
}
/// PNG of `width` x `height` pixels; `channels` samples per pixel of `bitDepth` (8 or 16) bits,
/// every sample `sample`; colour type grey (1), grey+alpha (2), RGB (3), RGBA (4).
std::string encodePng(int width, int height, int channels, int bitDepth, std::uint16_t sample) {
  const int colourTypes[] = {0, 0, 4, 2, 6};
  std::string raw;
  for (int row = 0; row < height; ++row) {
    raw.push_back('\0');  // filter: none
    for (int i = 0; i < width * channels; ++i) {
      if (bitDepth == 16) raw.push_back(static_cast<char>(sample >> 8));
      raw.push_back(static_cast<char>(sample & 0xFFu));
    }
  }
  std::string zlib = "\x78\x01";
  for (std::size_t at = 0; at < raw.size() || at == 0; at += 65535) {
    const std::size_t length = std::min<std::size_t>(65535, raw.size() - at);
    zlib.push_back(at + length >= raw.size() ? '\x01' : '\x00');
    zlib.push_back(static_cast<char>(length & 0xFFu));
    zlib.push_back(static_cast<char>(length >> 8));
    zlib.push_back(static_cast<char>(~length & 0xFFu));
    zlib.push_back(static_cast<char>((~length >> 8) & 0xFFu));
    zlib += raw.substr(at, length);
  }
  std::uint32_t a = 1, b = 0;
  for (unsigned char byte : raw) {
    a = (a + byte) % 65521u;
    b = (b + a) % 65521u;
  }
  appendBigEndian(zlib, (b << 16) | a);
  std::string header;
  appendBigEndian(header, static_cast<std::uint32_t>(width));
  appendBigEndian(header, static_cast<std::uint32_t>(height));
  header.push_back(static_cast<char>(bitDepth));
  header.push_back(static_cast<char>(colourTypes[channels]));
  header += std::string("\0\0\0", 3);
  std::string png = "\x89PNG\r\n\x1a\n";
  appendChunk(png, "IHDR", header);
  appendChunk(png, "IDAT", zlib);
  appendChunk(png, "IEND", "");
  return png;
}

/// `png` with its IHDR claiming `width` x `height` pixels (CRC recomputed, data unchanged).
std::string claimingSize(std::string png, std::uint32_t width, std::uint32_t height) {
  std::string size;
  appendBigEndian(size, width);
  appendBigEndian(size, height);
  png.replace(16, 8, size);
  std::string crc;
  appendBigEndian(crc, crc32(png.substr(12, 17)));  // IHDR type and its 13 data bytes
  return png.replace(29, 4, crc);
}

struct GoodImage {
  std::string file;
  std::string bytes;
  double level;  ///< the grey level every pixel must load as (0..1)
};

std::vector<GoodImage> goodImages() {
  return {
      // 7 x 5 pixels for a 64 x 64 bake: resampled; a uniform image samples to its value anywhere.
      {"robust_odd_size.png", encodePng(7, 5, 1, 8, 128), 128.0 / 255.0},
      {"robust_one_pixel.png", encodePng(1, 1, 1, 8, 51), 51.0 / 255.0},
      // Grey + alpha: alpha is ignored (ImageMap.hpp), so a transparent white is white.
      {"robust_grey_alpha.png", encodePng(8, 8, 2, 8, 255), 1.0},
      {"robust_rgba.png", encodePng(8, 8, 4, 8, 64), 64.0 / 255.0},
      // 16-bit keeps 16-bit precision: 0x8081 = 32897 is not a multiple of 257, so an 8-bit
      // reduction would give 128 / 255, 1.5e-5 away from 32897 / 65535 (the tolerance is 1e-7).
      {"robust_16bit.png", encodePng(9, 9, 1, 16, 0x8081), 32897.0 / 65535.0},
      {"robust_16bit_rgb.png", encodePng(4, 4, 3, 16, 0xFFFF), 1.0},
  };
}

struct BadImage {
  std::string file;
  std::string bytes;
};

std::vector<BadImage> badImages() {
  const std::string good = encodePng(16, 16, 1, 8, 200);
  std::string flipped = good;
  flipped[flipped.size() / 2] = static_cast<char>(flipped[flipped.size() / 2] ^ 0x5A);  // inside IDAT
  std::string badCrc = good;
  badCrc[29] = static_cast<char>(badCrc[29] ^ 0x01);  // IHDR's CRC
  return {
      {"robust_empty.png", ""},
      {"robust_text.png", "this is not an image\n"},
      {"robust_signature_only.png", "\x89PNG\r\n\x1a\n"},
      {"robust_truncated.png", good.substr(0, good.size() / 2)},
      {"robust_flipped_pixel_byte.png", flipped},
      {"robust_bad_crc.png", badCrc},
      // Claims 100000 x 100000 pixels (40 GB as floats) or 30000 x 30000 (under stb's own
      // limits) with one pixel of data behind it.
      {"robust_huge_claim.png", claimingSize(encodePng(1, 1, 1, 8, 0), 100000, 100000)},
      {"robust_large_claim.png", claimingSize(encodePng(1, 1, 1, 8, 0), 30000, 30000)},
  };
}

}  // namespace

TEST_CASE("images of any size, channel count and depth load as one grey channel", "[robustness][image]") {
  for (const GoodImage& good : goodImages()) {
    CAPTURE(good.file);
    const Expected<ImageMap> image = loadImageMap(writeScratch(good.file, good.bytes));
    INFO((image ? std::string() : image.error().message));
    REQUIRE(image.ok());
    REQUIRE(!image->values.empty());
    for (float value : image->values) CHECK(value == Approx(good.level).epsilon(1e-7));  // float storage
    CHECK(sampleImageMap(*image, 0.37, 0.91) == Approx(good.level).epsilon(1e-7));
  }
}

TEST_CASE("corrupt images give one line naming the file", "[robustness][image][bad-input]") {
  for (const BadImage& bad : badImages()) {
    CAPTURE(bad.file);
    const Expected<ImageMap> image = loadImageMap(writeScratch(bad.file, bad.bytes));
    REQUIRE_FALSE(image.ok());
    INFO(image.error().message);
    CHECK(image.error().message.find(bad.file) != std::string::npos);
    CHECK(image.error().message.find('\n') == std::string::npos);
  }
}

#ifdef HYDROTEX_TOOL_PATH
TEST_CASE("density maps through the tool: usable images give the mass, corrupt ones a clean failure",
          "[robustness][image][tool]") {
  using hydrotex::test::requireCleanFailure;
  using hydrotex::test::runTool;
  const std::string box = hydrotex::test::sourcePath("data/meshes/box.obj");
  for (const GoodImage& good : goodImages()) {
    CAPTURE(good.file);
    const std::string path = writeScratch(good.file, good.bytes);
    const test::ToolRun run = runTool("mass " + box + " --resolution 64 --density-map " + path +
                                          " --density-range 0,1000 --json",
                                      120);
    INFO(run.err);
    REQUIRE(run.exitCode == 0);
    // Unit cube: mass = 1000 level kg, to float storage of PT, VAT and the level (1e-5).
    CHECK(nlohmann::json::parse(run.out)["mass"].get<double>() == Approx(1000.0 * good.level).epsilon(1e-5));
  }
  for (const BadImage& bad : badImages()) {
    CAPTURE(bad.file);
    const std::string path = writeScratch(bad.file, bad.bytes);
    requireCleanFailure(runTool("mass " + box + " --resolution 64 --density-map " + path + " --density-range 0,1000", 120),
                        bad.file);
  }
}
#endif
