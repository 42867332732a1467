// SPDX-License-Identifier: Zlib
// Closed meshes from Bullet collision shapes (ShapeMesh.hpp): round primitives tessellated to a
// volume bound from closed forms, hulls through btConvexHullComputer, triangle meshes welded,
// compounds merged after a separating-axis check of their children.
#include "hydrotex/bullet/ShapeMesh.hpp"

#include <BulletCollision/CollisionShapes/btMultiSphereShape.h>
#include <BulletCollision/CollisionShapes/btScaledBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btUniformScalingShape.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <LinearMath/btConvexHullComputer.h>
#include <btBulletCollisionCommon.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "BulletEigen.hpp"
#include "ShapeKey.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/Primitives.hpp"

namespace hydrotex::bullet {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxCompoundDepth = 32;

/// The Bullet class behind a shape type, for messages.
std::string shapeName(const btCollisionShape& shape) {
  switch (shape.getShapeType()) {
    case BOX_SHAPE_PROXYTYPE: return "btBoxShape";
    case SPHERE_SHAPE_PROXYTYPE: return "btSphereShape";
    case CAPSULE_SHAPE_PROXYTYPE: return "btCapsuleShape";
    case CYLINDER_SHAPE_PROXYTYPE: return "btCylinderShape";
    case CONE_SHAPE_PROXYTYPE: return "btConeShape";
    case CONVEX_HULL_SHAPE_PROXYTYPE: return "btConvexHullShape";
    case MULTI_SPHERE_SHAPE_PROXYTYPE: return "btMultiSphereShape";
    case UNIFORM_SCALING_SHAPE_PROXYTYPE: return "btUniformScalingShape";
    case SCALED_TRIANGLE_MESH_SHAPE_PROXYTYPE: return "btScaledBvhTriangleMeshShape";
    case TRIANGLE_MESH_SHAPE_PROXYTYPE: return "btBvhTriangleMeshShape";
    case GIMPACT_SHAPE_PROXYTYPE: return "btGImpactMeshShape";
    case COMPOUND_SHAPE_PROXYTYPE: return "btCompoundShape";
    case STATIC_PLANE_PROXYTYPE: return "btStaticPlaneShape";
    case TERRAIN_SHAPE_PROXYTYPE: return "btHeightfieldTerrainShape";
    case CONVEX_TRIANGLEMESH_SHAPE_PROXYTYPE: return "btConvexTriangleMeshShape";
    case CONVEX_POINT_CLOUD_SHAPE_PROXYTYPE: return "btConvexPointCloudShape";
    case TRIANGLE_SHAPE_PROXYTYPE: return "btTriangleShape";
    case EMPTY_SHAPE_PROXYTYPE: return "btEmptyShape";
    default: return std::string(shape.getName()) + " (Bullet shape type " + std::to_string(shape.getShapeType()) + ")";
  }
}

/// Maps every vertex through p -> linear p + offset; a reflection (negative scaling) reverses the
/// triangles so that they stay counter-clockwise seen from outside.
void transformMesh(Mesh& mesh, const Eigen::Matrix3d& linear, const Eigen::Vector3d& offset) {
  for (Eigen::Vector3d& p : mesh.positions) p = linear * p + offset;
  if (linear.determinant() < 0.0) {
    for (Eigen::Vector3i& t : mesh.triangles) std::swap(t[1], t[2]);
    for (Eigen::Vector3i& t : mesh.uv.uvTriangles) std::swap(t[1], t[2]);
  }
}

/// The rotation taking `from` (a unit axis) to Bullet's axis `axis` (0, 1, 2).
Eigen::Matrix3d axisRotation(const Eigen::Vector3d& from, int axis) {
  return Eigen::Quaterniond::FromTwoVectors(from, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
}

/// Fraction of a circle's area its inscribed regular n-gon holds: n sin(2 pi / n) / (2 pi).
double polygonAreaRatio(int n) { return n / (2.0 * kPi) * std::sin(2.0 * kPi / n); }

/// Smallest slice count (a multiple of 4, so the mesh keeps the shape's mirror symmetries) whose
/// inscribed polygon, hence prism or pyramid, loses at most `error` of the volume.
int prismSlices(double error) {
  int n = 8;
  while (1.0 - polygonAreaRatio(n) > error) n += 4;
  return n;
}

/// Volume of primitives::capsule(r, h, 4 m, m) (uvSphere(r, 4 m, 2 m) when h = 0) in closed
/// form: every cross-section is a regular 4m-gon whose circumradius is linear between rings, so
/// the volume is the n-gon's area ratio times the frusta of the meridian polyline.
double capsuleMeshVolume(double r, double h, int m) {
  double meridian = 0.0;  // revolved volume of one cap's inscribed meridian polyline
  for (int j = 0; j < m; ++j) {
    const double a0 = 0.5 * kPi * j / m, a1 = 0.5 * kPi * (j + 1) / m;
    const double r0 = r * std::cos(a0), r1 = r * std::cos(a1);
    meridian += kPi * (r * std::sin(a1) - r * std::sin(a0)) / 3.0 * (r0 * r0 + r0 * r1 + r1 * r1);
  }
  return polygonAreaRatio(4 * m) * (2.0 * meridian + kPi * r * r * h);
}

/// Rings per hemisphere of a sphere or capsule mesh within `error` of the volume (4 m slices).
int capStacks(double r, double h, double error) {
  const double exact = kPi * r * r * (4.0 / 3.0 * r + h);
  int m = 2;
  while (1.0 - capsuleMeshVolume(r, h, m) / exact > error) ++m;
  return m;
}

/// Volume enclosed by a closed mesh (signed tetrahedra from the origin).
double enclosedVolume(const Mesh& mesh) {
  double sixTimes = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    sixTimes += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]]));
  }
  return sixTimes / 6.0;
}

