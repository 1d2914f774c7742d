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

// Resolves `source` against `base_dir` as load_texture does.
std::string resolve_texture_path(const std::string& source, const std::string& base_dir);

}  // namespace texsim
