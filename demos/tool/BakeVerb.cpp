// SPDX-License-Identifier: Zlib
// `hydrotex bake MESH --resolution N --out DIR`: the position texture (PT), the vector-area texture
// (VAT), texel areas and UV coverage, as PNG pictures a person can look at and as float data
// (PFM, the portable float map: exact float32 values, readable by common image tools).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ToolSupport.hpp"
#include "Verbs.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/mesh/ImageMap.hpp"

namespace hydrotex::tool {

namespace {
struct BakeOptions {
  std::string meshPath;
  MeshLoadSettings load;
  int resolution = 256;
  std::string outDir;
  bool json = false;
};

/// Writes a 3-channel PFM (rows bottom to top, as the format requires; little-endian).
Status writePfm(const std::string& path, int width, int height, const std::vector<float>& rgbTopDown) {
  std::ofstream file(path, std::ios::binary);
  if (!file) return Error{path + ": cannot be written"};
  file << "PF\n" << width << " " << height << "\n-1.0\n";
  for (int row = height - 1; row >= 0; --row)
    file.write(reinterpret_cast<const char*>(rgbTopDown.data() + static_cast<std::size_t>(row) * width * 3),
               static_cast<std::streamsize>(sizeof(float) * 3 * static_cast<std::size_t>(width)));
  if (!file) return Error{path + ": write failed"};
  return Ok{};
}

std::uint8_t toByte(double unit) { return static_cast<std::uint8_t>(std::lround(std::clamp(unit, 0.0, 1.0) * 255.0)); }

int runBake(const BakeOptions& options) {
  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = options.resolution;
  settings.load = options.load;
  settings.requireClosed = false;  // a bake is a surface quantity: open meshes bake too
  Expected<BodyGeometry> body = loadBodyGeometry(options.meshPath, settings);
  if (!body) return reportError(body.error());
  std::error_code ec;
  std::filesystem::create_directories(options.outDir, ec);
  if (ec) return reportError(Error{options.outDir + ": cannot create directory (" + ec.message() + ")"});

  const SurfaceBake& bake = body->bake;
  const SurfaceTextures& tex = body->textures;
  const int w = bake.width, h = bake.height;
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  std::vector<float> positionData(pixels * 3, 0.0f), areaVectorData(pixels * 3, 0.0f);
  std::vector<std::uint8_t> positionPng(pixels * 3, 0), normalPng(pixels * 3, 0), areaPng(pixels, 0), coveragePng(pixels, 0);

  // Coverage: the UV area of a texel's pieces over the texel's UV area.
  std::vector<double> triangleUvArea(body->mesh.triangles.size());
  const UvLayout& layout = body->atlas.layout;
  for (std::size_t t = 0; t < triangleUvArea.size(); ++t) {
    const Eigen::Vector2d a = layout.uvs[layout.uvTriangles[t][0]], b = layout.uvs[layout.uvTriangles[t][1]],
                          c = layout.uvs[layout.uvTriangles[t][2]];
    const Eigen::Vector2d ab = b - a, ac = c - a;
    triangleUvArea[t] = 0.5 * std::abs(ab.x() * ac.y() - ab.y() * ac.x());
  }
  const double texelUvArea = 1.0 / (static_cast<double>(w) * h);

  const Eigen::Vector3d lo = body->report.boundsMin, span = (body->report.boundsMax - lo).cwiseMax(1e-30);
  float maxArea = 0.0f;
  for (float a : tex.area) maxArea = std::max(maxArea, a);
  for (std::size_t i = 0; i < bake.coveredCount(); ++i) {
    const std::size_t pixel = bake.texelIndex[i];
    double coverage = 0.0;
    for (std::uint32_t k = bake.pieceStart[i]; k < bake.pieceStart[i + 1]; ++k)
      coverage += bake.pieces[k].areaFraction * triangleUvArea[bake.pieces[k].triangle];
    coveragePng[pixel] = toByte(coverage / texelUvArea);
    const Eigen::Vector3d p = tex.position[i].cast<double>(), a = tex.areaVector[i].cast<double>();
    const Eigen::Vector3d n = a.norm() > 0 ? Eigen::Vector3d(a.normalized()) : Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) {
      positionData[pixel * 3 + c] = tex.position[i][c];
      areaVectorData[pixel * 3 + c] = tex.areaVector[i][c];
      positionPng[pixel * 3 + c] = toByte((p[c] - lo[c]) / span[c]);
      normalPng[pixel * 3 + c] = toByte(0.5 + 0.5 * n[c]);
    }
    areaPng[pixel] = toByte(maxArea > 0 ? tex.area[i] / maxArea : 0.0);
  }

  const std::string dir = options.outDir + "/";
  for (const Status& written :
       {writePng(dir + "position.png", w, h, 3, positionPng), writePng(dir + "normal.png", w, h, 3, normalPng),
        writePng(dir + "area.png", w, h, 1, areaPng), writePng(dir + "coverage.png", w, h, 1, coveragePng),
        writePfm(dir + "position.pfm", w, h, positionData), writePfm(dir + "area_vector.pfm", w, h, areaVectorData)})
    if (!written) return reportError(written.error());

  nlohmann::json out;
  out["resolution"] = options.resolution;
  out["covered_texels"] = bake.coveredCount();
  out["pieces"] = bake.pieces.size();
  out["atlas_generated"] = body->atlas.generated;
  out["files"] = {"position.png", "normal.png", "area.png", "coverage.png", "position.pfm", "area_vector.pfm"};
  std::ostringstream text;
  text << options.meshPath << ": baked " << w << "x" << h << ", " << bake.coveredCount() << " covered texels, "
       << bake.pieces.size() << " triangle pieces, " << (body->atlas.generated ? "generated" : "artist") << " atlas"
       << (body->atlas.reason.empty() ? "" : " (" + body->atlas.reason + ")") << "\n  wrote position.png normal.png area.png "
       << "coverage.png position.pfm area_vector.pfm to " << options.outDir << "\n";
  printResult(options.json, out, text.str());
  return 0;
}
}  // namespace

void addBakeVerb(CLI::App& app, VerbAction& action) {
  auto options = std::make_shared<BakeOptions>();
  CLI::App* verb = addVerb(app, action, "bake", "write the position and vector-area textures as images and float data", options, &runBake);
  verb->add_option("MESH", options->meshPath, "mesh file")->required();
  addResolutionOption(*verb, options->resolution)->required();
  addMeshLoadOptions(*verb, options->load);
  verb->add_option("--out", options->outDir, "output directory (created)")->required();
}

}  // namespace hydrotex::tool
