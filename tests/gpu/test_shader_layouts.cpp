// SPDX-License-Identifier: Zlib
// Layout tests (no GL context): every storage struct of gpu/shaders/layouts*.glsl, laid out by the
// std430 rules (OpenGL 4.6 spec, section 7.6.2.2, rules 1-9 without the vec4 rounding of std140),
// must have the same member offsets and size as its C++ mirror in hydrotex/gpu/ShaderLayouts.hpp,
// or buffers filled by memcpy would be read wrongly by the shaders.
#include <catch2/catch.hpp>

#include <cstddef>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "hydrotex/gpu/EmbeddedShaders.hpp"
#include "hydrotex/gpu/ShaderLayouts.hpp"

namespace layout = hydrotex::gpu::layout;

namespace {

struct Member {
  std::string name;
  std::size_t offset;
};
struct StructLayout {
  std::vector<Member> members;
  std::size_t size = 0;
  std::size_t alignment = 0;
};

// std430 size and base alignment of the scalar and vector types the shaders use.
bool basicType(const std::string& type, std::size_t& size, std::size_t& alignment) {
  static const std::map<std::string, std::pair<std::size_t, std::size_t>> kTypes = {
      {"float", {4, 4}},   {"int", {4, 4}},     {"uint", {4, 4}},    {"bool", {4, 4}},
      {"vec2", {8, 8}},    {"vec3", {12, 16}},  {"vec4", {16, 16}},  {"uvec4", {16, 16}},
      {"double", {8, 8}},  {"dvec2", {16, 16}}, {"dvec3", {24, 32}}, {"dvec4", {32, 32}}};
  const auto found = kTypes.find(type);
  if (found == kTypes.end()) return false;
  size = found->second.first;
  alignment = found->second.second;
  return true;
}

std::size_t roundUp(std::size_t value, std::size_t alignment) { return (value + alignment - 1) / alignment * alignment; }

// Every `struct Name { type member; type member[N]; ... };` of a shader file, one member per line.
std::map<std::string, StructLayout> parseStructs(std::string_view text) {
  std::map<std::string, StructLayout> out;
  std::istringstream lines{std::string(text)};
  const std::regex open(R"(^\s*struct\s+(\w+)\s*\{\s*$)");
  const std::regex member(R"(^\s*(\w+)\s+(\w+)\s*(\[\s*(\d+)\s*\])?\s*;\s*$)");
  const std::regex close(R"(^\s*\};\s*$)");
  std::string line, current;
  std::size_t offset = 0;
  std::smatch match;
  while (std::getline(lines, line)) {
    if (std::regex_match(line, match, open)) {
      current = match[1];
      out[current] = StructLayout{};
      offset = 0;
    } else if (!current.empty() && std::regex_match(line, match, member)) {
      std::size_t size = 0, alignment = 0;
      INFO("member type " << match[1] << " of " << current);
      REQUIRE(basicType(match[1], size, alignment));
      const std::size_t count = match[4].matched ? std::stoul(match[4]) : 1;
      // An array's stride is its element's size rounded up to the element's alignment (std430).
      const std::size_t stride = roundUp(size, alignment);
      offset = roundUp(offset, alignment);
      out[current].members.push_back({match[2], offset});
      offset += count > 1 || match[4].matched ? stride * count : size;
      out[current].alignment = std::max(out[current].alignment, alignment);
    } else if (!current.empty() && std::regex_match(line, close)) {
      out[current].size = roundUp(offset, out[current].alignment);
      current.clear();
    }
  }
  return out;
}

#define HYDROTEX_MEMBER(type, name) Member{#name, offsetof(type, name)}

void checkLayout(const std::map<std::string, StructLayout>& shader, const std::string& name, std::size_t cppSize,
                 const std::vector<Member>& cppMembers) {
  INFO("struct " << name);
  const auto found = shader.find(name);
  REQUIRE(found != shader.end());
  const StructLayout& glsl = found->second;
  CHECK(glsl.size == cppSize);
  REQUIRE(glsl.members.size() == cppMembers.size());
  for (std::size_t i = 0; i < cppMembers.size(); ++i) {
    INFO("member " << glsl.members[i].name);
    CHECK(glsl.members[i].name == cppMembers[i].name);
    CHECK(glsl.members[i].offset == cppMembers[i].offset);
  }
}

}  // namespace

