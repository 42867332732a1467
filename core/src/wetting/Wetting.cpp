// SPDX-License-Identifier: Zlib
// The liquid texture step (paper section 4.2).
//  - Absorption: Darcy's law (paper eq. 9, Muskat), flux per area q = k dp / (mu L). The pores'
//    back-pressure grows with their saturation S, dp = P (1 - S), so under a constant head P a
//    texel fills as S(t) = 1 - exp(-t / tau), tau = mu L C / (k P) (docs/references.md "compartment
//    filling"); integrated exactly over the step, so it is stable at any dt.
//  - Diffusion: Fick's first law J = -D grad phi on the texel graph (TexelAdjacency), written as
//    antisymmetric pair fluxes F_ij = D g_ij (phi_i - phi_j) dt so that every volume leaving one
//    texel enters another (seams included). Explicit sub-steps while dt / (min_i A_i / sum_j D g_ij)
//    is small (that bound keeps phi >= 0, docs/references.md), backward Euler otherwise: (M + dt D L)
//    phi' = M phi solved by conjugate gradients (the matrix is symmetric positive definite), then
//    the pair fluxes of phi' are applied to phi, so the volume is conserved whatever the solver's
//    residual.
//  - Stiff texels are merged into control volumes (DiffusionGroups.hpp): their own equilibration
//    time is far below any step, so a shared content is what backward Euler would give them
//    anyway, and the group's volume is conserved.
//  - Evaporation: Hall and Hoff (2009, "Water Transport in Brick, Stone and Concrete", paper eq.
//    10), e = D_w (p_sat M / (R tau)) dH/dx with dH/dx = (1 - H) / boundary layer, per unit area,
//    while the surface is wet (constant-rate stage); below a critical saturation the liquid must
//    first reach the surface and the rate falls in proportion to saturation (falling-rate stage,
//    first-order drying). Both stages are integrated exactly over the step.
#include "hydrotex/wetting/Wetting.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <string>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "Avx2Lanes.hpp"

namespace hydrotex {

namespace {

constexpr double kGasConstant = 8.314462618;  // J / (mol K)

// Saturation vapour pressure of water (Pa) at `kelvin`: Magnus form, Alduchov and Eskridge 1996.
double saturationVapourPressure(double kelvin) {
  const double celsius = kelvin - 273.15;
  return 610.94 * std::exp(17.625 * celsius / (celsius + 243.04));
}

bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }

// Whether the exchange and the sweep run eight lanes (avx2LanesAllowed, asked once per pass, so
// that a test can compare both widths in one process).
bool wideLanes() { return detail::avx2LanesAllowed(); }

// Texels a lane block at a time in GCC/Clang vector extensions: four (SSE2 on x86-64, NEON on
// ARM) everywhere, eight in the exchange pass and the diffusion sweep where the processor has
// AVX2 (chosen at run time; the same IEEE operations per lane, without fused multiply-adds). The
// per-texel pass is arithmetic on independent texels, and the stage of each (under the liquid,
// wet, drying) is selected per lane instead of branched to. The types are spelt out per width:
// GCC drops vector_size from a type that depends on a template parameter.
template <std::size_t W>
struct LaneTypes;
template <>
struct LaneTypes<4> {
  using F = float __attribute__((vector_size(16)));
  using M = std::int32_t __attribute__((vector_size(16)));
  using B = std::uint8_t __attribute__((vector_size(4)));
};
template <>
struct LaneTypes<8> {
  using F = float __attribute__((vector_size(32)));
  using M = std::int32_t __attribute__((vector_size(32)));
  using B = std::uint8_t __attribute__((vector_size(8)));
};
constexpr std::size_t kLaneCount = 4;  // the width everywhere
#define HYDROTEX_LANE_INLINE inline __attribute__((always_inline))
// The eight-lane helpers are always inlined into the AVX2 kernel, never called across an ABI
// boundary: GCC's note that passing 32-byte vectors without AVX changes the ABI does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

template <class F>
HYDROTEX_LANE_INLINE F splat(float x) {
  return F{} + x;
}
template <class F, class M>
HYDROTEX_LANE_INLINE F select(M mask, F a, F b) {
  return reinterpret_cast<F>((mask & reinterpret_cast<M>(a)) | (~mask & reinterpret_cast<M>(b)));
}
template <class F>
HYDROTEX_LANE_INLINE F minimum(F a, F b) {
  return select(a < b, a, b);
}
// `count` (1..lanes) values from `p`; the lanes past them are 0. A whole block is one unaligned move.
template <class F>
HYDROTEX_LANE_INLINE F load(const float* p, std::size_t count) {
  F v{};
  if (count == sizeof(F) / sizeof(float))
    std::memcpy(&v, p, sizeof v);
  else
    for (std::size_t k = 0; k < count; ++k) v[k] = p[k];
  return v;
}
template <class F>
HYDROTEX_LANE_INLINE void store(float* p, std::size_t count, F v) {
  if (count == sizeof(F) / sizeof(float))
    std::memcpy(p, &v, sizeof v);
  else
    for (std::size_t k = 0; k < count; ++k) p[k] = v[k];
}
template <class M>
HYDROTEX_LANE_INLINE M loadMask(const std::uint8_t* p, std::size_t count) {
  typename LaneTypes<sizeof(M) / 4>::B bytes{};
  std::memcpy(&bytes, p, count);
  return __builtin_convertvector(bytes, M) != M{};
}
template <class M>
HYDROTEX_LANE_INLINE void storeMask(std::uint8_t* p, std::size_t count, M m) {
  const auto bytes = __builtin_convertvector(m & 1, typename LaneTypes<sizeof(M) / 4>::B);
  std::memcpy(p, &bytes, count);
}
// Sum of the lanes (a count of set mask lanes when fed with -mask).
template <class M>
HYDROTEX_LANE_INLINE std::int64_t horizontalSum(M m) {
  std::int64_t sum = 0;
  for (std::size_t k = 0; k < sizeof(M) / 4; ++k) sum += m[k];
  return sum;
}
// One bit per set lane (lane k: bit k).
template <class M>
HYDROTEX_LANE_INLINE int laneBits(M m) {
#if defined(__SSE2__)
  // Per 16-byte half (an AVX2 build of the kernel makes these VEX moves).
  if constexpr (sizeof(M) == 16) return _mm_movemask_ps(reinterpret_cast<__m128>(m));
  if constexpr (sizeof(M) == 32) {
    __m128 half[2];
    std::memcpy(half, &m, sizeof m);
    return _mm_movemask_ps(half[0]) | _mm_movemask_ps(half[1]) << 4;
  }
#endif
  int bits = 0;
  for (std::size_t k = 0; k < sizeof(M) / 4; ++k) bits |= m[k] ? 1 << k : 0;
  return bits;
}
template <class M>
HYDROTEX_LANE_INLINE bool any(M m) {
  return laneBits(m) != 0;
}
// Sum of the lanes in double, pairwise.
template <class F>
HYDROTEX_LANE_INLINE double volumeSum(F v) {
  double pairs[sizeof(F) / 8];
  for (std::size_t k = 0; k < sizeof(F) / 8; ++k) pairs[k] = static_cast<double>(v[2 * k]) + static_cast<double>(v[2 * k + 1]);
  double sum = 0.0;
  for (std::size_t k = 0; k < sizeof(F) / 8; k += 2) sum += pairs[k] + pairs[k + 1];
  return sum;
}

// exp(-x) for x >= 0 in float, the precision the contents are stored in (a NaN or negative x
// gives 1, +inf and x > 80 give e^-80 = 2e-35: nothing left of a content in metres): x = k ln 2
// + r with |r| <= ln 2 / 2, e^r by its Taylor series to r^6 (remainder 0.35^7 / 7! < 1.3e-8),
// 2^-k set in the exponent bits. Several times cheaper than std::exp.
template <class F>
HYDROTEX_LANE_INLINE F expNegative(F x) {
  using M = typename LaneTypes<sizeof(F) / 4>::M;
  x = select(x > splat<F>(0.0f), x, splat<F>(0.0f));
  x = minimum(x, splat<F>(80.0f));
  constexpr float kLn2 = 0.693147181f, kInvLn2 = 1.44269504f;
  // Rounded to nearest by truncation of a positive number.
  const M k = __builtin_convertvector(x * splat<F>(kInvLn2) + splat<F>(0.5f), M);
  const F kf = __builtin_convertvector(k, F);
  const F r = kf * splat<F>(kLn2) - x;
  F p = splat<F>(1.0f / 720.0f);
  p = p * r + splat<F>(1.0f / 120.0f);
  p = p * r + splat<F>(1.0f / 24.0f);
  p = p * r + splat<F>(1.0f / 6.0f);
  p = p * r + splat<F>(0.5f);
  p = p * r + splat<F>(1.0f);
  p = p * r + splat<F>(1.0f);
  const M exponent = (M{} + 127 - k) << 23;
  return p * reinterpret_cast<F>(exponent);
}

// 1 - e^-x in float, without the cancellation of 1 - expNegative(x) for small x (a short step
// under water): series to x^4 below 0.03 (remainder x^5 / 120 < 7e-9 relative to x).
// Each form is evaluated only when a lane needs it (short steps need only the series).
template <class F>
HYDROTEX_LANE_INLINE F oneMinusExpNegative(F x) {
  constexpr int kAll = (1 << (sizeof(F) / 4)) - 1;
  const auto small = x < splat<F>(0.03f);
  const int smallLanes = laneBits(small);
  F series{}, complement{};
  if (smallLanes != 0)
    series = x * (splat<F>(1.0f) - x * (splat<F>(0.5f) - x * (splat<F>(1.0f / 6.0f) - x * splat<F>(1.0f / 24.0f))));
  if (smallLanes != kAll) complement = splat<F>(1.0f) - expNegative(x);
  return select(small, series, complement);
}

}  // namespace

