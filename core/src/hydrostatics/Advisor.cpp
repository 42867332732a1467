// SPDX-License-Identifier: Zlib
// The advisor: measures errors against the exact path and times per query (Advisor.hpp).
#include "hydrotex/hydrostatics/Advisor.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/PreparedPolyhedron.hpp"

namespace hydrotex {

namespace {

// Fixed tilts (degrees, extrinsic X then Y then Z) after the mesh as modelled: chosen so that no
// face or axis of the primitives lines up with the water plane, where errors would cancel.
constexpr double kOrientationDegrees[8][3] = {
    {0, 0, 0}, {20, 10, 5}, {-35, 40, 15}, {60, -25, 30}, {90, 0, 20}, {10, 70, -45}, {-75, 15, 60}, {45, 45, 45}};

/// The mesh's name for messages.
std::string nameOf(const Mesh& mesh) { return mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName; }

volatile double timingSink = 0.0;  // keeps the optimiser from dropping timed answers

/// The axis-aligned bounds (m, body frame) of the mesh's vertices, as (lower, upper).
Eigen::AlignedBox3d boundsOf(const Mesh& mesh) {
  Eigen::AlignedBox3d box;  // empty
  for (const Eigen::Vector3d& p : mesh.positions) box.extend(p);
  return box;
}

}  // namespace

std::string methodName(HydrostaticsMethod method) {
  switch (method) {
    case HydrostaticsMethod::Exact: return "exact";
    case HydrostaticsMethod::TextureHierarchy: return "texture-hierarchy";
    case HydrostaticsMethod::TextureBruteForce: return "texture-brute-force";
  }
  return "unknown";
}

double meshSize(const Mesh& mesh) {
  if (mesh.positions.empty()) return 0.0;
  Eigen::Vector3d lo = mesh.positions.front(), hi = lo;
  for (const Eigen::Vector3d& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

std::vector<HydrostaticsQuery> sampleHydrostaticsQueries(const Mesh& mesh, const QuerySampling& sampling) {
  std::vector<HydrostaticsQuery> queries;
  if (mesh.positions.empty() || sampling.depthCount < 1 || sampling.orientationCount < 1 ||
      sampling.orientationCount > 8)
    return queries;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  if (Expected<MassProperties> solid = polyhedralMassProperties(mesh, 1.0)) centroid = solid->centerOfMass;
  for (int o = 0; o < sampling.orientationCount; ++o) {
    const double* degrees = kOrientationDegrees[o];
    const Pose rotated = Pose::fromDegreesXYZ(Eigen::Vector3d(degrees[0], degrees[1], degrees[2]), Eigen::Vector3d::Zero());
    double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
    for (const Eigen::Vector3d& p : mesh.positions) {
      const double y = rotated.rotation.row(1).dot(p);
      lowest = std::min(lowest, y);
      highest = std::max(highest, y);
    }
    for (int d = 0; d < sampling.depthCount; ++d) {
      const double fraction = double(d + 1) / double(sampling.depthCount + 1);
      HydrostaticsQuery query;
      query.pose = rotated;
      // Lowering the body by the water level's height in the rotated frame puts y = 0 there.
      query.pose.translation.y() = -(lowest + fraction * (highest - lowest));
      query.centerOfMass = centroid;
      queries.push_back(query);
    }
  }
  return queries;
}

void HydrostaticsErrors::keepMax(const HydrostaticsErrors& other) {
  volume = std::max(volume, other.volume);
  centerOfBuoyancy = std::max(centerOfBuoyancy, other.centerOfBuoyancy);
  force = std::max(force, other.force);
}

HydrostaticsErrors hydrostaticsErrors(const HydrostaticsResult& answer, const HydrostaticsResult& reference,
                                      const ErrorScales& scales) {
  HydrostaticsErrors errors;
  errors.volume = std::abs(answer.submergedVolume - reference.submergedVolume) / scales.totalVolume;
  errors.centerOfBuoyancy = (answer.centerOfBuoyancy - reference.centerOfBuoyancy).norm() / scales.size;
  errors.force = (answer.buoyancyForce - reference.buoyancyForce).norm() /
                 (scales.density * scales.gravity * scales.totalVolume);
  return errors;
}

MassErrors massErrors(const MassProperties& answer, const MassProperties& reference, double size) {
  MassErrors errors;
  errors.mass = std::abs(answer.mass - reference.mass) / std::abs(reference.mass);
  errors.centerOfMass = (answer.centerOfMass - reference.centerOfMass).norm() / size;
  errors.inertia = (answer.inertia - reference.inertia).norm() / reference.inertia.norm();
  return errors;
}

double medianSecondsPerCall(const std::function<void()>& work, const TimingSettings& settings) {
  using Clock = std::chrono::steady_clock;
  const int runs = std::max(1, settings.runs);
  work();  // warm caches and page in the data
  auto start = Clock::now();
  work();
  const double once = std::chrono::duration<double>(Clock::now() - start).count();
  const int batch = std::max(1, int(settings.batchSeconds / std::max(once, 1e-9)));
  std::vector<double> samples;
  for (int run = 0; run < runs; ++run) {
    start = Clock::now();
    for (int i = 0; i < batch; ++i) work();
    samples.push_back(std::chrono::duration<double>(Clock::now() - start).count() / batch);
  }
  std::nth_element(samples.begin(), samples.begin() + runs / 2, samples.end());
  return samples[std::size_t(runs / 2)];
}

Expected<MethodMeasurement> measureMethod(const HydrostaticsAnswer& answer, const std::vector<HydrostaticsQuery>& queries,
                                          const std::vector<HydrostaticsResult>& references,
                                          const ErrorScales& scales, const TimingSettings& timing) {
  if (queries.empty() || queries.size() != references.size())
    return Error{"measureMethod: " + std::to_string(queries.size()) + " queries for " +
                 std::to_string(references.size()) + " references"};
  MethodMeasurement measurement;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    Expected<HydrostaticsResult> result = answer(queries[i]);
    if (!result) return result.error();
    measurement.maxErrors.keepMax(hydrostaticsErrors(*result, references[i], scales));
  }
  if (timing.modeled) return measurement;  // the caller sets the modeled time (it knows the method)
  const double seconds = medianSecondsPerCall(
      [&] {
        for (const HydrostaticsQuery& query : queries) timingSink = timingSink + answer(query)->submergedVolume;
      },
      timing);
  measurement.microsecondsPerQuery = seconds * 1e6 / double(queries.size());
  return measurement;
}

double modeledMicrosecondsPerQuery(HydrostaticsMethod method, std::size_t triangles, int resolution, bool waves,
                                   double waterlineFactor) {
  const double r = double(resolution), rootT = std::sqrt(double(triangles));
  const double rows = r * std::max(1.0, waterlineFactor);  // tiles along the waterline
  switch (method) {
    case HydrostaticsMethod::Exact:
      return waves ? 30.0 + 0.35 * rootT : 0.01 + 0.05 * std::max(1.0, waterlineFactor) * rootT;
    case HydrostaticsMethod::TextureHierarchy:
      return waves ? 10.0 + 0.3 * rows : 0.9 + 0.089 * rows;
    case HydrostaticsMethod::TextureBruteForce:
      return waves ? 100.0 + 0.055 * r * r : 10.0 + 0.0045 * r * r;
  }
  return 0.0;
}

double waterlineFactor(const Mesh& mesh) {
  const double level = boundsOf(mesh).center().y();
  const auto count = mesh.positions.size();
  double length = 0.0, area = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    if (std::size_t(t[0]) >= count || std::size_t(t[1]) >= count || std::size_t(t[2]) >= count) continue;
    const Eigen::Vector3d* p[3] = {&mesh.positions[std::size_t(t[0])], &mesh.positions[std::size_t(t[1])],
                                   &mesh.positions[std::size_t(t[2])]};
    area += 0.5 * (*p[1] - *p[0]).cross(*p[2] - *p[0]).norm();
    // Where the plane y = level cuts the triangle's edges: a segment of the waterline.
    Eigen::Vector3d cut[3];
    int cuts = 0;
    for (int e = 0; e < 3; ++e) {
      const Eigen::Vector3d& a = *p[e];
      const Eigen::Vector3d& b = *p[(e + 1) % 3];
      if ((a.y() < level) != (b.y() < level) && cuts < 2) cut[cuts++] = a + (level - a.y()) / (b.y() - a.y()) * (b - a);
    }
    if (cuts == 2) length += (cut[1] - cut[0]).norm();
  }
  if (!(area > 0.0) || !std::isfinite(length)) return 1.0;
  return std::max(1.0, length / std::sqrt(3.141592653589793 * area));
}

double modeledExactMicroseconds(const ExactWaveWork& work) {
  return 0.05 * double(work.nodes) + 0.10 * double(work.models) + 0.045 * double(work.clippedTriangles) +
         0.31 * double(work.surfaceHeights) + 0.19 * double(work.jets) + 0.05 * double(work.sampledPieces);
}

Expected<double> modeledExactMicroseconds(const PreparedPolyhedron& body, const LiquidSurface& surface) {
  const Mesh& mesh = body.mesh();
  const bool waves = surface.hasFreeSurface() && !surface.flatHeight().has_value();
  const std::optional<SurfaceSmoothness> smooth = waves ? surface.smoothness(0.0) : std::nullopt;
  if (!smooth)
    return modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, mesh.triangles.size(), 0, waves, waterlineFactor(mesh));
  const std::pair<double, double> heights = surface.heightRange(0.0);
  const double level = std::isfinite(heights.first + heights.second) ? 0.5 * (heights.first + heights.second) : 0.0;
  const Eigen::Vector3d center = boundsOf(mesh).center();
  double total = 0.0;
  constexpr int kQueries = 4;
  for (int k = 0; k < kQueries; ++k) {
    HydrostaticsQuery query;
    query.pose = Pose{Eigen::Matrix3d::Identity(), Eigen::Vector3d(-center.x(), level - center.y(), -center.z())};
    query.time = double(k);
    ExactWaveWork work;
    const Expected<HydrostaticsResult> answer = polyhedralHydrostatics(body, surface, query, &work);
    if (!answer) return answer.error();
    total += modeledExactMicroseconds(work);
  }
  return total / kQueries;
}

