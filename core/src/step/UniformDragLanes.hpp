// SPDX-License-Identifier: Zlib
#pragma once
/// @file UniformDragLanes.hpp
/// rigidBodyDrag's sum in a still, flat, uniform liquid, several patches at a time in SIMD lanes:
/// two in SSE2 (DoubleLanes, every x86-64) or four in AVX2 with fused multiply-adds (QuadLanes,
/// UniformDragAvx2.cpp, chosen at run time where the processor has them). Both run this one
/// template, so the law and its derivative are written once (TexelDragLaw.hpp).
///
/// The AVX2 translation unit is compiled with -mavx2 -mfma, so it must not emit any function that
/// another unit also emits (the linker would keep one copy, perhaps the AVX2 one, for every
/// caller): the kernel's input and output are plain data with no constructors, and everything
/// it instantiates depends on its lane type, which has internal linkage there.

#include <cstdint>

#include "hydrostatics/TexelDragLaw.hpp"

namespace hydrotex::detail {

/// Patches [begin, end) of a DragPatchSet, with whether the cluster holding them lies wholly under
/// the surface (its ramp is 1 without asking each patch).
struct UniformDragSpan {
  std::uint32_t begin, end;
  bool whollyWet;
};

/// What the kernel reads: plain data (see the file comment), world frame, SI units.
struct UniformDragInput {
  const float *x, *y, *z, *ax, *ay, *az, *area;  ///< DragPatchSet's columns (mesh frame), padded
  const double* inverseRadius;                  ///< DragPatchSet::inverseRadius, padded
  const UniformDragSpan* spans;                 ///< the clusters to sum
  std::uint32_t spanCount;
  double rotation[3][3], translation[3];        ///< the mesh pose
  double center[3], linear[3], angular[3];      ///< centre of mass (m), its velocity (m/s), rad/s
  double level;                                 ///< the flat surface's height (m)
  double density, friction;                     ///< kg/m^3 (> 0), the skin friction coefficient
  const DragCoefficients* coefficients;
  bool linearized;                              ///< sum the law's derivative (DragDamping::Linearized)
};

/// What the kernel adds to: the force (N), the torque about the centre of mass (N m), the wetted
/// area (m^2), DampingSums<double>'s members, and the wet patches visited.
struct UniformDragSums {
  double force[3], torque[3], wetted;
  double outer[21], isotropic, moment[3], second[6];
  std::uint64_t visited;
};

/// Patches past a DragPatchSet's end that its columns hold (zeros), so that a group of lanes may
/// load past the last patch (the lanes past a span's end are masked out).
inline constexpr std::uint32_t kDragLanePadding = 3;

/// The sum over `in`'s spans, `L::kWidth` patches at a time, added to `out`. Each lane does the
/// scalar law's operations (a lane past a span's end, dry or without projected area adds exact
/// zeros). In chunks of up to eight wet groups, in two passes: the posing (to the normals' square
/// root and division), then the law (to the friction's square root). Each pass's iterations are
/// short and independent, so the processor overlaps their long latencies.
template <class L>
inline void sumUniformDragLanes(const UniformDragInput& in, UniformDragSums& out) {
  constexpr std::uint32_t kWidth = L::kWidth;
  L force[3] = {L(0.0), L(0.0), L(0.0)}, torque[3] = {L(0.0), L(0.0), L(0.0)}, wetted(0.0);
  DampingSums<L> damping;
  std::uint64_t visited = 0;
  const auto turn = [&in](int row, const L& x, const L& y, const L& z) {
    return L(in.rotation[row][0]) * x + L(in.rotation[row][1]) * y + L(in.rotation[row][2]) * z;
  };
  constexpr int kChunk = 8;
  struct Posed {
    L r[3], u[3], n[3], projected, frictionArea, wet, area;
  };
  Posed posed[kChunk];
  // The chunks run on across spans (a cluster holds a few groups: one chunk each would leave
  // the latencies in series again).
  std::uint32_t s = 0, i = in.spanCount > 0 ? in.spans[0].begin : 0;
  while (s < in.spanCount) {
    int count = 0;
    while (count < kChunk && s < in.spanCount) {
      const UniformDragSpan& span = in.spans[s];
      if (i >= span.end) {
        if (++s < in.spanCount) i = in.spans[s].begin;
        continue;
      }
      // Lanes past the span's end: wet 0 (their loads stay within the columns' padding).
      const std::uint32_t first = i;
      i += kWidth;
      const L active = L::firstLanes(span.end - first);
      const L px = L::loadFloats(in.x + first), py = L::loadFloats(in.y + first), pz = L::loadFloats(in.z + first);
      const L p[3] = {turn(0, px, py, pz) + L(in.translation[0]), turn(1, px, py, pz) + L(in.translation[1]),
                      turn(2, px, py, pz) + L(in.translation[2])};
      L wet = active;
      if (!span.whollyWet)
        wet = active * clampUnit(L(0.5) + L(0.5) * (L(in.level) - p[1]) * L::loadDoubles(in.inverseRadius + first));
      const int wetLanes = positiveLanes(wet);
      if (wetLanes == 0) continue;
      visited += std::uint64_t(__builtin_popcount(unsigned(wetLanes)));
      Posed& at = posed[count++];
      at.wet = wet;
      for (int k = 0; k < 3; ++k) at.r[k] = p[k] - L(in.center[k]);
      at.u[0] = L(in.linear[0]) + (L(in.angular[1]) * at.r[2] - L(in.angular[2]) * at.r[1]);
      at.u[1] = L(in.linear[1]) + (L(in.angular[2]) * at.r[0] - L(in.angular[0]) * at.r[2]);
      at.u[2] = L(in.linear[2]) + (L(in.angular[0]) * at.r[1] - L(in.angular[1]) * at.r[0]);
      const L ax = L::loadFloats(in.ax + first), ay = L::loadFloats(in.ay + first), az = L::loadFloats(in.az + first);
      const L a[3] = {turn(0, ax, ay, az), turn(1, ax, ay, az), turn(2, ax, ay, az)};
      at.projected = squareRoot(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      // A lane without projected area: normal and areas 0 (no force, as the law's early zero).
      const L hasArea = positiveMask(at.projected);
      const L inverse = L(1.0) / select(hasArea, at.projected, L(1.0));  // one division for the three components
      for (int k = 0; k < 3; ++k) at.n[k] = a[k] * inverse;
      at.area = L::loadFloats(in.area + first);
      at.frictionArea = select(hasArea, maximum(at.area, at.projected), L(0.0));
    }
    for (int j = 0; j < count; ++j) {
      const Posed& at = posed[j];
      L f[3];
      DragRates<L> rates;
      dragLawLanes(at.n, at.projected, at.frictionArea, at.u, in.density, in.friction, *in.coefficients, f,
                   in.linearized ? &rates : nullptr);
      if (in.linearized) addDragDamping(damping, at.n, at.r, rates, at.wet);
      for (int k = 0; k < 3; ++k) f[k] = at.wet * f[k];
      for (int k = 0; k < 3; ++k) force[k] += f[k];
      torque[0] += at.r[1] * f[2] - at.r[2] * f[1];
      torque[1] += at.r[2] * f[0] - at.r[0] * f[2];
      torque[2] += at.r[0] * f[1] - at.r[1] * f[0];
      wetted += at.wet * at.area;
    }
  }
  for (int k = 0; k < 3; ++k) {
    out.force[k] += force[k].sum();
    out.torque[k] += torque[k].sum();
  }
  out.wetted += wetted.sum();
  if (in.linearized) {
    for (int k = 0; k < 21; ++k) out.outer[k] += damping.outer[k].sum();
    out.isotropic += damping.isotropic.sum();
    for (int k = 0; k < 3; ++k) out.moment[k] += damping.moment[k].sum();
    for (int k = 0; k < 6; ++k) out.second[k] += damping.second[k].sum();
  }
  out.visited += visited;
}

/// The sum in AVX2 lanes (UniformDragAvx2.cpp) where this library was built with them and the
/// processor has AVX2 and FMA; false, nothing added, where not.
bool sumUniformDragAvx2(const UniformDragInput& in, UniformDragSums& out);

}  // namespace hydrotex::detail
