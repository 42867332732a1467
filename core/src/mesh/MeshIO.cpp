// SPDX-License-Identifier: Zlib
/// @file MeshIO.cpp
/// assimp import/export. assimp already converts every format's texture coordinates to the
/// OpenGL/OBJ convention (glTF's v is flipped by its importer and flipped back by its exporter),
/// so aiProcess_FlipUVs is deliberately NOT used; see Mesh.hpp.

#include "hydrotex/mesh/MeshIO.hpp"

#include "mesh/MeshImportFileSystem.hpp"
#include "mesh/OffGuard.hpp"
#include "mesh/PlyGuard.hpp"
#include "mesh/TextCase.hpp"

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <utility>

namespace hydrotex {
namespace {

Error fileError(const std::string& path, const std::string& what) { return Error{path + ": " + what}; }

/// assimp's messages may span lines and carry trailing blanks; errors here are one line.
std::string oneLine(const std::string& text) {
  std::string line;
  line.reserve(text.size());
  for (char c : text) {
    const bool blank = c == '\n' || c == '\r' || c == '\t' || c == ' ';
    if (blank) {
      if (!line.empty() && line.back() != ' ') line.push_back(' ');
    } else {
      line.push_back(c);
    }
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  constexpr std::size_t kMaxLength = 240;
  if (line.size() > kMaxLength) line = line.substr(0, kMaxLength) + "...";
  return line.empty() ? std::string("unknown reason") : line;
}

/// Bit pattern of a double with -0 folded onto +0, so that "exactly equal" positions hash equally.
std::uint64_t bitsOf(double value) {
  const double folded = value + 0.0;
  std::uint64_t bits = 0;
  std::memcpy(&bits, &folded, sizeof bits);
  return bits;
}

struct Vector3Key {
  std::uint64_t x, y, z;
  bool operator==(const Vector3Key&) const = default;
};
struct Vector3KeyHash {
  std::size_t operator()(const Vector3Key& key) const {
    // splitmix64-style mixing of the three bit patterns.
    std::uint64_t h = key.x * 0x9E3779B97F4A7C15ULL;
    h ^= (key.y + 0x632BE59BD9B4E019ULL) * 0xC2B2AE3D27D4EB4FULL;
    h ^= (key.z + 0x165667B19E3779F9ULL) * 0xFF51AFD7ED558CCDULL;
    h ^= h >> 31;
    return static_cast<std::size_t>(h);
  }
};

Eigen::Matrix4d toEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d result;
  result << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return result;
}

/// One placement of one assimp mesh in the scene (a mesh referenced by several nodes is placed
/// several times).
struct MeshInstance {
  const aiMesh* mesh;
  Eigen::Matrix4d transform;
};

std::vector<MeshInstance> flattenNodes(const aiScene& scene) {
  std::vector<MeshInstance> instances;
  if (scene.mRootNode == nullptr) return instances;
  // Explicit stack: a hostile file with a very deep node chain must not overflow the call stack.
  std::vector<std::pair<const aiNode*, Eigen::Matrix4d>> pending;
  pending.emplace_back(scene.mRootNode, toEigen(scene.mRootNode->mTransformation));
  while (!pending.empty()) {
    auto [node, transform] = pending.back();
    pending.pop_back();
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      const unsigned meshIndex = node->mMeshes[i];
      if (meshIndex < scene.mNumMeshes && scene.mMeshes[meshIndex] != nullptr)
        instances.push_back({scene.mMeshes[meshIndex], transform});
    }
    for (unsigned i = 0; i < node->mNumChildren; ++i) {
      const aiNode* child = node->mChildren[i];
      if (child != nullptr) pending.emplace_back(child, Eigen::Matrix4d(transform * toEigen(child->mTransformation)));
    }
  }
  return instances;
}

std::size_t triangleFaceCount(const aiMesh& mesh) {
  if ((mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) return 0;
  std::size_t count = 0;
  for (unsigned f = 0; f < mesh.mNumFaces; ++f)
    if (mesh.mFaces[f].mNumIndices == 3) ++count;
  return count;
}

bool hasUvChannel(const aiMesh& mesh) { return mesh.HasTextureCoords(0) && mesh.mNumUVComponents[0] >= 2; }

std::string formatVector(const Eigen::Vector3d& p) {
  std::ostringstream out;
  out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return out.str();
}

Expected<Mesh> convertScene(const aiScene& scene, const std::string& path) {
  const std::vector<MeshInstance> instances = flattenNodes(scene);
  std::size_t triangleCount = 0;
  bool everyTriangleHasUv = true;
  for (const MeshInstance& instance : instances) {
    const std::size_t count = triangleFaceCount(*instance.mesh);
    triangleCount += count;
    if (count > 0 && !hasUvChannel(*instance.mesh)) everyTriangleHasUv = false;
  }
  if (triangleCount == 0) return fileError(path, "contains no triangles (only points, lines or an empty scene)");
  if (triangleCount > kMaxMeshTriangles)
    return fileError(path, std::to_string(triangleCount) + " triangles exceed the limit of " +
                               std::to_string(kMaxMeshTriangles));

  Mesh result;
  result.sourceName = std::filesystem::path(path).filename().string();
  // A unit the file declares reaches us as its root node's scale (assimp applies COLLADA's
  // <unit meter> there, after its up-axis rotation): the cube root of the determinant.
  if (scene.mRootNode != nullptr) {
    const double determinant = std::abs(toEigen(scene.mRootNode->mTransformation).topLeftCorner<3, 3>().determinant());
    if (std::isfinite(determinant) && determinant > 0.0) result.fileUnitScale = std::cbrt(determinant);
  }
  result.triangles.reserve(triangleCount);
  if (everyTriangleHasUv) result.uv.uvTriangles.reserve(triangleCount);
  std::unordered_map<Vector3Key, int, Vector3KeyHash> positionIndex;
  std::unordered_map<Vector3Key, int, Vector3KeyHash> uvIndex;
  positionIndex.reserve(triangleCount);
  if (everyTriangleHasUv) uvIndex.reserve(triangleCount);

  std::vector<int> localToPosition;
  std::vector<int> localToUv;
  for (std::size_t m = 0; m < instances.size(); ++m) {
    const aiMesh& mesh = *instances[m].mesh;
    if (triangleFaceCount(mesh) == 0) continue;
    const Eigen::Matrix4d& transform = instances[m].transform;
    const Eigen::Matrix3d linear = transform.topLeftCorner<3, 3>();
    const Eigen::Vector3d translation = transform.topRightCorner<3, 1>();
    // A mirroring node transform turns counter-clockwise faces clockwise; undo that.
    const bool mirrored = linear.determinant() < 0.0;
    localToPosition.assign(mesh.mNumVertices, -1);
    localToUv.assign(mesh.mNumVertices, -1);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& source = mesh.mVertices[v];
      const Eigen::Vector3d raw(source.x, source.y, source.z);
      const std::string where = "vertex " + std::to_string(v) + " of mesh " + std::to_string(m) +
                                (mesh.mName.length > 0 ? " '" + std::string(mesh.mName.C_Str()) + "'" : std::string());
      if (!raw.allFinite()) {
        const bool hasNan = raw.hasNaN();
        return fileError(path, where + " has " + (hasNan ? "a NaN" : "an infinite") + " coordinate " + formatVector(raw));
      }
      const Eigen::Vector3d position = linear * raw + translation;
      if (!position.allFinite() || position.cwiseAbs().maxCoeff() > kMaxMeshCoordinate)
        return fileError(path, where + " is at " + formatVector(position) + ", beyond 1e12 m: not a plausible mesh");
      const Vector3Key key{bitsOf(position.x()), bitsOf(position.y()), bitsOf(position.z())};
      const auto [it, inserted] = positionIndex.try_emplace(key, static_cast<int>(result.positions.size()));
      if (inserted) result.positions.push_back(position);
      localToPosition[v] = it->second;
      if (everyTriangleHasUv) {
        const aiVector3D& t = mesh.mTextureCoords[0][v];
        const Eigen::Vector2d uv(t.x, t.y);
        if (!uv.allFinite()) return fileError(path, "texture coordinate of " + where + " is not finite");
        const Vector3Key uvKey{bitsOf(uv.x()), bitsOf(uv.y()), 0};
        const auto [uvIt, uvInserted] = uvIndex.try_emplace(uvKey, static_cast<int>(result.uv.uvs.size()));
        if (uvInserted) result.uv.uvs.push_back(uv);
        localToUv[v] = uvIt->second;
      }
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      unsigned corner[3] = {face.mIndices[0], face.mIndices[1], face.mIndices[2]};
      if (corner[0] >= mesh.mNumVertices || corner[1] >= mesh.mNumVertices || corner[2] >= mesh.mNumVertices)
        return fileError(path, "face " + std::to_string(f) + " of mesh " + std::to_string(m) + " indexes a missing vertex");
      if (mirrored) std::swap(corner[1], corner[2]);
      result.triangles.emplace_back(localToPosition[corner[0]], localToPosition[corner[1]], localToPosition[corner[2]]);
      if (everyTriangleHasUv)
        result.uv.uvTriangles.emplace_back(localToUv[corner[0]], localToUv[corner[1]], localToUv[corner[2]]);
    }
  }
  return result;
}

/// Why assimp must not be given these bytes (PlyGuard.hpp, OffGuard.hpp), or nothing. `bytes`:
/// the whole file for a PLY, at least its head otherwise; `extension`: the file's, or the format
/// hint, without the dot.
std::optional<std::string> readerTrap(std::string_view bytes, std::size_t size, const std::string& extension) {
  if (std::optional<std::string> trap = detail::plyTrap(bytes, size)) return trap;
  return detail::offTrap(bytes, size, detail::lowered(extension) == "off");
}

/// assimp exporter id for a file extension (with the dot, any case).
std::string exportFormatFor(const std::string& anyCase) {
  const std::string extension = detail::lowered(anyCase);
  if (extension == ".obj") return "obj";
  if (extension == ".gltf") return "gltf2";
  if (extension == ".glb") return "glb2";
  if (extension == ".ply") return "ply";
  if (extension == ".stl") return "stlb";
  return {};
}

// No aiProcess_FindDegenerates / FindInvalidData: degenerate triangles and bad values must reach
// the validator and the checks in convertScene instead of being silently dropped or patched.
constexpr unsigned kPostProcessFlags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType;

/// Reads `file` through the importer's file system, then post-processes it. The two are split
/// because Debian's assimp 5.2 is built with its assertions on, and its triangulation asserts
/// (aborting the process) when a mesh's primitive-type flags do not match its faces, as the PLY
/// reader leaves them after failing to parse a face (it keeps the face with no corners; found by
/// fuzz_mesh). In between, such a face is refused and the flags are recomputed from the faces.
/// Errors name `shownName` (the caller's name for an in-memory file).
Expected<const aiScene*> importScene(Assimp::Importer& importer, const std::string& file, const std::string& shownName) {
  const aiScene* read = importer.ReadFile(file, aiProcess_ValidateDataStructure);
  if (read == nullptr) return fileError(shownName, "not a readable mesh: " + oneLine(importer.GetErrorString()));
  // The importer owns the scene and hands it out read-only; it is not a const object.
  aiScene& scene = const_cast<aiScene&>(*read);
  for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
    aiMesh* mesh = scene.mMeshes[m];
    if (mesh == nullptr) continue;
    unsigned types = 0;
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const unsigned corners = mesh->mFaces[f].mNumIndices;
      if (corners == 0)
        return fileError(shownName, "face " + std::to_string(f) + " of mesh " + std::to_string(m) +
                                   " has no corners (a face record the reader could not parse)");
      types |= corners == 1   ? unsigned(aiPrimitiveType_POINT)
               : corners == 2 ? unsigned(aiPrimitiveType_LINE)
               : corners == 3 ? unsigned(aiPrimitiveType_TRIANGLE)
                              : unsigned(aiPrimitiveType_POLYGON);
    }
    mesh->mPrimitiveTypes = types;
  }
  const aiScene* processed = importer.ApplyPostProcessing(kPostProcessFlags);
  if (processed == nullptr) return fileError(shownName, "not a readable mesh: " + oneLine(importer.GetErrorString()));
  return processed;
}

}  // namespace

