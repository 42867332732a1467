// SPDX-License-Identifier: Zlib
#pragma once
/// @file Version.hpp
/// Library version, for tools and bug reports.

namespace hydrotex {
/// The library's version as "major.minor.patch".
const char* versionString();
}  // namespace hydrotex
