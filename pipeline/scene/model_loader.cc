#include "pipeline/scene/model_loader.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <exception>
#include <filesystem>
#include <functional>
#include <new>

#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "pipeline/scene/isolated_child.h"
#include "pipeline/scene/model_stream.h"

namespace texsim {

namespace {

// Assimp's file access with texsim's checks: a file that is there but is not regular or is over
// the limit is not opened (the error is kept and thrown after Assimp returns, as Assimp would
// otherwise report only "cannot open"). `allow_disk` false: nothing is opened (a model in memory).
// The files opened are kept: a child process's inputs become its parent's (model_stream.h).
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
      note_opened(file);
    } catch (const InputError&) {
      if (!error) error = std::current_exception();
      return nullptr;
    }
    return Assimp::DefaultIOSystem::Open(file, mode);
  }
  std::exception_ptr error;
  std::vector<std::string> opened;

 private:
  void note_opened(const std::string& file) {
    if (std::find(opened.begin(), opened.end(), file) != opened.end()) return;
    if (file.size() > kMaxModelPathBytes)
      throw InputError(file, "a path longer than " + std::to_string(kMaxModelPathBytes) + " bytes");
    if (opened.size() >= kMaxModelOpenedFiles) {
      throw InputError(file, "the model opens more than " + std::to_string(kMaxModelOpenedFiles) +
                                 " files, the limit");
    }
    opened.push_back(file);
  }
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

// The file's materials, each name and diffuse texture within the limits.
std::vector<ModelMaterial> read_materials(const aiScene& sc, const std::string& file,
                                          const std::string& dir) {
  if (sc.mNumMaterials > kMaxModelMaterials)
    throw InputError(file, count_text(sc.mNumMaterials) + " materials, over the limit of " +
                               count_text(kMaxModelMaterials));
  std::vector<ModelMaterial> out;
  for (unsigned i = 0; i < sc.mNumMaterials; ++i) {
    ModelMaterial mm;
    aiString s;
    if (sc.mMaterials[i]->Get(AI_MATKEY_NAME, s) == AI_SUCCESS) mm.name = s.C_Str();
    if (sc.mMaterials[i]->GetTexture(aiTextureType_DIFFUSE, 0, &s) == AI_SUCCESS && s.length > 0 &&
        s.C_Str()[0] != '*') {  // "*N": embedded, not a file
      std::filesystem::path p(s.C_Str());
      mm.texture = (p.is_absolute() || dir.empty() ? p : std::filesystem::path(dir) / p).string();
    }
    if (mm.name.size() > kMaxModelNameBytes || mm.texture.size() > kMaxModelPathBytes)
      throw InputError(file, "material " + count_text(i) + ": a name over " +
                                 count_text(kMaxModelNameBytes) + " bytes or a texture path over " +
                                 count_text(kMaxModelPathBytes));
    out.push_back(std::move(mm));
  }
  if (out.empty()) out.push_back({});
  return out;
}

Model convert(const aiScene& sc, const std::string& file, const std::string& dir,
              const MeshBudget& budget) {
  uint64_t vertices = 0, triangles = 0;
  for (unsigned m = 0; m < sc.mNumMeshes; ++m) {
    vertices += sc.mMeshes[m]->mNumVertices;
    triangles += sc.mMeshes[m]->mNumFaces;
  }
  check_model_counts(vertices, triangles, file, budget);
  Model out;
  out.mesh.source = file;
  out.mesh.has_uvs = true;
  out.materials = read_materials(sc, file, dir);
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
        // Without coordinates, zero (glm leaves them undefined): a projection replaces them.
        t.uv[c] = uv != nullptr ? glm::dvec2(uv[idx].x, uv[idx].y) : glm::dvec2(0.0);
      }
      out.mesh.triangles.push_back(t);
      out.triangle_material.push_back(mat);
    }
  }
  if (out.mesh.triangles.empty()) throw InputError(file, "the model has no triangles");
  return out;
}