Expected<Mesh> loadMesh(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) return fileError(path, "file not found");
  if (fs::is_directory(status)) return fileError(path, "is a directory, not a mesh file");
  const std::uintmax_t size = fs::file_size(path, error);
  if (error) return fileError(path, "cannot read the file size (" + error.message() + ")");
  if (size == 0) return fileError(path, "file is empty");
  if (size > kMaxMeshFileBytes)
    return fileError(path, "file of " + std::to_string(size) + " bytes exceeds the " +
                               std::to_string(kMaxMeshFileBytes) + "-byte limit");
  std::ifstream file(path, std::ios::binary);
  if (!file.good()) return fileError(path, "file cannot be opened for reading");
  // What assimp's PLY reader cannot be given is refused first (PlyGuard.hpp), from the whole file
  // (its list counts are in the body); other formats need only the head.
  std::string head(static_cast<std::size_t>(std::min<std::uintmax_t>(size, detail::kPlyHeadBytes)), '\0');
  file.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(file.gcount(), 0)));
  if (detail::isPly(head) && head.size() < size) {
    const std::size_t have = head.size();
    head.resize(static_cast<std::size_t>(size));
    file.read(head.data() + have, static_cast<std::streamsize>(head.size() - have));
    head.resize(have + static_cast<std::size_t>(std::max<std::streamsize>(file.gcount(), 0)));
  }
  const std::string extension = fs::path(path).extension().string();
  if (const std::optional<std::string> trap =
          readerTrap(head, static_cast<std::size_t>(size), extension.empty() ? extension : extension.substr(1)))
    return fileError(path, *trap);

  Assimp::Importer importer;
  importer.SetIOHandler(detail::MeshImportFileSystem::onDisk().release());  // the importer owns it
  const Expected<const aiScene*> scene = importScene(importer, path, path);
  if (!scene) return scene.error();
  return convertScene(**scene, path);
}

