// The liquid texture step (paper section 4.2).
//  - Absorption: Darcy's law (paper eq. 9, Muskat), flux per area q = k dp / (mu L). The pores'
//    back-pressure grows with their saturation S, dp = P (1 - S), so under a constant head P a
//    texel fills as S(t) = 1 - exp(-t / tau), tau = mu L C / (k P) (REFERENCES.md "compartment
//    filling"); integrated exactly over the step, so it is stable at any dt.
//  - Diffusion: Fick's first law J = -D grad phi on the texel graph (TexelAdjacency), written as
//    antisymmetric pair fluxes F_ij = D g_ij (phi_i - phi_j) dt so that every volume leaving one
//    texel enters another (seams included). Explicit sub-steps while dt / (min_i A_i / sum_j D g_ij)
//    is small (that bound keeps phi >= 0, REFERENCES.md), backward Euler otherwise: (M + dt D L)
//    phi' = M phi solved by conjugate gradients (the matrix is symmetric positive definite), then
//    the pair fluxes of phi' are applied to phi, so the volume is conserved whatever the solver's
//    residual.
//  - Stiff texels: the explicit bound is set by the smallest A_i / sum_j g_ij. Slivers at chart
//    borders and the squeezed texels near a UV sphere's poles make it tiny, so they are merged
//    with their most strongly coupled neighbour into one control volume (the finite-volume
//    "cell agglomeration" of cut-cell methods) until the group meets a fraction of the median
//    bound: their own equilibration time is far below any step, so a shared content is what
//    backward Euler would give them anyway, and the group's volume is conserved.
//  - Evaporation: Hall and Hoff (2009, "Water Transport in Brick, Stone and Concrete", paper eq.
//    10), e = D_w (p_sat M / (R tau)) dH/dx with dH/dx = (1 - H) / boundary layer, per unit area,
//    while the surface is wet (constant-rate stage); below a critical saturation the liquid must
//    first reach the surface and the rate falls in proportion to saturation (falling-rate stage,
//    first-order drying). Both stages are integrated exactly over the step.
#include "hydrotex/Wetting.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <string>

