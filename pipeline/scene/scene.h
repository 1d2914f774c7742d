#pragma once
// Scene description (TOML, docs/scenes.md): output size, camera, textures, materials with the
// effects each needs, textured planes and meshes, pipeline/memory/technology configuration.
#include <toml++/toml.h>

#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "blocks/base/energy_table.h"
#include "blocks/base/tech_table.h"
#include "blocks/geometry/camera.h"
#include "blocks/texture/decode/compressed_format.h"
#include "blocks/texture/memory/storage_format.h"
#include "pipeline/scene/camera_path.h"
#include "pipeline/scene/layered_source.h"
#include "pipeline/scene/object_space_config.h"
#include "pipeline/scene/raster_order_config.h"

namespace texsim {

struct SceneTexture {
  std::string name;
  std::string source;  // file path (relative to the scene file) or "procedural:..."
  // "file:line:column: textures.NAME.source" of the source value: messages about the texture
  // (a bad procedural spec, a missing or unreadable file) start with it.
  std::string where;
  // `format = "…"`: the texture is stored in this format (converted when loaded); none: as
  // the file or procedural source gives it (RGBA8 or RGBA32F).
  std::optional<StorageFormat> format;
  // `compress = { format = "…", encoder = "…", quality = "…" }`: the texture is encoded into
  // blocks of a compressed format when loaded (docs/formats.md#block-compressed-formats).
  struct Compress {
    CompressedFormat format = CompressedFormat::Bc1Rgb;
    std::string encoder;  // "squish", "nvtt" or "astcenc"
    std::string quality;  // the encoder's own level names; empty: its default
    std::string where;    // "file:line:column: textures.NAME.compress"
  };
  std::optional<Compress> compress;
  // `type = "cube" | "cube_array" | "1d_array" | "2d_array"` with `faces` or `layers`: the
  // slices, written into `source` as one "layered:…" string (layered_source.h).
  SceneTextureType type = SceneTextureType::Tex2D;
};

// A `[samplers.NAME]` table (docs/scenes.md): sampler state a material names as its default
// and a trace record's `sampler` field picks (id 1 + its place in name order). Its keys are
// checked when the materials are built (SamplerSetup::from_toml).
struct SceneSampler {
  std::string name;
  const toml::table* table = nullptr;  // points into Scene::root
};

// A material's own error budget for `texsim tune` (docs/tune.md): `budget = { psnr = 35 }`
// (PSNR at least, dB) or `budget = { nmse = 0.002 }` (NMSE at most). `texsim run` ignores it.
struct MaterialBudget {
  std::string kind;  // "psnr" or "nmse"; empty: none (the tuner's --budget applies)
  double value = 0;
};

struct SceneMaterial {
  std::string name;
  MaterialBudget budget;
  int texture = 0;  // index into Scene::textures
  // The material's table in the parsed document (effect tables filter, lod, coords, ...);
  // points into Scene::root so messages keep their line:column.
  const toml::table* effects = nullptr;
  int line = 0, column = 0;  // where it is declared, for messages
  // Effect `object_space`: the material's polygons are drawn by the object-space pipeline.
  std::optional<ObjectSpaceConfig> object_space;
};

// A textured planar primitive: the points origin + a·edge_u + b·edge_v with a, b >= 0 and
// either a, b <= 1 (a parallelogram: a [[planes]] entry) or a + b <= 1 (a triangle: a face of a
// [[meshes]] entry), with texture coordinates (u, v) = uv_origin + a·uv_edge_u + b·uv_edge_v.
struct ScenePrimitive {
  enum class Shape : uint8_t { Parallelogram, Triangle };
  Shape shape = Shape::Parallelogram;
  int material = 0;
  glm::dvec3 origin{0, 0, 0}, edge_u{1, 0, 0}, edge_v{0, 0, -1};
  glm::dvec2 uv_origin{0, 0}, uv_edge_u{1, 0}, uv_edge_v{0, 1};
  // Back-face culling: not drawn when the camera sees the side edge_v × edge_u points to (a
  // mesh's faces wound counter-clockwise seen from outside face edge_u × edge_v outwards).
  bool cull_back = false;
  int mesh = -1;  // index into Scene::meshes; -1 for a [[planes]] entry
};

// A [[meshes]] or [[models]] entry: its faces are Scene::primitives[first, first + count).
struct SceneMesh {
  std::string source;  // file path as given, or "box" / "grid"
  bool model = false;  // a [[models]] entry (read through Assimp)
  std::string uv;      // "file", "planar", "box" or "spherical"
  int material = 0;
  size_t first = 0, count = 0;
  size_t vertices = 0;  // distinct positions, each transformed once by the geometry subsystem
};

// Which pixel the ground truth is ([reference] pixel): the pixel's square with uniform weight,
// or the Gaussian of EWA's pixel model. The ranking of filters depends on it (a box favours
// probe filters, a Gaussian EWA; docs/studies/study-filters.md).
enum class TruthPixel : uint8_t { Box, Gaussian };
const char* to_string(TruthPixel p);

struct Scene {
  std::string path;      // file the scene came from ("<built-in>" for the default)
  std::string base_dir;  // relative texture paths resolve here
  int width = 320, height = 240;
  glm::dvec3 background{0, 0, 0};
  Camera camera;  // its image is the output's width × height (with a path: frame 0's)
  // [camera] path: keys the camera moves through; [output] frames: how many frames a run
  // renders along it (1 without a path).
  std::vector<CameraKey> camera_path;
  int frames = 1;
  std::vector<SceneTexture> textures;
  std::vector<SceneMaterial> materials;
  std::vector<SceneSampler> samplers;  // in name order
  // [[planes]] first, in order, then every mesh's faces: a fragment's `prim` indexes this.
  std::vector<ScenePrimitive> primitives;
  std::vector<SceneMesh> meshes;
  // The ground truth's samples ([reference] samples): 0 adaptive ("auto"), else n×n per pixel.
  int reference_samples = 0;
  TruthPixel reference_pixel = TruthPixel::Box;
  // [reference] relief = "per_sample": every sample of a relief material's pixel is shifted
  // along its own view ray (the deformed footprint); "pixel_centre" (default): by the offset
  // found at the pixel's centre.
  bool reference_relief_per_sample = false;
  const toml::table* pipeline = nullptr;  // [pipeline] table (in root), or null
  RasterOrder raster;                     // [raster]: the order fragments are emitted in
  TechTable tech = TechTable::defaults();
  EnergyTable energy = EnergyTable::defaults();  // [tech.energy]
  std::shared_ptr<toml::table> root;             // the parsed document (keeps source positions)
  // Effect tables of the materials made from a [[models]] file's own materials (they have no
  // table in the document); SceneMaterial::effects points into them.
  std::vector<std::shared_ptr<const toml::table>> model_effects;
};

// The camera of frame k (0 <= k < s.frames): s.camera, or posed along the path at frame k's time.
Camera frame_camera(const Scene& s, int k);

// Parses a scene file; throws InputError "file:line:column: what" on syntax, type, range and
// reference errors (unknown texture or material names, unknown keys, malformed procedural
// texture specs). Texture files are not opened here (load_scene_texture does).
// `overrides`: "KEY=VALUE" changes applied to the document before it is read
// (scene_overrides.h).
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
Scene parse_scene(const std::string& text, const std::string& source_name,
                  const std::string& base_dir, const std::vector<std::string>& overrides = {});
// The built-in default scene (procedural textures), so `texsim run` needs no files.
Scene default_scene(const std::vector<std::string>& overrides = {});
const char* default_scene_text();

}  // namespace texsim
