// SPDX-License-Identifier: Zlib
#pragma once
/// @file ContactSheet.hpp
/// A strip of chosen frames, tiled and shrunk, like the paper's figure strips.

#include <vector>

#include "GlRenderer.hpp"

namespace hydrotex::render {

/// Tiles `frames` (all the same size) into `columns` columns, each shrunk by an integer box
/// filter to at most `tileWidth` pixels wide, with a `border` of white pixels between tiles.
/// Empty input gives an empty image.
RgbImage makeContactSheet(const std::vector<RgbImage>& frames, int columns, int tileWidth, int border = 4);

/// Indices of `count` frames spread evenly over `frameCount` frames, first and last included.
std::vector<int> chooseSheetFrames(int frameCount, int count);

}  // namespace hydrotex::render
