#pragma once
// The benchmarks' grazing checkerboard floor: a 1024² procedural checker (with its mips) on a
// 200 × 200 plane seen from 1 unit above it, its texture loaded and its fragments generated
// once, in memory (bench_texture_unit, bench_scene_assembly, bench_peers).
#include <string>
#include <vector>

#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

struct BenchFloor {
  Scene scene;
  TextureSet textures;
  std::vector<Fragment> frags;
};

// The floor at width × height pixels; `material_keys` are extra lines of the floor's material
// table (e.g. "filter = { mode = \"bilinear\" }\n"), empty for its defaults.
inline BenchFloor make_bench_floor(int width, int height, const std::string& material_keys = "") {
  const std::string text =
      "[output]\nwidth = " + std::to_string(width) + "\nheight = " + std::to_string(height) +
      "\n[camera]\nposition = [0.0, 1.0, 0.0]\nlook_at = [0.0, 0.3, -10.0]\n"
      "[textures.checker]\nsource = \"procedural:checker?size=1024&cells=32\"\n"
      "[materials.floor]\ntexture = \"checker\"\n" +
      material_keys +
      "[[planes]]\nmaterial = \"floor\"\norigin = [-100.0, 0.0, -0.5]\n"
      "edge_u = [200.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, -200.0]\n"
      "uv_scale = [40.0, 40.0]\n";
  BenchFloor f{parse_scene(text, "bench", ""), {}, {}};
  f.textures.add(load_texture(f.scene.textures[0].source, ""));
  f.frags = generate_fragments(f.scene);
  return f;
}

}  // namespace texsim
