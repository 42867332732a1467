// SPDX-License-Identifier: Zlib
#pragma once
/// @file VideoEncoder.hpp
/// MP4 (H.264) from numbered PNG frames through the ffmpeg program (Debian's package `ffmpeg`).

#include <string>

#include "hydrotex/Expected.hpp"

namespace hydrotex::render {

/// True when an `ffmpeg` program runs.
bool ffmpegAvailable();

/// Encodes `framePattern` (printf style, e.g. "out/frames/frame_%04d.png") at `fps` frames per
/// second into `outputPath`. Errors: ffmpeg missing (says how to install it), or ffmpeg failed
/// (its exit status; its log is kept beside the video as .log).
Status encodeVideo(const std::string& framePattern, int fps, const std::string& outputPath);

}  // namespace hydrotex::render