/// The convex hull of `points` as an outward mesh. btConvexHullComputer passes the points through
/// an integer grid; with `snap` each hull vertex is moved back onto the nearest input point
/// (O(vertices x points): for a user's hull, whose points are exact, not for sampled spheres).
Expected<Mesh> hullMesh(const std::vector<Eigen::Vector3d>& points, const std::string& name, bool snap) {
  if (points.size() < 4) return Error{name + ": fewer than 4 points span no volume"};
  std::vector<double> coordinates;
  coordinates.reserve(3 * points.size());
  for (const Eigen::Vector3d& p : points) coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
  btConvexHullComputer computer;
  computer.compute(coordinates.data(), int(3 * sizeof(double)), int(points.size()), 0, 0);
  Mesh mesh;
  mesh.sourceName = name;
  for (int i = 0; i < computer.vertices.size(); ++i) {
    const Eigen::Vector3d v = toEigen(computer.vertices[i]);
    if (!snap) {
      mesh.positions.push_back(v);
      continue;
    }
    std::size_t best = 0;
    for (std::size_t k = 1; k < points.size(); ++k) {
      if ((points[k] - v).squaredNorm() < (points[best] - v).squaredNorm()) best = k;
    }
    mesh.positions.push_back(points[best]);
  }
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : mesh.positions) centre += p;
  centre /= double(std::max<std::size_t>(1, mesh.positions.size()));
  for (int f = 0; f < computer.faces.size(); ++f) {
    const btConvexHullComputer::Edge* start = &computer.edges[computer.faces[f]];
    std::vector<int> polygon;
    const btConvexHullComputer::Edge* edge = start;
    do {
      polygon.push_back(edge->getSourceVertex());
      edge = edge->getNextEdgeOfFace();
    } while (edge != start && polygon.size() <= std::size_t(computer.vertices.size()));
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      Eigen::Vector3i t(polygon[0], polygon[k], polygon[k + 1]);
      const Eigen::Vector3d& a = mesh.positions[t[0]];
      const Eigen::Vector3d normal = (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);
      if (normal.dot(a - centre) < 0.0) std::swap(t[1], t[2]);  // outward: away from the inner centre
      mesh.triangles.push_back(t);
    }
  }
  Eigen::Vector3d lower = points.front(), upper = lower;
  for (const Eigen::Vector3d& p : points) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  const double size = (upper - lower).norm();
  if (mesh.triangles.size() < 4 || !(enclosedVolume(mesh) > 1e-9 * size * size * size)) {
    return Error{name + ": its points are flat and span no volume"};
  }
  return mesh;
}

/// Collects triangles with their corners welded by exact position.
class TriangleWelder {
 public:
  explicit TriangleWelder(std::string name) { mesh_.sourceName = std::move(name); }
  void add(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3i t(index(a), index(b), index(c));
    if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) mesh_.triangles.push_back(t);
  }
  Mesh take() { return std::move(mesh_); }

 private:
  int index(const Eigen::Vector3d& p) {
    auto [it, inserted] = indices_.try_emplace({p.x(), p.y(), p.z()}, int(mesh_.positions.size()));
    if (inserted) mesh_.positions.push_back(p);
    return it->second;
  }
  Mesh mesh_;
  std::map<std::array<double, 3>, int> indices_;
};

