// SPDX-License-Identifier: Zlib
// The accuracy-versus-cost report (issue 10): what accuracy costs in time, per method and resolution.
//
//   hydrotex_accuracy_report [--quick] [--no-gpu] [OUTDIR]
//
// Sweeps methods (exact mesh, texture brute force, texture with hierarchy, the GL backend when it
// is built and a context opens), resolutions (32^2..2048^2; --quick: 32^2..128^2), shapes with
// closed forms (sphere, box at a tilt, horizontal cylinder, torus, Wigley hull; --quick: sphere
// and box) over sampled depths and orientations (Advisor.hpp), and mass properties. Per point: the
// worst relative error over the sample against the exact path on the same mesh (the exact path's
// own rows compare the mesh with the closed form of the true shape), time per query (median of
// timed batches, one thread; llvmpipe limited to one thread) and the bytes a query reads.
// Then mesh independence (a sphere at 1k..1M triangles) with where the exact and texture times
// cross, and the fitted exponents of time against resolution.
//
// Writes OUTDIR/accuracy.csv (shape,quantity,method,backend,resolution,triangles,rel_error,time_us,bytes),
// OUTDIR/accuracy.md, gnuplot data and script, and the PNG plots when gnuplot is on the PATH.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "hydrotex/hydrostatics/Advisor.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/backend/ComputeBackend.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/mesh/Primitives.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"
#if defined(HYDROTEX_WITH_GPU)
#include "hydrotex/gpu/GlBackend.hpp"
#endif

using namespace hydrotex;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDensity = 1000.0;  // kg/m^3, liquid and solid

volatile double sink = 0.0;  // keeps the optimiser from dropping timed work

/// Submerged volume (m^3) and centre of buoyancy (m, world) of the true shape.
struct ClosedForm {
  double volume = 0.0;
  Eigen::Vector3d centerOfBuoyancy = Eigen::Vector3d::Zero();
};

/// A shape with a closed form, meshed.
struct Shape {
  std::string name;
  Mesh mesh;
  double trueVolume = 0.0;  ///< of the true shape (m^3)
  /// Closed-form hydrostatics for queries with the identity rotation (water at y = 0); empty for
  /// others (and for the box, whose mesh is the shape: the exact path is its closed form).
  std::function<std::optional<ClosedForm>(const HydrostaticsQuery&)> closedForm;
};

/// Area below the chord y = h of a circle of radius r centred at the origin, and the first moment
/// of that area about y = 0: A = r^2 acos(-h/r) + h sqrt(r^2 - h^2) (docs/references.md, horizontal
/// cylinder); Int y dA = Int_{-r}^{h} 2 y sqrt(r^2 - y^2) dy = -(2/3) (r^2 - h^2)^(3/2).
std::pair<double, double> circleSegment(double r, double h) {
  h = std::clamp(h, -r, r);
  const double root = std::sqrt(r * r - h * h);
  return {r * r * std::acos(-h / r) + h * root, -2.0 / 3.0 * root * root * root};
}

bool isIdentity(const Pose& pose) { return (pose.rotation - Eigen::Matrix3d::Identity()).norm() < 1e-12; }

