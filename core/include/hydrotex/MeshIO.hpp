#pragma once
/// @file MeshIO.hpp
/// Reading and writing triangle meshes through assimp (OBJ, glTF/GLB, PLY, STL and every other
/// format assimp reads). The UV convention after loading is the one written in Mesh.hpp.

#include <cstddef>
#include <cstdint>
#include <string>

#include "hydrotex/Expected.hpp"
#include "hydrotex/Mesh.hpp"

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

/// Writes `mesh` (with its UVs when it has them) in the format given by the extension of `path`:
/// .obj (plus a .mtl beside it), .gltf (plus a .bin), .glb, .ply (ASCII), .stl (binary).
/// Coordinates are written as 32-bit floats (what every one of these formats stores).
Status saveMesh(const Mesh& mesh, const std::string& path);

}  // namespace hydrotex
