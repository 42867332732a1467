// SPDX-License-Identifier: Zlib
// The deformation effect: a body's vertices move (a callback or scale keyframes) and its texel
// fields, hydrostatics, mass model, drag patches and collision shape follow (issue 5). Scale
// keyframes scale the user's shape (setLocalScaling); a callback's vertices are written into a
// hull or triangle-mesh shape whose points are the mesh's vertices (DeformedCollision.hpp), or
// into a convex hull of them that hydrotex makes (FloatingBodySettings::deformedCollision).
#include <BulletCollision/CollisionShapes/btStridingMeshInterface.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "BulletEigen.hpp"
#include "FloatingBody.hpp"
#include "hydrotex/bullet/BuoyancyController.hpp"

namespace hydrotex::bullet {

namespace {

// Rest vertices sorted along x, to find the vertex a shape's point sits on without an O(n^2) scan.
class VertexLookup {
 public:
  explicit VertexLookup(const std::vector<Eigen::Vector3d>& positions) : positions_(positions), order_(positions.size()) {
    std::iota(order_.begin(), order_.end(), 0);
    std::sort(order_.begin(), order_.end(), [&](int a, int b) { return positions_[std::size_t(a)].x() < positions_[std::size_t(b)].x(); });
    Eigen::Vector3d lower = positions.front(), upper = lower;
    for (const Eigen::Vector3d& p : positions) {
      lower = lower.cwiseMin(p);
      upper = upper.cwiseMax(p);
    }
    // Shapes store float coordinates: a point within float rounding of the body's size is on the vertex.
    tolerance_ = 1e-5 * std::max((upper - lower).maxCoeff(), 1e-9);
  }
  // The vertex at `point` (mesh frame, m), or -1.
  int find(const Eigen::Vector3d& point) const {
    auto it = std::lower_bound(order_.begin(), order_.end(), point.x() - tolerance_,
                               [&](int index, double x) { return positions_[std::size_t(index)].x() < x; });
    for (; it != order_.end() && positions_[std::size_t(*it)].x() <= point.x() + tolerance_; ++it)
      if ((positions_[std::size_t(*it)] - point).norm() <= tolerance_) return *it;
    return -1;
  }
  double tolerance() const { return tolerance_; }

