// SPDX-License-Identifier: Zlib
// A soft body's motion as a whole from its nodes: the rigid-body quantities of a particle system
// (momentum / mass, I^-1 L about the centre of mass).
#include "hydrotex/bullet/SoftBodyMotion.hpp"

#include <cmath>

namespace hydrotex::bullet {

SoftBodyMotion softBodyMotion(const btSoftBody& body) {
  SoftBodyMotion motion;
  btVector3 weightedPosition(0, 0, 0), momentum(0, 0, 0);
  btScalar mass = 0;
  for (int i = 0; i < body.m_nodes.size(); ++i) {
    const btSoftBody::Node& node = body.m_nodes[i];
    if (!(node.m_im > 0)) continue;
    const btScalar m = 1 / node.m_im;
    mass += m;
    weightedPosition += m * node.m_x;
    momentum += m * node.m_v;
  }
  if (!(mass > 0)) return motion;
  motion.mass = double(mass);
  motion.centerOfMass = weightedPosition / mass;
  motion.linearVelocity = momentum / mass;
  btVector3 angularMomentum(0, 0, 0);
  btMatrix3x3 inertia(0, 0, 0, 0, 0, 0, 0, 0, 0);
  for (int i = 0; i < body.m_nodes.size(); ++i) {
    const btSoftBody::Node& node = body.m_nodes[i];
    if (!(node.m_im > 0)) continue;
    const btScalar m = 1 / node.m_im;
    const btVector3 r = node.m_x - motion.centerOfMass;
    angularMomentum += m * r.cross(node.m_v - motion.linearVelocity);
    // I = sum m (|r|^2 E - r r^T)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) inertia[a][b] += m * ((a == b ? r.length2() : btScalar(0)) - r[a] * r[b]);
  }
  const btScalar determinant = inertia.determinant();
  const btScalar scale = inertia[0][0] + inertia[1][1] + inertia[2][2];
  if (scale > 0 && std::abs(determinant) > btScalar(1e-9) * scale * scale * scale)
    motion.angularVelocity = inertia.inverse() * angularMomentum;
  if (body.m_pose.m_bframe) body.m_pose.m_rot.getRotation(motion.orientation);
  return motion;
}

}  // namespace hydrotex::bullet
