// SPDX-License-Identifier: Zlib
// Bodies floating as their own Bullet collision shapes (issue 20): meshes of every supported shape
// against closed-form volumes and centres, compounds, scaling, hulls, triangle meshes, refusals,
// addAllBodies in a world, and the scene key `shape`.

#include <BulletCollision/CollisionShapes/btMultiSphereShape.h>
#include <BulletCollision/CollisionShapes/btScaledBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btUniformScalingShape.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "PluginTestWorld.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/bullet/Scene.hpp"
#include "hydrotex/bullet/ShapeMesh.hpp"

using namespace hydrotex;
using namespace hydrotex::bullet;
using hydrotex::bullet::testing::solid;
using hydrotex::bullet::testing::TestWorld;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Volume and centre of the mesh of `shape`, after checking it is closed and outward.
MassProperties meshProperties(const btCollisionShape& shape, const ShapeTessellation& tessellation = {}) {
  Expected<Mesh> mesh = meshFromCollisionShape(shape, tessellation);
  INFO((mesh ? std::string("ok") : mesh.error().message));
  REQUIRE(mesh);
  const Status closed = checkClosedMesh(*mesh);
  INFO((closed ? std::string("closed") : closed.error().message));
  REQUIRE(closed);
  Expected<MassProperties> props = polyhedralMassProperties(*mesh, 1.0);
  REQUIRE(props);
  return *props;
}

/// Extent of the mesh of `shape` along world axis `axis`: [min, max].
std::array<double, 2> meshRange(const btCollisionShape& shape, int axis) {
  Expected<Mesh> mesh = meshFromCollisionShape(shape, {});
  REQUIRE(mesh);
  std::array<double, 2> range{INFINITY, -INFINITY};
  for (const Eigen::Vector3d& p : mesh->positions) {
    range[0] = std::min(range[0], p[axis]);
    range[1] = std::max(range[1], p[axis]);
  }
  return range;
}

/// A closed triangle mesh as Bullet's btTriangleMesh, every triangle's corners given anew (so
/// the conversion must weld them back).
std::unique_ptr<btTriangleMesh> bulletTriangles(const Mesh& mesh) {
  auto triangles = std::make_unique<btTriangleMesh>(true, false);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    btVector3 corners[3];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& p = mesh.positions[t[k]];
      corners[k] = btVector3(btScalar(p.x()), btScalar(p.y()), btScalar(p.z()));
    }
    triangles->addTriangle(corners[0], corners[1], corners[2], false);
  }
  return triangles;
}

}  // namespace

