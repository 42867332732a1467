/// @file PlyGuard.hpp
/// What assimp 5.2's PLY reader cannot be given (private to core; each found by fuzz_mesh):
/// a header without an "end_header" line (it loops forever), counts that declare more data than
/// the file holds (it allocates for the declared count first: a face list of 3e9 corners asked
/// for 11 GB), and ASCII entries that are not one line of exactly the numbers their properties
/// take (it then reads a later value as a list count).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace hydrotex::detail {

/// Bytes of a file's head that hold its PLY header (headers with comments are a few KB).
inline constexpr std::size_t kPlyHeadBytes = std::size_t{1} << 20;

/// True when `head` (a file's first bytes) starts a PLY file.
bool isPly(std::string_view head);

/// True when `head` starts an ASCII PLY file, whose list counts only the whole file shows.
bool isAsciiPly(std::string_view head);

/// Why assimp must not read these PLY bytes, or nothing. `bytes`: the whole file, or for a
/// binary one at least its first kPlyHeadBytes; `fileSize`: the whole file's size (bytes).
std::optional<std::string> plyTrap(std::string_view bytes, std::size_t fileSize);

}  // namespace hydrotex::detail
