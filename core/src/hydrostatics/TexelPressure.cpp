// SPDX-License-Identifier: Zlib
/// @file TexelPressure.cpp
/// Per-texel pressure of a posed surface and its vertex forces (TexelPressure.hpp).

#include "hydrotex/hydrostatics/TexelPressure.hpp"

#include <cmath>
#include <optional>

#include "hydrostatics/HydrostaticSums.hpp"
#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"

namespace hydrotex {

TexelPressureSums texelPressures(const SurfaceTextures& worldTextures, const LiquidSurface& surface, double time,
                                 double gravity, std::span<float> pressure, std::span<float> wetFraction) {
  TexelPressureSums sums;
  const SurfaceTextures& t = worldTextures;
  const double rhoG = surface.density() * gravity;
  const std::optional<double> flat = surface.flatHeight();
  const bool free = surface.hasFreeSurface();
  // Under waves the surface above each texel from a grid of jets over the texels' footprint, as
  // the exact path's vertices (kExactWaveHeightError), where that takes fewer samples than there
  // are texels: a Gerstner height is a Newton search (0.3 us), a soft ball at 64^2 has ~3,000 texels.
  detail::Footprint footprint;
  if (free && !flat)
    for (const Eigen::Vector3f& p : t.position) footprint.add(double(p.x()), double(p.z()));
  detail::SurfaceHeights heights(surface, time, footprint, kExactWaveHeightError, double(t.position.size()));
  for (std::size_t i = 0; i < t.position.size(); ++i) {
    const Eigen::Vector3d x = t.position[i].cast<double>();
    const Eigen::Vector3d areaVector = t.areaVector[i].cast<double>();
    const double area = double(t.area[i]);
    sums.enclosedVolume += x.dot(areaVector) / 3.0;
    if (!free) {
      pressure[i] = float(surface.pressure(x, time, gravity));
      wetFraction[i] = 1.0f;
      sums.wettedArea += area;
      continue;
    }
    const double height = flat ? *flat : heights.at(x.x(), x.z());
    // The texel as the parallelogram x + s eU + t eV (s, t in [-1/2, 1/2]) under a level surface
    // at the local height: the rigid texture path's rule for a texel cut by the waterline.
    const detail::WaterlineFractions wet =
        detail::waterlineFractions(height - x.y(), double(t.edgeU[i].y()), double(t.edgeV[i].y()));
    pressure[i] = float(rhoG * wet.depth);
    wetFraction[i] = float(wet.area);
    sums.wettedArea += wet.area * area;
    sums.submergedVolume -= wet.depth * areaVector.y();
  }
  if (!free) sums.submergedVolume = sums.enclosedVolume;
  return sums;
}

void texelPressureVertexForces(const SurfaceBake& bake, const Mesh& mesh,
                               std::span<const Eigen::Vector3d> triangleAreaVectors, std::span<const float> pressure,
                               std::span<Eigen::Vector3d> vertexForce) {
  for (Eigen::Vector3d& f : vertexForce) f.setZero();
  for (std::size_t i = 0; i < pressure.size(); ++i) {
    const double p = double(pressure[i]);
    if (!(p != 0.0) || !std::isfinite(p)) continue;  // dry, or a surface that answered NaN
    for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k) {
      const TexelPiece& piece = bake.pieces[k];
      const Eigen::Vector3i& tri = mesh.triangles[piece.triangle];
      const Eigen::Vector3d force = -p * double(piece.areaFraction) * triangleAreaVectors[piece.triangle];
      const double b1 = piece.centroidBary1, b2 = piece.centroidBary2;
      vertexForce[std::size_t(tri[0])] += (1.0 - b1 - b2) * force;
      vertexForce[std::size_t(tri[1])] += b1 * force;
      vertexForce[std::size_t(tri[2])] += b2 * force;
    }
  }
}

}  // namespace hydrotex