// Dimensions are dyadic (exact in float), so Bullet's float storage adds no error to the
// closed forms. Tessellated round shapes are inscribed: their volume lies in
// [(1 - e) V, V] for the bound e; and the segment count is the smallest one, so the error is
// not far below e either (consecutive counts change it by less than a factor 2: > 0.3 e).
TEST_CASE("round shapes are meshed within the volume bound, per axis, centred as Bullet centres them",
          "[shape][closed-form]") {
  const double bound = GENERATE(1.0e-2, 1.0e-3, 1.0e-4);
  const int axis = GENERATE(0, 1, 2);
  CAPTURE(bound, axis);
  ShapeTessellation tessellation;
  tessellation.maxRelativeVolumeError = bound;
  const double r = 0.375, h = 1.25;
  auto checkVolume = [&](const MassProperties& props, double exact) {
    CAPTURE(props.volume, exact);
    CHECK(props.volume <= exact * (1.0 + 1e-12));
    CHECK(props.volume >= exact * (1.0 - bound));
    CHECK(props.volume < exact * (1.0 - 0.3 * bound));
  };
  // Tolerance for centres: 1e-12 m, double rounding of sums over symmetric meshes.
  SECTION("capsule: V = pi r^2 (4/3 r + h), h the cylindrical part; centred") {
    std::unique_ptr<btCapsuleShape> capsule;
    if (axis == 0) capsule = std::make_unique<btCapsuleShapeX>(btScalar(r), btScalar(h));
    if (axis == 1) capsule = std::make_unique<btCapsuleShape>(btScalar(r), btScalar(h));
    if (axis == 2) capsule = std::make_unique<btCapsuleShapeZ>(btScalar(r), btScalar(h));
    const MassProperties props = meshProperties(*capsule, tessellation);
    checkVolume(props, kPi * r * r * (4.0 / 3.0 * r + h));
    CHECK(props.centerOfMass.norm() < 1e-12);
    // The poles are mesh vertices: the extent along the axis is exactly h + 2 r.
    const auto range = meshRange(*capsule, axis);
    CHECK(range[0] == Approx(-(0.5 * h + r)).margin(1e-12));
    CHECK(range[1] == Approx(0.5 * h + r).margin(1e-12));
  }
  SECTION("cylinder: V = pi r^2 h; centred") {
    btVector3 half{btScalar(r), btScalar(r), btScalar(r)};
    half[axis] = btScalar(0.5 * h);
    std::unique_ptr<btCylinderShape> cylinder;
    if (axis == 0) cylinder = std::make_unique<btCylinderShapeX>(half);
    if (axis == 1) cylinder = std::make_unique<btCylinderShape>(half);
    if (axis == 2) cylinder = std::make_unique<btCylinderShapeZ>(half);
    const MassProperties props = meshProperties(*cylinder, tessellation);
    checkVolume(props, kPi * r * r * h);
    CHECK(props.centerOfMass.norm() < 1e-12);
    const auto range = meshRange(*cylinder, axis);
    CHECK(range[1] - range[0] == Approx(h).margin(1e-12));
  }
  SECTION("cone: V = pi r^2 h / 3; centroid h/4 above the base, the base at -h/2 (Bullet centres its box)") {
    std::unique_ptr<btConeShape> cone;
    if (axis == 0) cone = std::make_unique<btConeShapeX>(btScalar(r), btScalar(h));
    if (axis == 1) cone = std::make_unique<btConeShape>(btScalar(r), btScalar(h));
    if (axis == 2) cone = std::make_unique<btConeShapeZ>(btScalar(r), btScalar(h));
    const MassProperties props = meshProperties(*cone, tessellation);
    checkVolume(props, kPi * r * r * h / 3.0);
    // A pyramid's centroid is h/4 above its base whatever the base polygon: exact for the mesh.
    Eigen::Vector3d expected = Eigen::Vector3d::Zero();
    expected[axis] = -0.5 * h + 0.25 * h;
    CHECK((props.centerOfMass - expected).norm() < 1e-12);
    const auto range = meshRange(*cone, axis);
    CHECK(range[0] == Approx(-0.5 * h).margin(1e-12));  // base
    CHECK(range[1] == Approx(0.5 * h).margin(1e-12));   // apex, towards +axis
  }
  SECTION("sphere: V = 4/3 pi r^3; centred") {
    btSphereShape sphere{btScalar(r)};
    const MassProperties props = meshProperties(sphere, tessellation);
    checkVolume(props, 4.0 / 3.0 * kPi * r * r * r);
    CHECK(props.centerOfMass.norm() < 1e-12);
    if (bound == 1.0e-3) {  // the counts ShapeMesh.hpp states
      CHECK(meshFromCollisionShape(sphere, tessellation)->triangles.size() == 17160);
      btCylinderShape cylinder(btVector3(1, 1, 1));
      CHECK(meshFromCollisionShape(cylinder, tessellation)->triangles.size() == 4 * 84);
    }
  }
}

TEST_CASE("a box is meshed exactly at the size it was given, whatever its margin", "[shape][closed-form]") {
  const double margin = GENERATE(0.0, 0.04, 0.1);
  CAPTURE(margin);
  btBoxShape box(btVector3(0.5f, 0.25f, 0.75f));
  box.setMargin(btScalar(margin));
  // Bullet keeps the box shrunk by the margin and adds it back in contacts.
  REQUIRE(double(box.getHalfExtentsWithoutMargin().x()) == Approx(0.5 - margin).margin(1e-7));
  const MassProperties props = meshProperties(box);
  // Exact: 8 triangles' worth of dyadic corners; 1e-12 relative is double rounding.
  CHECK(props.volume == Approx(8.0 * 0.5 * 0.25 * 0.75).epsilon(1e-12));
  CHECK(props.centerOfMass.norm() < 1e-12);
  CHECK(meshRange(box, 2)[1] == Approx(0.75).margin(1e-12));
}

