#pragma once
// Loads textures from any format OpenImageIO reads (PNG, JPEG, EXR, TIFF, mip-mapped .tx),
// or from a procedural source string.
#include <string>

#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/scene/scene.h"

namespace texsim {

enum class TexelFormatChoice { Auto, Rgba8, Rgba32f };

// `source` is a file path (relative paths resolve against `base_dir`) or "procedural:...".
// A file with a MIP chain (.tx from maketx) keeps its own levels; otherwise the pyramid is
// built. Auto picks Rgba8 for 8-bit files and Rgba32f for anything wider. Values are used as
// stored (no colour-space conversion). Throws InputError naming the file on any problem.
Texture load_texture(const std::string& source, const std::string& base_dir,
                     TexelFormatChoice format = TexelFormatChoice::Auto);

// Loads texture `index` of `scene` as load_texture does; an InputError then starts with the
// scene file and the line:column of the texture's source (SceneTexture::where).
Texture load_scene_texture(const Scene& scene, size_t index,
                           TexelFormatChoice format = TexelFormatChoice::Auto);

// `loaded` stored as `t` says: converted to t.format, encoded as t.compress (an encoder's
// InputError then starts with t.compress->where when it is set), or kept as loaded.
Texture store_texture(Texture loaded, const SceneTexture& t);

// A texture's storage as one line of text, the form a trace's texture table records
// (traces/FORMAT.md, "Texture table"): "" (as loaded), "format=NAME" or
// "compress=FORMAT,ENCODER[,QUALITY]" (the encoder as resolved, the quality when given).
std::string texture_storage_spec(const SceneTexture& t);
// Sets t.format and t.compress from such a spec (the encoder may be left out: the format's
// default, as in a scene). Throws InputError(where, ...) for an unknown kind, format, encoder
// or quality, with the same rules as a scene's `format` and `compress` keys.
void set_texture_storage(SceneTexture& t, const std::string& spec, const std::string& where);

// Resolves `source` against `base_dir` as load_texture does.
std::string resolve_texture_path(const std::string& source, const std::string& base_dir);

}  // namespace texsim