Status WettingSettings::validate() const {
  if (!(diffusivity >= 0.0 && std::isfinite(diffusivity)))
    return Error{"wetting diffusivity " + std::to_string(diffusivity) + " m^2/s is negative or not finite"};
  if (!finitePositive(viscosity)) return Error{"wetting viscosity " + std::to_string(viscosity) + " Pa s is not positive"};
  if (!(capillaryPressure >= 0.0 && std::isfinite(capillaryPressure)))
    return Error{"wetting capillary pressure " + std::to_string(capillaryPressure) + " Pa is negative or not finite"};
  if (!(relativeHumidity >= 0.0 && relativeHumidity <= 1.0))
    return Error{"wetting humidity " + std::to_string(relativeHumidity) + " is outside 0..1"};
  if (!(temperature > 200.0 && temperature < 400.0))
    return Error{"wetting temperature " + std::to_string(temperature) + " K is outside 200..400 K"};
  if (!finitePositive(boundaryLayer))
    return Error{"wetting boundary layer " + std::to_string(boundaryLayer) + " m is not positive"};
  if (!(criticalSaturation >= 0.0 && criticalSaturation <= 1.0))
    return Error{"wetting critical saturation " + std::to_string(criticalSaturation) + " is outside 0..1"};
  if (!finitePositive(liquidDensity) || !finitePositive(molarMass) || !(vapourDiffusivity >= 0.0 && std::isfinite(vapourDiffusivity)))
    return Error{"wetting liquid density, molar mass or vapour diffusivity is not positive"};
  if (!(mergeBelowFraction >= 0.0 && mergeBelowFraction <= 1.0))
    return Error{"wetting merge fraction " + std::to_string(mergeBelowFraction) + " is outside 0..1"};
  if (maxExplicitSubsteps < 0 || maxExplicitSubsteps > 1000)
    return Error{"wetting max explicit sub-steps " + std::to_string(maxExplicitSubsteps) + " is outside 0..1000"};
  return Ok{};
}

double WettingSettings::evaporationRate() const {
  const double vapourDensity = saturationVapourPressure(temperature) * molarMass / (kGasConstant * temperature);
  const double massFlux = vapourDiffusivity * vapourDensity * (1.0 - relativeHumidity) / boundaryLayer;
  return massFlux / liquidDensity;
}

struct Wetting::ImplicitSystem {
  Eigen::SparseMatrix<double> matrix;  // M + dt D L on the diffusion groups
  double dt = -1.0;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> solver;
  Eigen::VectorXd solution;
  // Scratch, kept so that a step allocates nothing once sized.
  Eigen::VectorXd rhs, start;
  std::vector<double> flux, volume, pigment;
};

// A source in the body frame: rain as the unit vector against its fall (a texel's facing is then
// n . up), a sphere by its centre.
struct Wetting::BodySource {
  bool rain;
  Eigen::Vector3f up;
  Eigen::Vector3f centre;
  float radiusSquared;
  float depth;  // supply over the step (m of liquid)
  double pigment;
};