std::vector<Shape> makeShapes(bool quick) {
  std::vector<Shape> shapes;
  {
    const double r = 1.0;
    Shape sphere{"sphere", primitives::uvSphere(r, 128, 64), 4.0 / 3.0 * kPi * r * r * r, {}};
    // Cap of depth d: V = pi d^2 (3r - d) / 3, centroid 3 (2r - d)^2 / (4 (3r - d)) below the
    // centre (docs/references.md); any rotation.
    sphere.closedForm = [r](const HydrostaticsQuery& q) -> std::optional<ClosedForm> {
      const Eigen::Vector3d& c = q.pose.translation;
      const double d = std::clamp(r - c.y(), 0.0, 2.0 * r);
      ClosedForm f;
      f.volume = kPi * d * d * (3.0 * r - d) / 3.0;
      f.centerOfBuoyancy = c - Eigen::Vector3d(0, 3.0 * (2.0 * r - d) * (2.0 * r - d) / (4.0 * (3.0 * r - d)), 0);
      return f;
    };
    shapes.push_back(sphere);
  }
  shapes.push_back(Shape{"box-tilted", primitives::box(Eigen::Vector3d(2.0, 1.0, 0.5)), 1.0, {}});
  if (quick) return shapes;
  {
    const double r = 0.5, length = 2.0;
    Shape cylinder{"cylinder-horizontal", primitives::cylinder(r, length, 128), kPi * r * r * length, {}};
    cylinder.closedForm = [r, length](const HydrostaticsQuery& q) -> std::optional<ClosedForm> {
      if (!isIdentity(q.pose)) return std::nullopt;
      const auto [area, moment] = circleSegment(r, -q.pose.translation.y());
      return ClosedForm{area * length, q.pose.translation + Eigen::Vector3d(0, moment / area, 0)};
    };
    shapes.push_back(cylinder);
  }
  {
    const double major = 1.0, minor = 0.3;
    Shape torus{"torus", primitives::torus(major, minor, 128, 48), 2.0 * kPi * kPi * major * minor * minor, {}};
    // Pappus: the tube's cross-section below the water, revolved; its centroid lies at the tube
    // centre's radius by symmetry, so V = 2 pi R A_segment.
    torus.closedForm = [major, minor](const HydrostaticsQuery& q) -> std::optional<ClosedForm> {
      if (!isIdentity(q.pose)) return std::nullopt;
      const auto [area, moment] = circleSegment(minor, -q.pose.translation.y());
      return ClosedForm{2.0 * kPi * major * area, q.pose.translation + Eigen::Vector3d(0, moment / area, 0)};
    };
    shapes.push_back(torus);
  }
  {
    const double length = 4.0, breadth = 0.4, draft = 0.25;
    Shape wigley{"wigley-hull", primitives::wigleyHull(length, breadth, draft, 128, 32), 4.0 / 9.0 * length * breadth * draft, {}};
    // Breadth 2 y(x, z) = B (1 - (2x/L)^2)(1 - (z/T)^2), z the depth below the deck: the x
    // integral is 2L/3, so V = B (2L/3) Int_{z0}^{T} (1 - z^2/T^2) dz (4/9 L B T for z0 = 0,
    // docs/references.md), and the centroid's depth is Int z (1 - z^2/T^2) dz over the same integral.
    wigley.closedForm = [length, breadth, draft](const HydrostaticsQuery& q) -> std::optional<ClosedForm> {
      if (!isIdentity(q.pose)) return std::nullopt;
      const double z0 = std::clamp(q.pose.translation.y(), 0.0, draft);  // depth of the water below the deck
      const auto area = [draft](double z) { return z - z * z * z / (3.0 * draft * draft); };
      const auto moment = [draft](double z) { return z * z / 2.0 - z * z * z * z / (4.0 * draft * draft); };
      const double section = area(draft) - area(z0);
      return ClosedForm{breadth * 2.0 * length / 3.0 * section,
                        q.pose.translation - Eigen::Vector3d(0, (moment(draft) - moment(z0)) / section, 0)};
    };
    shapes.push_back(wigley);
  }
  return shapes;
}

/// One CSV row.
struct Row {
  std::string shape, quantity, method, backend;
  int resolution = 0;
  std::size_t triangles = 0;
  double relError = 0.0, timeUs = 0.0;
  std::size_t bytes = 0;
};

/// What the run sweeps.
struct Plan {
  bool quick = false;
  bool gpu = true;
  std::vector<int> resolutions;
  QuerySampling sampling;
  TimingSettings timing;
  int gpuMaxResolution = 1024;
  std::vector<int> tessellationSlices;  // uv sphere slices (stacks = slices / 2) for mesh independence
  int tessellationResolution = 512;
};

Plan makePlan(bool quick) {
  Plan plan;
  plan.quick = quick;
  if (quick) {
    plan.resolutions = {32, 64, 128};
    plan.sampling = {3, 2};
    plan.timing = {3, 0.004};
    plan.tessellationSlices = {32, 100};
    plan.tessellationResolution = 64;
  } else {
    plan.resolutions = {32, 64, 128, 256, 512, 1024, 2048};
    plan.sampling = {5, 3};
    plan.timing = {5, 0.02};
    plan.tessellationSlices = {32, 100, 316, 1000};  // about 1k, 10k, 100k and 1M triangles
    plan.tessellationResolution = 512;
  }
  return plan;
}

/// A GPU backend for one shape's bodies (a fresh one per shape keeps memory bounded: bodies cannot
/// be removed). Empty when not built or no context opens.
std::unique_ptr<ComputeBackend> openGpu(const Plan& plan, std::string& renderer, bool& warned) {
#if defined(HYDROTEX_WITH_GPU)
  if (!plan.gpu) return nullptr;
  Expected<std::unique_ptr<ComputeBackend>> gl = gpu::makeGlBackend();
  if (!gl) {
    if (!warned) std::fprintf(stderr, "accuracy_report: no GPU backend (%s); GPU rows skipped\n", gl.error().message.c_str());
    warned = true;
    return nullptr;
  }
  renderer = (*gl)->renderer();
  return std::move(*gl);
#else
  (void)plan;
  (void)renderer;
  if (!warned) std::fprintf(stderr, "accuracy_report: built without hydrotex::gpu; GPU rows skipped\n");
  warned = true;
  return nullptr;
#endif
}

/// "gpu:llvmpipe" from "llvmpipe (LLVM 15.0.6, 256 bits)": short and free of commas for the CSV.
std::string gpuBackendLabel(const std::string& renderer) {
  std::string first = renderer.substr(0, renderer.find_first_of(" ,/("));
  return "gpu:" + (first.empty() ? std::string("unknown") : first);
}

