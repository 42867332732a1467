// SPDX-License-Identifier: Zlib
// Drag patches from a mesh's triangles (MeshDragPatches.hpp): exact areas and area vectors, the
// radius bound, lids left out, and the drag of a translating box equal to the closed form of the
// per-element law (and so to the texel patches' drag) while it needs a fifth of their patches.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/MeshDragPatches.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/step/RigidBodyStep.hpp"

using namespace hydrotex;

TEST_CASE("mesh drag patches: exact areas, one face each, within twice the radius", "[drag][patches]") {
  const Mesh box = primitives::box({1.0, 0.5, 1.0});
  const double radius = 0.2;
  const std::vector<DragPatch> patches = meshDragPatches(box, 0.9, radius);
  REQUIRE(!patches.empty());
  double area = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const DragPatch& patch : patches) {
    area += patch.area;
    sum += patch.areaVector.cast<double>();
    // A box's faces are orthogonal (cosine 0 < 0.9): a patch lies on one face, so its area vector
    // is as long as its area (float storage: 1e-6 relative).
    CHECK(patch.areaVector.norm() == Approx(patch.area).epsilon(1e-6));
    CHECK(patch.radius <= 2.0 * radius + 1e-6);
    // Its centre lies on the box's surface: one coordinate at the half extent.
    const Eigen::Vector3f n = patch.areaVector / patch.area;
    const Eigen::Vector3f half(0.5f, 0.25f, 0.5f);
    CHECK(std::abs(patch.position.dot(n)) == Approx(std::abs(half.dot(n.cwiseAbs()))).epsilon(1e-6));
  }
  CHECK(area == Approx(4.0).epsilon(1e-6));  // 2 (1 x 1) + 4 (1 x 0.5) m^2
  CHECK(sum.norm() <= 1e-6);                 // closed: the area vectors cancel
  // The 256^2 bake's tiles split each face into many more (337 at this radius).
  CHECK(patches.size() <= 64);

  // An infinite radius merges by normal alone: one patch a face.
  CHECK(meshDragPatches(box, 0.9).size() == 6);
  CHECK(meshDragPatches(box, 0.9, 0.0).empty());

  // A fine sphere: the pieces' areas sum to the mesh's area, whatever the merging.
  const Mesh sphere = primitives::icosphere(0.5, 3);
  double meshArea = 0.0;
  for (const Eigen::Vector3i& t : sphere.triangles)
    meshArea += 0.5 * (sphere.positions[t[1]] - sphere.positions[t[0]]).cross(sphere.positions[t[2]] - sphere.positions[t[0]]).norm();
  double sphereArea = 0.0;
  for (const DragPatch& patch : meshDragPatches(sphere, 0.9, 0.2)) {
    sphereArea += patch.area;
    CHECK(patch.radius <= 0.4 + 1e-6);
  }
  CHECK(sphereArea == Approx(meshArea).epsilon(1e-6));
}

TEST_CASE("mesh drag patches: lids over openings feel no drag", "[drag][patches]") {
  Mesh box = primitives::box({1.0, 1.0, 1.0});
  // The two triangles of the face at +y (normal +y) become a lid.
  for (std::uint32_t t = 0; t < box.triangles.size(); ++t) {
    const Eigen::Vector3i& tri = box.triangles[t];
    const Eigen::Vector3d n = (box.positions[tri[1]] - box.positions[tri[0]]).cross(box.positions[tri[2]] - box.positions[tri[0]]);
    if (n.normalized().y() > 0.99) box.openingTriangles.push_back(t);
  }
  REQUIRE(box.openingTriangles.size() == 2);
  double area = 0.0;
  for (const DragPatch& patch : meshDragPatches(box, 0.9, 0.3)) {
    area += patch.area;
    CHECK(patch.areaVector.y() <= 1e-6f);
  }
  CHECK(area == Approx(5.0).epsilon(1e-6));
}

