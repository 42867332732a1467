// SPDX-License-Identifier: Zlib
#pragma once
/// @file DragLanes.hpp
/// rigidBodyDrag's sum over its wet patches several at a time in SIMD lanes: two in SSE2
/// (DoubleLanes, every x86-64) or four in AVX2 (QuadLanes, DragLanesAvx2.cpp, chosen at run time
/// where the processor has it), both without fused multiply-adds: each lane rounds as the scalar
/// law does. Both run these templates,
/// so the law and its derivative are written once (TexelDragLaw.hpp). Two kernels: in a still,
/// flat, uniform liquid the patches are posed and tested wet in the lanes too
/// (sumUniformDragLanes); in any other liquid with a free surface the caller poses them, asks the
/// surface their wet fractions and the liquid's velocities, and the lanes take the law
/// (sumPosedDragLanes).
///
/// The AVX2 translation unit is compiled with -mavx2, so it must not emit any function that
/// another unit also emits (the linker would keep one copy, perhaps the AVX2 one, for every
/// caller): the kernels' input is plain data, their output (DragLaneSums) is only added to there
/// (none of its constructors is emitted), and everything they instantiate depends on the lane
/// type, which has internal linkage there.

#include <cstdint>

#include "hydrostatics/TexelDragLaw.hpp"

namespace hydrotex::detail {

/// Patches [begin, end) of a DragPatchSet, with whether the cluster holding them lies wholly under
/// the surface (its ramp is 1 without asking each patch).
struct UniformDragSpan {
  std::uint32_t begin, end;
  bool whollyWet;
};

/// The law's constants for a body and step.
struct DragLaneLaw {
  double density, friction;                     ///< kg/m^3 (> 0), the skin friction coefficient
  const DragCoefficients* coefficients;
  bool linearized;                              ///< sum the law's derivative (DragDamping::Linearized)
};

/// What sumUniformDragLanes reads: plain data (see the file comment), world frame, SI units.
struct UniformDragInput {
  const float *x, *y, *z, *ax, *ay, *az, *area;  ///< DragPatchSet's columns (mesh frame), padded
  const double* inverseRadius;                  ///< DragPatchSet::inverseRadius, padded
  const UniformDragSpan* spans;                 ///< the clusters to sum
  std::uint32_t spanCount;
  double rotation[3][3], translation[3];        ///< the mesh pose
  double center[3], linear[3], angular[3];      ///< centre of mass (m), its velocity (m/s), rad/s
  double level;                                 ///< the flat surface's height (m)
  DragLaneLaw law;
};

/// What sumPosedDragLanes reads: wet patches posed in the world, as columns of `count` entries
/// followed by kDragLanePadding zeros.
struct PosedDragInput {
  const double *rx, *ry, *rz;                   ///< from the centre of mass (m)
  const double *ux, *uy, *uz;                   ///< velocity relative to the liquid (m/s)
  const double *ax, *ay, *az;                   ///< area vector (m^2)
  const double *area, *wet;                     ///< m^2, wet fraction (0..1)
  std::uint32_t count;
  DragLaneLaw law;
};

/// A drag sum's totals, which the kernels add to (and rigidBodyDrag's scalar path too): the force
/// (N), the torque about the centre of mass (N m), the wetted area (m^2), the damping's sums, and
/// the wet patches visited. The kernels only add to it: DampingSums<double>'s constructor is
/// never emitted in the AVX2 unit (see the file comment).
struct DragLaneSums {
  double force[3] = {0.0, 0.0, 0.0}, torque[3] = {0.0, 0.0, 0.0}, wetted = 0.0;
  DampingSums<double> damping;
  std::uint64_t visited = 0;
};

/// Entries past the last that the kernels' columns must hold (zeros), so that a group of lanes
/// may load past it (those lanes are masked out): DragPatchSet::kPadding holds at least these.
inline constexpr std::uint32_t kDragLanePadding = 3;

/// A group of `L::kWidth` patches ready for the law: offset from the centre of mass r (m), relative
/// velocity u (m/s), unit normal n, projected area |A| and friction area max(area, |A|) (m^2),
/// wet fraction and area (m^2).
template <class L>
struct DragLaneGroup {
  L r[3], u[3], n[3], projected, frictionArea, wet, area;

  /// The normal and areas from the world area vector `a` (a lane without projected area: normal
  /// and areas 0, no force, as the law's early zero; one division for the three components).
  [[gnu::always_inline]] void setArea(const L (&a)[3], const L& patchArea) {
    projected = squareRoot(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    const L hasArea = positiveMask(projected);
    const L inverse = L(1.0) / select(hasArea, projected, L(1.0));
    for (int k = 0; k < 3; ++k) n[k] = a[k] * inverse;
    area = patchArea;
    frictionArea = select(hasArea, maximum(area, projected), L(0.0));
  }
};

/// The lanes' running sums, and the law on a group.
template <class L>
struct DragLaneAccumulator {
  L force[3] = {L(0.0), L(0.0), L(0.0)}, torque[3] = {L(0.0), L(0.0), L(0.0)}, wetted = L(0.0);
  DampingSums<L> damping;

