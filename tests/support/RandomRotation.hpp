// SPDX-License-Identifier: Zlib
#pragma once
// A rotation drawn uniformly over SO(3) (a normalized Gaussian quaternion), for suites that test
// a law at many random poses with a seeded generator.

#include <Eigen/Geometry>

#include <random>

namespace hydrotex::testing {

inline Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

}  // namespace hydrotex::testing
