#include "pipeline/render/colour_stage.h"

#include <algorithm>
#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace texsim {

namespace {

Rgba clamp01(const Rgba& c) { return glm::clamp(c, Rgba(0.0f), Rgba(1.0f)); }

// One blend factor (OpenGL 1.x: ZERO, ONE, SRC_COLOR .. SRC_ALPHA_SATURATE).
Rgba factor(uint32_t f, const Rgba& s, const Rgba& d) {
  switch (f) {
    case 0:
      return Rgba(0.0f);
    case 1:
      return Rgba(1.0f);
    case 0x0300:
      return s;
    case 0x0301:
      return Rgba(1.0f) - s;
    case 0x0302:
      return Rgba(s.a);
    case 0x0303:
      return Rgba(1.0f - s.a);
    case 0x0304:
      return Rgba(d.a);
    case 0x0305:
      return Rgba(1.0f - d.a);
    case 0x0306:
      return d;
    case 0x0307:
      return Rgba(1.0f) - d;
    default: {  // SRC_ALPHA_SATURATE (0x0308): f = min(As, 1 − Ad), alpha factor 1
      const float k = std::min(s.a, 1.0f - d.a);
      return {k, k, k, 1.0f};
    }
  }
}

}  // namespace

std::string colour_stage_unsupported(const Draw& d) {
  for (const DrawUnit& u : d.units) {
    if (u.env_mode == gl::kBlend) return "texture environment BLEND";
    if (u.env_mode == gl::kCombine) return "texture environment COMBINE";
  }
  return "";
}

Rgba texture_env(uint32_t mode, const Rgba& in, const Rgba& tex) {
  switch (mode) {
    case gl::kReplace:
      return tex;
    case gl::kDecal: {
      const glm::vec3 c = glm::vec3(in) * (1.0f - tex.a) + glm::vec3(tex) * tex.a;
      return {c, in.a};
    }
    case gl::kAdd:
      return clamp01({glm::vec3(in) + glm::vec3(tex), in.a * tex.a});
    default:  // MODULATE (BLEND and COMBINE are refused per draw before)
      return in * tex;
  }
}

Rgba blend(uint32_t sf, uint32_t df, const Rgba& src, const Rgba& dst) {
  return clamp01(src * factor(sf, src, dst) + dst * factor(df, src, dst));
}

}  // namespace texsim
