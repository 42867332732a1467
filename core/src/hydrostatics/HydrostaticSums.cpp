// SPDX-License-Identifier: Zlib
/// @file HydrostaticSums.cpp
/// Moments of wholly submerged element sets moved to the world, and the final assembly of a
/// HydrostaticsResult from the wetted-surface sums (derivation in HydrostaticSums.hpp).

#include "hydrostatics/HydrostaticSums.hpp"

namespace hydrotex::detail {

void WettedSums::addSubmergedMoments(const TextureHydrostatics::Moments& m, const Eigen::Matrix3d& r,
                                     const Eigen::Vector3d& b) {
  // World moments of x' = R p + b, A' = R A: W0 = Sum A', W1(i,k) = Sum x'_i A'_k,
  // W2[k](i,j) = Sum x'_i x'_j A'_k, expanded in the body moments.
  const Eigen::Vector3d sumA(m.sumA[0], m.sumA[1], m.sumA[2]);
  Eigen::Matrix3d bodyPA;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) bodyPA(i, k) = m.sumPA[i][k];
  static constexpr int kPair[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
  Eigen::Matrix3d bodyPPA[3];
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) bodyPPA[c](i, j) = m.sumPPA[kPair[i][j]][c];

  const Eigen::Vector3d w0 = r * sumA;
  const Eigen::Matrix3d rotatedPA = r * bodyPA * r.transpose();
  const Eigen::Matrix3d w1 = rotatedPA + b * w0.transpose();
  Eigen::Matrix3d rotatedPPA[3];
  for (int c = 0; c < 3; ++c) rotatedPPA[c] = r * bodyPPA[c] * r.transpose();
  Eigen::Matrix3d w2[3];
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix3d p2 = r(k, 0) * rotatedPPA[0] + r(k, 1) * rotatedPPA[1] + r(k, 2) * rotatedPPA[2];
    const Eigen::Vector3d column = rotatedPA.col(k);
    w2[k] = p2 + b * column.transpose() + column * b.transpose() + (b * b.transpose()) * w0(k);
  }

  // Wholly submerged under a flat surface at o_y: D = -y', Q = y'^2, frac = 1, h' = 0.
  for (int k = 0; k < 3; ++k) sumDA[k] -= w1(1, k);
  sumDxA[0] -= w2[2](1, 1) - w2[1](1, 2);
  sumDxA[1] -= w2[0](1, 2) - w2[2](1, 0);
  sumDxA[2] -= w2[1](1, 0) - w2[0](1, 1);
  sumDXAy -= w2[1](0, 1);
  sumDZAy -= w2[1](2, 1);
  sumYB += 0.5 * w2[1](1, 1);
  sumAy += w0(1);
  sumXAy += w1(0, 1);
  sumZAy += w1(2, 1);
  sumXXAy += w2[1](0, 0);
  sumXZAy += w2[1](0, 2);
  sumZZAy += w2[1](2, 2);
  wettedArea += m.sumArea;
}

HydrostaticsResult finishHydrostatics(const WettedSums& sums, const Eigen::Vector3d& origin, double density,
                                      const HydrostaticsQuery& query, ForceModel forceModel, bool hasWaterplane) {
  HydrostaticsResult result;
  result.fluidDensity = density;
  const double volume = -sums.sumDA[1];
  if (!(volume > 0.0)) return result;  // out of the liquid (or a round-off sliver of it)

  const double rhoG = density * query.gravity;
  const Eigen::Vector3d buoyancyOffset(-sums.sumDXAy / volume, sums.sumYB / volume, -sums.sumDZAy / volume);
  result.submergedVolume = volume;
  result.centerOfBuoyancy = origin + buoyancyOffset;

  Eigen::Vector3d torqueAboutFrameOrigin;
  if (forceModel == ForceModel::Archimedes) {
    result.buoyancyForce = Eigen::Vector3d(0.0, rhoG * volume, 0.0);
    torqueAboutFrameOrigin = buoyancyOffset.cross(result.buoyancyForce);
  } else {
    result.buoyancyForce = Eigen::Vector3d(sums.pressureForce[0], sums.pressureForce[1], sums.pressureForce[2]);
    torqueAboutFrameOrigin = Eigen::Vector3d(sums.pressureTorque[0], sums.pressureTorque[1], sums.pressureTorque[2]);
  }
  const Eigen::Vector3d centerOfMass = query.pose.apply(query.centerOfMass);
  // Moving the moment point from o to c: tau_c = tau_o - (c - o) x F.
  result.torqueAboutCenterOfMass = torqueAboutFrameOrigin - (centerOfMass - origin).cross(result.buoyancyForce);
  result.torqueAboutOrigin = torqueAboutFrameOrigin - (query.pose.translation - origin).cross(result.buoyancyForce);
  result.wettedArea = sums.wettedArea;

  const double mass = query.mass ? *query.mass : density * volume;
  if (!hasWaterplane) {
    // No free surface: only the buoyancy-gravity couple about the centre of mass restores.
    const double height = result.centerOfBuoyancy.y() - centerOfMass.y();
    result.stiffness = hydrostaticStiffness(0, 0, 0, 0, 0, 0, volume, height, 0.0, density, query.gravity, mass);
    return result;
  }

  // Cap integrals are minus the wetted surface's (closed surface: Int f(x, z) n_y dA = 0). A
  // wholly submerged body has no cap: its sum is then a residue of rounding (~1e-17 m^2 of either
  // sign), whose centroid would be noise, so a cap under 1e-12 of the wetted area is none.
  const double area = -sums.sumAy > 1e-12 * sums.wettedArea ? -sums.sumAy : 0.0;
  const double firstX = -sums.sumXAy, firstZ = -sums.sumZAy;
  result.waterplaneArea = area;
  result.waterplaneCentroid =
      area > 0.0 ? Eigen::Vector3d(origin.x() + firstX / area, origin.y(), origin.z() + firstZ / area)
                 : Eigen::Vector3d(centerOfMass.x(), origin.y(), centerOfMass.z());
  // Water-plane moments about O = (x_G, h, z_G).
  const double gx = centerOfMass.x() - origin.x(), gz = centerOfMass.z() - origin.z();
  const double momentX = firstX - gx * area, momentZ = firstZ - gz * area;
  const double momentXX = -sums.sumXXAy - 2.0 * gx * firstX + gx * gx * area;
  const double momentZZ = -sums.sumZZAy - 2.0 * gz * firstZ + gz * gz * area;
  const double momentXZ = -sums.sumXZAy - gx * firstZ - gz * firstX + gx * gz * area;
  result.stiffness = hydrostaticStiffness(area, momentX, momentZ, momentXX, momentXZ, momentZZ, volume,
                                          buoyancyOffset.y(), centerOfMass.y() - origin.y(), density,
                                          query.gravity, mass);
  return result;
}

}  // namespace hydrotex::detail
