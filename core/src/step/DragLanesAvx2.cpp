// SPDX-License-Identifier: Zlib
/// @file DragLanesAvx2.cpp
/// DragLanes.hpp's sums four patches at a time in AVX2 registers, without fused multiply-adds (as
/// the wetting's AVX2 lanes): each lane rounds as the scalar law does. With them (-mfma),
/// test_hard_cases' needle (1 m x 1 mm x 1 mm, texture path, double-precision Bullet) peaked at
/// 149 rad/s against the test's bound of 110. That needle never settles on the texture path,
/// with any of the lanes: from t = 9.5 s it rolls at 60-90 rad/s to the end (its roll inertia is
/// 8e-11 kg m^2), so a rounding-level change of the drag's sums moves its peaks.
/// core/CMakeLists.txt compiles this file alone with -mavx2 where the compiler takes it;
/// the processor is asked once, at the first call. Everything this file instantiates depends on
/// QuadLanes, which has internal linkage, so no AVX2 code can stand in for another unit's
/// (DragLanes.hpp); `nm` on its object lists no weak function from -O1 up (at -O0 GCC adds
/// the empty constructors of Eigen's placeholders `all` and `last`, which hold no vector code).

#include "Avx2Lanes.hpp"
#include "step/DragLanes.hpp"

#if defined(__AVX2__)
#include "QuadLanes.hpp"

namespace hydrotex::detail {
namespace {

// avx2LanesAllowed, asked at the first sum only: the drag runs per body and step, and the
// environment is a scan of strings.
bool wideLanes() {
  static const bool allowed = avx2LanesAllowed();
  return allowed;
}

}  // namespace

bool sumUniformDragAvx2(const UniformDragInput& in, DragLaneSums& out) {
  if (!wideLanes()) return false;
  sumUniformDragLanes<QuadLanes>(in, out);
  return true;
}

bool sumPosedDragAvx2(const PosedDragInput& in, DragLaneSums& out) {
  if (!wideLanes()) return false;
  sumPosedDragLanes<QuadLanes>(in, out);
  return true;
}

}  // namespace hydrotex::detail

#else

namespace hydrotex::detail {
bool sumUniformDragAvx2(const UniformDragInput&, DragLaneSums&) { return false; }
bool sumPosedDragAvx2(const PosedDragInput&, DragLaneSums&) { return false; }
}  // namespace hydrotex::detail

#endif
