// SPDX-License-Identifier: Zlib
#pragma once
/// @file MeshIO.hpp
/// Reading and writing triangle meshes through assimp (OBJ, glTF/GLB, PLY, STL and every other
/// format assimp reads). The UV convention after loading is the one written in Mesh.hpp.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "hydrotex/Expected.hpp"
#include "hydrotex/mesh/Mesh.hpp"
#include "hydrotex/mesh/MeshRepair.hpp"

namespace hydrotex {

/// Largest input file loadMesh accepts (bytes): 4 GiB. A guard so that a huge file fails with a
/// message instead of exhausting memory; a million-triangle OBJ is about 60 MB.
inline constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t{4} << 30;
/// Largest triangle count loadMesh accepts: 50 million (indices are 32-bit; about 3 GB of Mesh).
inline constexpr std::size_t kMaxMeshTriangles = 50'000'000;
/// Largest coordinate magnitude accepted (m); anything beyond is a unit or export error.
inline constexpr double kMaxMeshCoordinate = 1e12;

/// Loads every triangle of every mesh in the file, with node transforms applied, into one Mesh.
/// Vertices with exactly equal transformed positions are merged (UV seams stay watertight); UVs
/// (channel 0) are kept as their own index stream, only when every triangle has them. Points and
/// lines are ignored. Errors (one line, starting with `path`): missing or unreadable file, empty
/// file, file too large, not a mesh / unsupported format, no triangles, a NaN or infinite vertex,
/// coordinates beyond kMaxMeshCoordinate. Material libraries (.mtl) are never read: hydrotex uses
/// no materials, and assimp's MTL parser is unsafe on a corrupt one.
Expected<Mesh> loadMesh(const std::string& path);

/// loadMesh for a file already in memory (`size` bytes at `bytes`: a download, an archive entry, a
/// fuzzer's input). `formatHint` is the file extension that picks assimp's reader, without the dot
/// ("obj", "stl", "glb", ...); empty lets assimp detect it. Messages start with `name`. Only these
/// bytes are read: a format that refers to other files (a .gltf's .bin) fails, so use a
/// self-contained one (.glb). Same errors as loadMesh.
Expected<Mesh> loadMeshFromMemory(const void* bytes, std::size_t size, const std::string& formatHint,
                                  const std::string& name);

/// The axis a mesh file calls up. hydrotex is y up (gravity along -y).
enum class UpAxis {
  Y,  ///< y up: coordinates are kept
  Z,  ///< z up (CAD, ROS, most naval tools): (x, y, z) -> (x, z, -y), a right-handed rotation of -90 degrees about x
};

/// The axis named "y" or "z" (any case); an error naming `name` otherwise.
Expected<UpAxis> upAxisFromName(std::string_view name);

/// How a mesh file's coordinates become hydrotex's (metres, y up). The one conversion every
/// caller (tool verbs, scenes, plugin) uses, so that `--up` and `"up"` mean the same everywhere.
struct MeshLoadSettings {
  UpAxis up = UpAxis::Y;  ///< the file's up axis
  /// Metres per file unit, for files that declare no unit (OBJ, STL, PLY); applied after the unit
  /// a file declares itself (COLLADA's <unit>, which assimp applies while reading). > 0, finite.
  double scale = 1.0;
  /// Repairs applied after the conversion (MeshRepair.hpp); `repair.enabled = false` loads as is.
  RepairSettings repair;
  /// One line naming the first unusable value, or Ok.
  Status validate() const;
};

/// Rotates (settings.up) then scales (settings.scale) every position of `mesh` in place; UVs and
/// winding are untouched (a rotation and a positive scale keep the orientation). Errors: invalid
/// settings, a coordinate beyond kMaxMeshCoordinate after scaling (messages start with the mesh's
/// sourceName).
Status toHydrotexFrame(Mesh& mesh, const MeshLoadSettings& settings);

/// loadMesh(path), toHydrotexFrame(settings), then repairMesh(settings.repair). What was
/// repaired and what could not be is written to `repairs` when given: defects left do not fail
/// the load (inspect shows them); a caller that needs a closed body refuses with
/// RepairReport::requireRepaired.
Expected<Mesh> loadMesh(const std::string& path, const MeshLoadSettings& settings, RepairReport* repairs = nullptr);

/// Writes `mesh` (with its UVs when it has them) in the format given by the extension of `path`:
/// .obj (plus a .mtl beside it), .gltf (plus a .bin), .glb, .ply (ASCII), .stl (binary).
/// Coordinates are written as 32-bit floats (what every one of these formats stores).
Status saveMesh(const Mesh& mesh, const std::string& path);

}  // namespace hydrotex