std::size_t textureHydrostaticsBytes(const TextureHydrostatics& texture) {
  // Groups are about tiles / groupSize^2; count them as such (the class does not expose them).
  const std::size_t groupArea = std::size_t(std::max(1, texture.groupSize() * texture.groupSize()));
  const std::size_t tiles = texture.tileCount();
  return texture.texelCount() * sizeof(TextureHydrostatics::Texel) +
         texture.correctionCount() * sizeof(TextureHydrostatics::MomentCorrection) +
         (tiles + (tiles + groupArea - 1) / groupArea) * sizeof(TextureHydrostatics::Tile);
}

std::size_t meshBytes(const Mesh& mesh) {
  return mesh.positions.size() * sizeof(Eigen::Vector3d) + mesh.triangles.size() * sizeof(Eigen::Vector3i);
}

Expected<Advice> adviseHydrostatics(const Mesh& mesh, double targetError, const AdvisorSettings& settings) {
  if (!(targetError > 0.0) || !std::isfinite(targetError))
    return Error{"advise: the target error must be positive and finite (got " + std::to_string(targetError) + ")"};
  if (settings.sampling.depthCount < 1 || settings.sampling.orientationCount < 1 || settings.sampling.orientationCount > 8)
    return Error{"advise: sampling needs 1 or more depths and 1 to 8 orientations"};
  for (int resolution : settings.resolutions) {
    BakeSettings bake;
    bake.width = bake.height = resolution;
    if (Status valid = bake.validate(); !valid) return Error{"advise: resolution " + std::to_string(resolution) + ": " + valid.error().message};
  }
  Expected<MassProperties> solid = polyhedralMassProperties(mesh, 1.0);
  if (!solid) return Error{nameOf(mesh) + ": " + solid.error().message};

  const FlatSurface water(0.0, settings.density);
  const std::vector<HydrostaticsQuery> queries = sampleHydrostaticsQueries(mesh, settings.sampling);
  std::vector<HydrostaticsResult> references;
  references.reserve(queries.size());
  for (const HydrostaticsQuery& query : queries) {
    // The checked call once validates the mesh's closedness; the sample then needs no more checks.
    Expected<HydrostaticsResult> exact =
        references.empty() ? polyhedralHydrostatics(mesh, water, query) : polyhedralHydrostaticsUnchecked(mesh, water, query);
    if (!exact) return Error{nameOf(mesh) + ": " + exact.error().message};
    references.push_back(*exact);
  }
  ErrorScales scales;
  scales.totalVolume = solid->volume;
  scales.size = meshSize(mesh);
  scales.density = settings.density;

  Advice advice;
  advice.targetError = targetError;
  Expected<MethodMeasurement> exact = measureMethod(
      [&](const HydrostaticsQuery& query) { return polyhedralHydrostaticsUnchecked(mesh, water, query); }, queries,
      references, scales, settings.timing);
  if (!exact) return exact.error();
  exact->method = HydrostaticsMethod::Exact;
  // Modeled times grow with the waterline's length on both paths (waterlineFactor).
  const double factor = settings.timing.modeled ? waterlineFactor(mesh) : 1.0;
  if (settings.timing.modeled)
    exact->microsecondsPerQuery = modeledMicrosecondsPerQuery(HydrostaticsMethod::Exact, mesh.triangles.size(), 0, false, factor);
  exact->bytes = meshBytes(mesh);
  advice.candidates.push_back(*exact);
  advice.best = *exact;

  std::vector<int> resolutions = settings.resolutions;
  std::sort(resolutions.begin(), resolutions.end());
  for (int resolution : resolutions) {
    BodyGeometrySettings geometrySettings;
    geometrySettings.bake.width = geometrySettings.bake.height = resolution;
    Expected<BodyGeometry> body = prepareBodyGeometry(mesh, geometrySettings);
    if (!body) return Error{nameOf(mesh) + ": " + body.error().message};
    Expected<TextureHydrostatics> texture = TextureHydrostatics::build(body->bake, body->textures);
    if (!texture) return Error{nameOf(mesh) + ": " + texture.error().message};
    bool met = false, slower = true;
    for (HydrostaticsMethod method : {HydrostaticsMethod::TextureHierarchy, HydrostaticsMethod::TextureBruteForce}) {
      if (method == HydrostaticsMethod::TextureBruteForce && !settings.includeBruteForce) continue;
      const TexelTraversal traversal =
          method == HydrostaticsMethod::TextureHierarchy ? TexelTraversal::Hierarchy : TexelTraversal::BruteForce;
      Expected<MethodMeasurement> measured = measureMethod(
          [&](const HydrostaticsQuery& query) { return texture->query(water, query, traversal); }, queries, references,
          scales, settings.timing);
      if (!measured) return Error{nameOf(mesh) + ": " + measured.error().message};
      measured->method = method;
      measured->resolution = resolution;
      if (settings.timing.modeled)
        measured->microsecondsPerQuery =
            modeledMicrosecondsPerQuery(method, mesh.triangles.size(), resolution, false, factor);
      measured->bytes = textureHydrostaticsBytes(*texture);
      advice.candidates.push_back(*measured);
      const bool meets = measured->maxErrors.worst() <= targetError;
      met = met || meets;
      slower = slower && measured->microsecondsPerQuery > exact->microsecondsPerQuery;
      if (meets && measured->microsecondsPerQuery < advice.best.microsecondsPerQuery) advice.best = *measured;
    }
    if (met || slower) break;
  }
  return advice;
}

