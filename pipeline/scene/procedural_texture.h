#pragma once
// Procedural textures for built-in scenes: checkerboard, grid, value noise. A texture source
// string "procedural:KIND?key=value&..." names one exactly, so traces can record it.
#include <string>

#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

// Parses and builds e.g. "procedural:checker?size=512&cells=16". Keys (all optional):
//   size (texels, square, default 256), cells (checker/grid cells per side, default 8),
//   line (grid line width in texels, default 2), seed and octaves (noise), format (rgba8|rgba32f).
// Throws InputError naming `where` and the bad key on a malformed spec.
Texture make_procedural_texture(const std::string& source, const std::string& where);

bool is_procedural_source(const std::string& source);

}  // namespace texsim