Wetting::Wetting() = default;
Wetting::Wetting(Wetting&&) noexcept = default;
Wetting& Wetting::operator=(Wetting&&) noexcept = default;
Wetting::~Wetting() = default;

Expected<Wetting> Wetting::create(TexelAdjacency adjacency, const SurfaceTextures& textures,
                                  const WettingSettings& settings) {
  if (Status s = settings.validate(); !s) return s.error();
  const std::size_t n = adjacency.area.size();
  if (textures.size() != n || adjacency.centroid.size() != n || adjacency.conductanceSum.size() != n)
    return Error{"wetting: texel graph has " + std::to_string(n) + " texels, surface textures " +
                 std::to_string(textures.size())};
  for (std::size_t p = 0; p < adjacency.pairCount(); ++p)
    if (adjacency.first[p] >= n || adjacency.second[p] >= n || p >= adjacency.conductance.size())
      return Error{"wetting: texel graph pair " + std::to_string(p) + " names a texel out of range"};
  Wetting w;
  w.settings_ = settings;
  for (auto* v : {&w.px_, &w.py_, &w.pz_, &w.nx_, &w.ny_, &w.nz_}) v->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    w.px_[i] = static_cast<float>(adjacency.centroid[i].x());
    w.py_[i] = static_cast<float>(adjacency.centroid[i].y());
    w.pz_[i] = static_cast<float>(adjacency.centroid[i].z());
    const float norm = textures.areaVector[i].norm();
    const Eigen::Vector3f normal = norm > 0.0f ? Eigen::Vector3f(textures.areaVector[i] / norm) : Eigen::Vector3f::Zero();
    w.nx_[i] = normal.x();
    w.ny_[i] = normal.y();
    w.nz_[i] = normal.z();
  }
  w.submerged_.assign(n, 0);
  w.area_.resize(n);
  for (std::size_t i = 0; i < n; ++i) w.area_[i] = static_cast<float>(adjacency.area[i]);
  w.pressure_.assign(n, 0.0f);
  w.adjacency_ = std::move(adjacency);
  w.buildDiffusionGroups();
  w.implicit_ = std::make_unique<ImplicitSystem>();
  return w;
}

void Wetting::buildDiffusionGroups() {
  groups_ = mergeStiffTexels(adjacency_, settings_.mergeBelowFraction);
  const std::size_t n = groups_.nodeArea.size();
  inverseNodeArea_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    inverseNodeArea_[i] = groups_.nodeArea[i] > 0.0 ? static_cast<float>(1.0 / groups_.nodeArea[i]) : 0.0f;
  // The explicit sweep's layout: per holding texel, its pair to the next texel and one other pair
  // towards a higher index (the texel below, on a chart) in fixed slots, any more (seams) in a
  // list sorted by their lower texel; D g_ij in float. The ring that carries fluxes forward spans
  // the longest reach.
  nextConductance_.assign(n, 0.0f);
  otherConductance_.assign(n, 0.0f);
  otherOffset_.assign(n, 0);
  extraFirst_.clear();
  extraSecond_.clear();
  extraConductance_.clear();
  std::vector<std::uint32_t> order(groups_.pairFirst.size());
  std::iota(order.begin(), order.end(), 0u);
  auto low = [&](std::uint32_t p) { return std::min(groups_.pairFirst[p], groups_.pairSecond[p]); };
  auto high = [&](std::uint32_t p) { return std::max(groups_.pairFirst[p], groups_.pairSecond[p]); };
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return low(a) < low(b); });
  std::size_t reach = 1;
  for (const std::uint32_t p : order) {
    const std::uint32_t i = low(p), j = high(p);
    const auto c = static_cast<float>(settings_.diffusivity * groups_.pairGeometric[p]);
    if (!(c > 0.0f)) continue;  // carries nothing (D = 0)
    reach = std::max<std::size_t>(reach, j - i);
    if (j == i + 1 && nextConductance_[i] == 0.0f) {
      nextConductance_[i] = c;
    } else if (otherConductance_[i] == 0.0f) {
      otherConductance_[i] = c;
      otherOffset_[i] = j - i;
    } else {
      extraFirst_.push_back(i);
      extraSecond_.push_back(j);
      extraConductance_.push_back(c);
    }
  }
  // At least one block of eight lanes, so that a block's entries are contiguous in the ring.
  std::size_t ringSize = 8;
  while (ringSize <= reach) ringSize *= 2;
  ring_.assign(ringSize, 0.0f);
  pigmentRing_.assign(ringSize, 0.0f);
}

void liquidPressureAtTexels(const LiquidSurface& liquid, const WettingEnvironment& environment, const float* x,
                            const float* y, const float* z, std::size_t count, float* pressure, std::uint8_t* under) {
  const Eigen::Matrix3d& rotation = environment.pose.rotation;
  const Eigen::Vector3d& translation = environment.pose.translation;
  const bool freeSurface = liquid.hasFreeSurface();
  // Texels above the highest crest are in the air without asking the surface.
  const double highest = freeSurface ? liquid.heightRange(environment.time).second : std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d world = rotation * Eigen::Vector3d(x[i], y[i], z[i]) + translation;
    double p = 0.0;
    bool below = false;
    if (world.y() <= highest) {
      p = liquid.pressure(world, environment.time, environment.gravity);
      below = !freeSurface || p > 0.0;
    }
    pressure[i] = static_cast<float>(std::max(p, 0.0));
    under[i] = below ? 1 : 0;
  }
}

Status checkWettingStep(const WettingEnvironment& environment, double dt) {
  if (!(dt >= 0.0 && std::isfinite(dt))) return Error{"wetting: time step " + std::to_string(dt) + " s is not finite and >= 0"};
  if (!environment.pose.isFinite()) return Error{"wetting: body pose is not finite"};
  if (!(environment.gravity > 0.0 && std::isfinite(environment.gravity)))
    return Error{"wetting: gravity " + std::to_string(environment.gravity) + " m/s^2 is not positive"};
  if (environment.liquid) {
    if (Status s = environment.liquid->validate(); !s) return Error{"wetting: " + s.error().message};
  }
  for (const LiquidSource& source : environment.sources)
    if (!(source.rate >= 0.0 && std::isfinite(source.rate)) || !source.centre.allFinite() ||
        !source.direction.allFinite() || !(source.radius >= 0.0) || !(source.pigment >= 0.0 && source.pigment <= 1.0))
      return Error{"wetting: a liquid source has a negative rate or radius, a pigment outside 0..1, or a NaN"};
  return Ok{};
}