namespace hydrotex {

namespace {

constexpr double kGasConstant = 8.314462618;  // J / (mol K)

// Saturation vapour pressure of water (Pa) at `kelvin`: Magnus form, Alduchov and Eskridge 1996.
double saturationVapourPressure(double kelvin) {
  const double celsius = kelvin - 273.15;
  return 610.94 * std::exp(17.625 * celsius / (celsius + 243.04));
}

bool finitePositive(double x) { return std::isfinite(x) && x > 0.0; }

// exp(-x) for 0 <= x (NaN excluded) in float, the precision the contents are stored in: x =
// k ln 2 + r with |r| <= ln 2 / 2, e^r by its Taylor series to r^6 (remainder 0.35^7 / 7! <
// 1.3e-8), 2^-k set in the exponent bits. Several times cheaper than std::exp, and the per-texel
// pass runs one for every submerged or drying texel.
inline float expNegative(float x) {
  x = std::min(x, 80.0f);  // e^-80 = 2e-35: nothing left of a content in metres
  constexpr float kLn2 = 0.693147181f, kInvLn2 = 1.44269504f;
  // Rounded to nearest by truncation of a positive number (nearbyint is a library call on SSE2).
  const float k = static_cast<float>(static_cast<std::int32_t>(x * kInvLn2 + 0.5f));
  const float r = k * kLn2 - x;
  float p = 1.0f / 720.0f;
  p = p * r + 1.0f / 120.0f;
  p = p * r + 1.0f / 24.0f;
  p = p * r + 1.0f / 6.0f;
  p = p * r + 0.5f;
  p = p * r + 1.0f;
  p = p * r + 1.0f;
  const auto exponent = static_cast<std::uint32_t>(127 - static_cast<std::int32_t>(k)) << 23;
  float scale;
  std::memcpy(&scale, &exponent, sizeof scale);
  return p * scale;
}

// 1 - e^-x in float, without the cancellation of 1 - expNegative(x) for small x (a short step
// under water): series to x^4 below 0.03 (remainder x^5 / 120 < 7e-9 relative to x).
inline float oneMinusExpNegative(float x) {
  if (x < 0.03f) return x * (1.0f - x * (0.5f - x * (1.0f / 6.0f - x * (1.0f / 24.0f))));
  return 1.0f - expNegative(x);
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
  w.delta_.assign(n, 0.0f);
  w.adjacency_ = std::move(adjacency);
  w.buildDiffusionGroups();
  w.implicit_ = std::make_unique<ImplicitSystem>();
  return w;
}

void Wetting::buildDiffusionGroups() {
  const TexelAdjacency& g = adjacency_;
  const std::size_t n = g.area.size(), pairs = g.pairCount();
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  if (settings_.mergeBelowFraction > 0.0 && pairs > 0) {
    // Bound per texel (s * D): A_i / sum_j g_ij; the merge threshold is a fraction of the median.
    std::vector<double> bounds;
    bounds.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
      if (g.area[i] > 0.0 && g.conductanceSum[i] > 0.0) bounds.push_back(g.area[i] / g.conductanceSum[i]);
    std::nth_element(bounds.begin(), bounds.begin() + static_cast<std::ptrdiff_t>(bounds.size() / 2), bounds.end());
    const double threshold = settings_.mergeBelowFraction * bounds[bounds.size() / 2];
    std::vector<double> area(n), conductance(n), strongest(n);
    std::vector<std::uint32_t> partner(n);
    std::vector<std::uint8_t> merged(n);
    // Each pass pairs every stiff group with its most strongly coupled neighbour group (each group
    // joins at most one merge per pass, so groups grow by doubling, not by chains); 32 passes allow
    // groups of 2^32 texels, more than any texture holds.
    for (int pass = 0; pass < 32; ++pass) {
      std::fill(area.begin(), area.end(), 0.0);
      std::fill(conductance.begin(), conductance.end(), 0.0);
      std::fill(strongest.begin(), strongest.end(), 0.0);
      std::fill(merged.begin(), merged.end(), std::uint8_t{0});
      for (std::uint32_t i = 0; i < n; ++i) area[find(i)] += g.area[i];
      for (std::size_t p = 0; p < pairs; ++p) {
        const std::uint32_t a = find(g.first[p]), b = find(g.second[p]);
        if (a == b) continue;
        conductance[a] += g.conductance[p];
        conductance[b] += g.conductance[p];
        if (g.conductance[p] > strongest[a]) strongest[a] = g.conductance[p], partner[a] = b;
        if (g.conductance[p] > strongest[b]) strongest[b] = g.conductance[p], partner[b] = a;
      }
      bool any = false;
      for (std::uint32_t r = 0; r < n; ++r) {
        if (parent[r] != r || merged[r] || !(conductance[r] > 0.0) || area[r] >= threshold * conductance[r]) continue;
        const std::uint32_t other = partner[r];
        if (merged[other]) continue;
        // The larger group holds the union, so that the holding texel stays inside the bulk.
        const bool keep = area[r] >= area[other];
        parent[keep ? other : r] = keep ? r : other;
        merged[r] = merged[other] = 1;
        any = true;
      }
      if (!any) break;
    }
  }
  // Groups: the holding texel is the root; members listed after it.
  std::vector<std::uint32_t> count(n, 0);
  for (std::uint32_t i = 0; i < n; ++i) ++count[find(i)];
  nodeArea_.assign(n, 0.0);
  for (std::uint32_t i = 0; i < n; ++i) nodeArea_[find(i)] += g.area[i];
  groupStart_.clear();
  groupMembers_.clear();
  std::vector<std::uint32_t> slot(n, 0);
  for (std::uint32_t r = 0; r < n; ++r)
    if (parent[r] == r && count[r] > 1) {
      groupStart_.push_back(static_cast<std::uint32_t>(groupMembers_.size()));
      slot[r] = static_cast<std::uint32_t>(groupMembers_.size());
      groupMembers_.resize(groupMembers_.size() + count[r]);
      groupMembers_[slot[r]++] = r;
    }
  if (!groupStart_.empty()) groupStart_.push_back(static_cast<std::uint32_t>(groupMembers_.size()));
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t r = find(i);
    if (r != i && count[r] > 1) groupMembers_[slot[r]++] = i;
  }
  inverseNodeArea_.resize(n);
  for (std::size_t i = 0; i < n; ++i) inverseNodeArea_[i] = nodeArea_[i] > 0.0 ? static_cast<float>(1.0 / nodeArea_[i]) : 0.0f;
  // Pairs between groups, on their holding texels; internal pairs carry nothing (equal contents).
  pairFirst_.clear();
  pairSecond_.clear();
  pairGeometric_.clear();
  std::vector<double> conductanceSum(n, 0.0);
  for (std::size_t p = 0; p < pairs; ++p) {
    const std::uint32_t a = find(g.first[p]), b = find(g.second[p]);
    if (a == b) continue;
    pairFirst_.push_back(a);
    pairSecond_.push_back(b);
    pairGeometric_.push_back(g.conductance[p]);
    conductanceSum[a] += g.conductance[p];
    conductanceSum[b] += g.conductance[p];
  }
  pairConductance_.resize(pairGeometric_.size());
  for (std::size_t p = 0; p < pairGeometric_.size(); ++p)
    pairConductance_[p] = static_cast<float>(settings_.diffusivity * pairGeometric_[p]);
  stableStep_ = std::numeric_limits<double>::infinity();
  if (settings_.diffusivity > 0.0)
    for (std::size_t i = 0; i < n; ++i)
      if (conductanceSum[i] > 0.0) stableStep_ = std::min(stableStep_, nodeArea_[i] / (settings_.diffusivity * conductanceSum[i]));
}

Expected<WettingStepReport> Wetting::step(LiquidTexture& texture, const WettingEnvironment& environment, double dt) {
  const std::size_t n = adjacency_.area.size();
  if (texture.liquid.size() != n || texture.capacity.size() != n || texture.permeability.size() != n ||
      (!texture.pigment.empty() && texture.pigment.size() != n))
    return Error{"wetting: liquid texture has " + std::to_string(texture.liquid.size()) + " texels, the body " +
                 std::to_string(n)};
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
  WettingStepReport report;
  if (dynamic_cast<const FlatSurface*>(environment.liquid) || !environment.liquid)
    exchange<true>(texture, environment, dt, true, true, report);
  else
    exchange<false>(texture, environment, dt, true, true, report);
  report.diffusionSubsteps = diffuse(texture, dt);
  report.implicitDiffusion = report.diffusionSubsteps == 0 && dt > 0.0 && !pairFirst_.empty() &&
                             settings_.diffusivity > 0.0;
  return report;
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
  const std::size_t n = px_.size();
  const Eigen::Matrix3d& rotation = environment.pose.rotation;
  const Eigen::Vector3d& translation = environment.pose.translation;
  const LiquidSurface* liquid = absorbing ? environment.liquid : nullptr;
  // Only the world height matters under a flat surface: one row of the pose, in float.
  const float r0 = static_cast<float>(rotation(1, 0)), r1 = static_cast<float>(rotation(1, 1)),
              r2 = static_cast<float>(rotation(1, 2)), ty = static_cast<float>(translation.y());
  const auto* flat = dynamic_cast<const FlatSurface*>(liquid);
  const double surfaceHeight = flat ? flat->height() : 0.0;
  const double pressurePerDepth = flat ? flat->density() * environment.gravity : 0.0;
  const double highest = liquid ? (liquid->hasFreeSurface() ? liquid->heightRange(environment.time).second
                                                            : std::numeric_limits<double>::infinity())
                                : -std::numeric_limits<double>::infinity();
  const bool freeSurface = liquid && liquid->hasFreeSurface();
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

  const double rate = evaporating && dt > 0.0 ? settings_.evaporationRate() : 0.0;  // m/s, constant-rate stage
  // The per-texel arithmetic is in float, the precision the contents are stored in; the volumes
  // moved are summed in double from the stored values, so the balance stays exact.
  const float evaporationDepth = static_cast<float>(rate * dt);
  const float criticalSaturation = static_cast<float>(settings_.criticalSaturation);
  const float darcyFactor = static_cast<float>(dt / flowResistance);  // s / (Pa s m)
  const float capillary = static_cast<float>(settings_.capillaryPressure);
  const float* capacity = texture.capacity.data();
  const float* permeability = texture.permeability.data();
  float* phi = texture.liquid.data();
  float* pigment = texture.pigment.empty() ? nullptr : texture.pigment.data();
  const double* area = adjacency_.area.data();
  std::uint8_t* submerged = submerged_.data();
  double absorbed = 0.0, evaporated = 0.0;
  std::size_t submergedCount = 0;

  for (std::size_t i = 0; i < n; ++i) {
    if (!(area[i] > 0.0)) continue;
    const float held = phi[i];
    const float full = capacity[i];
    // Under the liquid?
    bool under = false;
    double pressure = 0.0;
    if (liquid) {
      if constexpr (Flat) {
        const float y = r0 * px_[i] + r1 * py_[i] + r2 * pz_[i] + ty;
        // A flat surface's pressure is rho g depth (FlatSurface::pressure; the class is final).
        pressure = pressurePerDepth * (surfaceHeight - static_cast<double>(y));
        under = pressure > 0.0;
      } else {
        const Eigen::Vector3d world = rotation * Eigen::Vector3d(px_[i], py_[i], pz_[i]) + translation;
        if (world.y() <= highest) {
          pressure = liquid->pressure(world, environment.time, environment.gravity);
          under = !freeSurface || pressure > 0.0;
        }
      }
    } else if (!absorbing) {
      under = submerged[i] != 0;  // evaporation alone: the mask of the last absorption
    }
    if (absorbing) submerged[i] = under ? 1 : 0;
    if (under) {
      ++submergedCount;
      if (!absorbing || !(full > held)) continue;
      // Darcy against the pores' back-pressure: exact exponential approach to capacity.
      const float drive = static_cast<float>(std::max(pressure, 0.0)) + capillary;
      const float exponent = permeability[i] * drive * darcyFactor / full;  // dt / tau
      const float stored = std::min(full, held + (full - held) * oneMinusExpNegative(exponent));
      absorbed += (static_cast<double>(stored) - held) * area[i];
      phi[i] = stored;
      continue;
    }
    // In the air: the sources' supply up to capacity (the rest runs off), then drying.
    float current = held;
    for (const BodySource& source : sources) {
      float supply;
      if (source.rain) {
        // Rain per horizontal area lands on the texel's projection across the fall direction.
        const float facing = nx_[i] * source.up.x() + ny_[i] * source.up.y() + nz_[i] * source.up.z();
        if (facing <= 0.0f) continue;
        supply = source.depth * facing;
      } else {
        const float dx = px_[i] - source.centre.x(), dy = py_[i] - source.centre.y(), dz = pz_[i] - source.centre.z();
        if (dx * dx + dy * dy + dz * dz > source.radiusSquared) continue;
        supply = source.depth;
      }
      const float stored = std::min(current + supply, full);
      if (!(stored > current)) continue;
      if (pigment) pigment[i] += static_cast<float>((static_cast<double>(stored) - current) * source.pigment);
      current = stored;
    }
    if (current != held) {
      absorbed += (static_cast<double>(current) - held) * area[i];
      phi[i] = current;
    }
    if (!(evaporationDepth > 0.0f)) continue;
    // Written without branches (the stage changes from texel to texel): constant rate through the
    // whole step while the content stays above the critical one; otherwise constant rate until it
    // reaches it (none when it starts below), then first order for the rest of the step.
    const float critical = criticalSaturation * full;
    const float constantNext = current - evaporationDepth;
    const float safeCritical = critical > 0.0f ? critical : 1.0f;
    const float fallingExponent = (evaporationDepth - std::max(0.0f, current - critical)) / safeCritical;
    const float falling = std::min(current, critical) * expNegative(std::max(0.0f, fallingExponent));
    const float next = constantNext >= critical || critical <= 0.0f ? std::max(0.0f, constantNext) : falling;
    evaporated += (static_cast<double>(current) - next) * area[i];
    phi[i] = next;
  }
  report.absorbed = absorbed;
  report.evaporated = evaporated;
  report.submergedTexels = submergedCount;
}

void Wetting::poolGroups(LiquidTexture& texture) const {
  for (std::size_t k = 0; k + 1 < groupStart_.size(); ++k) {
    double volume = 0.0, pigment = 0.0;
    for (std::uint32_t m = groupStart_[k]; m < groupStart_[k + 1]; ++m) {
      const std::uint32_t i = groupMembers_[m];
      volume += static_cast<double>(texture.liquid[i]) * adjacency_.area[i];
      if (!texture.pigment.empty()) pigment += static_cast<double>(texture.pigment[i]) * adjacency_.area[i];
    }
    const std::uint32_t holder = groupMembers_[groupStart_[k]];
    texture.liquid[holder] = static_cast<float>(volume / nodeArea_[holder]);
    if (!texture.pigment.empty()) texture.pigment[holder] = static_cast<float>(pigment / nodeArea_[holder]);
  }
}

void Wetting::spreadGroups(LiquidTexture& texture) const {
  for (std::size_t k = 0; k + 1 < groupStart_.size(); ++k) {
    const std::uint32_t holder = groupMembers_[groupStart_[k]];
    for (std::uint32_t m = groupStart_[k] + 1; m < groupStart_[k + 1]; ++m) {
      texture.liquid[groupMembers_[m]] = texture.liquid[holder];
      if (!texture.pigment.empty()) texture.pigment[groupMembers_[m]] = texture.pigment[holder];
    }
  }
}

int Wetting::diffuse(LiquidTexture& texture, double dt) {
  if (!(dt > 0.0) || pairFirst_.empty() || !(settings_.diffusivity > 0.0)) return 0;
  poolGroups(texture);
  const double substeps = std::ceil(dt / stableStep_);
  int count = 0;
  if (substeps <= settings_.maxExplicitSubsteps) {
    count = std::max(1, static_cast<int>(substeps));
    for (int k = 0; k < count; ++k) diffuseExplicit(texture, dt / count);
  } else {
    diffuseImplicit(texture, dt);
  }
  spreadGroups(texture);
  return count;
}

void Wetting::diffuseExplicit(LiquidTexture& texture, double dt) {
  const std::size_t pairs = pairConductance_.size();
  const std::uint32_t* first = pairFirst_.data();
  const std::uint32_t* second = pairSecond_.data();
  const float* conductance = pairConductance_.data();
  float* phi = texture.liquid.data();
  float* delta = delta_.data();
  const float step = static_cast<float>(dt);
  const bool withPigment = !texture.pigment.empty();
  if (withPigment) pigmentDelta_.assign(delta_.size(), 0.0f);
  for (std::size_t p = 0; p < pairs; ++p) {
    const std::uint32_t i = first[p], j = second[p];
    const float flux = step * conductance[p] * (phi[i] - phi[j]);  // m^3 from i to j
    delta[i] -= flux;
    delta[j] += flux;
    if (withPigment) {
      // The pigment travels with the liquid, at the concentration of the texel it leaves (upwind).
      const std::uint32_t from = flux > 0.0f ? i : j;
      const float concentration = phi[from] > 0.0f ? texture.pigment[from] / phi[from] : 0.0f;
      pigmentDelta_[i] -= flux * concentration;
      pigmentDelta_[j] += flux * concentration;
    }
  }
  const std::size_t n = delta_.size();
  const float* inverseArea = inverseNodeArea_.data();
  for (std::size_t i = 0; i < n; ++i) {
    phi[i] = std::max(0.0f, phi[i] + delta[i] * inverseArea[i]);
    delta[i] = 0.0f;
  }
  if (withPigment)
    for (std::size_t i = 0; i < n; ++i) texture.pigment[i] = std::max(0.0f, texture.pigment[i] + pigmentDelta_[i] * inverseArea[i]);
}

void Wetting::diffuseImplicit(LiquidTexture& texture, double dt) {
  const std::size_t n = nodeArea_.size();
  ImplicitSystem& system = *implicit_;
  if (system.dt != dt) {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(n + 4 * pairFirst_.size());
    for (std::size_t i = 0; i < n; ++i)
      // A texel without area (or inside a group) has no pairs; a unit diagonal keeps the matrix regular.
      entries.emplace_back(static_cast<int>(i), static_cast<int>(i), nodeArea_[i] > 0.0 ? nodeArea_[i] : 1.0);
    for (std::size_t p = 0; p < pairFirst_.size(); ++p) {
      const int i = static_cast<int>(pairFirst_[p]), j = static_cast<int>(pairSecond_[p]);
      const double c = dt * settings_.diffusivity * pairGeometric_[p];
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
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(n)), start(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    start[static_cast<Eigen::Index>(i)] = texture.liquid[i];
    rhs[static_cast<Eigen::Index>(i)] = (nodeArea_[i] > 0.0 ? nodeArea_[i] : 1.0) * texture.liquid[i];
  }
  system.solution = system.solver.solveWithGuess(rhs, start);
  std::vector<double> flux(pairFirst_.size());
  for (std::size_t p = 0; p < flux.size(); ++p)
    flux[p] = dt * settings_.diffusivity * pairGeometric_[p] *
              (system.solution[pairFirst_[p]] - system.solution[pairSecond_[p]]);
  applyPairFluxes(texture, flux);
}

void Wetting::applyPairFluxes(LiquidTexture& texture, const std::vector<double>& flux) {
  const std::size_t n = nodeArea_.size();
  std::vector<double> volume(n), pigment(texture.pigment.size());
  for (std::size_t i = 0; i < n; ++i) volume[i] = texture.liquid[i] * nodeArea_[i];
  for (std::size_t i = 0; i < pigment.size(); ++i) pigment[i] = texture.pigment[i] * nodeArea_[i];
  for (std::size_t p = 0; p < flux.size(); ++p) {
    const std::uint32_t i = pairFirst_[p], j = pairSecond_[p];
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
    if (!(nodeArea_[i] > 0.0)) continue;
    // A solver residual can leave a texel a rounding below zero; that is dropped, not stored.
    texture.liquid[i] = static_cast<float>(std::max(0.0, volume[i] / nodeArea_[i]));
    if (!pigment.empty()) texture.pigment[i] = static_cast<float>(std::max(0.0, pigment[i] / nodeArea_[i]));
  }
}

template void Wetting::exchange<true>(LiquidTexture&, const WettingEnvironment&, double, bool, bool, WettingStepReport&);
template void Wetting::exchange<false>(LiquidTexture&, const WettingEnvironment&, double, bool, bool, WettingStepReport&);

}  // namespace hydrotex
