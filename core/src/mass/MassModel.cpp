// SPDX-License-Identifier: Zlib
// A changing mass model (docs/design.md "Mass model"; paper section 2.3 and figure 13). The texel part
// (solid, shell, density map) is one TextureMassIntegrator pass (or, for a deforming body that
// follows triangles, TriangleMassIntegrator's per-triangle sums); point masses are added with the
// parallel-axis theorem (Steiner): about the combined centre C, a part of mass m, centre c and
// central inertia I_c contributes I_c + m (|r|^2 Id - r r^T), r = c - C (Goldstein, Classical
// Mechanics, 3rd ed., eq. 5.17).
#include "hydrotex/mass/MassModel.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace hydrotex {
namespace {

bool finiteNonNegative(double value) { return std::isfinite(value) && value >= 0.0; }

Eigen::Matrix3d steiner(double mass, const Eigen::Vector3d& offset) {
  return mass * (offset.squaredNorm() * Eigen::Matrix3d::Identity() - offset * offset.transpose());
}

}  // namespace

Status PointMass::validate() const {
  if (!finiteNonNegative(mass)) return Error{"point mass: mass " + std::to_string(mass) + " kg must be >= 0 and finite"};
  if (!position.allFinite()) return Error{"point mass: position is not finite"};
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (!std::isfinite(path[i].time) || !path[i].position.allFinite())
      return Error{"point mass: path[" + std::to_string(i) + "] is not finite"};
    if (i > 0 && !(path[i].time > path[i - 1].time))
      return Error{"point mass: path[" + std::to_string(i) + "] time must be after the previous key's"};
  }
  return Ok{};
}

Eigen::Vector3d pathPosition(const std::vector<PathKeyframe>& path, double time) {
  if (path.empty()) return Eigen::Vector3d::Zero();
  if (!(time > path.front().time)) return path.front().position;
  if (time >= path.back().time) return path.back().position;
  const auto next = std::upper_bound(path.begin(), path.end(), time,
                                     [](double t, const PathKeyframe& key) { return t < key.time; });
  const auto previous = next - 1;
  const double s = (time - previous->time) / (next->time - previous->time);
  return previous->position + s * (next->position - previous->position);
}

MassModel::MassModel(const SurfaceTextures& textures, const Eigen::Vector3d& referencePoint)
    : integrator_(textures, referencePoint), referencePoint_(referencePoint) {
  distributed_.referencePoint = referencePoint;
}

Status MassModel::setSolidDensity(double density, Conserved conserved) {
  if (!finiteNonNegative(density))
    return Error{"solid density " + std::to_string(density) + " kg/m^3 must be >= 0 and finite"};
  solidConserved_ = conserved;
  solidMass_ = density * volume();
  if (density == distributed_.solidDensity) return Ok{};
  distributed_.solidDensity = density;
  distributedRevision_ = ++revision_;
  return Ok{};
}

Status MassModel::setShellDensity(double density, Conserved conserved) {
  if (!finiteNonNegative(density))
    return Error{"shell density " + std::to_string(density) + " kg/m^2 must be >= 0 and finite"};
  shellConserved_ = conserved;
  shellMass_ = density * area();
  if (density == distributed_.shellDensity) return Ok{};
  distributed_.shellDensity = density;
  distributedRevision_ = ++revision_;
  return Ok{};
}

Status MassModel::setTexelDensity(std::vector<float> density) { return swapTexelDensity(density); }

Status MassModel::swapTexelDensity(std::vector<float>& density) {
  if (!density.empty() && density.size() != texelCount())
    return Error{"density map has " + std::to_string(density.size()) + " texels, the bake has " +
                 std::to_string(texelCount())};
  // Values are checked by the texel pass itself (TextureMassIntegrator::evaluate tracks the lowest
  // density and the sums' finiteness at no extra cost): a separate pass here would cost a third
  // of the texel pass for a map replaced every step.
  distributed_.texelDensity.swap(density);
  mapPending_ = true;
  distributedRevision_ = ++revision_;
  return Ok{};
}

Expected<std::size_t> MassModel::addPointMass(PointMass pointMass) {
  if (Status s = pointMass.validate(); !s) return s.error();
  pointMasses_.push_back(std::move(pointMass));
  ++revision_;
  return pointMasses_.size() - 1;
}

Status MassModel::setPointMassPosition(std::size_t index, const Eigen::Vector3d& position) {
  if (index >= pointMasses_.size()) return Error{"point mass " + std::to_string(index) + ": no such point mass"};
  if (!position.allFinite()) return Error{"point mass " + std::to_string(index) + ": position is not finite"};
  PointMass& point = pointMasses_[index];
  point.path.clear();
  if (point.position == position) return Ok{};
  point.position = position;
  ++revision_;
  return Ok{};
}

Status MassModel::setPointMassMass(std::size_t index, double mass) {
  if (index >= pointMasses_.size()) return Error{"point mass " + std::to_string(index) + ": no such point mass"};
  if (!finiteNonNegative(mass)) return Error{"point mass " + std::to_string(index) + ": mass must be >= 0 and finite"};
  if (pointMasses_[index].mass == mass) return Ok{};
  pointMasses_[index].mass = mass;
  ++revision_;
  return Ok{};
}

void MassModel::advanceTo(double time) {
  bool moved = false;
  for (PointMass& point : pointMasses_) {
    if (point.path.empty()) continue;
    const Eigen::Vector3d position = pathPosition(point.path, time);
    if (position != point.position) {
      point.position = position;
      moved = true;
    }
  }
  if (moved) ++revision_;
}