TEST_CASE("the layout parser follows std430 on known cases", "[layout]") {
  // vec3 aligns to 16 but occupies 12, so a float fits behind it; a double array aligns to 8.
  const auto parsed = parseStructs("struct A {\n  float a;\n  vec3 b;\n  float c;\n};\nstruct B {\n  float a;\n"
                                   "  double d[3];\n  dvec3 e;\n};\n");
  REQUIRE(parsed.count("A") == 1);
  CHECK(parsed.at("A").members[1].offset == 16);
  CHECK(parsed.at("A").members[2].offset == 28);
  CHECK(parsed.at("A").size == 32);
  CHECK(parsed.at("B").members[1].offset == 8);
  CHECK(parsed.at("B").members[2].offset == 32);
  CHECK(parsed.at("B").size == 64);
}

TEST_CASE("every shader storage struct matches its C++ mirror", "[layout]") {
  const std::string_view layouts = hydrotex::gpu::embeddedShader("layouts.glsl");
  const std::string_view layoutsFp64 = hydrotex::gpu::embeddedShader("layouts_fp64.glsl");
  REQUIRE(!layouts.empty());
  REQUIRE(!layoutsFp64.empty());
  const auto shader = parseStructs(layouts);
  const auto shaderFp64 = parseStructs(layoutsFp64);
  CHECK(shader.size() == 15);
  CHECK(shaderFp64.size() == 2);

  using layout::HydroTexel;
  checkLayout(shader, "HydroTexel", sizeof(HydroTexel),
              {HYDROTEX_MEMBER(HydroTexel, px), HYDROTEX_MEMBER(HydroTexel, py), HYDROTEX_MEMBER(HydroTexel, pz),
               HYDROTEX_MEMBER(HydroTexel, ax), HYDROTEX_MEMBER(HydroTexel, ay), HYDROTEX_MEMBER(HydroTexel, az),
               HYDROTEX_MEMBER(HydroTexel, area), HYDROTEX_MEMBER(HydroTexel, ux), HYDROTEX_MEMBER(HydroTexel, uy),
               HYDROTEX_MEMBER(HydroTexel, uz), HYDROTEX_MEMBER(HydroTexel, vx), HYDROTEX_MEMBER(HydroTexel, vy),
               HYDROTEX_MEMBER(HydroTexel, vz)});
  CHECK(sizeof(HydroTexel) == 52);  // the bandwidth figures of bench_gpu count 52 bytes per texel
  checkLayout(shader, "MassTexel", sizeof(layout::MassTexel), {HYDROTEX_MEMBER(layout::MassTexel, offsetAndVolume)});
  using layout::Chunk;
  checkLayout(shader, "Chunk", sizeof(Chunk),
              {HYDROTEX_MEMBER(Chunk, body), HYDROTEX_MEMBER(Chunk, begin), HYDROTEX_MEMBER(Chunk, count),
               HYDROTEX_MEMBER(Chunk, centerX), HYDROTEX_MEMBER(Chunk, centerY), HYDROTEX_MEMBER(Chunk, centerZ),
               HYDROTEX_MEMBER(Chunk, halfX), HYDROTEX_MEMBER(Chunk, halfY), HYDROTEX_MEMBER(Chunk, halfZ),
               HYDROTEX_MEMBER(Chunk, correctionBegin), HYDROTEX_MEMBER(Chunk, correctionCount),
               HYDROTEX_MEMBER(Chunk, table)});
  using layout::TexelCorrection;
  checkLayout(shader, "TexelCorrection", sizeof(TexelCorrection),
              {HYDROTEX_MEMBER(TexelCorrection, texel), HYDROTEX_MEMBER(TexelCorrection, moment),
               HYDROTEX_MEMBER(TexelCorrection, reach)});
  CHECK(sizeof(TexelCorrection) == 44);
  using layout::BodyPose;
  checkLayout(shader, "BodyPose", sizeof(BodyPose),
              {HYDROTEX_MEMBER(BodyPose, row0), HYDROTEX_MEMBER(BodyPose, row1), HYDROTEX_MEMBER(BodyPose, row2)});
  using layout::BodyRange;
  checkLayout(shader, "BodyRange", sizeof(BodyRange),
              {HYDROTEX_MEMBER(BodyRange, chunkBegin), HYDROTEX_MEMBER(BodyRange, chunkEnd),
               HYDROTEX_MEMBER(BodyRange, mode), HYDROTEX_MEMBER(BodyRange, uniformDensity)});
  checkLayout(shader, "Partial", sizeof(layout::Partial), {HYDROTEX_MEMBER(layout::Partial, value)});
  checkLayout(shader, "ChunkMoments", sizeof(layout::ChunkMoments), {HYDROTEX_MEMBER(layout::ChunkMoments, value)});
  using layout::SegmentCounters;
  checkLayout(shader, "SegmentCounters", sizeof(SegmentCounters),
              {HYDROTEX_MEMBER(SegmentCounters, crossingGroups), HYDROTEX_MEMBER(SegmentCounters, one0),
               HYDROTEX_MEMBER(SegmentCounters, one1), HYDROTEX_MEMBER(SegmentCounters, submergedChunks)});
  CHECK(sizeof(SegmentCounters) == 16);
  using layout::DeformPiece;
  checkLayout(shader, "DeformPiece", sizeof(DeformPiece),
              {HYDROTEX_MEMBER(DeformPiece, triangle), HYDROTEX_MEMBER(DeformPiece, areaFraction),
               HYDROTEX_MEMBER(DeformPiece, centroidBary1), HYDROTEX_MEMBER(DeformPiece, centroidBary2),
               HYDROTEX_MEMBER(DeformPiece, uvShare)});
  using layout::DeformTriangle;
  checkLayout(shader, "DeformTriangle", sizeof(DeformTriangle),
              {HYDROTEX_MEMBER(DeformTriangle, vertex0), HYDROTEX_MEMBER(DeformTriangle, vertex1),
               HYDROTEX_MEMBER(DeformTriangle, vertex2), HYDROTEX_MEMBER(DeformTriangle, cu1),
               HYDROTEX_MEMBER(DeformTriangle, cu2), HYDROTEX_MEMBER(DeformTriangle, cv1),
               HYDROTEX_MEMBER(DeformTriangle, cv2)});
  checkLayout(shader, "TriangleFrame", sizeof(layout::TriangleFrame), {HYDROTEX_MEMBER(layout::TriangleFrame, value)});  // glDispatchComputeIndirect reads x, y, z at 16-byte strides
  using layout::GerstnerComponent;
  checkLayout(shader, "GerstnerComponent", sizeof(GerstnerComponent),
              {HYDROTEX_MEMBER(GerstnerComponent, waveNumber), HYDROTEX_MEMBER(GerstnerComponent, dirX),
               HYDROTEX_MEMBER(GerstnerComponent, dirZ), HYDROTEX_MEMBER(GerstnerComponent, amplitude),
               HYDROTEX_MEMBER(GerstnerComponent, horizontal)});
  using layout::GridFrame;
  checkLayout(shader, "GridFrame", sizeof(GridFrame),
              {HYDROTEX_MEMBER(GridFrame, cellX), HYDROTEX_MEMBER(GridFrame, cellZ), HYDROTEX_MEMBER(GridFrame, fracX),
               HYDROTEX_MEMBER(GridFrame, fracZ), HYDROTEX_MEMBER(GridFrame, heightOffset),
               HYDROTEX_MEMBER(GridFrame, dryLevel)});
  checkLayout(shader, "MassBlock", sizeof(layout::MassBlock), {HYDROTEX_MEMBER(layout::MassBlock, value)});
  using layout::BlockGeometry;
  checkLayout(shaderFp64, "BlockGeometry", sizeof(BlockGeometry),
              {HYDROTEX_MEMBER(BlockGeometry, covariance), HYDROTEX_MEMBER(BlockGeometry, absVolume),
               HYDROTEX_MEMBER(BlockGeometry, unused)});
  checkLayout(shaderFp64, "BodySums", sizeof(layout::BodySums), {HYDROTEX_MEMBER(layout::BodySums, value)});
}