 private:
  const std::vector<Eigen::Vector3d>& positions_;
  std::vector<int> order_;
  double tolerance_ = 0.0;
};

bool isUnitScale(const btVector3& scale) { return scale == btVector3(1, 1, 1); }

// Maps every point of `hull` to the rest vertex it sits on; false when one sits on none.
bool matchHull(const btConvexHullShape& hull, const VertexLookup& lookup, std::vector<int>& hullVertex) {
  if (!isUnitScale(hull.getLocalScaling())) return false;
  hullVertex.resize(std::size_t(hull.getNumPoints()));
  for (int i = 0; i < hull.getNumPoints(); ++i) {
    hullVertex[std::size_t(i)] = lookup.find(toEigen(hull.getUnscaledPoints()[i]));
    if (hullVertex[std::size_t(i)] < 0) return false;
  }
  return hull.getNumPoints() > 0;
}

// True when `mesh` is one vertex array holding the rest vertices in order (float or double).
bool holdsRestVertices(const btStridingMeshInterface& mesh, const std::vector<Eigen::Vector3d>& rest, double tolerance) {
  if (mesh.getNumSubParts() != 1 || !isUnitScale(mesh.getScaling())) return false;
  const unsigned char *vertices = nullptr, *indices = nullptr;
  int vertexCount = 0, stride = 0, indexStride = 0, faceCount = 0;
  PHY_ScalarType type = PHY_FLOAT, indexType = PHY_INTEGER;
  mesh.getLockedReadOnlyVertexIndexBase(&vertices, vertexCount, type, stride, &indices, indexStride, faceCount, indexType, 0);
  bool same = std::size_t(vertexCount) == rest.size() && (type == PHY_FLOAT || type == PHY_DOUBLE) && vertices != nullptr;
  for (std::size_t i = 0; same && i < rest.size(); ++i) {
    const unsigned char* at = vertices + i * std::size_t(stride);
    Eigen::Vector3d p;
    for (int c = 0; c < 3; ++c)
      p[c] = type == PHY_FLOAT ? double(reinterpret_cast<const float*>(at)[c]) : reinterpret_cast<const double*>(at)[c];
    same = (p - rest[i]).norm() <= tolerance;
  }
  mesh.unLockReadOnlyVertexBase(0);
  return same;
}

void writeVertices(btStridingMeshInterface& mesh, const std::vector<Eigen::Vector3d>& positions) {
  unsigned char *vertices = nullptr, *indices = nullptr;
  int vertexCount = 0, stride = 0, indexStride = 0, faceCount = 0;
  PHY_ScalarType type = PHY_FLOAT, indexType = PHY_INTEGER;
  mesh.getLockedVertexIndexBase(&vertices, vertexCount, type, stride, &indices, indexStride, faceCount, indexType, 0);
  for (std::size_t i = 0; i < positions.size() && i < std::size_t(vertexCount); ++i) {
    unsigned char* at = vertices + i * std::size_t(stride);
    for (int c = 0; c < 3; ++c) {
      if (type == PHY_FLOAT)
        reinterpret_cast<float*>(at)[c] = float(positions[i][c]);
      else
        reinterpret_cast<double*>(at)[c] = positions[i][c];
    }
  }
  mesh.unLockVertexBase(0);
}

}  // namespace

Status BuoyancyController::attachDeformedCollision(FloatingBody& floating) {
  const FloatingBodySettings& settings = floating.settings;
  DeformationState& state = *floating.deformation;
  if (!settings.deformation || settings.deformedCollision == DeformedCollisionShape::Keep) return Ok{};
  DeformedCollision& collision = state.collision;
  const VertexLookup lookup(state.rest.positions);
  if (settings.deformedCollision == DeformedCollisionShape::Follow) {
    btCollisionShape* shape = floating.originalShape;
    if (auto* hull = dynamic_cast<btConvexHullShape*>(shape); hull && matchHull(*hull, lookup, collision.hullVertex)) {
      collision.hull = hull;
      return Ok{};
    }
    if (auto* gimpact = dynamic_cast<btGImpactMeshShape*>(shape);
        gimpact && isUnitScale(gimpact->getLocalScaling()) && gimpact->getMeshInterface() != nullptr &&
        holdsRestVertices(*gimpact->getMeshInterface(), state.rest.positions, lookup.tolerance())) {
      collision.gimpact = gimpact;
      collision.meshInterface = gimpact->getMeshInterface();
      return Ok{};
    }
    if (auto* bvh = dynamic_cast<btBvhTriangleMeshShape*>(shape);
        bvh && isUnitScale(bvh->getLocalScaling()) && bvh->getMeshInterface() != nullptr &&
        holdsRestVertices(*bvh->getMeshInterface(), state.rest.positions, lookup.tolerance())) {
      collision.bvh = bvh;
      collision.meshInterface = bvh->getMeshInterface();
      return Ok{};
    }
    return Error{std::string("deformation: the collision shape (") + shape->getName() +
                 ") cannot follow the moved vertices (only a btConvexHullShape whose points are mesh vertices, or a "
                 "btGImpactMeshShape or btBvhTriangleMeshShape over the mesh's vertices in order, can); set "
                 "deformedCollision to ConvexHull or Keep"};
  }
  // ConvexHull: a hull of every vertex, in the compound in place of the user's shape.
  collision.ownedHull = std::make_unique<btConvexHullShape>();
  for (const Eigen::Vector3d& p : state.rest.positions) collision.ownedHull->addPoint(toBullet(p), false);
  collision.ownedHull->setMargin(floating.originalShape->getMargin());
  collision.ownedHull->recalcLocalAabb();
  collision.hull = collision.ownedHull.get();
  collision.hullVertex.resize(state.rest.positions.size());
  std::iota(collision.hullVertex.begin(), collision.hullVertex.end(), 0);
  const btTransform childTransform = floating.compound->getChildTransform(0);
  floating.compound->removeChildShapeByIndex(0);
  floating.compound->addChildShape(childTransform, collision.ownedHull.get());
  return Ok{};
}

void BuoyancyController::deform(FloatingBody& floating) {
  DeformationState& state = *floating.deformation;
  const FloatingBodySettings& settings = floating.settings;
  std::vector<Eigen::Vector3d>& positions = state.current->positions;
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  if (settings.deformation) {
    state.positions = state.rest.positions;
    settings.deformation(time_, state.rest, state.positions);
    if (state.positions.size() != positions.size() || !std::all_of(state.positions.begin(), state.positions.end(),
                                                                    [](const Eigen::Vector3d& p) { return p.allFinite(); })) {
      ++statistics_.failedQueries;  // a callback that broke the topology: keep the last shape
      return;
    }
    positions.swap(state.positions);
  } else {
    scale = scaleAt(settings.scaleKeyframes, time_);
    for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = state.rest.positions[i].cwiseProduct(scale);
  }
  ++statistics_.deformations;
  // PT/VAT from the moved vertices through the kept texel pieces (docs/design.md "Exact texels").
  // In place, allocation-free: the evaluator, the hydrostatics and the mass model reuse their buffers.
  state.evaluator.evaluate(*state.current, state.textures);
  if (floating.backendBody && !backend_->updateSurface(*floating.backendBody, state.textures)) ++statistics_.failedQueries;
  // The mass model sums over the moved triangles (followTriangles at registration): O(triangles).
  if (floating.massModel && !floating.massModel->setGeometry(*state.current)) ++statistics_.failedQueries;
  if (settings.effects.has(Effect::Drag)) {
    setDragPatches(floating,
                   mergeTexelsIntoDragPatches(state.bake, state.textures, settings.dragPatchNormalCosine,
                                              settings.dragPatchRadiusFraction * floating.referenceLength),
                   DragDamping::Secant);
  }
  Eigen::Vector3d lower = positions.front(), upper = lower;
  for (const Eigen::Vector3d& p : positions) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  floating.boundsCenter = 0.5 * (lower + upper);
  floating.boundsRadius = 0.5 * (upper - lower).norm();
  if (!floating.compound) return;
  bool shapeChanged = false;
  if (!settings.scaleKeyframes.empty()) {
    floating.originalShape->setLocalScaling(toBullet(scale));
    shapeChanged = true;
  }
  DeformedCollision& collision = state.collision;
  if (collision.hull != nullptr) {
    btVector3* points = collision.hull->getUnscaledPoints();
    for (std::size_t i = 0; i < collision.hullVertex.size(); ++i)
      points[i] = toBullet(positions[std::size_t(collision.hullVertex[i])]);
    collision.hull->recalcLocalAabb();
    // Polyhedral features (SAT contacts), when the user asked for them, describe the old points.
    if (collision.hull->getConvexPolyhedron() != nullptr) collision.hull->initializePolyhedralFeatures();
    shapeChanged = true;
  } else if (collision.meshInterface != nullptr) {
    writeVertices(*collision.meshInterface, positions);
    if (collision.gimpact != nullptr) {
      collision.gimpact->postUpdate();
      collision.gimpact->updateBound();
    } else if (collision.bvh != nullptr) {
      // refit re-quantizes the tree over the new bounds, so a mesh that grows stays inside them.
      const btVector3 margin(collision.bvh->getMargin(), collision.bvh->getMargin(), collision.bvh->getMargin());
      collision.bvh->refitTree(toBullet(lower) - margin, toBullet(upper) + margin);
    }
    shapeChanged = true;
  }
  if (shapeChanged) {
    floating.compound->recalculateLocalAabb();
    if (floating.body->getBroadphaseHandle() != nullptr) world_.updateSingleAabb(floating.body);
  }
}

}  // namespace hydrotex::bullet
