#pragma once
// 3-D models through the packaged Assimp (glTF 2.0, 3DS, OBJ+MTL, MD3 and whatever else it
// reads): one texsim Mesh of triangles with the file's materials. Every file Assimp opens (the
// model, an OBJ's MTL, a glTF's buffers) goes through check_input_file first — a regular file
// within kMaxModelBytes — so a directory, FIFO or huge file is refused before Assimp reads it.
// Assimp triangulates, joins identical vertices and applies the node transforms
// (aiProcess_PreTransformVertices); points and lines are dropped. Texture coordinates are
// flipped to texsim's convention (v = 0 on the image's first row); Assimp's own is v = 0 on
// the last. Assimp runs in a child process (isolated_child.h) that sends the converted model
// back (model_stream.h): a file on which Assimp crashes, hangs or runs out of memory is an
// InputError naming it. docs/cli.md#input-limits lists the limits below.
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/scene/mesh.h"
#include "pipeline/scene/obj_loader.h"

namespace texsim {

inline constexpr uint64_t kMaxModelBytes = uint64_t{64} << 20;  // every file of a model
inline constexpr uint64_t kMaxModelVertices = uint64_t{1} << 22;
inline constexpr uint64_t kMaxModelTriangles = uint64_t{1} << 22;
inline constexpr double kMaxModelCoordinate = 1e12;  // |x|, |y|, |z| of a vertex
inline constexpr double kMaxModelTexcoord = 1e6;     // |u|, |v|
inline constexpr uint64_t kMaxModelMaterials = 4096;
inline constexpr uint64_t kMaxModelNameBytes = 1024;  // a material's name (Assimp's own cap)
inline constexpr uint64_t kMaxModelPathBytes = 4096;  // a texture's path (PATH_MAX)
// The child process of an import: its time, and its address space over texsim's.
inline constexpr int kModelImportTimeoutMs = 30'000;
inline constexpr uint64_t kModelImportMemory = uint64_t{4} << 30;

struct ModelMaterial {
  std::string name;     // the file's name for it (may be empty)
  std::string texture;  // its first diffuse texture, resolved against the model's directory;
                        // empty when it has none (or an embedded one, which texsim skips)
};

struct Model {
  Mesh mesh;  // mesh.has_uvs: every corner has a texture coordinate from the file
  std::vector<ModelMaterial> materials;
  std::vector<int> triangle_material;  // per mesh.triangles entry: index into materials
};

// Where Assimp runs: in a child process (texsim's way), or in this one (the child itself, and
// the fuzz harness, which compares the two).
enum class ImportIn { Child, ThisProcess };

// `path` relative to `base_dir` unless absolute. Throws InputError "FILE: what" (Assimp's own
// message when it cannot read the file), ChildFailure (an InputError) when the import crashed,
// timed out or sent malformed data.
Model load_model(const std::string& path, const std::string& base_dir,
                 const MeshBudget& budget = {}, ImportIn where = ImportIn::Child);
// The same from bytes in memory (`hint`: the format's file extension, e.g. "obj", "3ds"):
// the fuzz harness's entry. Files it refers to are not opened.
Model parse_model(const std::string& bytes, const std::string& hint, const std::string& file,
                  const MeshBudget& budget = {}, ImportIn where = ImportIn::Child);

// Throws InputError "FILE: …" when a model of these counts is over the limits above or
// `budget` (no triangles, too many vertices or triangles, too much memory). Both ends of the
// import check them: the child before it copies Assimp's data, the parent before it reads.
void check_model_counts(uint64_t vertices, uint64_t triangles, const std::string& file,
                        const MeshBudget& budget);

}  // namespace texsim