Expected<WettingStepReport> Wetting::step(LiquidTexture& texture, const WettingEnvironment& environment, double dt) {
  const std::size_t n = adjacency_.area.size();
  if (texture.liquid.size() != n || texture.capacity.size() != n || texture.permeability.size() != n ||
      (!texture.pigment.empty() && texture.pigment.size() != n))
    return Error{"wetting: liquid texture has " + std::to_string(texture.liquid.size()) + " texels, the body " +
                 std::to_string(n)};
  if (Status s = checkWettingStep(environment, dt); !s) return s.error();
  WettingStepReport report;
  const bool flat = dynamic_cast<const FlatSurface*>(environment.liquid) || !environment.liquid;
  const int substeps = explicitSubsteps(dt);
  if (substeps >= 1) {
    // The common case in one pass over memory: the exchange runs ahead of the first diffusion
    // sub-step's sweep by the sweep's reach, so every texel is exchanged before a flux reads it,
    // and each merged group is pooled once its members are exchanged, before its holder is read.
    if (flat)
      fusedStep<true>(texture, environment, dt, substeps, report);
    else
      fusedStep<false>(texture, environment, dt, substeps, report);
  } else {
    if (flat)
      exchange<true>(texture, environment, dt, true, true, report);
    else
      exchange<false>(texture, environment, dt, true, true, report);
    report.diffusionSubsteps = diffuse(texture, dt);
  }
  report.implicitDiffusion = substeps < 0;
  return report;
}

int Wetting::explicitSubsteps(double dt) const {
  return diffusionSubsteps(dt, stableTimeStep(), settings_.maxExplicitSubsteps);
}

template <bool Flat>
void Wetting::fusedStep(LiquidTexture& texture, const WettingEnvironment& environment, double dt, int substeps,
                        WettingStepReport& report) {
  const ExchangeConstants k = prepareExchange<Flat>(texture, environment, dt, true, true);
  const std::size_t n = px_.size();
  ExchangeTotals totals;
  std::size_t exchanged = 0;
  // The sweep of texels below `end` reads texels below end + reach (the ring's size bounds it).
  const std::size_t reach = ring_.size();
  const std::size_t groups = groups_.start.empty() ? 0 : groups_.start.size() - 1;
  // One past a group's highest member: members follow the holder in increasing index, so the
  // last one is the highest unless the holder is.
  auto groupEnd = [&](std::size_t g) -> std::size_t {
    return std::max(groups_.members[groups_.start[g]], groups_.members[groups_.start[g + 1] - 1]) + std::size_t{1};
  };
  std::size_t pooled = 0;  // groups below this one are pooled: every group whose holder is below `exchanged`
  auto ahead = [&](std::size_t end) {
    std::size_t upTo = std::min(n, end + reach);
    if (upTo <= exchanged) return;
    // A holder about to be read needs its whole group exchanged first (members may lie further on).
    std::size_t ready = pooled;
    while (ready < groups && groups_.members[groups_.start[ready]] < upTo) upTo = std::max(upTo, groupEnd(ready++));
    exchangeRange<Flat>(texture, k, exchanged, upTo, totals);
    exchanged = upTo;
    for (; pooled < ready; ++pooled) poolGroup(texture, pooled);
  };
  const auto step = static_cast<float>(dt / substeps);
  if (texture.pigment.empty())
    sweep<false>(texture, step, ahead);
  else
    sweep<true>(texture, step, ahead);
  for (int s = 1; s < substeps; ++s) diffuseExplicit(texture, dt / substeps);
  spreadGroups(texture);
  report.absorbed = totals.absorbed;
  report.evaporated = totals.evaporated;
  report.submergedTexels = totals.submerged;
  report.diffusionSubsteps = substeps;
}

double Wetting::absorb(LiquidTexture& texture, const WettingEnvironment& environment, double dt,
                       std::size_t& submergedCount) {
  WettingStepReport report;
  if (dynamic_cast<const FlatSurface*>(environment.liquid) || !environment.liquid)
    exchange<true>(texture, environment, dt, true, false, report);
  else
    exchange<false>(texture, environment, dt, true, false, report);
  submergedCount = report.submergedTexels;
  return report.absorbed;
}

double Wetting::evaporate(LiquidTexture& texture, double dt) {
  WettingStepReport report;
  exchange<true>(texture, WettingEnvironment{}, dt, false, true, report);
  return report.evaporated;
}

template <bool Flat>
void Wetting::exchange(LiquidTexture& texture, const WettingEnvironment& environment, double dt, bool absorbing,
                       bool evaporating, WettingStepReport& report) {
  const ExchangeConstants k = prepareExchange<Flat>(texture, environment, dt, absorbing, evaporating);
  report = WettingStepReport{};
  ExchangeTotals totals;
  exchangeRange<Flat>(texture, k, 0, px_.size(), totals);
  report.absorbed = totals.absorbed;
  report.evaporated = totals.evaporated;
  report.submergedTexels = totals.submerged;
}

