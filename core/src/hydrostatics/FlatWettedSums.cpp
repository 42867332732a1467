// SPDX-License-Identifier: Zlib
/// @file FlatWettedSums.cpp
/// Finishing a flat-surface hydrostatics result from sums accumulated outside core (a GPU): the
/// same assembly as the texture path (HydrostaticSums.cpp, finishHydrostatics), so that every
/// backend shares one formula for the result.

#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"

namespace hydrotex {

detail::WettedSums detail::wettedSumsOf(const FlatWettedSums& in) {
  WettedSums sums;
  sums.sumDA[1] = in.sumDAy;
  sums.sumDXAy = in.sumDXAy;
  sums.sumDZAy = in.sumDZAy;
  sums.sumYB = in.sumYB;
  sums.sumAy = in.sumAy;
  sums.sumXAy = in.sumXAy;
  sums.sumZAy = in.sumZAy;
  sums.sumXXAy = in.sumXXAy;
  sums.sumXZAy = in.sumXZAy;
  sums.sumZZAy = in.sumZZAy;
  sums.wettedArea = in.wettedArea;
  return sums;
}

HydrostaticsResult finishFlatHydrostatics(const FlatWettedSums& in, double surfaceHeight, double density,
                                          const HydrostaticsQuery& query) {
  const detail::WettedSums sums = detail::wettedSumsOf(in);
  const Eigen::Vector3d origin(query.pose.translation.x(), surfaceHeight, query.pose.translation.z());
  return detail::finishHydrostatics(sums, origin, density, query, detail::ForceModel::Archimedes, true);
}

}  // namespace hydrotex