TEST_CASE("a compound of two boxes follows its child transforms; overlapping children are refused",
          "[shape][closed-form]") {
  // A 1 m cube centred at (-0.5, 0, 0) and a 0.5 x 1 x 1.5 box turned 90 degrees about y (so
  // 1.5 m along x) centred at (0.75, 0, 0): they touch in the plane x = 0.
  btBoxShape cube(btVector3(0.5f, 0.5f, 0.5f));
  btBoxShape plank(btVector3(0.25f, 0.5f, 0.75f));
  btCompoundShape compound;
  compound.addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(-0.5f, 0, 0)), &cube);
  compound.addChildShape(btTransform(btQuaternion(btVector3(0, 1, 0), btScalar(kPi / 2)), btVector3(0.75f, 0, 0)),
                         &plank);
  const MassProperties props = meshProperties(compound);
  // Volumes 1 and 0.75 m^3; centroid x = (1 (-0.5) + 0.75 (0.75)) / 1.75. 1e-6: the child
  // rotation is a float quaternion (cos 45 degrees to 6e-8).
  CHECK(props.volume == Approx(1.75).epsilon(1e-6));
  CHECK(props.centerOfMass.x() == Approx((-0.5 + 0.75 * 0.75) / 1.75).margin(1e-6));
  CHECK(std::abs(props.centerOfMass.y()) < 1e-6);
  CHECK(std::abs(props.centerOfMass.z()) < 1e-6);
  CHECK(meshRange(compound, 0)[1] == Approx(1.5).margin(1e-6));

  // Moved 0.1 m into the cube: refused, naming both children.
  compound.updateChildTransform(1, btTransform(btQuaternion(btVector3(0, 1, 0), btScalar(kPi / 2)), btVector3(0.65f, 0, 0)));
  Expected<Mesh> overlapping = meshFromCollisionShape(compound, {});
  REQUIRE_FALSE(overlapping);
  INFO(overlapping.error().message);
  CHECK(overlapping.error().message.find("children 0 (btBoxShape) and 1 (btBoxShape) overlap") != std::string::npos);
  // A child wholly inside another is refused too.
  btBoxShape pebble(btVector3(0.1f, 0.1f, 0.1f));
  btCompoundShape nested;
  nested.addChildShape(btTransform::getIdentity(), &cube);
  nested.addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(0.2f, 0, 0)), &pebble);
  Expected<Mesh> inside = meshFromCollisionShape(nested, {});
  REQUIRE_FALSE(inside);
  CHECK(inside.error().message.find("children 0 (btBoxShape) and 1 (btBoxShape) overlap") != std::string::npos);
}

TEST_CASE("compound children whose bounding boxes overlap but which are apart are accepted", "[shape]") {
  // Two 2 x 0.2 x 1 slabs turned 45 degrees about z, 0.3 m apart along their common normal:
  // their axis-aligned boxes overlap widely, their own axes separate them.
  btBoxShape slab(btVector3(1.0f, 0.1f, 0.5f));
  btCompoundShape compound;
  const btQuaternion turn(btVector3(0, 0, 1), btScalar(kPi / 4));
  const btVector3 normal = btTransform(turn) * btVector3(0, 1, 0);
  compound.addChildShape(btTransform(turn, -0.15f * normal), &slab);
  compound.addChildShape(btTransform(turn, 0.15f * normal), &slab);
  // Two slabs of 0.4 m^3; 1e-6 for the float rotation.
  CHECK(meshProperties(compound).volume == Approx(0.8).epsilon(1e-6));
}

TEST_CASE("scaled shapes: local scaling, btUniformScalingShape, btScaledBvhTriangleMeshShape", "[shape][closed-form]") {
  SECTION("a box's local scaling") {
    btBoxShape box(btVector3(0.5f, 0.5f, 0.5f));
    box.setLocalScaling(btVector3(2.0f, 1.0f, 0.5f));
    CHECK(meshProperties(box).volume == Approx(1.0).epsilon(1e-12));
    CHECK(meshRange(box, 0)[1] == Approx(1.0).margin(1e-12));
  }
  SECTION("a uniformly scaled cylinder: V = pi (s r)^2 (s h)") {
    btCylinderShape cylinder(btVector3(0.25f, 0.5f, 0.25f));
    btUniformScalingShape scaled(&cylinder, 2.0f);
    const double exact = kPi * 0.5 * 0.5 * 2.0;
    const double volume = meshProperties(scaled).volume;
    CHECK(volume <= exact);
    CHECK(volume >= exact * (1.0 - ShapeTessellation{}.maxRelativeVolumeError));
  }
  SECTION("a scaled triangle mesh of a 1 m cube: scaling (1, 2, 3) gives 6 m^3") {
    const Mesh cube = primitives::box({1.0, 1.0, 1.0});
    auto triangles = bulletTriangles(cube);
    btBvhTriangleMeshShape bvh(triangles.get(), true);
    btScaledBvhTriangleMeshShape scaled(&bvh, btVector3(1.0f, 2.0f, 3.0f));
    const MassProperties props = meshProperties(scaled);
    CHECK(props.volume == Approx(6.0).epsilon(1e-12));
    CHECK(meshRange(scaled, 2)[1] == Approx(1.5).margin(1e-12));
  }
}

