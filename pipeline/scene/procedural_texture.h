#pragma once
// Procedural textures for built-in scenes: checkerboard, grid, value noise, a sky cube's faces. A
// texture source string "procedural:KIND?key=value&..." names one exactly, so traces can record it.
#include <string>

#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

// A parsed "procedural:KIND?key=value&..." source. Keys (all optional):
//   size (texels, square, default 256), cells (checker/grid cells per side, default 8),
//   line (grid line width in texels, default 2), seed and octaves (noise), format (rgba8|rgba32f),
//   face (sky: the cube face 0..5 in Vulkan's order +X −X +Y −Y +Z −Z; cells: the ground's
//   longitude sectors).
struct ProceduralSpec {
  std::string kind;  // checker, grid, noise or sky (one face of a sky cube)
  int size = 256, cells = 8, line = 2, seed = 1, octaves = 5, face = 0;
  int rows = 256;  // texel rows (1..size; the square's first rows): size × rows texels
  TexelFormat format = TexelFormat::Rgba8;
};

// Parses and checks a spec without building any texels (a scene checks its sources so).
// Throws InputError naming `where` and the bad key on a malformed spec.
ProceduralSpec parse_procedural_source(const std::string& source, const std::string& where);

// Parses and builds e.g. "procedural:checker?size=512&cells=16"; errors as above.
Texture make_procedural_texture(const std::string& source, const std::string& where);

bool is_procedural_source(const std::string& source);

}  // namespace texsim