template <bool Flat>
Wetting::ExchangeConstants Wetting::prepareExchange(const LiquidTexture& texture, const WettingEnvironment& environment,
                                                    double dt, bool absorbing, bool evaporating) {
  const std::size_t n = px_.size();
  const Eigen::Matrix3d& rotation = environment.pose.rotation;
  const Eigen::Vector3d& translation = environment.pose.translation;
  const LiquidSurface* liquid = absorbing ? environment.liquid : nullptr;
  const auto* flat = dynamic_cast<const FlatSurface*>(liquid);
  const double flowResistance = settings_.viscosity * texture.layerThickness;  // mu L (Pa s m)

  // Sources in the body frame, once per step (kept in a member: the step allocates nothing).
  std::vector<BodySource>& sources = bodySources_;
  sources.clear();
  if (absorbing)
    for (const LiquidSource& source : environment.sources) {
      if (!(source.rate > 0.0)) continue;
      const Eigen::Vector3d fall = source.direction.norm() > 0.0 ? source.direction.normalized() : Eigen::Vector3d(0.0, -1.0, 0.0);
      sources.push_back({source.kind == LiquidSourceKind::Rain, (-(rotation.transpose() * fall)).cast<float>(),
                         (rotation.transpose() * (source.centre - translation)).cast<float>(),
                         static_cast<float>(source.radius * source.radius), static_cast<float>(source.rate * dt),
                         source.pigment});
    }

  // Any other surface than a flat one: its pressure and the submerged mask per texel first, in
  // the scalar pass its virtual call needs; the lane pass then reads them.
  if constexpr (!Flat)
    liquidPressureAtTexels(*liquid, environment, px_.data(), py_.data(), pz_.data(), n, pressure_.data(), submerged_.data());

  ExchangeConstants k;
  k.absorbing = absorbing;
  k.withLiquid = liquid != nullptr;
  // Only the world height matters under a flat surface: one row of the pose, in float. A flat
  // surface's pressure is rho g depth (FlatSurface::pressure; the class is final).
  k.heightRow[0] = static_cast<float>(rotation(1, 0));
  k.heightRow[1] = static_cast<float>(rotation(1, 1));
  k.heightRow[2] = static_cast<float>(rotation(1, 2));
  k.heightRow[3] = static_cast<float>(translation.y() - (flat ? flat->height() : 0.0));
  k.pressurePerDepth = flat ? static_cast<float>(flat->density() * environment.gravity) : 0.0f;
  k.capillary = static_cast<float>(settings_.capillaryPressure);
  k.darcyFactor = static_cast<float>(dt / flowResistance);  // s / (Pa s m)
  const double rate = evaporating && dt > 0.0 ? settings_.evaporationRate() : 0.0;  // m/s, constant-rate stage
  k.evaporationDepth = static_cast<float>(rate * dt);
  k.criticalSaturation = static_cast<float>(settings_.criticalSaturation);
  k.wide = wideLanes();
  return k;
}