TEST_CASE("a convex hull of a box's 8 corners (and an inner point) is that box", "[shape][closed-form]") {
  btConvexHullShape hull;
  for (int i = 0; i < 8; ++i) {
    hull.addPoint(btVector3(i & 1 ? 0.5f : -0.5f, i & 2 ? 0.25f : -0.25f, i & 4 ? 0.75f : -0.75f), false);
  }
  hull.addPoint(btVector3(0.1f, 0.0f, -0.2f), true);  // inside: not a hull vertex
  Expected<Mesh> mesh = meshFromCollisionShape(hull, {});
  REQUIRE(mesh);
  CHECK(mesh->positions.size() == 8);
  CHECK(mesh->triangles.size() == 12);
  const MassProperties props = meshProperties(hull);
  CHECK(props.volume == Approx(0.75).epsilon(1e-12));
  CHECK(props.centerOfMass.norm() < 1e-12);
  // Local scaling scales the points (getScaledPoint).
  hull.setLocalScaling(btVector3(2.0f, 1.0f, 1.0f));
  CHECK(meshProperties(hull).volume == Approx(1.5).epsilon(1e-12));
  // Flat points span no volume: refused.
  btConvexHullShape flat;
  for (int i = 0; i < 4; ++i) flat.addPoint(btVector3(i & 1 ? 1.0f : 0.0f, 0.0f, i & 2 ? 1.0f : 0.0f), true);
  Expected<Mesh> none = meshFromCollisionShape(flat, {});
  REQUIRE_FALSE(none);
  CHECK(none.error().message.find("btConvexHullShape") != std::string::npos);
}

TEST_CASE("triangle mesh shapes give their closed mesh back, corners welded", "[shape][closed-form]") {
  const Mesh sphere = primitives::icosphere(0.5, 2);
  Expected<MassProperties> reference = polyhedralMassProperties(sphere, 1.0);
  REQUIRE(reference);
  auto triangles = bulletTriangles(sphere);
  // 1e-6 relative: the corners went through float.
  SECTION("btBvhTriangleMeshShape") {
    btBvhTriangleMeshShape bvh(triangles.get(), true);
    const MassProperties props = meshProperties(bvh);
    CHECK(props.volume == Approx(reference->volume).epsilon(1e-6));
    Expected<Mesh> mesh = meshFromCollisionShape(bvh, {});
    REQUIRE(mesh);
    CHECK(mesh->positions.size() == sphere.positions.size());
  }
  SECTION("btGImpactMeshShape, with local scaling 2") {
    btGImpactMeshShape gimpact(triangles.get());
    gimpact.setLocalScaling(btVector3(2.0f, 2.0f, 2.0f));
    gimpact.updateBound();
    CHECK(meshProperties(gimpact).volume == Approx(8.0 * reference->volume).epsilon(1e-6));
  }
}

TEST_CASE("a multi-sphere shape is the hull of its spheres, within the bound", "[shape][closed-form]") {
  // Two spheres of radius r, d apart: their hull is a capsule, V = pi r^2 (4/3 r + d).
  const double r = 0.25, d = 1.0;
  const btVector3 centres[2] = {btVector3(0, btScalar(-0.5 * d), 0), btVector3(0, btScalar(0.5 * d), 0)};
  const btScalar radii[2] = {btScalar(r), btScalar(r)};
  btMultiSphereShape pair(centres, radii, 2);
  const double exact = kPi * r * r * (4.0 / 3.0 * r + d);
  const double volume = meshProperties(pair).volume;
  CAPTURE(volume, exact);
  CHECK(volume <= exact * (1.0 + 1e-12));
  CHECK(volume >= exact * (1.0 - ShapeTessellation{}.maxRelativeVolumeError));
}

