// SPDX-License-Identifier: Zlib
// Buoyancy of Bullet soft bodies through texel pressure forces (issue 5; docs/design.md "Pressure
// integration", "Exact texels"). The force on a texel is -p A (A its vector area, outward); the
// texel's pieces carry -p fraction A_face each, and a piece's force acts at its centroid, which is
// the barycentric combination (1 - b1 - b2, b1, b2) of its face's nodes: giving the force to the
// nodes with these weights keeps the total force and its moment about any point (the moment of
// sum w_k f about x is (sum w_k x_k - x) x f, the centroid's). Drag (Effect::Drag) is the rigid
// bodies' law (TexelDrag.hpp) per texel, handed to the nodes the same way.
#include "hydrotex/bullet/SoftBodyBuoyancy.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"
#include "hydrotex/hydrostatics/TexelDrag.hpp"
#include "hydrotex/hydrostatics/TexelPressure.hpp"

namespace hydrotex::bullet {

Status SoftBodySettings::validate() const {
  if (resolution < 16 || resolution > 4096)
    return Error{"soft body resolution " + std::to_string(resolution) + " is outside 16..4096"};
  for (Effect effect : {Effect::AddedMass, Effect::VariableMass, Effect::Flooding, Effect::Deformation, Effect::Wetting})
    if (effects.has(effect))
      return Error{"soft body effects: '" + std::string(effectName(effect)) + "' is not available (buoyancy and drag only)"};
  const DragCoefficients& d = drag;
  for (double value : {d.advancingPressure, d.retreatingPressure, d.linearPressureVelocity, d.skinFrictionScale})
    if (!(value >= 0.0 && std::isfinite(value)))
      return Error{"soft body drag: coefficients must be >= 0 and finite (got " + std::to_string(value) + ")"};
  return Ok{};
}

namespace {

Eigen::Vector3d toEigen(const btVector3& v) { return {double(v.x()), double(v.y()), double(v.z())}; }

}  // namespace

Expected<SoftBodyBuoyancy> SoftBodyBuoyancy::create(btSoftBody* body, const SoftBodySettings& settings) {
  if (body == nullptr) return Error{"soft body: null btSoftBody"};
  if (Status valid = settings.validate(); !valid) return valid.error();
  const int nodeCount = body->m_nodes.size(), faceCount = body->m_faces.size();
  if (faceCount == 0) return Error{"soft body: no faces (buoyancy needs a closed surface of faces)"};
  SoftBodyBuoyancy out;
  out.body_ = body;
  out.settings_ = settings;
  out.faceCount_ = std::size_t(faceCount);
  out.mesh_.sourceName = "soft body";
  out.mesh_.positions.reserve(std::size_t(nodeCount));
  for (int i = 0; i < nodeCount; ++i) out.mesh_.positions.push_back(toEigen(body->m_nodes[i].m_x));
  const btSoftBody::Node* first = &body->m_nodes[0];
  double sixVolume = 0.0;
  for (int f = 0; f < faceCount; ++f) {
    Eigen::Vector3i triangle;
    for (int k = 0; k < 3; ++k) {
      const std::ptrdiff_t index = body->m_faces[f].m_n[k] - first;
      if (index < 0 || index >= nodeCount) return Error{"soft body: face " + std::to_string(f) + " names a foreign node"};
      triangle[k] = int(index);
    }
    const Eigen::Vector3d& a = out.mesh_.positions[std::size_t(triangle[0])];
    sixVolume += a.dot(out.mesh_.positions[std::size_t(triangle[1])].cross(out.mesh_.positions[std::size_t(triangle[2])]));
    out.mesh_.triangles.push_back(triangle);
  }
  // Bullet's faces have no required winding; hydrotex needs them outwards (positive volume).
  if (sixVolume < 0.0)
    for (Eigen::Vector3i& t : out.mesh_.triangles) std::swap(t[1], t[2]);

  BodyGeometrySettings geometrySettings;
  geometrySettings.bake.width = geometrySettings.bake.height = settings.resolution;
  Expected<BodyGeometry> geometry = prepareBodyGeometry(out.mesh_, geometrySettings);
  if (!geometry) return Error{"soft body: " + geometry.error().message};
  out.bake_ = std::move(geometry->bake);
  out.evaluator_ = SurfaceEvaluator(out.bake_, geometry->atlas.layout);
  out.textures_ = std::move(geometry->textures);
  out.texelPressure_.assign(out.textures_.size(), 0.0f);
  out.texelWetFraction_.assign(out.textures_.size(), 0.0f);
  out.nodeForce_.assign(std::size_t(nodeCount), Eigen::Vector3d::Zero());
  if (settings.effects.has(Effect::Drag)) {
    out.nodeDrag_.assign(std::size_t(nodeCount), Eigen::Vector3d::Zero());
    out.nodeRelative_.assign(std::size_t(nodeCount), Eigen::Vector3d::Zero());
    out.deformationChange_.assign(std::size_t(nodeCount), Eigen::Vector3d::Zero());
    out.nodeMass_.assign(std::size_t(nodeCount), 0.0);
  }
  out.faceAreaVector_.assign(out.mesh_.triangles.size(), Eigen::Vector3d::Zero());
  return out;
}

Status SoftBodyBuoyancy::apply(const LiquidSurface& surface, double time, double dt, const SoftBodyLiquid& liquid) {
  if (!(dt > 0.0) || !std::isfinite(dt)) return Error{"soft body: time step " + std::to_string(dt) + " s is not positive"};
  const std::size_t nodeCount = mesh_.positions.size();
  if (std::size_t(body_->m_nodes.size()) != nodeCount || std::size_t(body_->m_faces.size()) != faceCount_)
    return Error{"soft body: nodes or faces changed in number since registration"};
  SoftBodyReport report;
  report.steps = report_.steps + 1;
  for (std::size_t i = 0; i < nodeCount; ++i) {
    const btSoftBody::Node& node = body_->m_nodes[int(i)];
    const Eigen::Vector3d p = toEigen(node.m_x);
    if (!p.allFinite() || !toEigen(node.m_v).allFinite())
      return Error{"soft body: node " + std::to_string(i) + " is not finite"};
    mesh_.positions[i] = p;
  }
  evaluator_.evaluate(mesh_, textures_);
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh_.triangles[t];
    const Eigen::Vector3d& a = mesh_.positions[std::size_t(tri[0])];
    faceAreaVector_[t] = 0.5 * (mesh_.positions[std::size_t(tri[1])] - a).cross(mesh_.positions[std::size_t(tri[2])] - a);
  }

