// SPDX-License-Identifier: Zlib
#pragma once
/// @file IdealGas.hpp
/// Density of a gas from its pressure and temperature (hot-air balloons: the inner gas lightens as
/// it is heated).

namespace hydrotex {

/// Universal gas constant R (J / (mol K)), CODATA 2018 (exact since the 2019 SI).
inline constexpr double kGasConstant = 8.314462618;
/// Molar mass of dry air (kg/mol), ISO 2533 standard atmosphere.
inline constexpr double kMolarMassAir = 0.0289644;
/// Standard sea-level pressure (Pa).
inline constexpr double kStandardPressure = 101325.0;

/// Ideal gas law rho = p M / (R T): density (kg/m^3) of a gas of molar mass `molarMass` (kg/mol)
/// at `pressure` (Pa) and `temperature` (K, > 0). Air at 101325 Pa and 288.15 K: 1.225 kg/m^3.
constexpr double idealGasDensity(double pressure, double molarMass, double temperature) {
  return pressure * molarMass / (kGasConstant * temperature);
}

}  // namespace hydrotex
