// SPDX-License-Identifier: Zlib
#include "MeshInterning.hpp"

#include <algorithm>
#include <functional>
#include <string_view>

namespace hydrotex::bullet {
namespace {

template <typename T>
std::string_view bytesOf(const std::vector<T>& values) {
  return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)};
}

void combine(std::size_t& seed, std::size_t value) {
  seed ^= value + 0x9e3779b97f4a7c15ull + (seed << 6) + (seed >> 2);  // boost::hash_combine's mix
}

}  // namespace

bool sameMesh(const Mesh& a, const Mesh& b) {
  return a.positions == b.positions && a.triangles == b.triangles && a.uv.uvs == b.uv.uvs &&
         a.uv.uvTriangles == b.uv.uvTriangles && a.openingTriangles == b.openingTriangles &&
         a.sourceName == b.sourceName && a.fileUnitScale == b.fileUnitScale;
}

std::size_t meshContentHash(const Mesh& mesh) {
  const std::hash<std::string_view> hash;
  std::size_t seed = 0;
  combine(seed, hash(bytesOf(mesh.positions)));
  combine(seed, hash(bytesOf(mesh.triangles)));
  combine(seed, hash(bytesOf(mesh.uv.uvs)));
  combine(seed, hash(bytesOf(mesh.uv.uvTriangles)));
  combine(seed, hash(bytesOf(mesh.openingTriangles)));
  combine(seed, hash(mesh.sourceName));
  combine(seed, std::hash<double>{}(mesh.fileUnitScale));
  return seed;
}

std::shared_ptr<const Mesh> InternedMeshes::intern(std::shared_ptr<const Mesh> mesh) {
  if (mesh == nullptr) return mesh;
  std::vector<std::weak_ptr<const Mesh>>& bucket = byHash_[meshContentHash(*mesh)];
  std::erase_if(bucket, [](const std::weak_ptr<const Mesh>& held) { return held.expired(); });
  for (const std::weak_ptr<const Mesh>& held : bucket) {
    std::shared_ptr<const Mesh> interned = held.lock();
    if (interned && sameMesh(*interned, *mesh)) return interned;
  }
  bucket.push_back(mesh);
  return mesh;
}

std::shared_ptr<const Mesh> InternedMeshes::findShape(const std::string& key) const {
  const auto found = byShape_.find(key);
  return found != byShape_.end() ? found->second.lock() : nullptr;
}

void InternedMeshes::rememberShape(const std::string& key, const std::shared_ptr<const Mesh>& mesh) {
  std::erase_if(byShape_, [](const auto& entry) { return entry.second.expired(); });
  byShape_[key] = mesh;
}

}  // namespace hydrotex::bullet
