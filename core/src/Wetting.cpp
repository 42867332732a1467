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
  Eigen::SparseMatrix<double> matrix;  // M + dt D L
  double dt = -1.0;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> solver;
  Eigen::VectorXd solution;
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
  Wetting w;
  w.settings_ = settings;
  w.position_.resize(n);
  w.normal_.resize(n);
  w.inverseArea_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    w.position_[i] = adjacency.centroid[i].cast<float>();
    const float norm = textures.areaVector[i].norm();
    w.normal_[i] = norm > 0.0f ? Eigen::Vector3f(textures.areaVector[i] / norm) : Eigen::Vector3f::Zero();
    w.inverseArea_[i] = adjacency.area[i] > 0.0 ? static_cast<float>(1.0 / adjacency.area[i]) : 0.0f;
  }
  w.pairConductance_.resize(adjacency.pairCount());
  for (std::size_t p = 0; p < adjacency.pairCount(); ++p)
    w.pairConductance_[p] = static_cast<float>(settings.diffusivity * adjacency.conductance[p]);
  w.stableStep_ = adjacency.stableTimeStep(settings.diffusivity);
  w.submerged_.assign(n, 0);
  w.delta_.assign(n, 0.0f);
  w.adjacency_ = std::move(adjacency);
  w.implicit_ = std::make_unique<ImplicitSystem>();
  return w;
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
  report.absorbed = absorb(texture, environment, dt, report.submergedTexels);
  report.diffusionSubsteps = diffuse(texture, dt);
  report.implicitDiffusion = report.diffusionSubsteps == 0 && dt > 0.0 && !adjacency_.first.empty() &&
                             settings_.diffusivity > 0.0;
  report.evaporated = evaporate(texture, dt);
  return report;
}

double Wetting::absorb(LiquidTexture& texture, const WettingEnvironment& environment, double dt,
                       std::size_t& submergedCount) {
  const std::size_t n = position_.size();
  std::fill(submerged_.begin(), submerged_.end(), std::uint8_t{0});
  submergedCount = 0;
  const Eigen::Matrix3f rotation = environment.pose.rotation.cast<float>();
  const Eigen::Vector3f translation = environment.pose.translation.cast<float>();
  const LiquidSurface* liquid = environment.liquid;
  const double highest = liquid ? (liquid->hasFreeSurface() ? liquid->heightRange(environment.time).second
                                                            : std::numeric_limits<double>::infinity())
                                : -std::numeric_limits<double>::infinity();
  const bool freeSurface = liquid && liquid->hasFreeSurface();
  const auto* flat = dynamic_cast<const FlatSurface*>(liquid);
  const double flatPressurePerDepth = flat ? flat->density() * environment.gravity : 0.0;
  const double flowResistance = settings_.viscosity * texture.layerThickness;  // mu L (Pa s m)
  double absorbed = 0.0;

  // Under the liquid: Darcy against the pores' back-pressure, exact exponential approach to capacity.
  if (liquid) {
    for (std::size_t i = 0; i < n; ++i) {
      if (inverseArea_[i] == 0.0f) continue;
      const Eigen::Vector3f world = rotation * position_[i] + translation;
      if (world.y() > highest) continue;
      // A flat surface's pressure is rho g depth (what FlatSurface::pressure returns; the class is
      // final): computed here without two virtual calls per texel.
      const Eigen::Vector3d point = world.cast<double>();
      const double pressure = flat ? flatPressurePerDepth * (flat->height() - point.y())
                                   : liquid->pressure(point, environment.time, environment.gravity);
      if (freeSurface && !(pressure > 0.0)) continue;
      submerged_[i] = 1;
      ++submergedCount;
      const double capacity = texture.capacity[i];
      const double held = texture.liquid[i];
      if (!(capacity > held)) continue;
      const double drive = std::max(pressure, 0.0) + settings_.capillaryPressure;
      const double rate = texture.permeability[i] * drive / (flowResistance * capacity);  // 1 / tau (1/s)
      const double next = capacity - (capacity - held) * std::exp(-rate * dt);
      const float stored = static_cast<float>(std::min(next, capacity));
      absorbed += (static_cast<double>(stored) - held) * adjacency_.area[i];
      texture.liquid[i] = stored;
    }
  }

  // User sources on texels in the air: supply up to capacity, the rest runs off.
  for (const LiquidSource& source : environment.sources) {
    if (!(source.rate > 0.0)) continue;
    const Eigen::Vector3f fall = source.direction.norm() > 0.0 ? Eigen::Vector3f(source.direction.normalized().cast<float>())
                                                              : Eigen::Vector3f(0.0f, -1.0f, 0.0f);
    const Eigen::Vector3f centre = source.centre.cast<float>();
    const float radiusSquared = static_cast<float>(source.radius * source.radius);
    for (std::size_t i = 0; i < n; ++i) {
      if (submerged_[i] || inverseArea_[i] == 0.0f) continue;
      double supply = 0.0;  // m of liquid depth over the step
      if (source.kind == LiquidSourceKind::Rain) {
        // Rain per horizontal area lands on the texel's projection across the fall direction.
        const float facing = -(rotation * normal_[i]).dot(fall);
        if (facing <= 0.0f) continue;
        supply = source.rate * facing * dt;
      } else {
        const Eigen::Vector3f world = rotation * position_[i] + translation;
        if ((world - centre).squaredNorm() > radiusSquared) continue;
        supply = source.rate * dt;
      }
      const double held = texture.liquid[i];
      const float stored = static_cast<float>(std::min<double>(held + supply, texture.capacity[i]));
      if (!(stored > held)) continue;
      absorbed += (static_cast<double>(stored) - held) * adjacency_.area[i];
      texture.liquid[i] = stored;
      if (!texture.pigment.empty())
        texture.pigment[i] += static_cast<float>((static_cast<double>(stored) - held) * source.pigment);
    }
  }
  return absorbed;
}