void addHydrostaticsRows(std::vector<Row>& rows, const Row& base, const MethodMeasurement& m) {
  Row row = base;
  row.timeUs = m.microsecondsPerQuery;
  row.bytes = m.bytes;
  for (auto [quantity, error] : {std::pair{"volume", m.maxErrors.volume}, std::pair{"center_of_buoyancy", m.maxErrors.centerOfBuoyancy},
                                 std::pair{"force", m.maxErrors.force}}) {
    row.quantity = quantity;
    row.relError = error;
    rows.push_back(row);
  }
}

void addMassRows(std::vector<Row>& rows, const Row& base, const MassErrors& errors, double timeUs) {
  Row row = base;
  row.timeUs = timeUs;
  for (auto [quantity, error] : {std::pair{"mass", errors.mass}, std::pair{"center_of_mass", errors.centerOfMass},
                                 std::pair{"inertia", errors.inertia}}) {
    row.quantity = quantity;
    row.relError = error;
    rows.push_back(row);
  }
}

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "accuracy_report: %s\n", what.c_str());
  std::exit(1);
}

/// The hydrostatics and mass sweep of one shape.
void sweepShape(const Shape& shape, const Plan& plan, std::vector<Row>& rows, std::string& gpuRenderer, bool& gpuWarned) {
  const Mesh& mesh = shape.mesh;
  const FlatSurface water(0.0, kDensity);
  const std::vector<HydrostaticsQuery> queries = sampleHydrostaticsQueries(mesh, plan.sampling);
  Expected<MassProperties> exactMass = polyhedralMassProperties(mesh, kDensity);
  if (!exactMass) fail(shape.name + ": " + exactMass.error().message);
  std::vector<HydrostaticsResult> references;
  for (const HydrostaticsQuery& query : queries) {
    Expected<HydrostaticsResult> exact = polyhedralHydrostatics(mesh, water, query);
    if (!exact) fail(shape.name + ": " + exact.error().message);
    references.push_back(*exact);
  }
  const ErrorScales scales{exactMass->volume, meshSize(mesh), kDensity, 9.81};
  Row base{shape.name, "", "exact", "cpu", 0, mesh.triangles.size(), 0.0, 0.0, 0};

  // Exact path: its errors against itself are zero by definition; its rows carry the time, and
  // the mesh against the true shape where a closed form exists (the tessellation's own error).
  Expected<MethodMeasurement> exact = measureMethod(
      [&](const HydrostaticsQuery& q) { return polyhedralHydrostaticsUnchecked(mesh, water, q); }, queries, references,
      scales, plan.timing);
  if (!exact) fail(shape.name + ": " + exact.error().message);
  exact->bytes = meshBytes(mesh);
  addHydrostaticsRows(rows, base, *exact);
  if (shape.closedForm) {
    HydrostaticsErrors meshVsShape;
    bool any = false;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const std::optional<ClosedForm> truth = shape.closedForm(queries[i]);
      if (!truth) continue;
      any = true;
      HydrostaticsResult closed;
      closed.submergedVolume = truth->volume;
      closed.centerOfBuoyancy = truth->centerOfBuoyancy;
      closed.buoyancyForce = Eigen::Vector3d(0, kDensity * 9.81 * truth->volume, 0);
      meshVsShape.keepMax(hydrostaticsErrors(references[i], closed, ErrorScales{shape.trueVolume, scales.size, kDensity, 9.81}));
    }
    if (any) {
      Row row = base;
      row.timeUs = exact->microsecondsPerQuery;
      row.bytes = exact->bytes;
      row.quantity = "volume_vs_closed_form";
      row.relError = meshVsShape.volume;
      rows.push_back(row);
      row.quantity = "center_of_buoyancy_vs_closed_form";
      row.relError = meshVsShape.centerOfBuoyancy;
      rows.push_back(row);
    }
  }
  {
    const double seconds = medianSecondsPerCall([&] { sink = sink + polyhedralMassProperties(mesh, kDensity)->mass; }, plan.timing);
    Row row = base;
    row.bytes = meshBytes(mesh);
    addMassRows(rows, row, MassErrors{}, seconds * 1e6);
    row.quantity = "mass_vs_closed_form";
    row.relError = std::abs(exactMass->volume - shape.trueVolume) / shape.trueVolume;
    row.timeUs = seconds * 1e6;
    rows.push_back(row);
  }

  std::unique_ptr<ComputeBackend> gpuBackend = openGpu(plan, gpuRenderer, gpuWarned);
  for (int resolution : plan.resolutions) {
    BodyGeometrySettings settings;
    settings.bake.width = settings.bake.height = resolution;
    Expected<BodyGeometry> body = prepareBodyGeometry(mesh, settings);
    if (!body) fail(shape.name + ": " + body.error().message);
    Expected<TextureHydrostatics> texture = TextureHydrostatics::build(body->bake, body->textures);
    if (!texture) fail(shape.name + ": " + texture.error().message);
    Row row = base;
    row.resolution = resolution;
    for (TexelTraversal traversal : {TexelTraversal::Hierarchy, TexelTraversal::BruteForce}) {
      const bool hierarchy = traversal == TexelTraversal::Hierarchy;
      TimingSettings timing = plan.timing;
      if (!hierarchy && resolution >= 1024) timing.runs = 3;  // tens of ms per pass: fewer runs
      Expected<MethodMeasurement> m = measureMethod(
          [&](const HydrostaticsQuery& q) { return texture->query(water, q, traversal); }, queries, references, scales, timing);
      if (!m) fail(shape.name + ": " + m.error().message);
      m->bytes = textureHydrostaticsBytes(*texture);
      row.method = methodName(hierarchy ? HydrostaticsMethod::TextureHierarchy : HydrostaticsMethod::TextureBruteForce);
      addHydrostaticsRows(rows, row, *m);
    }
    // Texture mass properties: the cone sums from the mesh's centroid.
    {
      const TextureMassIntegrator integrator(body->textures, exactMass->centerOfMass);
      TextureMassModel model;
      model.solidDensity = kDensity;
      Expected<MassProperties> mass = integrator.evaluate(model);
      if (!mass) fail(shape.name + ": " + mass.error().message);
      const double seconds = medianSecondsPerCall([&] { sink = sink + integrator.evaluate(model)->mass; }, plan.timing);
      Row massRow = row;
      massRow.method = "texture";
      massRow.bytes = integrator.size() * 4 * sizeof(float);  // apex-to-base vector and cone volume per texel
      addMassRows(rows, massRow, massErrors(*mass, *exactMass, scales.size), seconds * 1e6);
    }
    if (gpuBackend && resolution <= plan.gpuMaxResolution) {
      Expected<BackendBodyId> id = gpuBackend->addBody(body->bake, body->textures, exactMass->centerOfMass);
      if (!id) fail(shape.name + ": GPU addBody: " + id.error().message);
      const BackendBodyId bodyId = *id;
      Expected<MethodMeasurement> m = measureMethod(
          [&](const HydrostaticsQuery& q) -> Expected<HydrostaticsResult> {
            const BackendHydrostaticsQuery batch{bodyId, q};
            HydrostaticsResult result;
            if (Status status = gpuBackend->hydrostatics(water, {&batch, 1}, {&result, 1}); !status) return status.error();
            return result;
          },
          queries, references, scales, plan.timing);
      if (!m) fail(shape.name + ": GPU: " + m.error().message);
      m->bytes = textureHydrostaticsBytes(*texture);
      Row gpuRow = row;
      gpuRow.method = "texture-gpu";
      gpuRow.backend = gpuBackendLabel(gpuRenderer);
      addHydrostaticsRows(rows, gpuRow, *m);
      TextureMassModel model;
      model.solidDensity = kDensity;
      MassProperties mass;
      if (Status status = gpuBackend->massProperties({&bodyId, 1}, {&model, 1}, {&mass, 1}); !status)
        fail(shape.name + ": GPU mass: " + status.error().message);
      const double seconds = medianSecondsPerCall(
          [&] {
            (void)gpuBackend->massProperties({&bodyId, 1}, {&model, 1}, {&mass, 1});
            sink = sink + mass.mass;
          },
          plan.timing);
      gpuRow.method = "texture-gpu";
      gpuRow.bytes = body->textures.size() * 4 * sizeof(float);
      addMassRows(rows, gpuRow, massErrors(mass, *exactMass, scales.size), seconds * 1e6);
    }
    std::printf("  %-20s %5d^2 done\n", shape.name.c_str(), resolution);
    std::fflush(stdout);
  }
}