namespace {

// What the exchange pass reads and writes, as plain arrays (texel order; `pressure` only off a
// flat surface, `pigment` null without the channel).
template <class Source>
struct ExchangeArrays {
  float* phi;
  float* pigment;
  const float *capacity, *permeability, *area, *px, *py, *pz, *nx, *ny, *nz, *pressure;
  std::uint8_t* submerged;
  const Source* sources;
  std::size_t sourceCount;
};
struct ExchangeSums {
  double absorbed, evaporated;
  std::int64_t submerged;
};

// The per-texel arithmetic of the exchange is in float, the precision the contents are stored
// in, W texels at a time (the stage of a texel is selected, not branched to); the volumes moved
// are summed in double from the stored values, so the balance stays exact to float rounding.
template <bool Flat, std::size_t W, class Constants, class Source>
HYDROTEX_LANE_INLINE ExchangeSums exchangeLanes(const Constants& k, const ExchangeArrays<Source>& in, std::size_t begin,
                                                std::size_t end) {
  using F = typename LaneTypes<W>::F;
  using M = typename LaneTypes<W>::M;
  const F evaporationDepth = splat<F>(k.evaporationDepth), criticalSaturation = splat<F>(k.criticalSaturation);
  const F darcyFactor = splat<F>(k.darcyFactor), capillary = splat<F>(k.capillary), zero = splat<F>(0.0f), one = splat<F>(1.0f);
  float* phi = in.phi;
  float* pigment = in.pigment;
  const float* capacity = in.capacity;
  const float* permeability = in.permeability;
  std::uint8_t* submerged = in.submerged;
  double absorbed = 0.0, evaporated = 0.0;
  F absorbedLanes = zero, evaporatedLanes = zero;  // m^3
  M submergedLanes{};
  const bool evaporating = k.evaporationDepth > 0.0f;
  // A block of `count` texels from i; called with a constant W for whole blocks, so that the
  // loads are single moves there, and once with the rest.
  auto block = [&](std::size_t i, std::size_t count) __attribute__((always_inline)) {
    const F held = load<F>(phi + i, count), full = load<F>(capacity + i, count), area = load<F>(in.area + i, count);
    const M active = area > zero;
    // Under the liquid? (Evaporation alone: the mask of the last absorption.)
    M under;
    F pressure = zero;
    if (!k.withLiquid) {
      under = k.absorbing ? M{} : loadMask<M>(submerged + i, count);
    } else if constexpr (Flat) {
      const F relativeHeight = splat<F>(k.heightRow[0]) * load<F>(in.px + i, count) +
                                   splat<F>(k.heightRow[1]) * load<F>(in.py + i, count) +
                                   splat<F>(k.heightRow[2]) * load<F>(in.pz + i, count) + splat<F>(k.heightRow[3]);
      pressure = splat<F>(-k.pressurePerDepth) * relativeHeight;
      under = pressure > zero;
    } else {
      pressure = load<F>(in.pressure + i, count);
      under = loadMask<M>(submerged + i, count);
    }
    under &= active;
    if (k.absorbing) storeMask(submerged + i, count, under);
    submergedLanes -= under;
    F current = held;
    // Blocks wholly under the liquid or wholly in the air (most are: the waterline crosses few)
    // skip the other stage's arithmetic.
    const M air = active & ~under;
    const bool anyUnder = any(under), anyAir = any(air);
    // One division per block, shared by Darcy's time constant and the falling-rate stage.
    const F inverseFull = one / select(full > zero, full, one);
    if (k.absorbing && anyUnder) {
      // Darcy against the pores' back-pressure: exact exponential approach to capacity.
      const F drive = select(pressure > zero, pressure, zero) + capillary;
      const F exponent = load<F>(permeability + i, count) * drive * darcyFactor * inverseFull;  // dt / tau
      const F darcy = minimum(full, held + (full - held) * oneMinusExpNegative(exponent));
      current = select(under & (full > held), darcy, held);
    }
    if (k.absorbing && anyAir) {
      // In the air: the sources' supply up to capacity (the rest runs off).
      for (std::size_t s = 0; s < in.sourceCount; ++s) {
        const auto& source = in.sources[s];
        F supply;
        if (source.rain) {
          // Rain per horizontal area lands on the texel's projection across the fall direction.
          const F facing = splat<F>(source.up.x()) * load<F>(in.nx + i, count) +
                               splat<F>(source.up.y()) * load<F>(in.ny + i, count) +
                               splat<F>(source.up.z()) * load<F>(in.nz + i, count);
          supply = select(facing > zero, splat<F>(source.depth) * facing, zero);
        } else {
          const F dx = load<F>(in.px + i, count) - splat<F>(source.centre.x());
          const F dy = load<F>(in.py + i, count) - splat<F>(source.centre.y());
          const F dz = load<F>(in.pz + i, count) - splat<F>(source.centre.z());
          supply = select(dx * dx + dy * dy + dz * dz <= splat<F>(source.radiusSquared), splat<F>(source.depth), zero);
        }
        const F stored = minimum(current + supply, full);
        const M takes = air & (stored > current);
        if (pigment) {
          const F carried = (stored - current) * splat<F>(static_cast<float>(source.pigment));
          store(pigment + i, count, load<F>(pigment + i, count) + select(takes, carried, zero));
        }
        current = select(takes, stored, current);
      }
    }
    absorbedLanes += (current - held) * area;
    if (evaporating && anyAir) {
      // Constant rate through the whole step while the content stays above the critical one;
      // otherwise constant rate until it reaches it (none when it starts below), then first
      // order for the rest of the step (Hall and Hoff's two stages, both integrated exactly).
      const F critical = criticalSaturation * full;
      const F constantNext = current - evaporationDepth;
      const M hasCritical = critical > zero;
      const F inverseCritical = select(hasCritical, inverseFull * splat<F>(1.0f / k.criticalSaturation), one);
      const F above = current - critical;
      const F fallingExponent = (evaporationDepth - select(above > zero, above, zero)) * inverseCritical;
      // The falling-rate stage's exponential only when a lane reaches it.
      const M reaches = ~(constantNext >= critical) & hasCritical & active & ~under;
      const F falling = any(reaches) ? minimum(current, critical) * expNegative(fallingExponent) : splat<F>(0.0f);
      const F constant = select(constantNext > zero, constantNext, zero);
      const F dried = select((constantNext >= critical) | ~hasCritical, constant, falling);
      const F next = select(active & ~under, dried, current);
      evaporatedLanes += (current - next) * area;
      current = next;
    }
    store(phi + i, count, current);
  };
  // The float lane sums go to double every 16 blocks: at most 16 float roundings (1e-6
  // relative) in any change counted.
  constexpr std::size_t kFlush = 16 * W;
  std::size_t i = begin;
  for (; i + W <= end;) {
    const std::size_t stop = std::min(end - (end - i) % W, i + kFlush);
    for (; i < stop; i += W) {
      // The pass reads ten streams at once, more than the hardware prefetcher follows well:
      // each is asked for 1 KiB ahead, once per 64-byte line (3 to 6 % of a step, measured).
      if ((i & 15) == 0) {
        constexpr std::size_t kAhead = 256;
        const float* streams[] = {phi, in.capacity, in.area, in.px, in.py, in.pz, in.nx, in.ny, in.nz, in.permeability};
        for (const float* stream : streams)
          __builtin_prefetch(stream + i + kAhead);
      }
      block(i, W);
    }
    absorbed += volumeSum(absorbedLanes);
    evaporated += volumeSum(evaporatedLanes);
    absorbedLanes = evaporatedLanes = zero;
  }
  if (i < end) block(i, end - i);
  absorbed += volumeSum(absorbedLanes);
  evaporated += volumeSum(evaporatedLanes);
  return {absorbed, evaporated, horizontalSum(submergedLanes)};
}

#if defined(__x86_64__) && defined(__GNUC__)
// Eight lanes where the processor has AVX2: the same kernel, compiled for it (no FMA, so every
// lane rounds as the four-lane code does).
template <bool Flat, class Constants, class Source>
__attribute__((target("avx2"))) ExchangeSums exchangeLanesAvx2(const Constants& k, const ExchangeArrays<Source>& in,
                                                                std::size_t begin, std::size_t end) {
  return exchangeLanes<Flat, 8>(k, in, begin, end);
}
#endif

// What the explicit sweep's lane blocks read and write (Wetting::sweep explains the ring).
struct SweepBlockArrays {
  const float *next, *other;
  const std::uint32_t* offset;
  const float* inverseArea;
  float* phi;
  float* ring;
  std::size_t mask;
  const std::uint32_t *extraFirst, *extraSecond;
  const float* extraConductance;
  std::size_t extras;
};

// W texels at a time from `i` while the next block exists (below `end`): their fluxes to the
// next texel from one shifted load, to the other pair's texel from one load when all W share
// the offset (inside a chart: the texel one row below) or a gather (chart borders); the ring is
// read after the block has sent its own (a pair inside the block lands there). Returns where the
// scalar code goes on.
template <std::size_t W>
HYDROTEX_LANE_INLINE std::size_t sweepBlocks(const SweepBlockArrays& a, float step, std::size_t i, std::size_t end,
                                             std::size_t& extra, float& carried) {
  using F = typename LaneTypes<W>::F;
  using M = typename LaneTypes<W>::M;
  constexpr int kAll = (1 << W) - 1;
  const F stepLanes = splat<F>(step);
  for (; i + W < end; i += W) {
    const F phiBlock = load<F>(a.phi + i, W);
    const F toNext = stepLanes * load<F>(a.next + i, W) * (phiBlock - load<F>(a.phi + i + 1, W));
    const std::uint32_t firstOffset = a.offset[i];
    M offsets;
    std::memcpy(&offsets, a.offset + i, sizeof offsets);
    const std::size_t otherSlot = (i + firstOffset) & a.mask;
    F toOther;
    if (laneBits(offsets == M{} + static_cast<std::int32_t>(firstOffset)) == kAll && otherSlot + W <= a.mask + 1) {
      toOther = stepLanes * load<F>(a.other + i, W) * (phiBlock - load<F>(a.phi + i + firstOffset, W));
      store(a.ring + otherSlot, W, load<F>(a.ring + otherSlot, W) + toOther);
    } else {
      F otherPhi;
      std::size_t otherIndex[W];
      for (std::size_t k = 0; k < W; ++k) {
        otherIndex[k] = i + k + a.offset[i + k];
        otherPhi[k] = a.phi[otherIndex[k]];
      }
      toOther = stepLanes * load<F>(a.other + i, W) * (phiBlock - otherPhi);
      for (std::size_t k = 0; k < W; ++k) a.ring[otherIndex[k] & a.mask] += toOther[k];
    }
    F extraDelta{};
    for (; extra < a.extras && a.extraFirst[extra] < i + W; ++extra) {
      const std::uint32_t from = a.extraFirst[extra], j = a.extraSecond[extra];
      const float flux = step * a.extraConductance[extra] * (a.phi[from] - a.phi[j]);
      extraDelta[from - i] -= flux;
      a.ring[j & a.mask] += flux;
    }
    const F received = load<F>(a.ring + (i & a.mask), W);
    store(a.ring + (i & a.mask), W, F{});
    F fromPrevious;
    fromPrevious[0] = carried;
    for (std::size_t k = 1; k < W; ++k) fromPrevious[k] = toNext[k - 1];
    carried = toNext[W - 1];
    const F delta = received + fromPrevious - toNext - toOther + extraDelta;
    const F updated = phiBlock + delta * load<F>(a.inverseArea + i, W);
    store(a.phi + i, W, select(updated > F{}, updated, F{}));
  }
  return i;
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) std::size_t sweepBlocksAvx2(const SweepBlockArrays& a, float step, std::size_t i,
                                                             std::size_t end, std::size_t& extra, float& carried) {
  return sweepBlocks<8>(a, step, i, end, extra, carried);
}
#endif

}  // namespace