Expected<Mesh> loadMeshFromMemory(const void* bytes, std::size_t size, const std::string& formatHint,
                                  const std::string& name) {
  if (bytes == nullptr || size == 0) return fileError(name, "file is empty");
  if (size > kMaxMeshFileBytes)
    return fileError(name, "file of " + std::to_string(size) + " bytes exceeds the " +
                               std::to_string(kMaxMeshFileBytes) + "-byte limit");
  // The hint becomes the extension of assimp's in-memory file name: letters and digits only.
  const bool hintIsExtension = formatHint.size() <= 16 && std::all_of(formatHint.begin(), formatHint.end(), [](char c) {
                                 return std::isalnum(static_cast<unsigned char>(c)) != 0;
                               });
  if (!hintIsExtension)
    return fileError(name, "format hint '" + formatHint + "' is not a file extension without the dot");
  if (const std::optional<std::string> trap = readerTrap(std::string_view(static_cast<const char*>(bytes), size), size, formatHint))
    return fileError(name, *trap);
  // Not ReadFileFromMemory: its file system serves the mesh bytes as the OBJ reader's material
  // library too (see MeshImportFileSystem.hpp). Without a hint, assimp detects the format.
  const std::string memoryName = formatHint.empty() ? std::string("mesh") : "mesh." + formatHint;
  Assimp::Importer importer;
  importer.SetIOHandler(detail::MeshImportFileSystem::inMemory(bytes, size, memoryName).release());  // owned
  const Expected<const aiScene*> scene = importScene(importer, memoryName, name);
  if (!scene) return scene.error();
  return convertScene(**scene, name);
}

