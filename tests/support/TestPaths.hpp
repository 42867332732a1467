// SPDX-License-Identifier: Zlib
#pragma once
// Where tests find the repository's files and where they may write.
#include <string>

namespace hydrotex::test {
/// Absolute path of a file in the source tree, e.g. sourcePath("data/meshes/ship.obj").
inline std::string sourcePath(const std::string& relative) { return std::string(HYDROTEX_SOURCE_DIR) + "/" + relative; }
/// Absolute path of a scratch file in the build tree.
inline std::string outputPath(const std::string& name) { return std::string(HYDROTEX_TEST_OUTPUT_DIR) + "/" + name; }
}  // namespace hydrotex::test