  // Pressure per texel and its nodal forces: core's law (TexelPressure.hpp), the waterline rule
  // the rigid texture path uses.
  const double gravity = double(body_->getWorldInfo()->m_gravity.length());
  const bool buoyancy = settings_.effects.has(Effect::Buoyancy);
  report.pressureApplied = buoyancy;
  const TexelPressureSums sums = texelPressures(textures_, surface, time, gravity, texelPressure_, texelWetFraction_);
  report.enclosedVolume = sums.enclosedVolume;
  report.submergedVolume = sums.submergedVolume;
  report.wettedArea = sums.wettedArea;
  if (buoyancy) {
    texelPressureVertexForces(bake_, mesh_, faceAreaVector_, texelPressure_, nodeForce_);
  } else {
    for (Eigen::Vector3d& f : nodeForce_) f.setZero();
  }
  if (settings_.effects.has(Effect::Drag)) applyDrag(surface, time, dt, liquid, report);
  // What btSoftBody::predictMotion does with a node force (semi-implicit Euler), done here
  // because Bullet clears m_f before its next predictMotion (see the header).
  const btScalar step = btScalar(dt);
  for (std::size_t n = 0; n < nodeCount; ++n) {
    const btVector3 f(btScalar(nodeForce_[n].x()), btScalar(nodeForce_[n].y()), btScalar(nodeForce_[n].z()));
    btSoftBody::Node& node = body_->m_nodes[int(n)];
    if (f.isZero() || node.m_im <= 0) continue;
    const btVector3 deltaV = f * (node.m_im * step);
    node.m_v += deltaV;
    node.m_x += deltaV * step;
    report.buoyancyForce += f;
    report.buoyancyTorque += node.m_x.cross(f);
  }
  if (!report.buoyancyForce.isZero() || !report.dragForce.isZero()) body_->activate();
  report_ = report;
  return Ok{};
}