int Wetting::diffuse(LiquidTexture& texture, double dt) {
  if (!(dt > 0.0) || adjacency_.first.empty() || !(settings_.diffusivity > 0.0)) return 0;
  const double substeps = std::ceil(dt / stableStep_);
  if (substeps <= settings_.maxExplicitSubsteps) {
    const int count = std::max(1, static_cast<int>(substeps));
    for (int k = 0; k < count; ++k) diffuseExplicit(texture, dt / count);
    return count;
  }
  diffuseImplicit(texture, dt);
  return 0;
}

void Wetting::diffuseExplicit(LiquidTexture& texture, double dt) {
  const std::size_t pairs = pairConductance_.size();
  const std::uint32_t* first = adjacency_.first.data();
  const std::uint32_t* second = adjacency_.second.data();
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
  for (std::size_t i = 0; i < n; ++i) {
    phi[i] = std::max(0.0f, phi[i] + delta[i] * inverseArea_[i]);
    delta[i] = 0.0f;
  }
  if (withPigment)
    for (std::size_t i = 0; i < n; ++i) texture.pigment[i] = std::max(0.0f, texture.pigment[i] + pigmentDelta_[i] * inverseArea_[i]);
}

void Wetting::diffuseImplicit(LiquidTexture& texture, double dt) {
  const std::size_t n = adjacency_.area.size();
  ImplicitSystem& system = *implicit_;
  if (system.dt != dt) {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(n + 4 * adjacency_.pairCount());
    for (std::size_t i = 0; i < n; ++i)
      // A texel without area has no pairs; a unit diagonal keeps the matrix regular.
      entries.emplace_back(static_cast<int>(i), static_cast<int>(i), adjacency_.area[i] > 0.0 ? adjacency_.area[i] : 1.0);
    for (std::size_t p = 0; p < adjacency_.pairCount(); ++p) {
      const int i = static_cast<int>(adjacency_.first[p]), j = static_cast<int>(adjacency_.second[p]);
      const double c = dt * settings_.diffusivity * adjacency_.conductance[p];
      entries.emplace_back(i, i, c);
      entries.emplace_back(j, j, c);
      entries.emplace_back(i, j, -c);
      entries.emplace_back(j, i, -c);
    }
    system.matrix.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    system.matrix.setFromTriplets(entries.begin(), entries.end());
    // The pair fluxes conserve the volume whatever the residual, but dividing by sliver texels'
    // areas amplifies it: 1e-10 keeps phi within 1e-4 of backward Euler's at any dt.
    system.solver.setTolerance(1e-10);
    system.solver.setMaxIterations(std::max<Eigen::Index>(100, static_cast<Eigen::Index>(n)));
    system.solver.compute(system.matrix);
    system.dt = dt;
  }
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(n)), start(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    start[static_cast<Eigen::Index>(i)] = texture.liquid[i];
    rhs[static_cast<Eigen::Index>(i)] = adjacency_.area[i] * texture.liquid[i];
  }
  system.solution = system.solver.solveWithGuess(rhs, start);
  std::vector<double> flux(adjacency_.pairCount());
  for (std::size_t p = 0; p < flux.size(); ++p)
    flux[p] = dt * settings_.diffusivity * adjacency_.conductance[p] *
              (system.solution[adjacency_.first[p]] - system.solution[adjacency_.second[p]]);
  applyPairFluxes(texture, flux);
}

void Wetting::applyPairFluxes(LiquidTexture& texture, const std::vector<double>& flux) {
  const std::size_t n = adjacency_.area.size();
  std::vector<double> volume(n), pigment(texture.pigment.size());
  for (std::size_t i = 0; i < n; ++i) volume[i] = texture.liquid[i] * adjacency_.area[i];
  for (std::size_t i = 0; i < pigment.size(); ++i) pigment[i] = texture.pigment[i] * adjacency_.area[i];
  for (std::size_t p = 0; p < flux.size(); ++p) {
    const std::uint32_t i = adjacency_.first[p], j = adjacency_.second[p];
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
    if (!(adjacency_.area[i] > 0.0)) continue;
    // A solver residual can leave a texel a rounding below zero; that is dropped, not stored.
    texture.liquid[i] = static_cast<float>(std::max(0.0, volume[i] / adjacency_.area[i]));
    if (!pigment.empty()) texture.pigment[i] = static_cast<float>(std::max(0.0, pigment[i] / adjacency_.area[i]));
  }
}

double Wetting::evaporate(LiquidTexture& texture, double dt) {
  const double rate = settings_.evaporationRate();  // m/s, constant-rate stage
  if (!(rate > 0.0) || !(dt > 0.0)) return 0.0;
  const std::size_t n = texture.liquid.size();
  double evaporated = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double held = texture.liquid[i];
    if (held <= 0.0 || submerged_[i]) continue;
    const double critical = settings_.criticalSaturation * texture.capacity[i];
    double next;
    if (held >= critical) {
      // Constant rate until the critical content, then first order for the rest of the step.
      const double constantTime = (held - critical) / rate;
      if (dt <= constantTime || critical <= 0.0)
        next = std::max(0.0, held - rate * dt);
      else
        next = critical * std::exp(-(dt - constantTime) * rate / critical);
    } else {
      next = held * std::exp(-dt * rate / critical);
    }
    const float stored = static_cast<float>(next);
    evaporated += (held - static_cast<double>(stored)) * adjacency_.area[i];
    texture.liquid[i] = stored;
  }
  return evaporated;
}

}  // namespace hydrotex
