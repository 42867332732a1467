// SPDX-License-Identifier: Zlib
// Buoyancy of Bullet soft bodies through texel pressure forces (issue 5; docs/design.md "Pressure
// integration", "Exact texels"). The force on a texel is -p A (A its vector area, outward); the
// texel's pieces carry -p fraction A_face each, and a piece's force acts at its centroid, which is
// the barycentric combination (1 - b1 - b2, b1, b2) of its face's nodes: giving the force to the
// nodes with these weights keeps the total force and its moment about any point (the moment of
// sum w_k f about x is (sum w_k x_k - x) x f, the centroid's). Drag (Effect::Drag) is core's
// SoftBodyDrag (the rigid bodies' law per texel, handed to the nodes the same way); this file only
// reads Bullet's nodes into core's inputs and adds the results to them.
#include "hydrotex/bullet/SoftBodyBuoyancy.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/step/SoftBodyDrag.hpp"
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
    out.nodeVelocity_.assign(std::size_t(nodeCount), Eigen::Vector3d::Zero());
    out.velocityChange_.assign(std::size_t(nodeCount), Eigen::Vector3d::Zero());
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
  // Node velocities as they were at the end of the last step: Bullet's predictMotion has already
  // added g dt, which drag must not see (a ball at rest would read dt g downwards and be held up
  // by its own drag; the rigid bodies avoid it the same way). Pinned nodes have no mass.
  const Eigen::Vector3d gravityStep = dt * toEigen(body_->getWorldInfo()->m_gravity);
  const std::size_t nodeCount = mesh_.positions.size();
  for (std::size_t n = 0; n < nodeCount; ++n) {
    const btSoftBody::Node& node = body_->m_nodes[int(n)];
    const bool movable = node.m_im > 0;
    nodeVelocity_[n] = toEigen(node.m_v) - (movable ? gravityStep : Eigen::Vector3d::Zero());
    nodeMass_[n] = movable ? 1.0 / double(node.m_im) : 0.0;
  }
  // Core's law (SoftBodyDrag.hpp): the texels' drag, taken so that it never adds kinetic energy.
  SoftBodyDragInput input;
  input.mesh = &mesh_;
  input.bake = &bake_;
  input.textures = &textures_;
  input.wetFraction = texelWetFraction_;
  input.triangleAreaVectors = faceAreaVector_;
  input.vertexVelocity = nodeVelocity_;
  input.vertexMass = nodeMass_;
  input.surface = &surface;
  input.current = liquid.current;
  input.viscosity = liquid.viscosity;
  input.time = time;
  input.dt = dt;
  input.coefficients = settings_.drag;
  const SoftBodyDragResult drag = drag_.step(input, velocityChange_);
  report.dragForce = btVector3(btScalar(drag.force.x()), btScalar(drag.force.y()), btScalar(drag.force.z()));
  report.dragTorque = btVector3(btScalar(drag.torque.x()), btScalar(drag.torque.y()), btScalar(drag.torque.z()));
  report.dragPower = drag.power;
  report.dragTexelsVisited = drag.texelsVisited;
  // As a semi-implicit Euler step: the velocity change, and the position moved by it times dt.
  for (std::size_t n = 0; n < nodeCount; ++n) {
    const Eigen::Vector3d& change = velocityChange_[n];
    if (!(nodeMass_[n] > 0.0) || !change.allFinite()) continue;
    const btVector3 applied(btScalar(change.x()), btScalar(change.y()), btScalar(change.z()));
    btSoftBody::Node& node = body_->m_nodes[int(n)];
    node.m_v += applied;
    node.m_x += applied * btScalar(dt);
  }
}

}  // namespace hydrotex::bullet
