#include "pipeline/scene/model_loader.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <exception>
#include <filesystem>

#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"

namespace texsim {

namespace {

// Assimp's file access with texsim's checks: a file that is there but is not regular or is over
// the limit is not opened (the error is kept and thrown after Assimp returns, as Assimp would
// otherwise report only "cannot open"). `allow_disk` false: nothing is opened (a model in memory).
class CheckedIoSystem : public Assimp::DefaultIOSystem {
 public:
  explicit CheckedIoSystem(bool allow_disk) : allow_disk_(allow_disk) {}
  // Assimp's own Exists opens the file, which blocks on a FIFO: stat it instead.
  bool Exists(const char* file) const override {
    std::error_code ec;
    return allow_disk_ && std::filesystem::exists(file, ec);
  }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (!allow_disk_ || mode == nullptr || mode[0] != 'r') return nullptr;
    // A file that is not there is Assimp's to judge: formats probe optional files (an MD3's
    // shader scripts and skins).
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) return nullptr;
    try {
      (void)check_input_file(file, "model file", kMaxModelBytes);
    } catch (const InputError&) {
      if (!error) error = std::current_exception();
      return nullptr;
    }
    return Assimp::DefaultIOSystem::Open(file, mode);
  }
  std::exception_ptr error;

 private:
  bool allow_disk_;
};

constexpr unsigned kImportFlags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_SortByPType | aiProcess_PreTransformVertices |
                                  aiProcess_FlipUVs | aiProcess_ValidateDataStructure;

void configure(Assimp::Importer& imp) {
  imp.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // MD3: the one file named, not the player's other parts found beside it.
  imp.SetPropertyBool(AI_CONFIG_IMPORT_MD3_HANDLE_MULTIPART, false);
}

std::string count_text(uint64_t n) { return std::to_string(n); }

