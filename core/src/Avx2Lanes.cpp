// SPDX-License-Identifier: Zlib
/// @file Avx2Lanes.cpp
/// Avx2Lanes.hpp: the one rule for choosing the AVX2 forms at run time.

#include "Avx2Lanes.hpp"

#include <cstdlib>

namespace hydrotex::detail {

bool avx2LanesAllowed() noexcept {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool hasAvx2 = __builtin_cpu_supports("avx2");
  return hasAvx2 && std::getenv("HYDROTEX_DISABLE_AVX2") == nullptr;
#else
  return false;
#endif
}

}  // namespace hydrotex::detail
