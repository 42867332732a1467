// SPDX-License-Identifier: Zlib
// libFuzzer target: mesh loading, validation, physics atlas, bake, mass and hydrostatics.
// The first input byte picks how the rest is read: one of assimp's readers (by file extension),
// or raw little-endian values straight into a Mesh (positions, triangles, UVs), which reaches the
// validator, atlas and bake with values no importer would let through (NaN, huge, out of range).
// Anything may fail with an Error; nothing may crash, leak, hang or trip a sanitizer.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "hydrotex/mesh/Atlas.hpp"
#include "hydrotex/bake/BodyGeometry.hpp"
#include "hydrotex/hydrostatics/LiquidSurface.hpp"
#include "hydrotex/mass/MassProperties.hpp"
#include "hydrotex/mesh/MeshIO.hpp"
#include "hydrotex/mesh/MeshRepair.hpp"
#include "hydrotex/mesh/MeshValidation.hpp"
#include "hydrotex/hydrostatics/PolyhedralHydrostatics.hpp"
#include "hydrotex/hydrostatics/TextureHydrostatics.hpp"

namespace {

/// Reads values from the input in order; zeros once it runs out.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  T next() {
    T value{};
    const std::size_t count = std::min(sizeof(T), size_ - std::min(size_, at_));
    if (count > 0) std::memcpy(&value, data_ + at_, count);
    at_ += sizeof(T);
    return value;
  }
  bool done() const { return at_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

/// A Mesh from raw values: counts (small), then float positions, int16 indices (may be out of
/// range or negative), and optionally UVs.
hydrotex::Mesh rawMesh(const std::uint8_t* data, std::size_t size) {
  ByteReader reader(data, size);
  hydrotex::Mesh mesh;
  mesh.sourceName = "raw";
  const int vertices = reader.next<std::uint8_t>() % 64;
  const int triangles = reader.next<std::uint8_t>() % 96;
  const bool withUvs = (reader.next<std::uint8_t>() & 1) != 0;
  for (int v = 0; v < vertices; ++v)
    mesh.positions.emplace_back(reader.next<float>(), reader.next<float>(), reader.next<float>());
  for (int t = 0; t < triangles; ++t)
    mesh.triangles.emplace_back(reader.next<std::int16_t>(), reader.next<std::int16_t>(), reader.next<std::int16_t>());
  if (withUvs) {
    for (int v = 0; v < vertices; ++v) mesh.uv.uvs.emplace_back(reader.next<float>(), reader.next<float>());
    mesh.uv.uvTriangles = mesh.triangles;
  }
  return mesh;
}

void exercise(hydrotex::Mesh mesh) {
  using namespace hydrotex;
  const MeshReport report = validateMesh(mesh);
  (void)report.summary();
  // The repair every loading path runs (MeshLoadSettings), then the exact mass of its result.
  Mesh repaired = mesh;
  if (const Expected<RepairReport> repairs = repairMesh(repaired, RepairSettings{})) {
    (void)repairs->summary();
    (void)validateMesh(repaired, false);
    (void)polyhedralMassProperties(repaired, 1000.0);
  }
  // The open-hull repair too: loops too large to be holes capped by lids (RepairSettings::openHull).
  Mesh opened = mesh;
  RepairSettings openHull;
  openHull.openHull = true;
  if (const Expected<RepairReport> repairs = repairMesh(opened, openHull)) {
    (void)repairs->summary();
    (void)validateMesh(opened, false);
    (void)polyhedralMassProperties(opened, 1000.0);
  }
  (void)countEdgeTopology(mesh);
  const Expected<MassProperties> exact = polyhedralMassProperties(mesh, 1000.0);
  const FlatSurface water(0.0, 1000.0);
  HydrostaticsQuery query;
  if (exact) query.pose.translation = -exact->centerOfMass;  // the water plane through the centre
  (void)polyhedralHydrostatics(mesh, water, query);

  BodyGeometrySettings settings;
  settings.bake.width = settings.bake.height = 16;
  settings.bake.tileSize = 4;
  settings.requireClosed = false;  // surfaces bake too; reach the atlas and bake with open meshes
  const Expected<BodyGeometry> body = prepareBodyGeometry(std::move(mesh), settings);
  if (!body) return;
  const MassProperties texture = textureMassProperties(body->textures, TextureMassModel{});
  (void)texture;
  const Expected<TextureHydrostatics> hydrostatics = TextureHydrostatics::build(body->bake, body->textures);
  if (hydrostatics) (void)hydrostatics->query(water, query);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  // Formats whose readers we rely on (MeshIO.hpp); others are assimp's business, not ours.
  static const char* const kFormats[] = {"obj", "stl", "ply", "glb", "off"};
  constexpr std::size_t kFormatCount = sizeof(kFormats) / sizeof(kFormats[0]);
  const std::size_t mode = data[0] % (kFormatCount + 1);
  if (mode == kFormatCount) {
    exercise(rawMesh(data + 1, size - 1));
    return 0;
  }
  const std::string hint = kFormats[mode];
  hydrotex::Expected<hydrotex::Mesh> mesh = hydrotex::loadMeshFromMemory(data + 1, size - 1, hint, "fuzz." + hint);
  if (mesh) exercise(std::move(mesh).value());
  return 0;
}