Model convert(const aiScene& sc, const std::string& file, const std::string& dir,
              const MeshBudget& budget) {
  uint64_t vertices = 0, triangles = 0;
  for (unsigned m = 0; m < sc.mNumMeshes; ++m) {
    vertices += sc.mMeshes[m]->mNumVertices;
    triangles += sc.mMeshes[m]->mNumFaces;
  }
  if (triangles == 0) throw InputError(file, "the model has no triangles");
  if (vertices > kMaxModelVertices)
    throw InputError(file, count_text(vertices) + " vertices, over the limit of " +
                               count_text(kMaxModelVertices));
  if (triangles > kMaxModelTriangles || triangles > budget.max_triangles)
    throw InputError(file, count_text(triangles) + " triangles, over the limit of " +
                               count_text(std::min(kMaxModelTriangles, budget.max_triangles)) +
                               " (with the scene's faces before it)");
  const uint64_t bytes = mesh_bytes(vertices, 3 * triangles, triangles, budget);
  if (bytes > budget.max_bytes)
    throw InputError(file, "the model would take an estimated " + count_text(bytes >> 20) +
                               " MiB, over the memory limit (--max-memory) with the faces "
                               "before it");
  Model out;
  out.mesh.source = file;
  out.mesh.has_uvs = true;
  for (unsigned i = 0; i < sc.mNumMaterials; ++i) {
    ModelMaterial mm;
    aiString s;
    if (sc.mMaterials[i]->Get(AI_MATKEY_NAME, s) == AI_SUCCESS) mm.name = s.C_Str();
    if (sc.mMaterials[i]->GetTexture(aiTextureType_DIFFUSE, 0, &s) == AI_SUCCESS && s.length > 0 &&
        s.C_Str()[0] != '*') {  // "*N": embedded, not a file
      std::filesystem::path p(s.C_Str());
      mm.texture = (p.is_absolute() || dir.empty() ? p : std::filesystem::path(dir) / p).string();
    }
    out.materials.push_back(std::move(mm));
  }
  if (out.materials.empty()) out.materials.push_back({});
  out.mesh.positions.reserve(vertices);
  out.mesh.triangles.reserve(triangles);
  out.triangle_material.reserve(triangles);
  for (unsigned m = 0; m < sc.mNumMeshes; ++m) {
    const aiMesh& am = *sc.mMeshes[m];
    const auto base = static_cast<int>(out.mesh.positions.size());
    const aiVector3D* uv = am.mTextureCoords[0];
    if (uv == nullptr) out.mesh.has_uvs = false;
    for (unsigned v = 0; v < am.mNumVertices; ++v) {
      const glm::dvec3 p(am.mVertices[v].x, am.mVertices[v].y, am.mVertices[v].z);
      for (int k = 0; k < 3; ++k) {
        if (!(std::fabs(p[k]) <= kMaxModelCoordinate))
          throw InputError(file, "mesh " + std::to_string(m) + ", vertex " + std::to_string(v) +
                                     ": coordinate not finite or beyond ±1e12");
      }
      if (uv != nullptr &&
          !(std::fabs(uv[v].x) <= kMaxModelTexcoord && std::fabs(uv[v].y) <= kMaxModelTexcoord)) {
        throw InputError(file, "mesh " + std::to_string(m) + ", vertex " + std::to_string(v) +
                                   ": texture coordinate not finite or beyond ±1e6");
      }
      out.mesh.positions.push_back(p);
    }
    const int mat =
        am.mMaterialIndex < out.materials.size() ? static_cast<int>(am.mMaterialIndex) : 0;
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
      const aiFace& face = am.mFaces[f];
      if (face.mNumIndices != 3) continue;  // SortByPType removed the rest; be sure
      MeshTriangle t;
      for (int c = 0; c < 3; ++c) {
        const unsigned idx = face.mIndices[c];
        if (idx >= am.mNumVertices)
          throw InputError(file, "mesh " + std::to_string(m) + ", face " + std::to_string(f) +
                                     ": vertex index out of range");
        t.v[c] = base + static_cast<int>(idx);
        if (uv != nullptr) t.uv[c] = {uv[idx].x, uv[idx].y};
      }
      out.mesh.triangles.push_back(t);
      out.triangle_material.push_back(mat);
    }
  }
  if (out.mesh.triangles.empty()) throw InputError(file, "the model has no triangles");
  return out;
}

std::string assimp_error(const Assimp::Importer& imp) {
  const std::string e = imp.GetErrorString();
  return e.empty() ? "Assimp cannot read it as a model" : "not a model Assimp reads: " + e;
}

}  // namespace

Model load_model(const std::string& path, const std::string& base_dir, const MeshBudget& budget) {
  std::filesystem::path p(path);
  if (!p.is_absolute() && !base_dir.empty()) p = std::filesystem::path(base_dir) / p;
  const std::string file = p.string();
  (void)check_input_file(file, "model file", kMaxModelBytes);
  Assimp::Importer imp;
  configure(imp);
  auto* io = new CheckedIoSystem(true);  // the importer owns it
  imp.SetIOHandler(io);
  const aiScene* sc = imp.ReadFile(file, kImportFlags);
  if (io->error) std::rethrow_exception(io->error);
  if (sc == nullptr) throw InputError(file, assimp_error(imp));
  return convert(*sc, file, p.parent_path().string(), budget);
}

Model parse_model(const std::string& bytes, const std::string& hint, const std::string& file,
                  const MeshBudget& budget) {
  if (bytes.size() > kMaxModelBytes) throw InputError(file, "over the size limit");
  Assimp::Importer imp;
  configure(imp);
  imp.SetIOHandler(new CheckedIoSystem(false));
  const aiScene* sc =
      imp.ReadFileFromMemory(bytes.data(), bytes.size(), kImportFlags, hint.c_str());
  if (sc == nullptr) throw InputError(file, assimp_error(imp));
  return convert(*sc, file, "", budget);
}

}  // namespace texsim
