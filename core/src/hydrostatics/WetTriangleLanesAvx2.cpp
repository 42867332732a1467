// SPDX-License-Identifier: Zlib
/// @file WetTriangleLanesAvx2.cpp
/// WetTriangleClipping.hpp's wet triangles (the prepared exact path's water line under waves) four
/// at a time in AVX2 registers, without fused multiply-adds (each lane rounds as the scalar law).
/// core/CMakeLists.txt compiles this file alone with -mavx2 where the compiler takes it; the
/// processor is asked once, at the first call. Everything it instantiates depends on QuadLanes,
/// which has internal linkage (QuadLanes.hpp).

#include "Avx2Lanes.hpp"
#include "hydrostatics/WetTriangleClipping.hpp"

#if defined(__AVX2__)
#include "QuadLanes.hpp"

namespace hydrotex::detail {

bool sumWetTrianglesAvx2(const WetTriangleBatch& in, WettedSums& out) {
  // Asked once: a query runs this per 32 wet triangles, and the environment is a scan of strings.
  static const bool allowed = avx2LanesAllowed();
  if (!allowed) return false;
  sumWetTriangleLanes<QuadLanes>(in, out);
  return true;
}

}  // namespace hydrotex::detail

#else

namespace hydrotex::detail {
bool sumWetTrianglesAvx2(const WetTriangleBatch&, WettedSums&) { return false; }
}  // namespace hydrotex::detail

#endif