/// Triangles of a btStridingMeshInterface, its own scaling applied.
class InterfaceCollector : public btInternalTriangleIndexCallback {
 public:
  explicit InterfaceCollector(TriangleWelder& welder) : welder_(welder) {}
  void internalProcessTriangleIndex(btVector3* triangle, int, int) override {
    welder_.add(toEigen(triangle[0]), toEigen(triangle[1]), toEigen(triangle[2]));
  }

 private:
  TriangleWelder& welder_;
};

Mesh stridingMesh(const btStridingMeshInterface& meshInterface, const std::string& name) {
  TriangleWelder welder(name);
  InterfaceCollector collector(welder);
  const btVector3 huge(BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT);
  meshInterface.InternalProcessAllTriangles(&collector, -huge, huge);
  return welder.take();
}

/// Triangles of a btGImpactMeshShape through its parts' primitive managers, which hold the
/// scaling Bullet collides with (setLocalScaling replaces the parts' scale, not the interface's).
Expected<Mesh> gimpactMesh(const btGImpactMeshShape& shape) {
  TriangleWelder welder("btGImpactMeshShape");
  for (int part = 0; part < shape.getMeshPartCount(); ++part) {
    // Reading needs the part's lock (a read lock of the vertex arrays), which Bullet declares
    // on the non-const manager.
    auto* manager = const_cast<btGImpactMeshShapePart*>(shape.getMeshPart(part))->getTrimeshPrimitiveManager();
    manager->lock();
    for (int face = 0; face < manager->get_primitive_count(); ++face) {
      unsigned int i0 = 0, i1 = 0, i2 = 0;
      manager->get_indices(face, i0, i1, i2);
      btVector3 a, b, c;
      manager->get_vertex(i0, a);
      manager->get_vertex(i1, b);
      manager->get_vertex(i2, c);
      welder.add(toEigen(a), toEigen(b), toEigen(c));
    }
    manager->unlock();
  }
  return welder.take();
}

/// Points of a mesh projected on `axis`: [min, max].
std::array<double, 2> project(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& axis) {
  std::array<double, 2> range{INFINITY, -INFINITY};
  for (const Eigen::Vector3d& p : points) {
    const double s = p.dot(axis);
    range[0] = std::min(range[0], s);
    range[1] = std::max(range[1], s);
  }
  return range;
}

/// A compound child's mesh in the compound's frame and its frame's axes (columns).
struct ChildMesh {
  Mesh mesh;
  Eigen::Matrix3d axes;
  std::string name;
};

/// True unless a separating axis among the compound's axes, the two children's axes and their
/// cross products shows the children apart (touching counts as apart). Exact for two boxes;
/// conservative otherwise (projections of the vertices bound the children).
bool childrenOverlap(const ChildMesh& a, const ChildMesh& b) {
  std::vector<Eigen::Vector3d> axes;
  for (int i = 0; i < 3; ++i) {
    axes.push_back(Eigen::Vector3d::Unit(i));
    axes.push_back(a.axes.col(i));
    axes.push_back(b.axes.col(i));
    for (int j = 0; j < 3; ++j) axes.push_back(a.axes.col(i).cross(b.axes.col(j)));
  }
  for (Eigen::Vector3d axis : axes) {
    const double length = axis.norm();
    if (!(length > 1e-9)) continue;  // parallel axes: already among the children's own
    axis /= length;
    const auto ra = project(a.mesh.positions, axis), rb = project(b.mesh.positions, axis);
    // Bullet's shapes are in float: positions that touch may differ by float rounding.
    const double tolerance = 1e-6 * std::max({ra[1] - ra[0], rb[1] - rb[0], std::abs(ra[0]), std::abs(rb[0])});
    if (ra[1] <= rb[0] + tolerance || rb[1] <= ra[0] + tolerance) return false;
  }
  return true;
}

Expected<Mesh> shapeMesh(const btCollisionShape& shape, const ShapeTessellation& tessellation, int depth);