TEST_CASE("mesh drag patches: a translating box's drag is the per-face closed form", "[drag][patches]") {
  // Wholly under water and translating, every element of a face moves alike, so the pressure law
  // -rho |A| (C/2 |v_n| v_n + c_lin v_n) n summed over a face is the face's, however it is split:
  // the mesh patches and the texel patches give the same force (float patch data: 1e-5).
  const Mesh box = primitives::box({1.0, 0.5, 1.0});
  const FlatSurface water(0.0, 1000.0);
  const DragLiquid liquid{&water, Eigen::Vector3d::Zero(), 1e-3, 0.0};
  RigidBodyMotion motion;
  motion.meshPose.translation = Eigen::Vector3d(0.0, -3.0, 0.0);
  motion.center = motion.meshPose.translation;
  motion.linearVelocity = Eigen::Vector3d(0.7, -0.3, 0.2);
  motion.mass = 250.0;
  motion.inertiaWorld = Eigen::Matrix3d::Identity() * 30.0;
  DragCoefficients coefficients;
  coefficients.skinFrictionScale = 0.0;  // pressure only: the closed form below

  auto dragOf = [&](const std::vector<DragPatch>& patches) {
    DragBody body;
    body.patches = patches;
    for (const DragPatch& patch : patches) body.totalPatchArea += patch.area;
    body.referenceLength = 1.0;
    body.coefficients = coefficients;
    return rigidBodyDrag(body, motion, liquid, 1.0 / 60.0);
  };
  const std::vector<DragPatch> meshPatches = meshDragPatches(box, 0.9, 0.2);
  const DragLoads fromMesh = dragOf(meshPatches);

  // The closed form over the six faces (outward normal n, area |A|).
  const double rho = 1000.0;
  Eigen::Vector3d expected = Eigen::Vector3d::Zero();
  const Eigen::Vector3d normals[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
  const double faceAreas[3] = {0.5, 1.0, 0.5};
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {1.0, -1.0}) {
      const Eigen::Vector3d n = sign * normals[axis];
      const double vn = motion.linearVelocity.dot(n);
      const double c = vn > 0.0 ? coefficients.advancingPressure : coefficients.retreatingPressure;
      expected -= rho * faceAreas[axis] * (0.5 * c * std::abs(vn) * vn + coefficients.linearPressureVelocity * vn) * n;
    }
  CHECK((fromMesh.force - expected).norm() <= 1e-5 * expected.norm());
  CHECK(fromMesh.wettedArea == Approx(4.0).epsilon(1e-6));

  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = 64;
  const Expected<BodyGeometry> geometry = prepareBodyGeometry(box, settings);
  REQUIRE(geometry.ok());
  const std::vector<DragPatch> texelPatches = mergeTexelsIntoDragPatches(geometry->bake, geometry->textures, 0.9, 0.2);
  CHECK(meshPatches.size() < texelPatches.size());
  CHECK((dragOf(texelPatches).force - expected).norm() <= 1e-5 * expected.norm());
}

TEST_CASE("mesh drag patches: a box's layout is mirror-symmetric, so heaving turns it nowhere", "[drag][patches]") {
  // The 2 x 1 x 2 m box of robustness_test_hard_cases' energy check, half under a flat surface,
  // heaving at 0.5 m/s: every face's patches are centred in the cells that tile it, so the drag
  // (pressure on the floor, skin friction on the walls, wet fractions by height) has no torque
  // about the centre, to rounding (float patch data: 1e-6 of force times size). A first-come merge
  // across a face's diagonal left one (the box then drifted 0.3-0.6 mm in 20 s).
  const Mesh box = primitives::box({2.0, 1.0, 2.0});
  const std::vector<DragPatch> patches = meshDragPatches(box, 0.9, 0.2 * 2.0);
  for (const DragPatch& patch : patches) {
    // Mirror images: each patch's reflection through every axis is a patch too.
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Vector3f mirrored = patch.position;
      mirrored[axis] = -mirrored[axis];
      const bool found = std::any_of(patches.begin(), patches.end(), [&](const DragPatch& other) {
        return (other.position - mirrored).norm() < 1e-5f && std::abs(other.area - patch.area) < 1e-6f;
      });
      CHECK(found);
    }
  }
  const FlatSurface water(0.0, 1000.0);
  DragBody body;
  body.patches = patches;
  for (const DragPatch& patch : patches) body.totalPatchArea += patch.area;
  body.referenceLength = 2.0;
  RigidBodyMotion motion;
  motion.mass = 2000.0;
  motion.inertiaWorld = Eigen::Matrix3d::Identity() * 833.0;
  motion.meshPose.translation = {3.0, 0.1, -2.0};
  motion.center = motion.meshPose.translation;
  motion.linearVelocity = {0.0, -0.5, 0.0};
  const DragLoads loads = rigidBodyDrag(body, motion, DragLiquid{&water, Eigen::Vector3d::Zero(), 1e-3, 0.0}, 1.0 / 60.0);
  REQUIRE(loads.force.y() > 0.0);
  CHECK(loads.torque.norm() <= 1e-6 * loads.force.norm() * 2.0);
  CHECK(std::abs(loads.force.x()) + std::abs(loads.force.z()) <= 1e-6 * loads.force.norm());
}