template <bool Flat>
void Wetting::exchangeRange(LiquidTexture& texture, const ExchangeConstants& k, std::size_t begin, std::size_t end,
                            ExchangeTotals& totals) {
  const ExchangeArrays<BodySource> in{texture.liquid.data(), texture.pigment.empty() ? nullptr : texture.pigment.data(),
                                      texture.capacity.data(), texture.permeability.data(), area_.data(), px_.data(),
                                      py_.data(), pz_.data(), nx_.data(), ny_.data(), nz_.data(), pressure_.data(),
                                      submerged_.data(), bodySources_.data(), bodySources_.size()};
  ExchangeSums sums;
#if defined(__x86_64__) && defined(__GNUC__)
  if (k.wide)
    sums = exchangeLanesAvx2<Flat>(k, in, begin, end);
  else
#endif
    sums = exchangeLanes<Flat, kLaneCount>(k, in, begin, end);
  totals.absorbed += sums.absorbed;
  totals.evaporated += sums.evaporated;
  totals.submerged += static_cast<std::size_t>(sums.submerged);
}

void Wetting::poolGroups(LiquidTexture& texture) const {
  for (std::size_t k = 0; k + 1 < groups_.start.size(); ++k) poolGroup(texture, k);
}

void Wetting::poolGroup(LiquidTexture& texture, std::size_t k) const {
  double volume = 0.0, pigment = 0.0;
  for (std::uint32_t m = groups_.start[k]; m < groups_.start[k + 1]; ++m) {
    const std::uint32_t i = groups_.members[m];
    volume += static_cast<double>(texture.liquid[i]) * adjacency_.area[i];
    if (!texture.pigment.empty()) pigment += static_cast<double>(texture.pigment[i]) * adjacency_.area[i];
  }
  const std::uint32_t holder = groups_.members[groups_.start[k]];
  texture.liquid[holder] = static_cast<float>(volume / groups_.nodeArea[holder]);
  if (!texture.pigment.empty()) texture.pigment[holder] = static_cast<float>(pigment / groups_.nodeArea[holder]);
}

void Wetting::spreadGroups(LiquidTexture& texture) const {
  for (std::size_t k = 0; k + 1 < groups_.start.size(); ++k) {
    const std::uint32_t holder = groups_.members[groups_.start[k]];
    for (std::uint32_t m = groups_.start[k] + 1; m < groups_.start[k + 1]; ++m) {
      texture.liquid[groups_.members[m]] = texture.liquid[holder];
      if (!texture.pigment.empty()) texture.pigment[groups_.members[m]] = texture.pigment[holder];
    }
  }
}

int Wetting::diffuse(LiquidTexture& texture, double dt) {
  const int substeps = explicitSubsteps(dt);
  if (substeps == 0) return 0;
  poolGroups(texture);
  if (substeps > 0)
    for (int k = 0; k < substeps; ++k) diffuseExplicit(texture, dt / substeps);
  else
    diffuseImplicit(texture, dt);
  spreadGroups(texture);
  return std::max(substeps, 0);
}

void Wetting::diffuseExplicit(LiquidTexture& texture, double dt) {
  if (texture.pigment.empty())
    sweep<false>(texture, static_cast<float>(dt), [](std::size_t) {});
  else
    sweep<true>(texture, static_cast<float>(dt), [](std::size_t) {});
}

template <bool WithPigment, class Ahead>
void Wetting::sweep(LiquidTexture& texture, float step, Ahead&& ahead) {
  // One forward pass: texel i receives, from a ring, the fluxes its lower neighbours sent it,
  // sends its own to its higher neighbours (from the contents before this sub-step: theirs are not
  // yet updated, its own is updated only now) and is then final. Each pair's flux is formed once
  // and moved with opposite signs, so the volume is conserved to the rounding of the sums.
  const std::size_t n = nextConductance_.size();
  const float* next = nextConductance_.data();
  const float* other = otherConductance_.data();
  const std::uint32_t* offset = otherOffset_.data();
  const float* inverseArea = inverseNodeArea_.data();
  float* phi = texture.liquid.data();
  float* pigment = WithPigment ? texture.pigment.data() : nullptr;
  float* ring = ring_.data();
  float* pigmentRing = pigmentRing_.data();
  const std::size_t mask = ring_.size() - 1;
  std::size_t extra = 0;
  const std::size_t extras = extraFirst_.size();
  // The pigment travels with the liquid, at the concentration of the texel it leaves (upwind).
  auto pigmentFlux = [&](std::size_t i, std::size_t j, float flux) {
    const float fromPhi = flux > 0.0f ? phi[i] : phi[j], fromPigment = flux > 0.0f ? pigment[i] : pigment[j];
    return flux * (fromPhi > 0.0f ? fromPigment / fromPhi : 0.0f);
  };
  // The flux to the next texel is carried in a register: through the ring it would make every
  // texel wait for the previous one's store. A missing pair has conductance 0 (and the other
  // slot offset 0: a zero flux to itself), so the common case has no branch.
  float carried = 0.0f, pigmentCarried = 0.0f;
  const bool wide = wideLanes();
  const SweepBlockArrays blocks{next, other, offset, inverseArea, phi, ring, mask,
                                extraFirst_.data(), extraSecond_.data(), extraConductance_.data(), extras};
  constexpr std::size_t kChunk = 256;
  for (std::size_t chunk = 0; chunk < n; chunk += kChunk) {
    const std::size_t chunkEnd = std::min(n, chunk + kChunk);
    ahead(chunkEnd);
    std::size_t i = chunk;
    if constexpr (!WithPigment) {
#if defined(__x86_64__) && defined(__GNUC__)
      if (wide)
        i = sweepBlocksAvx2(blocks, step, i, std::min(n, chunkEnd + 1), extra, carried);
      else
#endif
        i = sweepBlocks<kLaneCount>(blocks, step, i, std::min(n, chunkEnd + 1), extra, carried);
    }
    for (; i < chunkEnd; ++i) {
      const float phiI = phi[i];
      const std::size_t nextIndex = i + 1 < n ? i + 1 : i, otherIndex = i + offset[i];
      const float toNext = step * next[i] * (phiI - phi[nextIndex]);  // m^3 from i to i + 1
      const float toOther = step * other[i] * (phiI - phi[otherIndex]);
      float delta = ring[i & mask] + carried - toNext - toOther;
      ring[i & mask] = 0.0f;
      ring[otherIndex & mask] += toOther;
      carried = toNext;
      float pigmentDelta = 0.0f;
      if constexpr (WithPigment) {
        const float movedNext = pigmentFlux(i, nextIndex, toNext), movedOther = pigmentFlux(i, otherIndex, toOther);
        pigmentDelta = pigmentRing[i & mask] + pigmentCarried - movedNext - movedOther;
        pigmentRing[i & mask] = 0.0f;
        pigmentRing[otherIndex & mask] += movedOther;
        pigmentCarried = movedNext;
      }
      for (; extra < extras && extraFirst_[extra] == i; ++extra) {
        const std::uint32_t j = extraSecond_[extra];
        const float flux = step * extraConductance_[extra] * (phiI - phi[j]);
        delta -= flux;
        ring[j & mask] += flux;
        if constexpr (WithPigment) {
          const float moved = pigmentFlux(i, j, flux);
          pigmentDelta -= moved;
          pigmentRing[j & mask] += moved;
        }
      }
      phi[i] = std::max(0.0f, phiI + delta * inverseArea[i]);
      if constexpr (WithPigment) pigment[i] = std::max(0.0f, pigment[i] + pigmentDelta * inverseArea[i]);
    }
  }
}

