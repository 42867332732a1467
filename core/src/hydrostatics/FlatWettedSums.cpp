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
  sums.volumeScale = in.volumeScale;
  return sums;
}

HydrostaticsResult finishFlatHydrostatics(const FlatWettedSums& in, double surfaceHeight, double density,
                                          const HydrostaticsQuery& query) {
  const detail::WettedSums sums = detail::wettedSumsOf(in);
  const Eigen::Vector3d origin(query.pose.translation.x(), surfaceHeight, query.pose.translation.z());
  return detail::finishHydrostatics(sums, origin, density, query, detail::ForceModel::Archimedes, true);
}

TexelVolumeCalibration TexelVolumeCalibration::fromTextures(const SurfaceTextures& textures) {
  TexelVolumeCalibration out;
  double tripleVolume = 0.0;
  for (std::size_t i = 0; i < textures.size(); ++i) {
    const Eigen::Vector3d p = textures.position[i].cast<double>();
    const Eigen::Vector3d a = textures.areaVector[i].cast<double>();
    out.sumPA += p * a.transpose();
    tripleVolume += p.dot(a);
  }
  out.enclosedVolume = tripleVolume / 3.0;
  return out;
}

double TexelVolumeCalibration::scale(const Eigen::Matrix3d& rotation) const {
  // Sum (r1 . p)(r1 . A) = r1^T (Sum p A^T) r1 (the vertical offset's term, offset Sum A, is zero
  // for a closed body and left out as the texture path does).
  const Eigen::Vector3d r1 = rotation.row(1).transpose();
  const double wholeBody = r1.dot(sumPA * r1);
  return wholeBody > 0.0 ? enclosedVolume / wholeBody : 1.0;
}

}  // namespace hydrotex