std::optional<double> surfaceCurvatureBound(const LiquidSurface& surface) {
  if (surface.flatHeight() || !surface.hasFreeSurface()) return 0.0;
  if (const auto* waves = dynamic_cast<const GerstnerWaves*>(&surface)) {
    // Per wave, at a crest: d2y/dx2 = -A k^2 / (1 - Q A k)^2 (x = x0 - Q A sin k x0, y = A cos k x0);
    // summed with the smallest squeeze of all waves together.
    double curvature = 0.0, squeeze = 0.0;
    for (const GerstnerWaves::Component& c : waves->components()) {
      curvature += c.amplitude * c.waveNumber * c.waveNumber;
      squeeze += c.steepness * c.amplitude * c.waveNumber;
    }
    if (!(squeeze < 1.0)) return std::nullopt;  // crests may loop: no bound
    return curvature / ((1.0 - squeeze) * (1.0 - squeeze));
  }
  return std::nullopt;
}

double exactLinearizationError(const Mesh& mesh, double volume, const LiquidSurface& surface) {
  const std::optional<double> curvature = surfaceCurvatureBound(surface);
  if (!curvature) return std::numeric_limits<double>::infinity();
  if (*curvature == 0.0) return 0.0;
  if (mesh.positions.empty() || !(volume > 0.0)) return std::numeric_limits<double>::infinity();
  double longest = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (mesh.positions[t[(k + 1) % 3]] - mesh.positions[t[k]]).squaredNorm());
  const Eigen::Vector3d e = boundsOf(mesh).sizes();
  const double largestFace = std::max({e.x() * e.y(), e.y() * e.z(), e.x() * e.z()});
  // The vertices' heights may be interpolated too (polyhedralHydrostaticsUnchecked): their bound adds.
  return (*curvature * longest / 8.0 + kExactWaveHeightError) * largestFace / volume;
}

double preparedExactSurfaceError(const Mesh& mesh, double volume, const LiquidSurface& surface, double time) {
  if (surface.flatHeight() || !surface.hasFreeSurface()) return 0.0;
  // The prepared path's hierarchy serves exactly the surfaces with smoothness bounds
  // (wavePolyhedralHydrostatics); any other goes the plain path's way.
  const std::optional<SurfaceSmoothness> smooth = surface.smoothness(time);
  if (smooth && std::isfinite(smooth->third) && std::isfinite(smooth->fourth) && smooth->third >= 0.0 &&
      smooth->fourth >= 0.0)
    return 0.0;
  return exactLinearizationError(mesh, volume, surface);
}

}  // namespace hydrotex