void Wetting::diffuseImplicit(LiquidTexture& texture, double dt) {
  const std::size_t n = groups_.nodeArea.size();
  ImplicitSystem& system = *implicit_;
  if (system.dt != dt) {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(n + 4 * groups_.pairFirst.size());
    for (std::size_t i = 0; i < n; ++i)
      // A texel without area (or inside a group) has no pairs; a unit diagonal keeps the matrix regular.
      entries.emplace_back(static_cast<int>(i), static_cast<int>(i), groups_.nodeArea[i] > 0.0 ? groups_.nodeArea[i] : 1.0);
    for (std::size_t p = 0; p < groups_.pairFirst.size(); ++p) {
      const int i = static_cast<int>(groups_.pairFirst[p]), j = static_cast<int>(groups_.pairSecond[p]);
      const double c = dt * settings_.diffusivity * groups_.pairGeometric[p];
      entries.emplace_back(i, i, c);
      entries.emplace_back(j, j, c);
      entries.emplace_back(i, j, -c);
      entries.emplace_back(j, i, -c);
    }
    system.matrix.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    system.matrix.setFromTriplets(entries.begin(), entries.end());
    // The pair fluxes conserve the volume whatever the residual, but dividing by small texels'
    // areas amplifies it: 1e-10 keeps phi within 1e-4 of backward Euler's at any dt.
    system.solver.setTolerance(1e-10);
    system.solver.setMaxIterations(std::max<Eigen::Index>(100, static_cast<Eigen::Index>(n)));
    system.solver.compute(system.matrix);
    system.dt = dt;
  }
  system.rhs.resize(static_cast<Eigen::Index>(n));
  system.start.resize(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    system.start[static_cast<Eigen::Index>(i)] = texture.liquid[i];
    system.rhs[static_cast<Eigen::Index>(i)] = (groups_.nodeArea[i] > 0.0 ? groups_.nodeArea[i] : 1.0) * texture.liquid[i];
  }
  system.solution = system.solver.solveWithGuess(system.rhs, system.start);
  system.flux.resize(groups_.pairFirst.size());
  for (std::size_t p = 0; p < system.flux.size(); ++p)
    system.flux[p] = dt * settings_.diffusivity * groups_.pairGeometric[p] *
                     (system.solution[groups_.pairFirst[p]] - system.solution[groups_.pairSecond[p]]);
  applyPairFluxes(texture);
}

void Wetting::applyPairFluxes(LiquidTexture& texture) {
  const std::size_t n = groups_.nodeArea.size();
  std::vector<double>& flux = implicit_->flux;
  std::vector<double>& volume = implicit_->volume;
  std::vector<double>& pigment = implicit_->pigment;
  volume.resize(n);
  pigment.resize(texture.pigment.size());
  for (std::size_t i = 0; i < n; ++i) volume[i] = texture.liquid[i] * groups_.nodeArea[i];
  for (std::size_t i = 0; i < pigment.size(); ++i) pigment[i] = texture.pigment[i] * groups_.nodeArea[i];
  for (std::size_t p = 0; p < flux.size(); ++p) {
    const std::uint32_t i = groups_.pairFirst[p], j = groups_.pairSecond[p];
    volume[i] -= flux[p];
    volume[j] += flux[p];
    if (!pigment.empty()) {
      const std::uint32_t from = flux[p] > 0.0 ? i : j;
      const double concentration = texture.liquid[from] > 0.0f ? double(texture.pigment[from]) / texture.liquid[from] : 0.0;
      pigment[i] -= flux[p] * concentration;
      pigment[j] += flux[p] * concentration;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!(groups_.nodeArea[i] > 0.0)) continue;
    // A solver residual can leave a texel a rounding below zero; that is dropped, not stored.
    texture.liquid[i] = static_cast<float>(std::max(0.0, volume[i] / groups_.nodeArea[i]));
    if (!pigment.empty()) texture.pigment[i] = static_cast<float>(std::max(0.0, pigment[i] / groups_.nodeArea[i]));
  }
}

template void Wetting::exchange<true>(LiquidTexture&, const WettingEnvironment&, double, bool, bool, WettingStepReport&);
template void Wetting::exchange<false>(LiquidTexture&, const WettingEnvironment&, double, bool, bool, WettingStepReport&);

}  // namespace hydrotex
