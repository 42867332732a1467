// SPDX-License-Identifier: Zlib
#include "VideoEncoder.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace hydrotex::render {
namespace {
// Single quotes for the shell; a quote inside becomes '\''.
std::string shellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}
}  // namespace

bool ffmpegAvailable() { return std::system("ffmpeg -hide_banner -version > /dev/null 2>&1") == 0; }

Status encodeVideo(const std::string& framePattern, int fps, const std::string& outputPath) {
  if (!ffmpegAvailable())
    return Error{"ffmpeg not found: install Debian's ffmpeg (apt-get install ffmpeg) to get " + outputPath +
                 "; the PNG frames and the contact sheet are written without it"};
  // yuv420p and even sizes: what every player accepts; -preset fast keeps the 2-core CI quick.
  const std::string command = "ffmpeg -hide_banner -loglevel error -y -framerate " + std::to_string(fps) + " -i " +
                              shellQuoted(framePattern) +
                              " -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -preset fast -crf 23 -pix_fmt yuv420p " +
                              shellQuoted(outputPath) + " > " + shellQuoted(outputPath + ".log") + " 2>&1";
  const int status = std::system(command.c_str());
  if (status != 0) return Error{"ffmpeg failed (status " + std::to_string(status) + ") making " + outputPath + "; see " + outputPath + ".log"};
  std::remove((outputPath + ".log").c_str());
  return Ok{};
}

}  // namespace hydrotex::render
