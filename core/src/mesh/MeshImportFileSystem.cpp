// SPDX-License-Identifier: Zlib
/// @file MeshImportFileSystem.cpp
/// See MeshImportFileSystem.hpp for why assimp's own file systems are not used.

#include "mesh/MeshImportFileSystem.hpp"
#include "mesh/TextCase.hpp"

#include <assimp/DefaultIOSystem.h>
#include <assimp/MemoryIOWrapper.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace hydrotex::detail {
namespace {

bool isMaterialLibrary(const std::string& file) {
  return lowered(std::filesystem::path(file).extension().string()) == ".mtl";
}

/// Read-only opens only: importing never writes.
bool isReadMode(const char* mode) { return mode != nullptr && std::string(mode).find_first_of("wa+") == std::string::npos; }

}  // namespace

std::unique_ptr<MeshImportFileSystem> MeshImportFileSystem::inMemory(const void* bytes, std::size_t size,
                                                                     std::string meshName) {
  std::unique_ptr<MeshImportFileSystem> system(new MeshImportFileSystem());
  system->bytes_ = static_cast<const std::uint8_t*>(bytes);
  system->size_ = size;
  system->meshName_ = std::move(meshName);
  return system;
}

std::unique_ptr<MeshImportFileSystem> MeshImportFileSystem::onDisk() {
  return std::unique_ptr<MeshImportFileSystem>(new MeshImportFileSystem());
}

bool MeshImportFileSystem::isServedFromMemory(const std::string& file) const {
  // assimp may prefix the import directory ("./"); compare without it.
  std::string name = file;
  while (name.rfind("./", 0) == 0) name.erase(0, 2);
  return name == meshName_;
}

bool MeshImportFileSystem::Exists(const char* file) const {
  if (file == nullptr) return false;
  if (bytes_ != nullptr) return isServedFromMemory(file);
  if (isMaterialLibrary(file)) return false;
  std::error_code error;
  return std::filesystem::is_regular_file(file, error);
}

char MeshImportFileSystem::getOsSeparator() const { return '/'; }

Assimp::IOStream* MeshImportFileSystem::Open(const char* file, const char* mode) {
  if (file == nullptr || !isReadMode(mode) || !Exists(file)) return nullptr;
  if (bytes_ != nullptr) return new Assimp::MemoryIOStream(bytes_, size_);
  // DefaultIOSystem::Open only fopens; it holds no state of its own.
  Assimp::DefaultIOSystem disk;
  return disk.Open(file, mode);
}

void MeshImportFileSystem::Close(Assimp::IOStream* stream) { delete stream; }

}  // namespace hydrotex::detail