void SoftBodyBuoyancy::applyDrag(const LiquidSurface& surface, double time, double dt, const SoftBodyLiquid& liquid,
                                 SoftBodyReport& report) {
  report.dragApplied = true;
  const double density = surface.density();
  const bool uniform = surface.hasFreeSurface();
  const bool still = surface.flatHeight().has_value() && liquid.current.isZero();
  const std::size_t nodeCount = mesh_.positions.size();
  // Node velocities relative to the liquid as they were at the end of the last step: Bullet's
  // predictMotion has already added g dt, which drag must not see (a ball at rest would read
  // dt g downwards and be held up by its own drag; the rigid bodies avoid it the same way).
  const Eigen::Vector3d gravityStep = dt * toEigen(body_->getWorldInfo()->m_gravity);
  double mass = 0.0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero(), momentum = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < nodeCount; ++n) {
    const btSoftBody::Node& node = body_->m_nodes[int(n)];
    const Eigen::Vector3d& x = mesh_.positions[n];
    const Eigen::Vector3d liquidVelocity = still ? liquid.current : Eigen::Vector3d(surface.velocity(x, time) + liquid.current);
    const bool movable = node.m_im > 0;
    nodeRelative_[n] = toEigen(node.m_v) - (movable ? gravityStep : Eigen::Vector3d::Zero()) - liquidVelocity;
    nodeMass_[n] = movable ? 1.0 / double(node.m_im) : 0.0;
    mass += nodeMass_[n];
    center += nodeMass_[n] * x;
    momentum += nodeMass_[n] * nodeRelative_[n];
  }
  if (!(mass > 0.0)) return;
  center /= mass;
  const Eigen::Vector3d meanVelocity = momentum / mass;

  // One skin friction coefficient per body and step from its Reynolds number, as for rigid bodies
  // (the ITTC line is a whole-body correlation); the reference length is the nodes' largest extent.
  double friction = 0.0;
  if (settings_.drag.skinFrictionScale > 0.0 && liquid.viscosity > 0.0) {  // the extent only when friction needs it
    Eigen::Vector3d lower = mesh_.positions.front(), upper = lower;
    for (const Eigen::Vector3d& p : mesh_.positions) {
      lower = lower.cwiseMin(p);
      upper = upper.cwiseMax(p);
    }
    friction = bodySkinFriction(density, meanVelocity.norm(), (upper - lower).maxCoeff(), liquid.viscosity, settings_.drag);
  }

  // Texel by texel: the law on the texel's relative velocity (its pieces' barycentric node
  // velocities, weighted by area), times its wet fraction; the force back to the nodes as the
  // pressure goes.
  for (Eigen::Vector3d& f : nodeDrag_) f.setZero();
  Eigen::Vector3d totalForce = Eigen::Vector3d::Zero(), totalTorque = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < textures_.size(); ++i) {
    const double wet = double(texelWetFraction_[i]);
    if (!(wet > 0.0)) continue;
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
    double weightSum = 0.0;
    for (std::uint32_t k = bake_.pieceStart[i]; k < bake_.pieceStart[i + 1]; ++k) {
      const TexelPiece& piece = bake_.pieces[k];
      const Eigen::Vector3i& tri = mesh_.triangles[piece.triangle];
      const double w = double(piece.areaFraction) * faceAreaVector_[piece.triangle].norm();
      const double b1 = piece.centroidBary1, b2 = piece.centroidBary2;
      velocity += w * ((1.0 - b1 - b2) * nodeRelative_[std::size_t(tri[0])] + b1 * nodeRelative_[std::size_t(tri[1])] +
                       b2 * nodeRelative_[std::size_t(tri[2])]);
      weightSum += w;
    }
    if (!(weightSum > 0.0)) continue;
    velocity /= weightSum;
    const Eigen::Vector3d x = textures_.position[i].cast<double>();
    const Eigen::Vector3d force =
        wet * texelDragForceWithFriction(textures_.areaVector[i].cast<double>(), double(textures_.area[i]), velocity,
                                         uniform ? density : surface.densityAt(x), friction, settings_.drag);
    if (!force.allFinite()) continue;
    ++report.dragTexelsVisited;
    totalForce += force;
    totalTorque += (x - center).cross(force);
    for (std::uint32_t k = bake_.pieceStart[i]; k < bake_.pieceStart[i + 1]; ++k) {
      const TexelPiece& piece = bake_.pieces[k];
      const Eigen::Vector3i& tri = mesh_.triangles[piece.triangle];
      const Eigen::Vector3d share = (double(piece.areaFraction) * faceAreaVector_[piece.triangle].norm() / weightSum) * force;
      const double b1 = piece.centroidBary1, b2 = piece.centroidBary2;
      nodeDrag_[std::size_t(tri[0])] += (1.0 - b1 - b2) * share;
      nodeDrag_[std::size_t(tri[1])] += b1 * share;
      nodeDrag_[std::size_t(tri[2])] += b2 * share;
    }
  }
  report.dragForce = btVector3(btScalar(totalForce.x()), btScalar(totalForce.y()), btScalar(totalForce.z()));
  report.dragTorque = btVector3(btScalar(totalTorque.x()), btScalar(totalTorque.y()), btScalar(totalTorque.z()));

  // The nodes' motion splits, orthogonally in the mass metric, into the motion as a rigid body
  // (V, omega about the centre of mass, omega = I^-1 L) and a deformation w_n with no momentum
  // and no angular momentum; kinetic energy is the sum of the two parts'. The drag's total force
  // and torque change the rigid part, the rest of the node forces the deformation:
  // - rigid part: the rigid bodies' step (BuoyancyController) on (V, omega), the component along
  //   the motion taken implicitly (secant damping 1 / (1 + lambda)), so it slows the motion and
  //   never reverses it at any dt; what remains may turn the motion but not lengthen it;
  // - deformation: the same per node on w_n, then projected back onto motions with no momentum.
  // Neither part's energy can grow, so drag never adds kinetic energy (relative to the liquid),
  // and a body moving as a whole gets no deformation from its own drag, whatever dt.
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Eigen::Vector3d angularMomentum = Eigen::Vector3d::Zero();
  for (std::size_t n = 0; n < nodeCount; ++n) {
    const Eigen::Vector3d r = mesh_.positions[n] - center;
    inertia += nodeMass_[n] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    angularMomentum += nodeMass_[n] * r.cross(nodeRelative_[n]);
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
  for (std::size_t n = 0; n < nodeCount; ++n) {
    deformationChange_[n].setZero();
    if (!(nodeMass_[n] > 0.0)) continue;
    const Eigen::Vector3d r = mesh_.positions[n] - center;
    const Eigen::Vector3d w = nodeRelative_[n] - meanVelocity - omega.cross(r);
    const double ww = w.squaredNorm();
    if (!(ww > 0.0)) continue;  // no deformation to damp: any push would add energy
    const Eigen::Vector3d delta = dt / nodeMass_[n] * (nodeDrag_[n] - nodeMass_[n] * (forcePerMass + angularAcceleration.cross(r)));
    const double along = delta.dot(w) / ww;
    const double lambda = std::max(0.0, -along);
    Eigen::Vector3d next = w + (delta - along * w) + along / (1.0 + lambda) * w;
    if (const double nextSquared = next.squaredNorm(); nextSquared > ww) next *= std::sqrt(ww / nextSquared);
    deformationChange_[n] = next - w;
    strayMomentum += nodeMass_[n] * deformationChange_[n];
    strayAngularMomentum += nodeMass_[n] * r.cross(deformationChange_[n]);
  }
  const Eigen::Vector3d strayV = strayMomentum / mass, strayOmega = inverseInertia(strayAngularMomentum);
  double energyChange = 0.0;  // J
  for (std::size_t n = 0; n < nodeCount; ++n) {
    if (!(nodeMass_[n] > 0.0)) continue;
    const Eigen::Vector3d r = mesh_.positions[n] - center;
    const Eigen::Vector3d change = deltaV + deltaOmega.cross(r) + deformationChange_[n] - strayV - strayOmega.cross(r);
    if (!change.allFinite()) continue;
    energyChange += 0.5 * nodeMass_[n] * ((nodeRelative_[n] + change).squaredNorm() - nodeRelative_[n].squaredNorm());
    const btVector3 applied(btScalar(change.x()), btScalar(change.y()), btScalar(change.z()));
    btSoftBody::Node& node = body_->m_nodes[int(n)];
    node.m_v += applied;
    node.m_x += applied * btScalar(dt);
  }
  report.dragPower = energyChange / dt;
}

}  // namespace hydrotex::bullet