/// Mesh independence: a unit sphere at increasing triangle counts, texture path at one resolution.
void sweepTessellation(const Plan& plan, std::vector<Row>& rows) {
  const FlatSurface water(0.0, kDensity);
  for (int slices : plan.tessellationSlices) {
    const Mesh mesh = primitives::uvSphere(1.0, slices, slices / 2);
    const std::vector<HydrostaticsQuery> queries = sampleHydrostaticsQueries(mesh, plan.sampling);
    std::vector<HydrostaticsResult> references;
    for (const HydrostaticsQuery& q : queries) references.push_back(*polyhedralHydrostaticsUnchecked(mesh, water, q));
    const ErrorScales scales{polyhedralMassProperties(mesh, 1.0)->volume, meshSize(mesh), kDensity, 9.81};
    Row row{"sphere-tessellation", "volume", "exact", "cpu", 0, mesh.triangles.size(), 0.0, 0.0, 0};
    Expected<MethodMeasurement> exact = measureMethod(
        [&](const HydrostaticsQuery& q) { return polyhedralHydrostaticsUnchecked(mesh, water, q); }, queries, references,
        scales, plan.timing);
    if (!exact) fail("tessellation: " + exact.error().message);
    row.timeUs = exact->microsecondsPerQuery;
    row.bytes = meshBytes(mesh);
    rows.push_back(row);
    BodyGeometrySettings settings;
    settings.bake.width = settings.bake.height = plan.tessellationResolution;
    Expected<BodyGeometry> body = prepareBodyGeometry(mesh, settings);
    if (!body) fail("tessellation: " + body.error().message);
    Expected<TextureHydrostatics> texture = TextureHydrostatics::build(body->bake, body->textures);
    if (!texture) fail("tessellation: " + texture.error().message);
    for (TexelTraversal traversal : {TexelTraversal::Hierarchy, TexelTraversal::BruteForce}) {
      Expected<MethodMeasurement> m = measureMethod(
          [&](const HydrostaticsQuery& q) { return texture->query(water, q, traversal); }, queries, references, scales,
          plan.timing);
      if (!m) fail("tessellation: " + m.error().message);
      row.method = methodName(traversal == TexelTraversal::Hierarchy ? HydrostaticsMethod::TextureHierarchy
                                                                     : HydrostaticsMethod::TextureBruteForce);
      row.resolution = plan.tessellationResolution;
      row.timeUs = m->microsecondsPerQuery;
      row.relError = m->maxErrors.volume;
      row.bytes = textureHydrostaticsBytes(*texture);
      rows.push_back(row);
    }
    std::printf("  sphere %8zu triangles done\n", mesh.triangles.size());
    std::fflush(stdout);
  }
}

