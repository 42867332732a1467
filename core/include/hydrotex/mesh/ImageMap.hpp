// SPDX-License-Identifier: Zlib
#pragma once
/// @file ImageMap.hpp
/// Extra per-texel maps (density, permeability, porosity) from PNG images, resampled to a bake.
/// Row convention: image column 0 is u = 0 and the image's LAST row is v = 0 (Mesh.hpp); the
/// mapping is written once, in ImageMap.cpp (pixelCoordinates), and used by every function here.

#include <cstdint>
#include <string>
#include <vector>

#include "hydrotex/Expected.hpp"
#include "hydrotex/bake/SurfaceBake.hpp"

namespace hydrotex {

/// A one-channel image with values in [0,1] (0 = black, 1 = white).
struct ImageMap {
  int width = 0;              ///< pixels per row
  int height = 0;             ///< rows
  std::vector<float> values;  ///< row-major, row 0 = top of the image; size width * height
  /// Value of pixel (row, column), row 0 at the top.
  float at(int row, int column) const { return values[static_cast<std::size_t>(row) * width + column]; }
};

/// Loads a PNG (or any image stb_image reads), grayscale or RGB(A), 8 or 16 bit, as one channel in
/// [0,1]: 16-bit images keep 16-bit precision (value / 65535). Colour becomes luminance with the
/// Rec. 709 weights 0.2126 R + 0.7152 G + 0.0722 B applied to the stored (gamma-encoded) values,
/// so that a gray pixel keeps its value exactly; alpha is ignored. Errors (one line starting with
/// `path`): missing, empty, corrupt or not an image (a PNG chunk with a wrong CRC included), zero
/// size, more than 2^28 pixels, unsupported channel count.
Expected<ImageMap> loadImageMap(const std::string& path);

/// Bilinear sample at texture coordinates (u, v) (see the row convention above), pixel values at
/// pixel centres, clamped at the borders: the pixel in row r, column c has its centre at
/// u = (c + 0.5) / width, v = 1 - (r + 0.5) / height. 0 for an empty image.
float sampleImageMap(const ImageMap& image, double u, double v);

/// One value per covered texel of `bake` (same order as SurfaceBake::texelIndex), sampled at the
/// texel centre. When the image has the bake's size, texel (row, column) gets pixel (row, column).
std::vector<float> resampleToTexels(const ImageMap& image, const SurfaceBake& bake);

/// Writes an 8-bit PNG (`channels` 1..4, rows top to bottom, `pixels` of width*height*channels
/// bytes). Errors: bad sizes, or the file cannot be written.
Status writePng(const std::string& path, int width, int height, int channels, const std::vector<std::uint8_t>& pixels);

}  // namespace hydrotex