Expected<Mesh> compoundMesh(const btCompoundShape& compound, const ShapeTessellation& tessellation, int depth) {
  if (compound.getNumChildShapes() == 0) return Error{"btCompoundShape: has no children"};
  std::vector<ChildMesh> children;
  for (int i = 0; i < compound.getNumChildShapes(); ++i) {
    const btCollisionShape* child = compound.getChildShape(i);
    Expected<Mesh> mesh = shapeMesh(*child, tessellation, depth + 1);
    if (!mesh) return Error{"btCompoundShape: child " + std::to_string(i) + ": " + mesh.error().message};
    const btTransform& transform = compound.getChildTransform(i);
    const Eigen::Matrix3d rotation = toEigen(transform.getBasis());
    transformMesh(*mesh, rotation, toEigen(transform.getOrigin()));
    children.push_back({std::move(mesh).value(), rotation, shapeName(*child)});
  }
  for (std::size_t i = 0; i < children.size(); ++i) {
    for (std::size_t j = i + 1; j < children.size(); ++j) {
      if (childrenOverlap(children[i], children[j])) {
        return Error{"btCompoundShape: children " + std::to_string(i) + " (" + children[i].name + ") and " +
                     std::to_string(j) + " (" + children[j].name +
                     ") overlap; their union is not computed (their common volume would count twice): "
                     "separate them or give a mesh"};
      }
    }
  }
  if (children.size() == 1) return std::move(children.front().mesh);
  // Several children: one mesh of separate closed parts; their UV charts would overlap, so the
  // physics atlas is generated for the whole.
  Mesh merged;
  merged.sourceName = "btCompoundShape";
  for (ChildMesh& child : children) {
    const int offset = int(merged.positions.size());
    merged.positions.insert(merged.positions.end(), child.mesh.positions.begin(), child.mesh.positions.end());
    for (const Eigen::Vector3i& t : child.mesh.triangles) merged.triangles.push_back(t + Eigen::Vector3i::Constant(offset));
  }
  return merged;
}

/// The hull of a btMultiSphereShape's spheres: the hull of each sphere's inscribed mesh, refined
/// until the hull of the same meshes scaled to circumscribe their spheres is within the bound
/// (the true shape lies between the two hulls).
Expected<Mesh> multiSphereMesh(const btMultiSphereShape& shape, double error) {
  const btVector3 scaling = shape.getLocalScaling();
  if (!(scaling.x() == scaling.y() && scaling.y() == scaling.z())) {
    return Error{"btMultiSphereShape: non-uniform local scaling is not supported"};
  }
  double largest = 0.0;
  for (int i = 0; i < shape.getSphereCount(); ++i) largest = std::max(largest, double(shape.getSphereRadius(i)));
  if (shape.getSphereCount() == 0 || !(largest > 0.0)) return Error{"btMultiSphereShape: has no sphere"};
  const double s = scaling.x();
  // The gap between the hulls is about 3 (1 - inner) = 3 pi^2 / (16 m^2): start where that meets
  // the bound, and refine while the measured gap does not.
  const int first = std::max(capStacks(1.0, 0.0, error), int(std::ceil(kPi / (4.0 * std::sqrt(error / 3.0)))));
  for (int m = first; m <= 512; m += std::max(1, m / 4)) {
    const Mesh unit = primitives::uvSphere(1.0, 4 * m, 2 * m);
    double inner = 1.0;  // the unit mesh holds the ball of this radius: its nearest face plane
    for (const Eigen::Vector3i& t : unit.triangles) {
      const Eigen::Vector3d& a = unit.positions[t[0]];
      const Eigen::Vector3d normal = (unit.positions[t[1]] - a).cross(unit.positions[t[2]] - a).normalized();
      inner = std::min(inner, std::abs(normal.dot(a)));
    }
    std::vector<Eigen::Vector3d> in, out;
    for (int i = 0; i < shape.getSphereCount(); ++i) {
      const Eigen::Vector3d centre = s * toEigen(shape.getSpherePosition(i));
      const double radius = s * double(shape.getSphereRadius(i));
      for (const Eigen::Vector3d& u : unit.positions) {
        in.push_back(centre + radius * u);
        out.push_back(centre + radius / inner * u);
      }
    }
    Expected<Mesh> lower = hullMesh(in, "btMultiSphereShape", false);
    if (!lower) return lower;
    Expected<Mesh> upper = hullMesh(out, "btMultiSphereShape", false);
    if (!upper) return upper;
    const double volumeIn = enclosedVolume(*lower), volumeOut = enclosedVolume(*upper);
    if (volumeOut - volumeIn <= error * volumeIn) return lower;
  }
  return Error{"btMultiSphereShape: no tessellation within the volume error bound"};
}

