// SPDX-License-Identifier: Zlib
/// @file SoftBodyDrag.cpp
/// The drag of a body whose vertices move on their own (SoftBodyDrag.hpp). Texel by texel: the
/// rigid bodies' law (TexelDrag.hpp) on the texel's velocity relative to the liquid (its pieces'
/// barycentric vertex velocities, weighted by area), times its wet fraction; the force goes to the
/// vertices through the pieces as the pressure does (TexelPressure.hpp), which keeps the total
/// force and its moment.
///
/// The vertices' motion splits, orthogonally in the mass metric, into the motion as a rigid body
/// (V, omega about the centre of mass, omega = I^-1 L) and a deformation w_n with no momentum and
/// no angular momentum; kinetic energy is the sum of the two parts'. The drag's total force and
/// torque change the rigid part, the rest of the vertex forces the deformation:
/// - rigid part: the rigid bodies' step on (V, omega), the component along the motion taken
///   implicitly (secant damping 1 / (1 + lambda)), so it slows the motion and never reverses it at
///   any dt; what remains may turn the motion but not lengthen it;
/// - deformation: the same per vertex on w_n, then projected back onto motions with no momentum.
/// Neither part's energy can grow, so drag never adds kinetic energy (relative to the liquid), and
/// a body moving as a whole gets no deformation from its own drag, whatever dt.
#include "hydrotex/step/SoftBodyDrag.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "hydrostatics/SurfaceJetGrid.hpp"
#include "hydrostatics/TexelDragLaw.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"