TEST_CASE("unsupported shapes are refused with one line naming the shape type", "[shape][bad-input]") {
  btStaticPlaneShape plane(btVector3(0, 1, 0), 0);
  Expected<Mesh> mesh = meshFromCollisionShape(plane, {});
  REQUIRE_FALSE(mesh);
  CHECK(mesh.error().message.find("btStaticPlaneShape is not supported") != std::string::npos);
  CHECK(mesh.error().message.find('\n') == std::string::npos);
  // Inside a compound, the child is named too.
  btBoxShape box(btVector3(0.5f, 0.5f, 0.5f));
  btCompoundShape compound;
  compound.addChildShape(btTransform::getIdentity(), &box);
  compound.addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(3, 0, 0)), &plane);
  Expected<Mesh> child = meshFromCollisionShape(compound, {});
  REQUIRE_FALSE(child);
  CHECK(child.error().message.find("child 1: collision shape btStaticPlaneShape") != std::string::npos);
  // A tessellation bound out of range is refused.
  ShapeTessellation fine;
  fine.maxRelativeVolumeError = 0.0;
  CHECK_FALSE(meshFromCollisionShape(box, fine));
  // And through addBody, with no mesh given.
  TestWorld world;
  btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &plane));
  const Status added = world.controller().addBody(&body, solid(500.0, {Effect::Buoyancy}));
  REQUIRE_FALSE(added);
  CHECK(added.error().message.find("btStaticPlaneShape") != std::string::npos);
  // And through addAllBodies: the first error names the object; the bodies before it stay.
  btBoxShape cubeShape(btVector3(0.5f, 0.5f, 0.5f));
  btRigidBody cube(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &cubeShape));
  world.world().addRigidBody(&cube);
  world.world().addRigidBody(&body);
  Expected<std::size_t> all = world.controller().addAllBodies(solid(500.0, {Effect::Buoyancy}));
  REQUIRE_FALSE(all);
  INFO(all.error().message);
  CHECK(all.error().message.find("collision object 1 (after 1 bodies added): shape: collision shape btStaticPlaneShape") == 0);
  CHECK(world.controller().bodyCount() == 1);
  world.controller().removeBody(&cube);
  world.world().removeRigidBody(&cube);
  world.world().removeRigidBody(&body);
}

TEST_CASE("a long thin capsule is meshed within the volume bound in a bounded number of triangles",
          "[shape][closed-form]") {
  // fuzz_scene found a 110 m capsule of 0.25 m radius (fuzz/corpus/scene/long-capsule-rows-
  // timeout.json): its cylinder took rows as tall as the caps' 19 mm rings, 5,882 of them, a
  // million triangles (its scene took 6.3 s, 60 s under the sanitizers). The side is ruled, so
  // the rows do not change the volume: at most `slices` of them now (ShapeMesh: slices = 4 m, m
  // rings per cap), 2 slices (2 m + slices) triangles at most, and the volume within the bound.
  const double r = 0.25, h = 110.0;
  const btCapsuleShapeZ capsule{btScalar(r), btScalar(h)};
  Expected<Mesh> mesh = meshFromCollisionShape(capsule, {});
  REQUIRE(mesh);
  const double exact = kPi * r * r * (4.0 / 3.0 * r + h);
  const MassProperties props = meshProperties(capsule);
  CAPTURE(mesh->triangles.size(), props.volume, exact);
  // The default bound, 1e-3 of the volume (ShapeTessellation), needs m = 21 rings a cap here
  // (84 slices: the cylinder's polygon loses (2 pi / n)^2 / 6 of its area, 9.3e-4 at n = 84):
  // 2 * 84 * (42 + 84) = 21,168 triangles at most.
  CHECK(mesh->triangles.size() <= 21168);
  CHECK(props.volume <= exact * (1.0 + 1e-12));
  CHECK(props.volume >= exact * (1.0 - 1e-3));
  // One chart with each row at its arc length: the cylinder's few tall rows get as much of the
  // chart per square metre as the caps' rings. Texel density (chart area / surface area) is the
  // same on every side triangle, and within 1 % of the triangles of the caps' rings next to the
  // equator: those rings lie within pi / (2 m) of it, so their circumference is at least
  // cos(pi / 42) = 0.997 of the cylinder's for the same chart width. With the rows evenly spaced
  // in the chart (stop 44, run), the side's density was 0.0055 against the equator rings' 0.26:
  // 84 rows of 126 for 110 m of side, 42 for 0.8 m of caps' arc.
  REQUIRE(mesh->hasUvs());
  double sideLow = INFINITY, sideHigh = 0.0, capSum = 0.0;
  int capCount = 0;
  for (std::size_t t = 0; t < mesh->triangles.size(); ++t) {
    Eigen::Vector3d p[3];
    Eigen::Vector2d q[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = mesh->positions[std::size_t(mesh->triangles[t][k])];
      q[k] = mesh->uv.uvs[std::size_t(mesh->uv.uvTriangles[t][k])];
    }
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    const Eigen::Vector2d u = q[1] - q[0], v = q[2] - q[0];
    const double density = 0.5 * std::abs(u.x() * v.y() - u.y() * v.x()) / area;
    bool side = true, nearEquator = true;
    for (const Eigen::Vector3d& c : p) {
      side = side && std::abs(c.z()) <= 0.5 * h + 1e-9;
      nearEquator = nearEquator && std::abs(c.z()) >= 0.5 * h - 1e-9 && std::hypot(c.x(), c.y()) >= 0.99 * r;
    }
    if (side) {
      sideLow = std::min(sideLow, density);
      sideHigh = std::max(sideHigh, density);
    } else if (nearEquator) {
      capSum += density;
      ++capCount;
    }
  }
  REQUIRE(capCount > 0);
  CAPTURE(sideLow, sideHigh, capSum / capCount);
  CHECK(sideHigh <= sideLow * (1.0 + 1e-6));
  CHECK(capSum / capCount == Approx(sideLow).epsilon(0.01));
}