  // Always inlined: a call would pass the lanes through memory (and GCC keeps it out of line).
  [[gnu::always_inline]] void add(const DragLaneGroup<L>& at, const DragLaneLaw& law) {
    L f[3];
    DragRates<L> rates;
    dragLawLanes(at.n, at.projected, at.frictionArea, at.u, law.density, law.friction, *law.coefficients, f,
                 law.linearized ? &rates : nullptr);
    if (law.linearized) addDragDamping(damping, at.n, at.r, rates, at.wet);
    for (int k = 0; k < 3; ++k) f[k] = at.wet * f[k];
    for (int k = 0; k < 3; ++k) force[k] += f[k];
    torque[0] += at.r[1] * f[2] - at.r[2] * f[1];
    torque[1] += at.r[2] * f[0] - at.r[0] * f[2];
    torque[2] += at.r[0] * f[1] - at.r[1] * f[0];
    wetted += at.wet * at.area;
  }

  /// The lanes' sums added to `out`.
  void addTo(DragLaneSums& out, bool linearized) const {
    for (int k = 0; k < 3; ++k) {
      out.force[k] += force[k].sum();
      out.torque[k] += torque[k].sum();
    }
    out.wetted += wetted.sum();
    if (!linearized) return;
    for (int k = 0; k < 21; ++k) out.damping.outer[k] += damping.outer[k].sum();
    out.damping.isotropic += damping.isotropic.sum();
    for (int k = 0; k < 3; ++k) out.damping.moment[k] += damping.moment[k].sum();
    for (int k = 0; k < 6; ++k) out.damping.second[k] += damping.second[k].sum();
  }
};

/// Groups per chunk: the kernels make a chunk's groups ready in one pass (to the normals' square
/// root and division) and take the law in another (to the friction's square root). Each pass's
/// iterations are short and independent, so the processor overlaps their long latencies.
inline constexpr int kDragLaneChunk = 8;

/// The sum over `in`'s spans, `L::kWidth` patches at a time, added to `out`. Each lane does the
/// scalar law's operations (a lane past a span's end, dry or without projected area adds exact
/// zeros). The chunks of wet groups run on across spans (a cluster holds a few groups: one chunk
/// each would leave the latencies in series again).
template <class L>
inline void sumUniformDragLanes(const UniformDragInput& in, DragLaneSums& out) {
  constexpr std::uint32_t kWidth = L::kWidth;
  DragLaneAccumulator<L> sums;
  std::uint64_t visited = 0;
  const auto turn = [&in](int row, const L& x, const L& y, const L& z) {
    return L(in.rotation[row][0]) * x + L(in.rotation[row][1]) * y + L(in.rotation[row][2]) * z;
  };
  DragLaneGroup<L> chunk[kDragLaneChunk];
  std::uint32_t s = 0, i = in.spanCount > 0 ? in.spans[0].begin : 0;
  while (s < in.spanCount) {
    int count = 0;
    while (count < kDragLaneChunk && s < in.spanCount) {
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
      DragLaneGroup<L>& at = chunk[count++];
      at.wet = wet;
      for (int k = 0; k < 3; ++k) at.r[k] = p[k] - L(in.center[k]);
      at.u[0] = L(in.linear[0]) + (L(in.angular[1]) * at.r[2] - L(in.angular[2]) * at.r[1]);
      at.u[1] = L(in.linear[1]) + (L(in.angular[2]) * at.r[0] - L(in.angular[0]) * at.r[2]);
      at.u[2] = L(in.linear[2]) + (L(in.angular[0]) * at.r[1] - L(in.angular[1]) * at.r[0]);
      const L ax = L::loadFloats(in.ax + first), ay = L::loadFloats(in.ay + first), az = L::loadFloats(in.az + first);
      const L a[3] = {turn(0, ax, ay, az), turn(1, ax, ay, az), turn(2, ax, ay, az)};
      at.setArea(a, L::loadFloats(in.area + first));
    }
    for (int j = 0; j < count; ++j) sums.add(chunk[j], in.law);
  }
  sums.addTo(out, in.law.linearized);
  out.visited += visited;
}

/// The law over `in`'s posed patches, `L::kWidth` at a time, added to `out` (the lanes past the
/// last patch load the padding's zeros: wet 0, no area, nothing added).
template <class L>
inline void sumPosedDragLanes(const PosedDragInput& in, DragLaneSums& out) {
  constexpr std::uint32_t kWidth = L::kWidth;
  DragLaneAccumulator<L> sums;
  DragLaneGroup<L> chunk[kDragLaneChunk];
  for (std::uint32_t i = 0; i < in.count;) {
    int count = 0;
    for (; count < kDragLaneChunk && i < in.count; i += kWidth) {
      DragLaneGroup<L>& at = chunk[count++];
      at.r[0] = L::loadDoubles(in.rx + i);
      at.r[1] = L::loadDoubles(in.ry + i);
      at.r[2] = L::loadDoubles(in.rz + i);
      at.u[0] = L::loadDoubles(in.ux + i);
      at.u[1] = L::loadDoubles(in.uy + i);
      at.u[2] = L::loadDoubles(in.uz + i);
      at.wet = L::loadDoubles(in.wet + i);
      const L a[3] = {L::loadDoubles(in.ax + i), L::loadDoubles(in.ay + i), L::loadDoubles(in.az + i)};
      at.setArea(a, L::loadDoubles(in.area + i));
    }
    for (int j = 0; j < count; ++j) sums.add(chunk[j], in.law);
  }
  sums.addTo(out, in.law.linearized);
}

/// The sums in AVX2 lanes (DragLanesAvx2.cpp) where this library was built with them and the
/// processor has AVX2 (and HYDROTEX_DISABLE_AVX2 is not set); false, nothing added,
/// where not.
bool sumUniformDragAvx2(const UniformDragInput& in, DragLaneSums& out);
bool sumPosedDragAvx2(const PosedDragInput& in, DragLaneSums& out);

}  // namespace hydrotex::detail
