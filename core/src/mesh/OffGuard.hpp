// SPDX-License-Identifier: Zlib
/// @file OffGuard.hpp
/// What assimp 5.2's OFF reader cannot be given (private to core; found by fuzz_mesh): vertex or
/// face counts beyond what the file holds. It allocates for the counts first (a face count of
/// 1e25, wrapped to 2.3e9, asked for 37 GB).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace hydrotex::detail {

/// Why assimp must not read these OFF bytes, or nothing. `head`: the file's first bytes (the
/// counts are on its first lines); `fileSize`: the whole file's size (bytes); `offHint`: the file
/// name or format hint says OFF (the counts may then come without the "OFF" keyword).
std::optional<std::string> offTrap(std::string_view head, std::size_t fileSize, bool offHint);

}  // namespace hydrotex::detail
