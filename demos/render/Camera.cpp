// SPDX-License-Identifier: Zlib
#include "Camera.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace hydrotex::render {
namespace {

// gluLookAt (OpenGL 2.1 reference pages).
Eigen::Matrix4f lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, Eigen::Vector3d up) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  if (std::abs(forward.dot(up)) > 0.999) up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d side = forward.cross(up).normalized();
  const Eigen::Vector3d trueUp = side.cross(forward);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = side.transpose();
  m.block<1, 3>(1, 0) = trueUp.transpose();
  m.block<1, 3>(2, 0) = -forward.transpose();
  m(0, 3) = -side.dot(eye);
  m(1, 3) = -trueUp.dot(eye);
  m(2, 3) = forward.dot(eye);
  return m.cast<float>();
}

}  // namespace

Eigen::Matrix4f Camera::view() const { return lookAt(eye, target, Eigen::Vector3d::UnitY()); }

// gluPerspective (OpenGL 2.1 reference pages).
Eigen::Matrix4f Camera::projection(double aspect) const {
  const double f = 1.0 / std::tan(0.5 * verticalFovDegrees * std::numbers::pi / 180.0);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
  m(2, 3) = 2.0 * farPlane * nearPlane / (nearPlane - farPlane);
  m(3, 2) = -1.0;
  return m.cast<float>();
}

// glOrtho (OpenGL 2.1 reference pages) around the light's look-at.
Eigen::Matrix4f lightViewProjection(const Eigen::Vector3d& direction, const Eigen::Vector3d& centre, double radius) {
  const Eigen::Vector3d eye = centre - direction.normalized() * 2.0 * radius;
  const Eigen::Matrix4f view = lookAt(eye, centre, Eigen::Vector3d::UnitY());
  const double nearPlane = 0.01, farPlane = 4.0 * radius;
  Eigen::Matrix4d ortho = Eigen::Matrix4d::Identity();
  ortho(0, 0) = 1.0 / radius;
  ortho(1, 1) = 1.0 / radius;
  ortho(2, 2) = -2.0 / (farPlane - nearPlane);
  ortho(2, 3) = -(farPlane + nearPlane) / (farPlane - nearPlane);
  return ortho.cast<float>() * view;
}

}  // namespace hydrotex::render
