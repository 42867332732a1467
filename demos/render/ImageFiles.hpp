// SPDX-License-Identifier: Zlib
#pragma once
/// @file ImageFiles.hpp
/// Reading and writing the renderer's RGB images as PNG files.

#include <string>

#include "GlRenderer.hpp"
#include "hydrotex/Expected.hpp"

namespace hydrotex::render {

/// Loads any image stb_image reads as 8-bit RGB (gray is replicated, alpha dropped). Error naming
/// `path` when it is missing or not an image.
Expected<RgbImage> loadRgbImage(const std::string& path);

/// Writes `image` as a PNG. Error naming `path` when it cannot be written.
Status saveRgbImage(const RgbImage& image, const std::string& path);

/// Standard deviation of the pixel values (0..255, all channels): 0 for a blank picture.
double pixelStandardDeviation(const RgbImage& image);

}  // namespace hydrotex::render
