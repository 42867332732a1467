// Buoyancy of Bullet soft bodies through texel pressure forces (issue 5; DESIGN.md "Pressure
// integration", "Exact texels"). The force on a texel is -p A (A its vector area, outward); the
// texel's pieces carry -p fraction A_face each, and a piece's force acts at its centroid, which is
// the barycentric combination (1 - b1 - b2, b1, b2) of its face's nodes: giving the force to the
// nodes with these weights keeps the total force and its moment about any point (the moment of
// sum w_k f about x is (sum w_k x_k - x) x f, the centroid's).
#include "hydrotex/bullet/SoftBodyBuoyancy.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <optional>
#include <string>

#include "hydrotex/BodyGeometry.hpp"

namespace hydrotex::bullet {

Status SoftBodySettings::validate() const {
  if (resolution < 16 || resolution > 4096)
    return Error{"soft body resolution " + std::to_string(resolution) + " is outside 16..4096"};
  return Ok{};
}

namespace {

Eigen::Vector3d toEigen(const btVector3& v) { return {double(v.x()), double(v.y()), double(v.z())}; }

// Mean of max(0, d) and the wet fraction over a texel whose depth is d0 at its centre and spreads
// uniformly over [d0 - s, d0 + s] (s: half its vertical span). Exact for a texel tilted along one
// of its edges; continuous in d0, so a body crossing the surface sees no jump.
struct WetPart {
  double meanDepth;  // m
  double fraction;   // 0..1
};
WetPart wetPart(double d0, double s) {
  if (!(s > 0.0)) return d0 > 0.0 ? WetPart{d0, 1.0} : WetPart{0.0, 0.0};
  if (d0 >= s) return {d0, 1.0};
  if (d0 <= -s) return {0.0, 0.0};
  return {(d0 + s) * (d0 + s) / (4.0 * s), (d0 + s) / (2.0 * s)};
}

}  // namespace

Expected<SoftBodyBuoyancy> SoftBodyBuoyancy::create(btSoftBody* body, const SoftBodySettings& settings) {
  if (body == nullptr) return Error{"soft body: null btSoftBody"};
  if (Status valid = settings.validate(); !valid) return valid.error();
  const int nodeCount = body->m_nodes.size(), faceCount = body->m_faces.size();
  if (faceCount == 0) return Error{"soft body: no faces (buoyancy needs a closed surface of faces)"};
  SoftBodyBuoyancy out;
  out.body_ = body;
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
  out.nodeForce_.assign(std::size_t(nodeCount), btVector3(0, 0, 0));
  out.faceAreaVector_.assign(out.mesh_.triangles.size(), Eigen::Vector3d::Zero());
  return out;
}

Status SoftBodyBuoyancy::apply(const LiquidSurface& surface, double time, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) return Error{"soft body: time step " + std::to_string(dt) + " s is not positive"};
  const std::size_t nodeCount = mesh_.positions.size();
  if (std::size_t(body_->m_nodes.size()) != nodeCount || std::size_t(body_->m_faces.size()) != faceCount_)
    return Error{"soft body: nodes or faces changed in number since registration"};
  for (std::size_t i = 0; i < nodeCount; ++i) {
    const Eigen::Vector3d p = toEigen(body_->m_nodes[int(i)].m_x);
    if (!p.allFinite()) return Error{"soft body: node " + std::to_string(i) + " is not finite"};
    mesh_.positions[i] = p;
  }
  evaluator_.evaluate(mesh_, textures_);
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = mesh_.triangles[t];
    const Eigen::Vector3d& a = mesh_.positions[std::size_t(tri[0])];
    faceAreaVector_[t] = 0.5 * (mesh_.positions[std::size_t(tri[1])] - a).cross(mesh_.positions[std::size_t(tri[2])] - a);
  }

  const double gravity = double(body_->getWorldInfo()->m_gravity.length());
  const double rhoG = surface.density() * gravity;
  const std::optional<double> flat = surface.flatHeight();
  const bool free = surface.hasFreeSurface();
  SoftBodyReport report;
  report.steps = report_.steps + 1;
  for (btVector3& f : nodeForce_) f.setZero();
  for (std::size_t i = 0; i < textures_.size(); ++i) {
    const Eigen::Vector3d x = textures_.position[i].cast<double>();
    const float area = textures_.area[i];
    report.enclosedVolume += x.dot(textures_.areaVector[i].cast<double>()) / 3.0;
    double pressure = 0.0;
    if (free) {
      const double height = flat ? *flat : surface.surfaceHeight(x.x(), x.z(), time);
      const double halfSpan = 0.5 * (std::abs(double(textures_.edgeU[i].y())) + std::abs(double(textures_.edgeV[i].y())));
      const WetPart wet = wetPart(height - x.y(), halfSpan);
      pressure = rhoG * wet.meanDepth;
      report.wettedArea += wet.fraction * double(area);
    } else {
      pressure = surface.pressure(x, time, gravity);
      report.wettedArea += double(area);
    }
    texelPressure_[i] = float(pressure);
    if (!(pressure != 0.0) || !std::isfinite(pressure)) continue;  // dry, or a surface that answered NaN
    for (std::uint32_t k = bake_.pieceStart[i]; k < bake_.pieceStart[i + 1]; ++k) {
      const TexelPiece& piece = bake_.pieces[k];
      const Eigen::Vector3i& tri = mesh_.triangles[piece.triangle];
      const Eigen::Vector3d force = -pressure * double(piece.areaFraction) * faceAreaVector_[piece.triangle];
      const double b1 = piece.centroidBary1, b2 = piece.centroidBary2;
      const double weight[3] = {1.0 - b1 - b2, b1, b2};
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector3d share = weight[c] * force;
        nodeForce_[std::size_t(tri[c])] += btVector3(btScalar(share.x()), btScalar(share.y()), btScalar(share.z()));
      }
    }
  }
  // What btSoftBody::predictMotion does with a node force (semi-implicit Euler), done here
  // because Bullet clears m_f before its next predictMotion (see the header).
  const btScalar step = btScalar(dt);
  for (std::size_t n = 0; n < nodeCount; ++n) {
    const btVector3& f = nodeForce_[n];
    btSoftBody::Node& node = body_->m_nodes[int(n)];
    if (f.isZero() || node.m_im <= 0) continue;
    const btVector3 deltaV = f * (node.m_im * step);
    node.m_v += deltaV;
    node.m_x += deltaV * step;
    report.buoyancyForce += f;
    report.buoyancyTorque += node.m_x.cross(f);
  }
  if (!report.buoyancyForce.isZero()) body_->activate();
  report_ = report;
  return Ok{};
}

}  // namespace hydrotex::bullet
