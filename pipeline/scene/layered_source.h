#pragma once
// A layered texture's source as one string, so a trace's texture table can record it as it
// records a file or a procedural spec: "layered:TYPE;SLICE;SLICE;...", TYPE one of cube,
// cube_array, 1d_array, 2d_array, 3d (a volume's z-slices, z = 0 first) and each SLICE a file
// path or procedural spec (a cube's faces
// in Vulkan's order +X −X +Y −Y +Z −Z; docs/texture-types.md). A scene writes it from the
// texture's `type` and `faces` or `layers` (docs/scenes.md).
#include <cstdint>
#include <string>
#include <vector>

namespace texsim {

// `type = "…"` of a scene texture: a 2-D image, or a layered texture of slices (a 3-D texture's
// are its depth slices).
enum class SceneTextureType : uint8_t { Tex2D, Cube, CubeArray, Array1D, Array2D, Volume3D };
const char* to_string(SceneTextureType t);

struct LayeredSource {
  SceneTextureType type = SceneTextureType::Cube;
  std::vector<std::string> slices;
};

// Largest number of slices (Vulkan's maxImageArrayLayers on common devices).
inline constexpr int kMaxTextureSlices = 2048;

bool is_layered_source(const std::string& source);
std::string layered_source(const LayeredSource& s);
// Parses "layered:…"; throws InputError(where, …) on an unknown type, an empty slice, a slice
// count the type does not allow (cube: 6; cube_array: a multiple of 6; arrays, 3d: at least 1;
// all at most kMaxTextureSlices) or a malformed procedural slice.
LayeredSource parse_layered_source(const std::string& source, const std::string& where);

}  // namespace texsim