Status MassModel::setGeometry(const SurfaceTextures& textures) {
  if (triangles_)
    return Error{"mass model: it follows triangles (followTriangles), give setGeometry the moved mesh"};
  if (!distributed_.texelDensity.empty() && textures.size() != integrator_.size())
    return Error{"deformed surface has " + std::to_string(textures.size()) + " texels, the density map " +
                 std::to_string(integrator_.size())};
  integrator_.update(textures);  // in place: a deforming body allocates nothing per step
  ++geometryRevision_;
  conserveMasses();
  distributedRevision_ = ++revision_;
  return Ok{};
}

void MassModel::conserveMasses() {
  // Matter does not appear because a mesh grows: a part that keeps its mass spreads it over the
  // new volume or area. A geometry with no volume or area keeps the last density (its mass is
  // then zero whatever the density, which properties() reports).
  if (solidConserved_ == Conserved::Mass && volume() > 0.0) distributed_.solidDensity = solidMass_ / volume();
  if (shellConserved_ == Conserved::Mass && area() > 0.0) distributed_.shellDensity = shellMass_ / area();
}

Status MassModel::followTriangles(const SurfaceBake& bake, const UvLayout& layout, const Mesh& mesh) {
  Expected<TriangleMassIntegrator> created = TriangleMassIntegrator::create(bake, layout, referencePoint_);
  if (!created) return created.error();
  if (!distributed_.texelDensity.empty() && distributed_.texelDensity.size() != created->texelCount())
    return Error{"mass model: the density map has " + std::to_string(distributed_.texelDensity.size()) +
                 " texels, the bake has " + std::to_string(created->texelCount())};
  if (Status s = created->update(mesh); !s) return s.error();
  triangles_.emplace(std::move(created).value());
  mapPending_ = true;  // the map (if any) is yet to be handed over
  // The texel pass is not used any more: release its per-texel arrays.
  integrator_ = TextureMassIntegrator(SurfaceTextures{}, referencePoint_);
  // A change of method, not of geometry: the kept masses are the densities over the exact sums.
  solidMass_ = distributed_.solidDensity * volume();
  shellMass_ = distributed_.shellDensity * area();
  distributedRevision_ = ++revision_;
  return Ok{};
}

Status MassModel::setGeometry(const Mesh& mesh) {
  if (!triangles_) return Error{"mass model: setGeometry(mesh) needs followTriangles first"};
  // A failed update leaves the integrator without geometry: the next properties() says so.
  Status updated = triangles_->update(mesh);
  if (updated) conserveMasses();
  distributedRevision_ = ++revision_;
  return updated;
}

Expected<MassProperties> MassModel::evaluateTriangles() {
  if (mapPending_) {
    // A new map: one pass over the texel pieces (values checked there). An empty map costs nothing.
    if (!distributed_.texelDensity.empty()) ++texelPasses_;
    if (Status s = triangles_->setTexelDensity(distributed_.texelDensity); !s) return s.error();
    mapPending_ = false;
  }
  ++trianglePasses_;
  return triangles_->evaluate(distributed_.solidDensity, distributed_.shellDensity);
}

Expected<MassProperties> MassModel::properties() {
  if (evaluatedCombined_ == revision_) return combined_;
  if (evaluatedDistributed_ != distributedRevision_) {
    Expected<MassProperties> part = triangles_ ? evaluateTriangles() : integrator_.evaluate(distributed_);
    if (!triangles_) ++texelPasses_;
    if (!part) return part.error();
    distributedProperties_ = *part;
    evaluatedDistributed_ = distributedRevision_;
  }
  return combine();
}

void MassModel::lendTexelModel(TextureMassModel& batch) {
  batch.solidDensity = distributed_.solidDensity;
  batch.shellDensity = distributed_.shellDensity;
  batch.referencePoint = distributed_.referencePoint;
  batch.texelDensity.swap(distributed_.texelDensity);
}

void MassModel::takeBackTexelModel(TextureMassModel& batch) { batch.texelDensity.swap(distributed_.texelDensity); }

Expected<MassProperties> MassModel::finish(const MassProperties& texelPart) {
  if (!needsTexelPass()) return Error{"mass model: no texel pass is due (finish without needsTexelPass)"};
  if (!std::isfinite(texelPart.mass) || !std::isfinite(texelPart.volume) || !texelPart.centerOfMass.allFinite() ||
      !texelPart.inertia.allFinite())
    return Error{"mass model: the texel pass's mass properties are not finite"};
  ++texelPasses_;
  distributedProperties_ = texelPart;
  evaluatedDistributed_ = distributedRevision_;
  return combine();
}

Expected<MassProperties> MassModel::combine() {
  ++combinations_;
  const MassProperties& part = distributedProperties_;
  double mass = part.mass;
  Eigen::Vector3d first = part.mass * part.centerOfMass;
  for (const PointMass& point : pointMasses_) {
    mass += point.mass;
    first += point.mass * point.position;
  }
  if (!(mass > 0.0) || !std::isfinite(mass)) return Error{"mass model: total mass " + std::to_string(mass) + " kg is not positive"};
  MassProperties result;
  result.mass = mass;
  result.volume = part.volume;
  result.centerOfMass = first / mass;
  result.inertia = part.inertia + steiner(part.mass, part.centerOfMass - result.centerOfMass);
  for (const PointMass& point : pointMasses_) result.inertia += steiner(point.mass, point.position - result.centerOfMass);
  combined_ = result;
  evaluatedCombined_ = revision_;
  return combined_;
}

}  // namespace hydrotex