TEST_CASE("addAllBodies floats a world's boxes and capsules as their own shapes at the closed-form draft",
          "[shape][floating][closed-form]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture);
  CAPTURE(method == HydrostaticsMethod::Texture);
  TestWorld world;
  // An existing world: a static floor, a kinematic platform, a 2 x 1 x 1.5 m box and a capsule
  // lying along z, both dynamic.
  btStaticPlaneShape floorShape(btVector3(0, 1, 0), -20);
  btRigidBody floor(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &floorShape));
  btBoxShape platformShape(btVector3(1, 0.1f, 1));
  btRigidBody platform(btRigidBody::btRigidBodyConstructionInfo(0, nullptr, &platformShape));
  platform.setCollisionFlags(platform.getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  platform.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 5, 0)));
  btBoxShape boxShape(btVector3(1.0f, 0.5f, 0.75f));
  btRigidBody box(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &boxShape));
  box.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(-3, 0.3f, 0)));
  btCapsuleShapeZ capsuleShape(0.25f, 1.0f);
  btRigidBody capsule(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &capsuleShape));
  capsule.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(3, 0.3f, 0)));
  btRigidBody* all[] = {&floor, &platform, &box, &capsule};
  for (btRigidBody* body : all) world.world().addRigidBody(body);

  FloatingBodySettings defaults = solid(500.0, {Effect::Buoyancy, Effect::Drag}, method);  // no mesh: the shapes
  Expected<std::size_t> added = world.controller().addAllBodies(defaults);
  INFO((added ? std::string("ok") : added.error().message));
  REQUIRE(added);
  CHECK(*added == 2);  // the floor and the platform are skipped
  CHECK(world.controller().bodyCount() == 2);
  Expected<std::size_t> again = world.controller().addAllBodies(defaults);
  REQUIRE(again);
  CHECK(*again == 0);  // already registered
  // Masses from the shapes' meshes: the box exactly 500 x 3 m^3.
  CHECK(world.controller().report(&box)->massProperties.mass == Approx(1500.0).epsilon(1e-9));

  const double dt = 1.0 / 120.0;
  for (int i = 0; i < int(25.0 / dt); ++i) world.step(dt);
  // Half the density of water: both float half immersed, the box's centre (draft h/2 = 0.5 m of
  // its 1 m) and the capsule's axis at the surface, y = 0 (the capsule by symmetry whatever its
  // tessellation). 2 mm as in test_floating: float positions, residual motion, a texel's
  // waterline at 64^2.
  CHECK(double(box.getCenterOfMassPosition().y()) == Approx(0.0).margin(2e-3));
  CHECK(double(capsule.getCenterOfMassPosition().y()) == Approx(0.0).margin(2e-3));
  CHECK(double(box.getLinearVelocity().length()) < 1e-2);
  for (btRigidBody* body : all) {
    world.controller().removeBody(body);
    world.world().removeRigidBody(body);
  }
}

TEST_CASE("a box shape's drag in flat water runs on its faces' nodes on the exact path; without drag on none",
          "[shape][floating][drag]") {
  // Half in still water, level, the drag sums its law on the 2 x 2 nodes of each wetted face's
  // one piece (the bottom, wholly wet, and the four sides, cut by the water line from side to side:
  // 20 a step), not on the box mesh's 64 patches: test_rigid_body_step checks the drag they give.
  // A body that asks no drag pays for none: no drag pass, no node visited.
  for (bool drag : {true, false}) {
    INFO("drag " << drag);
    TestWorld world;
    btBoxShape shape(btVector3(0.5f, 0.25f, 0.5f));
    btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, &shape, btVector3(1, 1, 1)));
    body.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.3f, 0.02f, 0.1f)));
    FloatingBodySettings settings = solid(500.0, drag ? EffectSet{Effect::Buoyancy, Effect::Drag} : EffectSet{Effect::Buoyancy},
                                          HydrostaticsMethod::Polyhedral);
    REQUIRE(world.controller().addBody(&body, settings).ok());
    world.world().addRigidBody(&body);
    const int steps = 30;
    for (int i = 0; i < steps; ++i) world.step(1.0 / 60.0);
    const ControllerStatistics& statistics = world.controller().statistics();
    CHECK(statistics.failedQueries == 0);
    CHECK(statistics.dragPasses == (drag ? std::uint64_t(steps) : 0u));
    CHECK(statistics.dragPatchesVisited == (drag ? std::uint64_t(steps) * 20u : 0u));
    world.world().removeRigidBody(&body);
    world.controller().removeBody(&body);
  }
}