/// Least-squares slope of log(y) against log(x).
double logSlope(const std::vector<std::pair<double, double>>& points) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double(points.size());
  for (auto [x, y] : points) {
    const double lx = std::log(x), ly = std::log(y);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  const double denominator = n * sxx - sx * sx;
  return denominator > 0 ? (n * sxy - sx * sy) / denominator : std::nan("");
}

/// Triangle count where the exact path's time reaches `textureUs`, by log-log interpolation
/// between the measured tessellations (extrapolated from the nearest two outside them).
double crossingTriangles(const std::vector<std::pair<double, double>>& exact, double textureUs) {
  if (exact.size() < 2) return std::nan("");
  std::size_t i = 0;
  while (i + 2 < exact.size() && exact[i + 1].second < textureUs) ++i;
  const auto [t0, u0] = exact[i];
  const auto [t1, u1] = exact[i + 1];
  const double slope = std::log(u1 / u0) / std::log(t1 / t0);
  return t0 * std::exp(std::log(textureUs / u0) / slope);
}

std::string formatError(double e) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", e);
  return text;
}

std::string formatBytes(double bytes) {
  char text[32];
  if (bytes >= 1 << 20)
    std::snprintf(text, sizeof text, "%.1f MB", bytes / double(1 << 20));
  else
    std::snprintf(text, sizeof text, "%.0f kB", bytes / 1024.0);
  return text;
}

std::string formatTime(double us) {
  char text[32];
  std::snprintf(text, sizeof text, us < 10 ? "%.2f" : us < 100 ? "%.1f" : "%.0f", us);
  return text;
}

/// Everything derived from the rows: the tables, the fits and the crossing.
struct Summary {
  /// Resolution ranges of the fits: label, lowest, highest (texels per side).
  std::vector<std::tuple<std::string, int, int>> ranges;
  /// method -> range label -> slope of log time against log resolution per side
  std::map<std::string, std::map<std::string, double>> exponents;
  std::map<std::string, double> crossings;   // texture method -> triangles where exact costs as much
  int tessellationResolution = 0;
};

const Row* findRow(const std::vector<Row>& rows, const std::string& shape, const std::string& quantity,
                   const std::string& method, int resolution) {
  for (const Row& row : rows)
    if (row.shape == shape && row.quantity == quantity && row.method == method && row.resolution == resolution) return &row;
  return nullptr;
}

Summary summarize(const std::vector<Row>& rows, const Plan& plan) {
  Summary summary;
  summary.tessellationResolution = plan.tessellationResolution;
  if (plan.quick)
    summary.ranges = {{"32^2-128^2", 32, 128}};
  else
    summary.ranges = {{"128^2-512^2", 128, 512}, {"512^2-2048^2", 512, 2048}};
  // Two ranges: while a body's texels fit in the caches (up to 512^2, 17 MB) and beyond, where
  // the hierarchy's scattered waterline tiles start to miss.
  for (const std::string method : {"texture-hierarchy", "texture-brute-force", "texture-gpu"}) {
    for (const auto& [label, lowest, highest] : summary.ranges) {
      std::vector<std::pair<double, double>> points;
      for (int resolution : plan.resolutions)
        if (resolution >= lowest && resolution <= highest)
          if (const Row* row = findRow(rows, "sphere", "volume", method, resolution)) points.push_back({resolution, row->timeUs});
      if (points.size() >= 2) summary.exponents[method][label] = logSlope(points);
    }
  }
  std::vector<std::pair<double, double>> exact;
  for (const Row& row : rows)
    if (row.shape == "sphere-tessellation" && row.method == "exact") exact.push_back({double(row.triangles), row.timeUs});
  std::sort(exact.begin(), exact.end());
  for (const std::string method : {"texture-hierarchy", "texture-brute-force"}) {
    std::vector<double> times;
    for (const Row& row : rows)
      if (row.shape == "sphere-tessellation" && row.method == method) times.push_back(row.timeUs);
    if (times.empty()) continue;
    std::sort(times.begin(), times.end());
    summary.crossings[method] = crossingTriangles(exact, times[times.size() / 2]);
  }
  return summary;
}

