// SPDX-License-Identifier: Zlib
#include "DebugLineCollector.hpp"

#include <cstdio>

namespace hydrotex::render {
namespace {
Eigen::Vector3f toEigen(const btVector3& v) { return {float(v.x()), float(v.y()), float(v.z())}; }
}  // namespace

void DebugLineCollector::drawLine(const btVector3& from, const btVector3& to, const btVector3& color) {
  lines_.push_back({toEigen(from), toEigen(to), toEigen(color)});
}

void DebugLineCollector::drawContactPoint(const btVector3& point, const btVector3& normal, btScalar distance,
                                          int /*lifeTime*/, const btVector3& color) {
  drawLine(point, point + normal * distance, color);
}

void DebugLineCollector::reportErrorWarning(const char* warningString) { std::fprintf(stderr, "bullet: %s\n", warningString); }

}  // namespace hydrotex::render