Expected<Mesh> shapeMesh(const btCollisionShape& shape, const ShapeTessellation& tessellation, int depth) {
  if (depth > kMaxCompoundDepth) return Error{"btCompoundShape: nested deeper than " + std::to_string(kMaxCompoundDepth)};
  const double error = tessellation.maxRelativeVolumeError;
  const std::string name = shapeName(shape);
  auto positive = [&](double value, const char* what) -> Status {
    if (!(std::isfinite(value) && value > 0.0)) return Error{name + ": " + what + " " + std::to_string(value) + " is not > 0"};
    return Ok{};
  };
  Mesh mesh;
  switch (shape.getShapeType()) {
    case BOX_SHAPE_PROXYTYPE: {
      // The box as constructed: Bullet keeps it shrunk by the margin and adds the margin back.
      const Eigen::Vector3d half = toEigen(static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin());
      for (int i = 0; i < 3; ++i) {
        if (Status s = positive(half[i], "half extent"); !s) return s.error();
      }
      mesh = primitives::box(2.0 * half);
      break;
    }
    case SPHERE_SHAPE_PROXYTYPE: {
      const double r = static_cast<const btSphereShape&>(shape).getRadius();
      if (Status s = positive(r, "radius"); !s) return s.error();
      const int m = capStacks(r, 0.0, error);
      mesh = primitives::uvSphere(r, 4 * m, 2 * m);
      break;
    }
    case CAPSULE_SHAPE_PROXYTYPE: {
      const auto& capsule = static_cast<const btCapsuleShape&>(shape);
      const double r = capsule.getRadius(), h = 2.0 * double(capsule.getHalfHeight());
      if (Status s = positive(r, "radius"); !s) return s.error();
      if (!(std::isfinite(h) && h >= 0.0)) return Error{name + ": height " + std::to_string(h) + " is negative"};
      const int m = capStacks(r, h, error);
      mesh = primitives::capsule(r, h, 4 * m, m);
      transformMesh(mesh, axisRotation(Eigen::Vector3d::UnitY(), capsule.getUpAxis()), Eigen::Vector3d::Zero());
      break;
    }
    case CYLINDER_SHAPE_PROXYTYPE: {
      const auto& cylinder = static_cast<const btCylinderShape&>(shape);
      const int axis = cylinder.getUpAxis();
      const double r = cylinder.getRadius(), h = 2.0 * double(cylinder.getHalfExtentsWithMargin()[axis]);
      if (Status s = positive(r, "radius"); !s) return s.error();
      if (Status s = positive(h, "height"); !s) return s.error();
      mesh = primitives::cylinder(r, h, prismSlices(error));
      transformMesh(mesh, axisRotation(Eigen::Vector3d::UnitZ(), axis), Eigen::Vector3d::Zero());
      break;
    }
    case CONE_SHAPE_PROXYTYPE: {
      // Bullet centres the cone on its bounding box: base at -height/2, apex at +height/2.
      const auto& cone = static_cast<const btConeShape&>(shape);
      const double r = cone.getRadius(), h = cone.getHeight();
      if (Status s = positive(r, "radius"); !s) return s.error();
      if (Status s = positive(h, "height"); !s) return s.error();
      mesh = primitives::cone(r, h, prismSlices(error));
      transformMesh(mesh, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.0, -0.5 * h, 0.0));
      transformMesh(mesh, axisRotation(Eigen::Vector3d::UnitY(), cone.getConeUpIndex()), Eigen::Vector3d::Zero());
      break;
    }
    case CONVEX_HULL_SHAPE_PROXYTYPE: {
      const auto& hull = static_cast<const btConvexHullShape&>(shape);
      std::vector<Eigen::Vector3d> points;
      for (int i = 0; i < hull.getNumPoints(); ++i) points.push_back(toEigen(hull.getScaledPoint(i)));
      return hullMesh(points, name, true);
    }
    case MULTI_SPHERE_SHAPE_PROXYTYPE:
      return multiSphereMesh(static_cast<const btMultiSphereShape&>(shape), error);
    case UNIFORM_SCALING_SHAPE_PROXYTYPE: {
      const auto& scaled = static_cast<const btUniformScalingShape&>(shape);
      const double factor = scaled.getUniformScalingFactor();
      if (Status s = positive(factor, "scaling factor"); !s) return s.error();
      Expected<Mesh> child = shapeMesh(*scaled.getChildShape(), tessellation, depth + 1);
      if (!child) return Error{name + ": " + child.error().message};
      mesh = std::move(child).value();
      transformMesh(mesh, factor * Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
      break;
    }
    case SCALED_TRIANGLE_MESH_SHAPE_PROXYTYPE: {
      const auto& scaled = static_cast<const btScaledBvhTriangleMeshShape&>(shape);
      Expected<Mesh> child = shapeMesh(*scaled.getChildShape(), tessellation, depth + 1);
      if (!child) return Error{name + ": " + child.error().message};
      mesh = std::move(child).value();
      transformMesh(mesh, Eigen::Matrix3d(toEigen(scaled.getLocalScaling()).asDiagonal()), Eigen::Vector3d::Zero());
      mesh.sourceName = name;
      break;
    }
    case TRIANGLE_MESH_SHAPE_PROXYTYPE:
      mesh = stridingMesh(*static_cast<const btTriangleMeshShape&>(shape).getMeshInterface(), name);
      break;
    case GIMPACT_SHAPE_PROXYTYPE: {
      const auto& gimpact = static_cast<const btGImpactShapeInterface&>(shape);
      if (gimpact.getGImpactShapeType() != CONST_GIMPACT_TRIMESH_SHAPE) {
        return Error{"GImpact shape " + std::string(shape.getName()) + " is not supported (btGImpactMeshShape is)"};
      }
      return gimpactMesh(static_cast<const btGImpactMeshShape&>(shape));
    }
    case COMPOUND_SHAPE_PROXYTYPE:
      return compoundMesh(static_cast<const btCompoundShape&>(shape), tessellation, depth);
    default:
      return Error{"collision shape " + name +
                   " is not supported (give a mesh, or a box, sphere, capsule, cylinder, cone, convex hull, "
                   "multi-sphere, triangle mesh or a compound of these)"};
  }
  if (mesh.triangles.empty()) return Error{name + ": has no triangles"};
  mesh.sourceName = name;
  return mesh;
}

}  // namespace