TEST_CASE("every shader storage block binds within GL 4.3's guaranteed 8 (bindings 0..7)", "[layout]") {
  // GL 4.3 guarantees GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS and GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS
  // of at least 8 (OpenGL 4.3 spec, table 23.64): a binding past 7 may fail to link on a driver
  // at that minimum. Variants under #if (hydrostatics_surface.comp) reuse a binding number.
  const char* names[] = {"deform_mass.comp",          "deform_texel.glsl",       "deform_texels.comp",
                         "deform_triangles.comp",     "flooding_texels.comp",    "hydrostatics_classify.comp",
                         "hydrostatics_flat.comp",    "hydrostatics_surface.comp", "mass_moments.comp",
                         "reduce_partials.comp",      "wet_shading_eval.comp",   "wetting_diffuse.comp",
                         "wetting_exchange.comp",     "wetting_groups.comp",     "wetting_implicit.comp",
                         "wetting_implicit_reduce.comp"};
  const std::regex binding(R"(binding\s*=\s*(\d+))");
  for (const char* name : names) {
    const std::string text(hydrotex::gpu::embeddedShader(name));
    INFO(name);
    REQUIRE(!text.empty());
    for (std::sregex_iterator it(text.begin(), text.end(), binding), end; it != end; ++it)
      CHECK(std::stoi((*it)[1].str()) <= 7);
  }
}

TEST_CASE("an unknown shader name gives an empty text", "[layout]") {
  CHECK(hydrotex::gpu::embeddedShader("missing.comp").empty());
  CHECK(hydrotex::gpu::embeddedShader("hydrostatics_flat.comp").find("void main()") != std::string_view::npos);
}
