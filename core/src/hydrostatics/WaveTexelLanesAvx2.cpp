// SPDX-License-Identifier: Zlib
/// @file WaveTexelLanesAvx2.cpp
/// WaveTexelLanes.hpp's texels four at a time in AVX2 registers, without fused multiply-adds
/// (each lane rounds as the scalar loop). core/CMakeLists.txt compiles this file alone with
/// -mavx2 where the compiler takes it; the processor is asked once, at the first call.
/// Everything it instantiates depends on QuadLanes, which has internal linkage (QuadLanes.hpp).

#include "Avx2Lanes.hpp"
#include "hydrostatics/WaveTexelLanes.hpp"

#if defined(__AVX2__)
#include "QuadLanes.hpp"

namespace hydrotex::detail {

bool sumWaveTexelsAvx2(const WaveTexelInput& in, WettedSums& out, std::uint32_t& reached) {
  // Asked once: a query runs this per tile, and the environment is a scan of strings.
  static const bool allowed = avx2LanesAllowed();
  if (!allowed) return false;
  reached = sumWaveTexelLanes<QuadLanes>(in, out);
  return true;
}

}  // namespace hydrotex::detail

#else

namespace hydrotex::detail {
bool sumWaveTexelsAvx2(const WaveTexelInput&, WettedSums&, std::uint32_t&) { return false; }
}  // namespace hydrotex::detail

#endif