TEST_CASE("scene bodies given by `shape` float as Bullet primitives", "[shape][scene]") {
  const std::string scene = R"({
    "dt": 0.0083333333, "duration": 25,
    "fluid": {"density": 1000, "surface": {"type": "plane", "height": 0}},
    "bodies": [
      {"name": "crate", "shape": {"type": "box", "half_extents": [1, 0.5, 0.75]}, "density": 500,
       "position": [-3, 0.3, 0], "resolution": 64, "method": "polyhedral"},
      {"name": "log", "shape": {"type": "capsule", "radius": 0.25, "height": 1.0, "axis": "z"}, "density": 500,
       "position": [3, 0.3, 0], "resolution": 64, "method": "polyhedral"}
    ]})";
  Expected<Scene> parsed = parseScene(scene, ".", "shapes.json");
  INFO((parsed ? std::string("ok") : parsed.error().message));
  REQUIRE(parsed);
  REQUIRE(parsed->bodies[1].shape);
  CHECK(parsed->bodies[1].shape->axis == 2);
  Expected<std::unique_ptr<SceneWorld>> world = SceneWorld::create(*parsed);
  INFO((world ? std::string("ok") : world.error().message));
  REQUIRE(world);
  for (long long i = 0; i < parsed->stepCount(); ++i) (*world)->step();
  // As in the addAllBodies test: half the density of water, centres at the surface (2 mm).
  for (btRigidBody* body : (*world)->bodies()) CHECK(double(body->getCenterOfMassPosition().y()) == Approx(0.0).margin(2e-3));
}

TEST_CASE("bad `shape` keys are refused with one line naming the key and value", "[shape][scene][bad-input]") {
  auto error = [](const std::string& shape) {
    const std::string text = R"({"bodies": [{"name": "b", "density": 500, "shape": )" + shape + "}]}";
    Expected<Scene> parsed = parseScene(text, ".", "bad.json");
    REQUIRE_FALSE(parsed);
    CHECK(parsed.error().message.find('\n') == std::string::npos);
    return parsed.error().message;
  };
  CHECK(error(R"({"type": "torus", "radius": 1})") == "bad.json: bodies[0].shape.type: 'torus' is not one of box, sphere, capsule, cylinder, cone");
  CHECK(error(R"({"type": "sphere", "radius": -0.5})") == "bad.json: bodies[0].shape.radius: -0.5 must be > 0 (m)");
  CHECK(error(R"({"type": "box", "half_extents": [1, 0, 1]})") == "bad.json: bodies[0].shape.half_extents: [1,0,1] must all be > 0 (m)");
  CHECK(error(R"({"type": "capsule", "radius": 0.3, "height": -1})") == "bad.json: bodies[0].shape.height: -1 must be >= 0 (m)");
  CHECK(error(R"({"type": "cone", "radius": 0.3, "height": 1, "axis": "w"})") == "bad.json: bodies[0].shape.axis: 'w' is not x, y or z");
  CHECK(error(R"({"type": "sphere", "radius": 1, "height": 2})") == "bad.json: bodies[0].shape.height: unknown key for a sphere");
  CHECK(error(R"({"type": "cylinder", "radius": 1})") == "bad.json: bodies[0].shape.height: missing (m)");
  CHECK(error(R"("box")").find("bodies[0].shape: expected an object") != std::string::npos);
}