void writeCsv(const std::filesystem::path& path, const std::vector<Row>& rows) {
  std::ofstream csv(path);
  csv << "shape,quantity,method,backend,resolution,triangles,rel_error,time_us,bytes\n";
  csv.precision(6);
  for (const Row& r : rows)
    csv << r.shape << ',' << r.quantity << ',' << r.method << ',' << r.backend << ',' << r.resolution << ',' << r.triangles
        << ',' << r.relError << ',' << r.timeUs << ',' << r.bytes << '\n';
}

/// Worst error of `quantity` for (method, resolution) over every swept shape.
double worstOverShapes(const std::vector<Row>& rows, const std::string& quantity, const std::string& method, int resolution) {
  double worst = 0.0;
  for (const Row& row : rows)
    if (row.shape != "sphere-tessellation" && row.quantity == quantity && row.method == method && row.resolution == resolution)
      worst = std::max(worst, row.relError);
  return worst;
}

void writeMarkdown(const std::filesystem::path& path, const std::vector<Row>& rows, const Plan& plan,
                   const Summary& summary, const std::vector<Shape>& shapes, const std::string& gpuRenderer) {
  std::ofstream md(path);
  std::string shapeList;
  for (const Shape& shape : shapes) shapeList += (shapeList.empty() ? "" : ", ") + shape.name + " (" + std::to_string(shape.mesh.triangles.size()) + " triangles)";
  md << "# Accuracy against cost" << (plan.quick ? " (quick mode)" : "") << "\n\n"
     << "Generated by `hydrotex_accuracy_report" << (plan.quick ? " --quick" : "") << "`. Shapes: " << shapeList << ". "
     << "Each error is the worst over " << plan.sampling.depthCount << " water levels x " << plan.sampling.orientationCount
     << " orientations and over every shape, relative to the exact path on the same mesh: submerged volume relative to "
     << "the total volume, centre of buoyancy relative to the bounding-box diagonal. Times are per query on one thread "
     << "(median of " << plan.timing.runs << " timed batches), on the sphere; memory is what a query reads.\n\n";
  md << "| Method | Resolution | Volume error | Centre of buoyancy error | Time per query (us) | Memory |\n"
     << "|---|---|---|---|---|---|\n";
  if (const Row* exact = findRow(rows, "sphere", "volume", "exact", 0)) {
    const double meshVolume = worstOverShapes(rows, "volume_vs_closed_form", "exact", 0);
    md << "| exact (mesh) | - | 0 (reference; mesh vs true shape " << formatError(meshVolume) << ") | 0 | "
       << formatTime(exact->timeUs) << " | " << formatBytes(double(exact->bytes)) << " |\n";
  }
  for (const std::string method : {"texture-hierarchy", "texture-brute-force", "texture-gpu"}) {
    for (int resolution : plan.resolutions) {
      const Row* row = findRow(rows, "sphere", "volume", method, resolution);
      if (!row) continue;
      md << "| " << method << (method == "texture-gpu" ? " (" + row->backend + ")" : "") << " | " << resolution << "^2 | "
         << formatError(worstOverShapes(rows, "volume", method, resolution)) << " | "
         << formatError(worstOverShapes(rows, "center_of_buoyancy", method, resolution)) << " | " << formatTime(row->timeUs)
         << " | " << formatBytes(double(row->bytes)) << " |\n";
    }
  }
  md << "\nExact-path rows: the mesh against the true shape (closed forms at the modelled orientation; the box is its own "
     << "closed form): worst submerged volume error";
  for (const Shape& shape : shapes)
    if (const Row* row = findRow(rows, shape.name, "volume_vs_closed_form", "exact", 0))
      md << " " << shape.name << " " << formatError(row->relError) << ";";
  md << " this is the tessellation's error, which no method removes.\n\n";
  md << "Time against resolution on the sphere, fitted exponent of the resolution per side (brute force reads every "
     << "texel: area, 2; the hierarchy reads the texels along the waterline: its length, 1):\n\n| Method |";
  for (const auto& range : summary.ranges) md << " " << std::get<0>(range) << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < summary.ranges.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& [method, byRange] : summary.exponents) {
    md << "| " << method << " |";
    for (const auto& range : summary.ranges) {
      const auto found = byRange.find(std::get<0>(range));
      char text[32];
      std::snprintf(text, sizeof text, " %.2f |", found == byRange.end() ? std::nan("") : found->second);
      md << text;
    }
    md << "\n";
  }
  md << "\n";

  md << "## Mesh independence\n\nA unit sphere at increasing triangle counts; texture path at "
     << summary.tessellationResolution << "^2.\n\n| Triangles | Exact (us) | Texture hierarchy (us) | Texture brute force (us) |\n|---|---|---|---|\n";
  std::map<std::size_t, std::map<std::string, double>> byTriangles;
  for (const Row& row : rows)
    if (row.shape == "sphere-tessellation") byTriangles[row.triangles][row.method] = row.timeUs;
  for (auto& [triangles, times] : byTriangles)
    md << "| " << triangles << " | " << formatTime(times["exact"]) << " | " << formatTime(times["texture-hierarchy"]) << " | "
       << formatTime(times["texture-brute-force"]) << " |\n";
  md << "\n";
  for (const auto& [method, triangles] : summary.crossings) {
    char text[160];
    std::snprintf(text, sizeof text, "The exact path costs as much as %s at %d^2 at about %.0f triangles.\n", method.c_str(),
                  summary.tessellationResolution, triangles);
    md << text;
  }

  md << "\n## Mass properties\n\nUniform solid; texture cone sums against the exact polyhedral mass properties, worst over "
     << "the shapes (centre of mass relative to the bounding-box diagonal, inertia in the Frobenius norm); time on the sphere.\n\n"
     << "| Method | Resolution | Mass error | Centre of mass error | Inertia error | Time (us) |\n|---|---|---|---|---|---|\n";
  if (const Row* exact = findRow(rows, "sphere", "mass", "exact", 0))
    md << "| exact (mesh) | - | 0 (reference; mesh vs true shape " << formatError(worstOverShapes(rows, "mass_vs_closed_form", "exact", 0))
       << ") | 0 | 0 | " << formatTime(exact->timeUs) << " (with the closedness check) |\n";
  for (const std::string method : {"texture", "texture-gpu"})
    for (int resolution : plan.resolutions)
      if (const Row* row = findRow(rows, "sphere", "mass", method, resolution))
        md << "| " << method << (method == "texture-gpu" ? " (" + row->backend + ")" : "") << " | " << resolution << "^2 | "
           << formatError(worstOverShapes(rows, "mass", method, resolution)) << " | "
           << formatError(worstOverShapes(rows, "center_of_mass", method, resolution)) << " | "
           << formatError(worstOverShapes(rows, "inertia", method, resolution)) << " | " << formatTime(row->timeUs) << " |\n";
  md << "\nGPU: " << (gpuRenderer.empty() ? std::string("not measured") : gpuRenderer + " (LP_NUM_THREADS=1 for llvmpipe)") << ".\n";
}

