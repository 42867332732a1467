// SPDX-License-Identifier: Zlib
// Lekner and Dorf 1988, "Why some things are darker when wet", Applied Optics 27(7), 1278-1280:
// eq. for R_bar(n) (isotropic internal reflectance of a smooth liquid surface), p = 1 - (1 - R_bar)
// / n^2, absorbed fraction A = (1 - R1) a / (1 - p (1 - a)). Worked numbers in docs/references.md.
// The film transmittance T per crossing (coloured liquids) multiplies every pass through the film:
// in and out once per bounce, hence T^2 in the numerator and in the geometric series.
#include "hydrotex/wetting/WetShading.hpp"

#include <algorithm>
#include <cmath>

namespace hydrotex {

double averageInternalReflectance(double n) {
  const double n2 = n * n, n3 = n2 * n;
  const double np1 = n + 1.0, n2p1 = n2 + 1.0, n2m1 = n2 - 1.0;
  return (3.0 * n2 + 2.0 * n + 1.0) / (3.0 * np1 * np1) -
         2.0 * n3 * (n2 + 2.0 * n - 1.0) / (n2p1 * n2p1 * n2m1) + n2 * n2p1 * std::log(n) / (n2m1 * n2m1) -
         n2 * n2m1 * n2m1 / (n2p1 * n2p1 * n2p1) * std::log(n * np1 / (n - 1.0));
}

double internalReflectionProbability(double n) { return 1.0 - (1.0 - averageInternalReflectance(n)) / (n * n); }

double filmReflectance(double n) {
  const double r = (n - 1.0) / (n + 1.0);
  return r * r;
}

WetAlbedo wetAlbedo(double dryAlbedo, double n, double filmTransmittance) {
  const double albedo = std::clamp(dryAlbedo, 0.0, 1.0);
  const double t2 = filmTransmittance * filmTransmittance;
  const double p = internalReflectionProbability(n);
  const double r1 = filmReflectance(n);
  WetAlbedo result;
  result.diffuse = (1.0 - r1) * albedo * (1.0 - p) * t2 / (1.0 - p * albedo * t2);
  result.total = result.diffuse + r1;
  return result;
}

Eigen::Vector3d wetDiffuseRgb(const Eigen::Vector3d& dryRgb, double n, const Eigen::Vector3d& filmTransmittance) {
  Eigen::Vector3d wet;
  for (int c = 0; c < 3; ++c) wet[c] = wetAlbedo(dryRgb[c], n, filmTransmittance[c]).diffuse;
  return wet;
}

Eigen::Vector3d wetSurfaceRgb(const Eigen::Vector3d& dryRgb, double saturation, double n,
                              const Eigen::Vector3d& filmTransmittance) {
  const double w = std::clamp(saturation, 0.0, 1.0);
  return (1.0 - w) * dryRgb + w * wetDiffuseRgb(dryRgb, n, filmTransmittance);
}

}  // namespace hydrotex
