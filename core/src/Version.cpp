// SPDX-License-Identifier: Zlib
#include "hydrotex/Version.hpp"

namespace hydrotex {
// HYDROTEX_VERSION is the project's version from CMake (core/CMakeLists.txt), given to this file alone.
const char* versionString() { return HYDROTEX_VERSION; }
}  // namespace hydrotex