/// Writes the gnuplot data and script and runs gnuplot when it is there. Returns whether it ran.
bool writePlots(const std::filesystem::path& dir, const std::vector<Row>& rows, const Plan& plan) {
  // error_vs_time: per method, (time, worst of volume and centre-of-buoyancy error) on the sphere.
  const std::vector<std::string> methods = {"texture-hierarchy", "texture-brute-force", "texture-gpu"};
  std::vector<std::string> curves;
  for (const std::string& method : methods) {
    std::ofstream dat(dir / ("plot_" + method + ".dat"));
    dat << "# resolution time_us worst_error\n";
    int points = 0;
    for (int resolution : plan.resolutions) {
      const Row* volume = findRow(rows, "sphere", "volume", method, resolution);
      const Row* center = findRow(rows, "sphere", "center_of_buoyancy", method, resolution);
      if (!volume || !center) continue;
      dat << resolution << ' ' << volume->timeUs << ' ' << std::max(volume->relError, center->relError) << '\n';
      ++points;
    }
    if (points > 0) curves.push_back(method);
  }
  {
    std::ofstream dat(dir / "plot_exact.dat");
    dat << "# time_us mesh_vs_closed_form_volume_error (sphere)\n";
    const Row* exact = findRow(rows, "sphere", "volume", "exact", 0);
    const Row* mesh = findRow(rows, "sphere", "volume_vs_closed_form", "exact", 0);
    if (exact && mesh) dat << exact->timeUs << ' ' << std::max(mesh->relError, 1e-12) << '\n';
  }
  {
    std::ofstream dat(dir / "plot_tessellation.dat");
    dat << "# triangles exact_us hierarchy_us brute_force_us\n";
    std::map<std::size_t, std::map<std::string, double>> byTriangles;
    for (const Row& row : rows)
      if (row.shape == "sphere-tessellation") byTriangles[row.triangles][row.method] = row.timeUs;
    for (auto& [triangles, times] : byTriangles)
      dat << triangles << ' ' << times["exact"] << ' ' << times["texture-hierarchy"] << ' ' << times["texture-brute-force"] << '\n';
  }
  std::ofstream gp(dir / "plots.gp");
  gp << "# gnuplot script written by hydrotex_accuracy_report; run in this directory.\n"
     << "set terminal png size 900,600\nset grid\nset logscale xy\nset key bottom left\n"
     << "set output 'error_vs_time.png'\nset title 'Sphere: worst error (volume, centre of buoyancy) against time per query'\n"
     << "set xlabel 'time per query (us, one thread)'\nset ylabel 'relative error'\n"
     << "plot ";
  for (const std::string& method : curves)
    gp << "'plot_" << method << ".dat' using 2:3 with linespoints title '" << method << "', '' using 2:3:(sprintf('%d', $1)) with labels offset 0,1 notitle, ";
  gp << "'plot_exact.dat' using 1:2 with points pt 7 ps 2 title 'exact (mesh vs true sphere)'\n"
     << "set output 'time_vs_resolution.png'\nset title 'Sphere: time per query against resolution'\n"
     << "set xlabel 'texels per side'\nset ylabel 'time per query (us)'\nset key top left\nplot ";
  for (std::size_t i = 0; i < curves.size(); ++i)
    gp << (i ? ", " : "") << "'plot_" << curves[i] << ".dat' using 1:2 with linespoints title '" << curves[i] << "'";
  gp << ", x**2/2000 with lines dt 2 title 'slope 2 (area)', x/20 with lines dt 3 title 'slope 1 (waterline)'\n"
     << "set output 'mesh_independence.png'\nset title 'Sphere: time per query against triangle count'\n"
     << "set xlabel 'triangles'\nset ylabel 'time per query (us)'\n"
     << "plot 'plot_tessellation.dat' using 1:2 with linespoints title 'exact', '' using 1:3 with linespoints title 'texture hierarchy "
     << plan.tessellationResolution << "^2', '' using 1:4 with linespoints title 'texture brute force " << plan.tessellationResolution << "^2'\n";
  gp.close();
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) return false;
  const std::string command = "cd '" + dir.string() + "' && gnuplot plots.gp";
  return std::system(command.c_str()) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, noGpu = false;
  std::filesystem::path outDir = ".";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick")
      quick = true;
    else if (arg == "--no-gpu")
      noGpu = true;
    else if (arg == "--help" || arg == "-h") {
      std::printf("usage: hydrotex_accuracy_report [--quick] [--no-gpu] [OUTDIR]\n");
      return 0;
    } else if (!arg.empty() && arg[0] == '-') {
      std::fprintf(stderr, "accuracy_report: unknown option '%s' (--quick, --no-gpu, OUTDIR)\n", arg.c_str());
      return 2;
    } else
      outDir = arg;
  }
  std::error_code error;
  std::filesystem::create_directories(outDir, error);
  if (error) fail("cannot create " + outDir.string() + ": " + error.message());
  // One thread for every figure: llvmpipe would otherwise spread a GPU pass over every core.
  setenv("LP_NUM_THREADS", "1", 0);

  Plan plan = makePlan(quick);
  plan.gpu = !noGpu;
  const std::vector<Shape> shapes = makeShapes(quick);
  std::vector<Row> rows;
  std::string gpuRenderer;
  bool gpuWarned = false;
  for (const Shape& shape : shapes) sweepShape(shape, plan, rows, gpuRenderer, gpuWarned);
  sweepTessellation(plan, rows);

  const Summary summary = summarize(rows, plan);
  writeCsv(outDir / "accuracy.csv", rows);
  writeMarkdown(outDir / "accuracy.md", rows, plan, summary, shapes, gpuRenderer);
  const bool plotted = writePlots(outDir, rows, plan);

  std::printf("\n%-22s %-20s %6s %10s %10s %12s\n", "shape", "method", "res", "vol err", "CoB err", "us/query");
  for (const Row& row : rows)
    if (row.quantity == "volume" && row.shape != "sphere-tessellation") {
      const Row* center = findRow(rows, row.shape, "center_of_buoyancy", row.method, row.resolution);
      std::printf("%-22s %-20s %6d %10.2e %10.2e %12.2f\n", row.shape.c_str(), row.method.c_str(), row.resolution, row.relError,
                  center ? center->relError : 0.0, row.timeUs);
    }
  for (const auto& [method, byRange] : summary.exponents)
    for (const auto& [range, exponent] : byRange) std::printf("exponent %-20s %-14s %.2f\n", method.c_str(), range.c_str(), exponent);
  for (const auto& [method, triangles] : summary.crossings)
    std::printf("exact = %-20s at %.0f triangles (%d^2)\n", method.c_str(), triangles, summary.tessellationResolution);
  std::printf("wrote %s, %s%s\n", (outDir / "accuracy.csv").string().c_str(), (outDir / "accuracy.md").string().c_str(),
              plotted ? " and PNG plots" : " (plots skipped: gnuplot not found or failed)");
  return 0;
}
