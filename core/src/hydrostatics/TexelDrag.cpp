// SPDX-License-Identifier: Zlib
#include "hydrotex/hydrostatics/TexelDrag.hpp"

#include <algorithm>
#include <cmath>

#include "hydrostatics/TexelDragLaw.hpp"

namespace hydrotex {

double skinFrictionCoefficient(double reynolds) {
  // Laminar flat plate: Blasius (Schlichting, Boundary-Layer Theory, eq. 7.33): Cf = 1.328/sqrt(Re).
  // Turbulent: ITTC 1957 model-ship correlation line: Cf = 0.075 / (log10 Re - 2)^2.
  const double re = std::isfinite(reynolds) ? std::max(reynolds, 1.0) : 1.0;
  const double laminar = 1.328 / std::sqrt(re);
  const double logRe = std::log10(std::max(re, 1.0e4)) - 2.0;
  const double turbulent = 0.075 / (logRe * logRe);
  return std::max(laminar, turbulent);
}

Eigen::Vector3d texelDragForceWithFriction(const Eigen::Vector3d& areaVector, double area,
                                           const Eigen::Vector3d& relativeVelocity, double density,
                                           double frictionCoefficient, const DragCoefficients& coefficients) {
  return detail::texelDragLaw(areaVector, area, relativeVelocity, density, frictionCoefficient, coefficients);
}

Eigen::Vector3d texelDragForce(const Eigen::Vector3d& areaVector, double area, const Eigen::Vector3d& relativeVelocity,
                               double density, double viscosity, double referenceLength,
                               const DragCoefficients& coefficients) {
  double friction = 0.0;
  if (coefficients.skinFrictionScale > 0.0 && viscosity > 0.0 && referenceLength > 0.0 && density > 0.0) {
    const double reynolds = density * relativeVelocity.norm() * referenceLength / viscosity;
    friction = coefficients.skinFrictionScale * skinFrictionCoefficient(reynolds);
  }
  return texelDragForceWithFriction(areaVector, area, relativeVelocity, density, friction, coefficients);
}

std::vector<DragPatch> mergeTexelsIntoDragPatches(const SurfaceBake& bake, const SurfaceTextures& textures,
                                                  double normalCosine, double maxPatchRadius) {
  std::vector<DragPatch> patches;
  const std::size_t count = textures.size();
  if (count != bake.coveredCount() || textures.areaVector.size() != count || textures.area.size() != count ||
      bake.tileStart.empty() || bake.tileStart.back() != count) {
    return patches;
  }
  struct Accumulator {
    Eigen::Vector3d normal, seed, areaVector, weightedPosition;
    double area;
    std::vector<std::uint32_t> members;
  };
  std::vector<Accumulator> open;
  for (std::size_t tile = 0; tile + 1 < bake.tileStart.size(); ++tile) {
    open.clear();
    for (std::uint32_t t = bake.tileStart[tile]; t < bake.tileStart[tile + 1]; ++t) {
      // A lid over an opening (Mesh.hpp) is no wall: the liquid flows through it, not against it.
      const bool lid = textures.openingArea.size() == count && textures.openingAreaVector.size() == count;
      const Eigen::Vector3d a = (textures.areaVector[t] - (lid ? textures.openingAreaVector[t] : Eigen::Vector3f::Zero())).cast<double>();
      const double norm = a.norm();
      const double area = double(textures.area[t]) - (lid ? double(textures.openingArea[t]) : 0.0);
      if (!(norm > 0.0) || !(area > 0.0) || !a.allFinite()) continue;
      const Eigen::Vector3d n = a / norm;
      const Eigen::Vector3d p = textures.position[t].cast<double>();
      auto it = std::find_if(open.begin(), open.end(), [&](const Accumulator& acc) {
        return acc.normal.dot(n) >= normalCosine && (p - acc.seed).norm() <= maxPatchRadius;
      });
      if (it == open.end()) {
        open.push_back({n, p, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0, {}});
        it = std::prev(open.end());
      }
      it->areaVector += a;
      it->weightedPosition += area * p;
      it->area += area;
      it->members.push_back(t);
    }
    for (const Accumulator& acc : open) {
      DragPatch patch;
      const Eigen::Vector3d centroid = acc.weightedPosition / acc.area;
      double radius = 0.0;
      for (std::uint32_t t : acc.members) {
        // A texel reaches about half its diagonal beyond its centroid.
        const double reach = 0.5 * (textures.edgeU.size() == count && textures.edgeV.size() == count
                                        ? (textures.edgeU[t] + textures.edgeV[t]).cast<double>().norm()
                                        : 0.0);
        radius = std::max(radius, (textures.position[t].cast<double>() - centroid).norm() + reach);
      }
      patch.position = centroid.cast<float>();
      patch.areaVector = acc.areaVector.cast<float>();
      patch.area = static_cast<float>(acc.area);
      patch.radius = static_cast<float>(radius);
      patches.push_back(patch);
    }
  }
  return patches;
}

}  // namespace hydrotex