std::string assimp_error(const Assimp::Importer& imp) {
  std::string e = imp.GetErrorString();
  if (e.size() > 1024) e = e.substr(0, 1024) + "…";  // it may quote the file
  return e.empty() ? "Assimp cannot read it as a model" : "not a model Assimp reads: " + e;
}

const char* const kImporter = "the model importer (Assimp)";

Model import_file(const std::string& file, const std::string& dir, const MeshBudget& budget,
                  std::vector<std::string>* opened) {
  Assimp::Importer imp;
  configure(imp);
  auto* io = new CheckedIoSystem(true);  // the importer owns it
  imp.SetIOHandler(io);
  const aiScene* sc = imp.ReadFile(file, kImportFlags);
  if (io->error) std::rethrow_exception(io->error);
  if (sc == nullptr) throw InputError(file, assimp_error(imp));
  if (opened != nullptr) *opened = io->opened;
  return convert(*sc, file, dir, budget);
}

Model import_bytes(const std::string& bytes, const std::string& hint, const std::string& file,
                   const MeshBudget& budget) {
  Assimp::Importer imp;
  configure(imp);
  imp.SetIOHandler(new CheckedIoSystem(false));
  const aiScene* sc =
      imp.ReadFileFromMemory(bytes.data(), bytes.size(), kImportFlags, hint.c_str());
  if (sc == nullptr) throw InputError(file, assimp_error(imp));
  return convert(*sc, file, "", budget);
}

// The child's error as the InputError it was: its message is "WHERE: WHAT", and splitting it at
// any ": " rebuilds the same text.
[[noreturn]] void throw_message(const std::string& message, const std::string& file) {
  const size_t k = message.find(": ");
  if (k == std::string::npos) throw InputError(file, message);
  throw InputError(message.substr(0, k), message.substr(k + 2));
}

// `import` (Assimp and the conversion) in a child process; its inputs become this process's.
Model import_isolated(const std::string& file, const MeshBudget& budget,
                      const std::function<Model(std::vector<std::string>*)>& import) {
  ModelMessage got;
  run_isolated(
      file, kImporter,
      [&](ByteSink& out) {
        ModelMessage m;
        try {
          m.model = import(&m.opened);
        } catch (const InputError& e) {
          m.failed = true;
          m.error = e.what();
        } catch (const std::bad_alloc&) {
          m.failed = true;
          m.error = file + ": " + kImporter +
                    " ran out of memory (its limit: " + count_text(kModelImportMemory >> 20) +
                    " MiB over texsim's own)";
        }
        write_model_message(out, m);
      },
      [&](ByteSource& in) {
        got = read_model_message(in, file, kImporter, budget);
        if (got.failed) throw_message(got.error, file);
      },
      ChildLimits{kModelImportTimeoutMs, kModelImportMemory});
  for (const std::string& f : got.opened) (void)check_input_file(f, "model file", kMaxModelBytes);
  got.model.mesh.source = file;
  return std::move(got.model);
}

}  // namespace

void check_model_counts(uint64_t vertices, uint64_t triangles, const std::string& file,
                        const MeshBudget& budget) {
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
}

Model load_model(const std::string& path, const std::string& base_dir, const MeshBudget& budget,
                 ImportIn where) {
  std::filesystem::path p(path);
  if (!p.is_absolute() && !base_dir.empty()) p = std::filesystem::path(base_dir) / p;
  const std::string file = p.string();
  (void)check_input_file(file, "model file", kMaxModelBytes);
  const std::string dir = p.parent_path().string();
  if (where == ImportIn::ThisProcess) return import_file(file, dir, budget, nullptr);
  return import_isolated(file, budget, [&](std::vector<std::string>* opened) {
    return import_file(file, dir, budget, opened);
  });
}

Model parse_model(const std::string& bytes, const std::string& hint, const std::string& file,
                  const MeshBudget& budget, ImportIn where) {
  if (bytes.size() > kMaxModelBytes) throw InputError(file, "over the size limit");
  if (where == ImportIn::ThisProcess) return import_bytes(bytes, hint, file, budget);
  return import_isolated(file, budget, [&](std::vector<std::string>*) {
    return import_bytes(bytes, hint, file, budget);
  });
}

}  // namespace texsim
