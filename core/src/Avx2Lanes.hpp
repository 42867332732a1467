// SPDX-License-Identifier: Zlib
#pragma once
/// @file Avx2Lanes.hpp
/// Private to core: whether the code that has an AVX2 form (the wetting's eight lanes, the drag
/// sum's four) may run it.

namespace hydrotex::detail {

/// True where the processor has AVX2 (asked once) and the environment variable
/// HYDROTEX_DISABLE_AVX2 is not set (read on every call, so that a caller may read it once per
/// pass, or once for good). Out of line: the AVX2 units call it, and nothing they emit may stand
/// in for another unit's code.
bool avx2LanesAllowed() noexcept;

}  // namespace hydrotex::detail