namespace hydrotex {

SoftBodyDragResult SoftBodyDrag::step(const SoftBodyDragInput& input, std::span<Eigen::Vector3d> velocityChange) {
  SoftBodyDragResult result;
  const Mesh& mesh = *input.mesh;
  const SurfaceBake& bake = *input.bake;
  const SurfaceTextures& textures = *input.textures;
  const LiquidSurface& surface = *input.surface;
  const double dt = input.dt, time = input.time;
  const std::size_t vertexCount = mesh.positions.size();
  const double density = surface.density();
  const bool uniform = surface.hasFreeSurface();
  const bool still = surface.flatHeight().has_value() && input.current.isZero();
  relative_.resize(vertexCount);
  vertexDrag_.resize(vertexCount);
  deformationChange_.resize(vertexCount);
  for (Eigen::Vector3d& change : velocityChange) change.setZero();

  // The liquid's velocity at every vertex, into relative_ first. Under a free surface in motion
  // the surface height above each vertex, from jets over the vertices' footprint where the surface
  // offers them (waves: a Newton search per vertex otherwise; as the rigid bodies' drag), then
  // velocitiesBelow for all vertices at once.
  if (still) {
    for (std::size_t n = 0; n < vertexCount; ++n) relative_[n] = input.current;
  } else if (uniform) {
    surfaceHeights_.resize(vertexCount);
    const std::optional<double> flat = surface.flatHeight();
    detail::Footprint footprint;
    if (!flat)
      for (const Eigen::Vector3d& x : mesh.positions) footprint.add(x.x(), x.z());
    detail::SurfaceHeights heights(surface, time, footprint, detail::kDragSurfaceHeightError, double(vertexCount));
    for (std::size_t n = 0; n < vertexCount; ++n)
      surfaceHeights_[n] = flat ? *flat : heights.at(mesh.positions[n].x(), mesh.positions[n].z());
    surface.velocitiesBelow(mesh.positions, surfaceHeights_, time, relative_);
    for (std::size_t n = 0; n < vertexCount; ++n) relative_[n] += input.current;
  } else {
    for (std::size_t n = 0; n < vertexCount; ++n) relative_[n] = surface.velocity(mesh.positions[n], time) + input.current;
  }

  double mass = 0.0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), momentum = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < vertexCount; ++n) {
    const Eigen::Vector3d& x = mesh.positions[n];
    relative_[n] = input.vertexVelocity[n] - relative_[n];
    const double m = input.vertexMass[n];
    mass += m;
    center += m * x;
    momentum += m * relative_[n];
  }
  if (!(mass > 0.0)) return result;
  center /= mass;
  const Eigen::Vector3d meanVelocity = momentum / mass;

  // One skin friction coefficient per body and step from its Reynolds number, as for rigid bodies
  // (the ITTC line is a whole-body correlation); the reference length is the vertices' largest extent.
  double friction = 0.0;
  if (input.coefficients.skinFrictionScale > 0.0 && input.viscosity > 0.0) {  // the extent only when friction needs it
    Eigen::Vector3d lower = mesh.positions.front(), upper = lower;
    for (const Eigen::Vector3d& p : mesh.positions) {
      lower = lower.cwiseMin(p);
      upper = upper.cwiseMax(p);
    }
    friction = bodySkinFriction(density, meanVelocity.norm(), (upper - lower).maxCoeff(), input.viscosity, input.coefficients);
  }

  // Texel by texel: the law on the texel's relative velocity, times its wet fraction; the force
  // back to the vertices as the pressure goes.
  for (Eigen::Vector3d& f : vertexDrag_) f.setZero();
  Eigen::Vector3d totalForce = Eigen::Vector3d::Zero(), totalTorque = Eigen::Vector3d::Zero();
  const std::span<const Eigen::Vector3d> areaVectors = input.triangleAreaVectors;
  for (std::size_t i = 0; i < textures.size(); ++i) {
    const double wet = double(input.wetFraction[i]);
    if (!(wet > 0.0)) continue;
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
    double weightSum = 0.0;
    for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k) {
      const TexelPiece& piece = bake.pieces[k];
      const Eigen::Vector3i& tri = mesh.triangles[piece.triangle];
      const double w = double(piece.areaFraction) * areaVectors[piece.triangle].norm();
      const double b1 = piece.centroidBary1, b2 = piece.centroidBary2;
      velocity += w * ((1.0 - b1 - b2) * relative_[std::size_t(tri[0])] + b1 * relative_[std::size_t(tri[1])] +
                       b2 * relative_[std::size_t(tri[2])]);
      weightSum += w;
    }
    if (!(weightSum > 0.0)) continue;
    velocity /= weightSum;
    const Eigen::Vector3d x = textures.position[i].cast<double>();
    const Eigen::Vector3d force =
        wet * texelDragForceWithFriction(textures.areaVector[i].cast<double>(), double(textures.area[i]), velocity,
                                         uniform ? density : surface.densityAt(x), friction, input.coefficients);
    if (!force.allFinite()) continue;
    ++result.texelsVisited;
    totalForce += force;
    totalTorque += (x - center).cross(force);
    for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k) {
      const TexelPiece& piece = bake.pieces[k];
      const Eigen::Vector3i& tri = mesh.triangles[piece.triangle];
      const Eigen::Vector3d share = (double(piece.areaFraction) * areaVectors[piece.triangle].norm() / weightSum) * force;
      const double b1 = piece.centroidBary1, b2 = piece.centroidBary2;
      vertexDrag_[std::size_t(tri[0])] += (1.0 - b1 - b2) * share;
      vertexDrag_[std::size_t(tri[1])] += b1 * share;
      vertexDrag_[std::size_t(tri[2])] += b2 * share;
    }
  }
  result.force = totalForce;
  result.torque = totalTorque;

  // The rigid part and the deformation (file comment).
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Eigen::Vector3d angularMomentum = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < vertexCount; ++n) {
    const Eigen::Vector3d r = mesh.positions[n] - center;
    inertia += input.vertexMass[n] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    angularMomentum += input.vertexMass[n] * r.cross(relative_[n]);
  }
  const Eigen::LDLT<Eigen::Matrix3d> inertiaSolve(inertia);
  const bool rotates = inertiaSolve.info() == Eigen::Success && inertiaSolve.isPositive() &&
                       inertia.determinant() > 1e-12 * std::pow(inertia.trace(), 3);
  auto inverseInertia = [&](const Eigen::Vector3d& v) -> Eigen::Vector3d {
    return rotates ? Eigen::Vector3d(inertiaSolve.solve(v)) : Eigen::Vector3d::Zero();
  };
  const Eigen::Vector3d omega = inverseInertia(angularMomentum);
  Eigen::Vector3d deltaV = dt / mass * totalForce, deltaOmega = dt * inverseInertia(totalTorque);
  {
    const double energy2 = mass * meanVelocity.squaredNorm() + omega.dot(inertia * omega);  // 2 x kinetic energy
    const double along = energy2 > 0.0 ? (mass * meanVelocity.dot(deltaV) + omega.dot(inertia * deltaOmega)) / energy2 : 0.0;
    const double lambda = std::max(0.0, -along);
    Eigen::Vector3d nextV = meanVelocity + (deltaV - along * meanVelocity) + along / (1.0 + lambda) * meanVelocity;
    Eigen::Vector3d nextOmega = omega + (deltaOmega - along * omega) + along / (1.0 + lambda) * omega;
    const double nextEnergy2 = mass * nextV.squaredNorm() + nextOmega.dot(inertia * nextOmega);
    if (nextEnergy2 > energy2) {
      const double shrink = energy2 > 0.0 ? std::sqrt(energy2 / nextEnergy2) : 0.0;
      nextV *= shrink;
      nextOmega *= shrink;
    }
    deltaV = nextV - meanVelocity;
    deltaOmega = nextOmega - omega;
  }
  const Eigen::Vector3d forcePerMass = totalForce / mass, angularAcceleration = inverseInertia(totalTorque);
  Eigen::Vector3d strayMomentum = Eigen::Vector3d::Zero(), strayAngularMomentum = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < vertexCount; ++n) {
    deformationChange_[n].setZero();
    const double m = input.vertexMass[n];
    if (!(m > 0.0)) continue;
    const Eigen::Vector3d r = mesh.positions[n] - center;
    const Eigen::Vector3d w = relative_[n] - meanVelocity - omega.cross(r);
    const double ww = w.squaredNorm();
    if (!(ww > 0.0)) continue;  // no deformation to damp: any push would add energy
    const Eigen::Vector3d delta = dt / m * (vertexDrag_[n] - m * (forcePerMass + angularAcceleration.cross(r)));
    const double along = delta.dot(w) / ww;
    const double lambda = std::max(0.0, -along);
    Eigen::Vector3d next = w + (delta - along * w) + along / (1.0 + lambda) * w;
    if (const double nextSquared = next.squaredNorm(); nextSquared > ww) next *= std::sqrt(ww / nextSquared);
    deformationChange_[n] = next - w;
    strayMomentum += m * deformationChange_[n];
    strayAngularMomentum += m * r.cross(deformationChange_[n]);
  }
  const Eigen::Vector3d strayV = strayMomentum / mass, strayOmega = inverseInertia(strayAngularMomentum);
  double energyChange = 0.0;  // J
  for (std::size_t n = 0; n < vertexCount; ++n) {
    const double m = input.vertexMass[n];
    if (!(m > 0.0)) continue;
    const Eigen::Vector3d r = mesh.positions[n] - center;
    const Eigen::Vector3d change = deltaV + deltaOmega.cross(r) + deformationChange_[n] - strayV - strayOmega.cross(r);
    velocityChange[n] = change;
    if (!change.allFinite()) continue;
    energyChange += 0.5 * m * ((relative_[n] + change).squaredNorm() - relative_[n].squaredNorm());
  }
  result.power = energyChange / dt;
  return result;
}

}  // namespace hydrotex