Status ShapeTessellation::validate() const {
  if (!(maxRelativeVolumeError >= 1.0e-5 && maxRelativeVolumeError <= 0.1)) {
    return Error{"maxRelativeVolumeError: " + std::to_string(maxRelativeVolumeError) + " is outside 1e-5..0.1"};
  }
  return Ok{};
}

std::optional<std::string> primitiveShapeKey(const btCollisionShape& shape, const ShapeTessellation& tessellation) {
  // The values shapeMesh's cases read (keep the two together): a change there must change this.
  double values[4] = {0.0, 0.0, 0.0, 0.0};
  switch (shape.getShapeType()) {
    case BOX_SHAPE_PROXYTYPE: {
      const btVector3 half = static_cast<const btBoxShape&>(shape).getHalfExtentsWithMargin();
      values[0] = half.x(), values[1] = half.y(), values[2] = half.z();
      break;
    }
    case SPHERE_SHAPE_PROXYTYPE:
      values[0] = static_cast<const btSphereShape&>(shape).getRadius();
      break;
    case CAPSULE_SHAPE_PROXYTYPE: {
      const auto& capsule = static_cast<const btCapsuleShape&>(shape);
      values[0] = capsule.getRadius(), values[1] = capsule.getHalfHeight(), values[2] = capsule.getUpAxis();
      break;
    }
    case CYLINDER_SHAPE_PROXYTYPE: {
      const auto& cylinder = static_cast<const btCylinderShape&>(shape);
      const int axis = cylinder.getUpAxis();
      values[0] = cylinder.getRadius(), values[1] = cylinder.getHalfExtentsWithMargin()[axis], values[2] = axis;
      break;
    }
    case CONE_SHAPE_PROXYTYPE: {
      const auto& cone = static_cast<const btConeShape&>(shape);
      values[0] = cone.getRadius(), values[1] = cone.getHeight(), values[2] = cone.getConeUpIndex();
      break;
    }
    default:
      return std::nullopt;
  }
  values[3] = tessellation.maxRelativeVolumeError;
  std::string key = std::to_string(shape.getShapeType()) + ":";
  key.append(reinterpret_cast<const char*>(values), sizeof(values));
  return key;
}

Expected<Mesh> meshFromCollisionShape(const btCollisionShape& shape, const ShapeTessellation& tessellation) {
  if (Status s = tessellation.validate(); !s) return Error{"shape tessellation: " + s.error().message};
  return shapeMesh(shape, tessellation, 0);
}

}  // namespace hydrotex::bullet
