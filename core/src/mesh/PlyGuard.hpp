// SPDX-License-Identifier: Zlib
/// @file PlyGuard.hpp
/// What assimp 5.2's PLY reader cannot be given (private to core; each found by fuzz_mesh):
/// a header without an "end_header" line (it loops forever), a header line the format does not
/// allow (it reads other elements from it than a strict reader), counts that declare more data
/// than the file holds (it allocates for the declared count first: a face list of 3e9 corners
/// asked for 11 GB, in ASCII or binary), and ASCII entries that are not one line of exactly the
/// numbers their properties take (it then reads a later value as a list count).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace hydrotex::detail {

/// Bytes of a file's head read to tell its format (a PLY file is then read whole).
inline constexpr std::size_t kPlyHeadBytes = std::size_t{1} << 20;

/// True when `head` (a file's first bytes) starts a PLY file.
bool isPly(std::string_view head);

/// Why assimp must not read these PLY bytes, or nothing. `bytes`: the whole file (a shorter
/// read gets the header's checks only); `fileSize`: the whole file's size (bytes).
std::optional<std::string> plyTrap(std::string_view bytes, std::size_t fileSize);

}  // namespace hydrotex::detail