Expected<UpAxis> upAxisFromName(std::string_view name) {
  const std::string lower = detail::lowered(std::string(name));
  if (lower == "y") return UpAxis::Y;
  if (lower == "z") return UpAxis::Z;
  return Error{"up axis '" + std::string(name) + "' is not y or z"};
}

Status MeshLoadSettings::validate() const {
  if (!(std::isfinite(scale) && scale > 0.0))
    return Error{"scale " + std::to_string(scale) + " must be a finite number > 0 (metres per file unit)"};
  if (up != UpAxis::Y && up != UpAxis::Z) return Error{"up axis must be y or z"};
  return repair.validate();
}

Status toHydrotexFrame(Mesh& mesh, const MeshLoadSettings& settings) {
  const std::string name = mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName;
  if (Status valid = settings.validate(); !valid) return Error{name + ": " + valid.error().message};
  for (Eigen::Vector3d& p : mesh.positions) {
    // z up -> y up: the file's +z becomes +y and its +y becomes -z (right-handed, det = +1).
    if (settings.up == UpAxis::Z) p = Eigen::Vector3d(p.x(), p.z(), -p.y());
    p *= settings.scale;
    if (!(p.cwiseAbs().maxCoeff() <= kMaxMeshCoordinate))
      return Error{name + ": a vertex lies beyond 1e12 m after scaling by " + std::to_string(settings.scale)};
  }
  return Ok{};
}

