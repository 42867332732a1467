// SPDX-License-Identifier: Zlib
/// @file PressureWettedSums.cpp
/// finishPressureHydrostatics: wetted sums accumulated elsewhere (a GPU) under waves, grids or a
/// medium, finished by core's own assembly (HydrostaticSums.cpp) so that backends differ only in
/// how the sums were added up.

#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"

namespace hydrotex {

HydrostaticsResult finishPressureHydrostatics(const FlatWettedSums& in, const PressureSums& pressure,
                                              const Eigen::Vector3d& origin, double density,
                                              const HydrostaticsQuery& query, bool hasWaterplane) {
  detail::WettedSums sums = detail::wettedSumsOf(in);
  for (int k = 0; k < 3; ++k) {
    sums.pressureForce[k] = pressure.force[k];
    sums.pressureTorque[k] = pressure.torque[k];
  }
  return detail::finishHydrostatics(sums, origin, density, query, detail::ForceModel::PressureSums, hasWaterplane);
}

}  // namespace hydrotex
