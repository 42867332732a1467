// SPDX-License-Identifier: Zlib
/// @file OffGuard.cpp
/// See OffGuard.hpp. Only the counts are checked; everything else is assimp's reader's job.

#include "mesh/OffGuard.hpp"
#include "mesh/TextCase.hpp"

#include <cctype>
#include <charconv>
#include <cstdint>

namespace hydrotex::detail {
namespace {

/// The next whitespace-separated token from `at`, skipping '#' comments to their line's end.
std::string_view nextToken(std::string_view text, std::size_t& at) {
  while (at < text.size()) {
    if (std::isspace(static_cast<unsigned char>(text[at])) != 0) {
      ++at;
    } else if (text[at] == '#') {
      while (at < text.size() && text[at] != '\n') ++at;
    } else {
      break;
    }
  }
  const std::size_t start = at;
  while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at])) == 0) ++at;
  return text.substr(start, at - start);
}

}  // namespace

std::optional<std::string> offTrap(std::string_view head, std::size_t fileSize, bool offHint) {
  std::size_t at = 0;
  std::string_view token = nextToken(head, at);
  // The keyword (OFF, COFF, NOFF, STOFF, 4OFF, ...) may be left out when the name says OFF. The
  // reader goes on right after the keyword, inside its token too: "OFF02" is 2 vertices to it,
  // and "OFF#" starts a comment (both let a face count of 1e17 or more through to an allocation
  // of gigabytes: fuzz_mesh in CI's runs), and so does this check.
  const std::size_t keyword = lowered(token).find("off");
  if (keyword != std::string_view::npos) {
    at = std::size_t(token.data() - head.data()) + keyword + 3;
    token = nextToken(head, at);
  } else if (!offHint) {
    return std::nullopt;
  }
  // Vertex count, then face count: each entry takes at least 2 bytes (a digit and a blank), so a
  // count beyond half the file is no data, only an allocation. The reader takes a token's leading
  // digits as the count ("1000000000$0" is 1e9 to it; fuzz_mesh), and so does this check.
  for (const char* what : {"vertices", "faces"}) {
    std::uint64_t count = 0;
    const auto [stop, error] = std::from_chars(token.data(), token.data() + token.size(), count);
    if (stop == token.data()) return std::nullopt;  // no digits: assimp's reader says what is wrong
    if (error != std::errc() || count > fileSize / 2)
      return "OFF header declares " + std::string(token.substr(0, 32)) + " " + what + ", more than the file's " +
             std::to_string(fileSize) + " bytes hold";
    token = nextToken(head, at);
  }
  return std::nullopt;
}

}  // namespace hydrotex::detail