TEST_CASE("bodies of one shape, of shapes alike, or of one mesh file share one model", "[shape][model]") {
  const auto method = GENERATE(HydrostaticsMethod::Polyhedral, HydrostaticsMethod::Texture, HydrostaticsMethod::Auto);
  CAPTURE(int(method));
  TestWorld world;
  BuoyancyController& controller = world.controller();
  // Five 1 x 0.5 x 1 m boxes: two of one btBoxShape, one of another btBoxShape of the same extents,
  // one of a mesh file (the same box, saved), one more of that file; a 1 x 0.6 x 1 m box; two
  // spheres of their own btSphereShapes of one radius.
  btBoxShape shared(btVector3(0.5f, 0.25f, 0.5f)), alike(btVector3(0.5f, 0.25f, 0.5f)), taller(btVector3(0.5f, 0.3f, 0.5f));
  btSphereShape ball(0.4f), sameBall(0.4f), scaledBall(0.8f), coarseBall(0.4f);
  scaledBall.setLocalScaling(btVector3(0.5f, 0.5f, 0.5f));  // radius 0.4 m as well
  const std::string path = (std::filesystem::temp_directory_path() / "hydrotex_test_interned_box.obj").string();
  REQUIRE(saveMesh(primitives::box({1.0, 0.5, 1.0}), path));
  struct Made {
    btCollisionShape* shape;
    bool fromFile = false;
    double volumeError = ShapeTessellation{}.maxRelativeVolumeError;
  };
  const Made made[] = {{&shared},     {&shared},   {&alike},      {&shared, true},     {&shared, true},
                       {&taller},     {&ball},     {&sameBall},   {&scaledBall},       {&coarseBall, false, 1e-2}};
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  FloatingBodySettings settings = solid(500.0, {Effect::Buoyancy, Effect::Drag}, method);
  controller.resetStatistics();
  for (std::size_t i = 0; i < std::size(made); ++i) {
    auto body = std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(1, nullptr, made[i].shape));
    body->setWorldTransform(btTransform(btQuaternion(btVector3(1, 0, 0), btScalar(0.1)), btVector3(btScalar(3 * i), 0.1f, 0)));
    FloatingBodySettings own = settings;
    if (made[i].fromFile) own.meshPath = path;
    own.shape.maxRelativeVolumeError = made[i].volumeError;
    const Status added = controller.addBody(body.get(), own);
    INFO((added ? std::string("ok") : added.error().message));
    REQUIRE(added);
    world.world().addRigidBody(body.get());
    bodies.push_back(std::move(body));
  }
  std::filesystem::remove(path);
  auto shares = [&](std::size_t i) { return controller.report(bodies[i].get())->sharesModel; };
  CHECK_FALSE(shares(0));
  CHECK(shares(1));        // the same btBoxShape
  CHECK(shares(2));        // another btBoxShape of the same extents: the same mesh to the bit
  CHECK_FALSE(shares(3));  // the file's mesh names the file: a mesh of its own kind ...
  CHECK(shares(4));        // ... which the second body of the file shares
  CHECK_FALSE(shares(5));  // other extents
  CHECK_FALSE(shares(6));
  CHECK(shares(7));        // a sphere of the same radius (closed forms in flat water unless on texels)
  CHECK(shares(8));        // ... and one whose scaling gives it that radius
  CHECK_FALSE(shares(9));  // the same sphere tessellated more coarsely: another mesh
  for (std::size_t i : {1, 2, 4, 7, 8}) CHECK(controller.report(bodies[i].get())->effectMemoryBytes == 0);
  // Auto measures a kind once: the box, the file's box and the taller box (a true sphere in flat
  // water takes its closed forms without asking Auto).
  if (method == HydrostaticsMethod::Auto) CHECK(controller.statistics().autoMethodChoices == 3);

  // Sharing changes no number: the bodies of one kind, released alike, move alike (within the
  // rounding of their different x, as in "bodies of one mesh and the same settings share one
  // model": 1e-15 m in double-precision Bullet, equal in float).
  for (int i = 0; i < 60; ++i) world.step(1.0 / 60.0);
  const double rounding = sizeof(btScalar) == sizeof(double) ? 1e-14 : 0.0;
  auto height = [&](std::size_t i) { return double(bodies[i]->getCenterOfMassPosition().y()); };
  for (std::size_t i : {1, 2}) CHECK(std::abs(height(i) - height(0)) <= rounding);
  CHECK(std::abs(height(4) - height(3)) <= rounding);
  // The file's box is the shape's box, its triangles in another order; but on the exact path the
  // btBoxShape's drag is summed on its faces' nodes (DragBody::boxHalfExtents) and the file's on its
  // mesh's patches, whose wet ramp at the water line is coarser: 0.77 mm apart after the second.
  const bool boxNodes = controller.report(bodies[0].get())->method == HydrostaticsMethod::Polyhedral;
  CHECK(std::abs(height(3) - height(0)) <= (boxNodes ? 2e-3 : 1e-6));
  if (boxNodes) CHECK(std::abs(height(3) - height(0)) > 1e-6);  // the nodes are taken
  for (std::size_t i : {7, 8}) CHECK(std::abs(height(i) - height(6)) <= rounding);
  CHECK(std::abs(height(5) - height(0)) > 1e-3);  // the taller box floats otherwise: the check can fail
  CHECK(controller.statistics().failedQueries == 0);
  for (auto& body : bodies) {
    controller.removeBody(body.get());
    world.world().removeRigidBody(body.get());
  }
}
