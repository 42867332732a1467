// SPDX-License-Identifier: Zlib
/// @file MeshImportFileSystem.hpp
/// The files assimp may open while importing one mesh (private to core).
///
/// Why not assimp's own: `Importer::ReadFileFromMemory` serves every name starting with its magic
/// prefix from the caller's buffer, so the OBJ reader's fallback material library
/// ("$$$___magic___$$$.mtl") is the mesh bytes themselves, and assimp 5.2's MTL parser writes
/// through a wild pointer on binary garbage (fuzz/crashes/assimp-segv-obj-hint.bin). Names that do
/// not carry the prefix go to the working directory (an in-memory OBJ's `mtllib` opened a file
/// there). Materials carry nothing hydrotex uses, so here no material library is ever opened.
#pragma once

#include <assimp/IOSystem.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace hydrotex::detail {

/// An assimp file system for one import: the mesh file itself (from a caller's buffer or from
/// disk) and, for a file on disk, the side files its format needs (a .gltf's .bin buffers), never a
/// material library (.mtl). Refused files look absent, which every reader tolerates for materials.
class MeshImportFileSystem final : public Assimp::IOSystem {
 public:
  /// Serves `bytes` (not copied; they must outlive the import) under `meshName`, and nothing else.
  static std::unique_ptr<MeshImportFileSystem> inMemory(const void* bytes, std::size_t size, std::string meshName);
  /// Serves files from disk: the mesh and its side files, minus material libraries.
  static std::unique_ptr<MeshImportFileSystem> onDisk();

  bool Exists(const char* file) const override;
  char getOsSeparator() const override;
  Assimp::IOStream* Open(const char* file, const char* mode) override;
  void Close(Assimp::IOStream* stream) override;

 private:
  MeshImportFileSystem() = default;
  bool isServedFromMemory(const std::string& file) const;

  const std::uint8_t* bytes_ = nullptr;  ///< the in-memory mesh, or null for disk
  std::size_t size_ = 0;                 ///< bytes in the in-memory mesh
  std::string meshName_;                 ///< the name the in-memory mesh is served under
};

}  // namespace hydrotex::detail
