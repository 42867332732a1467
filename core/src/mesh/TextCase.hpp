// SPDX-License-Identifier: Zlib
/// @file TextCase.hpp
/// Private to core: ASCII lower case, as file formats and extensions compare their keywords
/// ("PLY", "Format ASCII", ".OFF", ".MTL" are the same to their readers).
#pragma once

#include <cctype>
#include <string>
#include <string_view>

namespace hydrotex::detail {

/// `text` with ASCII letters in lower case (other bytes unchanged).
inline std::string lowered(std::string_view text) {
  std::string result(text);
  for (char& c : result) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return result;
}

}  // namespace hydrotex::detail