Expected<Mesh> loadMesh(const std::string& path, const MeshLoadSettings& settings, RepairReport* repairs) {
  if (Status valid = settings.validate(); !valid) return Error{path + ": " + valid.error().message};
  Expected<Mesh> mesh = loadMesh(path);
  if (!mesh) return mesh;
  if (Status framed = toHydrotexFrame(*mesh, settings); !framed) return framed.error();
  Expected<RepairReport> repaired = repairMesh(*mesh, settings.repair);
  if (!repaired) return Error{path + ": " + repaired.error().message};
  if (repairs != nullptr) *repairs = std::move(repaired).value();
  return mesh;
}

Status saveMesh(const Mesh& mesh, const std::string& path) {
  const std::string format = exportFormatFor(std::filesystem::path(path).extension().string());
  if (format.empty()) return fileError(path, "unknown mesh extension (use .obj, .gltf, .glb, .ply or .stl)");
  if (mesh.triangles.empty()) return fileError(path, "mesh '" + mesh.sourceName + "' has no triangles to write");
  const int positionCount = static_cast<int>(mesh.positions.size());
  const bool withUv = mesh.hasUvs();
  const int uvCount = static_cast<int>(mesh.uv.uvs.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const int p = mesh.triangles[t][c];
      if (p < 0 || p >= positionCount)
        return fileError(path, "triangle " + std::to_string(t) + " indexes missing vertex " + std::to_string(p));
      if (withUv && (mesh.uv.uvTriangles[t][c] < 0 || mesh.uv.uvTriangles[t][c] >= uvCount))
        return fileError(path, "UV triangle " + std::to_string(t) + " indexes a missing texture coordinate");
    }
  }

  // assimp meshes carry one attribute set per vertex, so a vertex is a (position, uv) pair.
  std::unordered_map<std::uint64_t, unsigned> cornerVertex;
  std::vector<std::pair<int, int>> vertices;
  std::vector<unsigned> indices;
  indices.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const int p = mesh.triangles[t][c];
      const int u = withUv ? mesh.uv.uvTriangles[t][c] : 0;
      const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(p)) << 32) |
                                static_cast<std::uint32_t>(u);
      const auto [it, inserted] = cornerVertex.try_emplace(key, static_cast<unsigned>(vertices.size()));
      if (inserted) vertices.emplace_back(p, u);
      indices.push_back(it->second);
    }
  }

  auto scene = std::make_unique<aiScene>();
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial*[1]{new aiMaterial()};
  scene->mNumMeshes = 1;
  scene->mMeshes = new aiMesh*[1]{new aiMesh()};
  scene->mRootNode = new aiNode("root");
  scene->mRootNode->mNumMeshes = 1;
  scene->mRootNode->mMeshes = new unsigned[1]{0};

  aiMesh& out = *scene->mMeshes[0];
  out.mName = aiString(mesh.sourceName.empty() ? std::string("mesh") : mesh.sourceName);
  out.mMaterialIndex = 0;
  out.mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  out.mNumVertices = static_cast<unsigned>(vertices.size());
  out.mVertices = new aiVector3D[vertices.size()];
  if (withUv) {
    out.mTextureCoords[0] = new aiVector3D[vertices.size()];
    out.mNumUVComponents[0] = 2;
  }
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const Eigen::Vector3d& p = mesh.positions[static_cast<std::size_t>(vertices[v].first)];
    out.mVertices[v] = aiVector3D(static_cast<ai_real>(p.x()), static_cast<ai_real>(p.y()), static_cast<ai_real>(p.z()));
    if (withUv) {
      const Eigen::Vector2d& uv = mesh.uv.uvs[static_cast<std::size_t>(vertices[v].second)];
      out.mTextureCoords[0][v] = aiVector3D(static_cast<ai_real>(uv.x()), static_cast<ai_real>(uv.y()), 0);
    }
  }
  out.mNumFaces = static_cast<unsigned>(mesh.triangles.size());
  out.mFaces = new aiFace[mesh.triangles.size()];
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    aiFace& face = out.mFaces[t];
    face.mNumIndices = 3;
    face.mIndices = new unsigned[3]{indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
  }

  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), format, path) != aiReturn_SUCCESS)
    return fileError(path, "cannot write: " + oneLine(exporter.GetErrorString()));
  return Ok{};
}

}  // namespace hydrotex
