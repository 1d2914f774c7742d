#include "pipeline/scene/layered_source.h"

#include "blocks/base/input_error.h"
#include "pipeline/scene/procedural_texture.h"

namespace texsim {

namespace {
constexpr const char* kPrefix = "layered:";
constexpr const char* kTypes[] = {"2d", "cube", "cube_array", "1d_array", "2d_array", "3d"};
}  // namespace

const char* to_string(SceneTextureType t) { return kTypes[static_cast<int>(t)]; }

bool is_layered_source(const std::string& source) { return source.rfind(kPrefix, 0) == 0; }

std::string layered_source(const LayeredSource& s) {
  std::string out = std::string(kPrefix) + to_string(s.type);
  for (const auto& slice : s.slices) out.append(";").append(slice);
  return out;
}

LayeredSource parse_layered_source(const std::string& source, const std::string& where) {
  if (!is_layered_source(source)) throw InputError(where, "not a layered texture: " + source);
  std::vector<std::string> parts;
  for (size_t at = std::string(kPrefix).size();;) {
    const size_t semi = source.find(';', at);
    parts.push_back(source.substr(at, semi == std::string::npos ? semi : semi - at));
    if (semi == std::string::npos) break;
    at = semi + 1;
  }
  LayeredSource s;
  bool known = false;
  for (int k = 1; k < 6; ++k) {
    if (parts[0] != kTypes[k]) continue;
    s.type = static_cast<SceneTextureType>(k);
    known = true;
  }
  const std::string bad = "layered texture '" + source + "': ";
  if (!known) {
    throw InputError(where, bad + "unknown type '" + parts[0] +
                                "' (one of cube, cube_array, 1d_array, 2d_array, 3d)");
  }
  s.slices.assign(parts.begin() + 1, parts.end());
  const auto n = static_cast<int>(s.slices.size());
  if (s.type == SceneTextureType::Cube && n != 6)
    throw InputError(where, bad + "a cube has 6 faces, not " + std::to_string(n));
  if (s.type == SceneTextureType::CubeArray && (n == 0 || n % 6 != 0))
    throw InputError(where, bad + "a cube array has 6 faces per cube, not " + std::to_string(n));
  if (n == 0) throw InputError(where, bad + "no layers");
  if (n > kMaxTextureSlices) {
    throw InputError(where, bad + std::to_string(n) + " slices (at most " +
                                std::to_string(kMaxTextureSlices) + ")");
  }
  for (const auto& slice : s.slices) {
    if (slice.empty()) throw InputError(where, bad + "an empty slice source");
    if (is_procedural_source(slice)) (void)parse_procedural_source(slice, where);
  }
  return s;
}

}  // namespace texsim
