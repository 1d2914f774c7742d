#include "blocks/texel_blend.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace texsim {

TexelBlend::Config TexelBlend::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"taps_per_cycle"});
  Config c;
  c.taps_per_cycle = static_cast<int>(r.get_int("taps_per_cycle", c.taps_per_cycle, 1, 32));
  if (!std::has_single_bit(static_cast<unsigned>(c.taps_per_cycle))) {
    r.fail("taps_per_cycle", "must be a power of two (the adder tree is binary)");
  }
  return c;
}

namespace {

// Four float lanes (GCC/Clang vector extension): each lane is one IEEE float32 operation,
// exactly as the component-wise Rgba arithmetic, but kept in one register.
typedef float F4 __attribute__((vector_size(16)));

// Texel fetch and conversion to float; RGBA8 channels are c · (1/255) as in Texture::texel.
struct FetchRgba8 {
  static F4 at(const Texture::Level& lv, int x, int y) {
    const uint8_t* p = lv.rgba8.data() + (static_cast<size_t>(y) * static_cast<size_t>(lv.width) +
                                          static_cast<size_t>(x)) * 4;
    constexpr float k = 1.0f / 255.0f;
    return F4{p[0] * k, p[1] * k, p[2] * k, p[3] * k};
  }
};
struct FetchRgba32f {
  static F4 at(const Texture::Level& lv, int x, int y) {
    const float* p = lv.rgba32f.data() + (static_cast<size_t>(y) * static_cast<size_t>(lv.width) +
                                          static_cast<size_t>(x)) * 4;
    return F4{p[0], p[1], p[2], p[3]};
  }
};

// Binary adder tree over prod[0 .. n), as the hardware sums its lanes: pairs, an odd last
// element passed up unchanged.
F4 tree_sum(F4* prod, int n) {
  switch (n) {
    case 1: return prod[0];
    case 4: return (prod[0] + prod[1]) + (prod[2] + prod[3]);
    case 8:
      return ((prod[0] + prod[1]) + (prod[2] + prod[3])) + ((prod[4] + prod[5]) + (prod[6] + prod[7]));
    default: break;
  }
  for (int width = n; width > 1; width = (width + 1) / 2) {
    for (int k = 0; k < width / 2; ++k) prod[k] = prod[2 * k] + prod[2 * k + 1];
    if (width & 1) prod[width / 2] = prod[width - 1];
  }
  return prod[0];
}

template <class Fetch>
Rgba blend_taps(const FilterTaps& taps, const Texture& tex, int g) {
  F4 acc = {0.0f, 0.0f, 0.0f, 0.0f};
  F4 prod[32];
  const TexelTap* t = taps.tap.data();
  for (int base = 0; base < taps.count; base += g) {
    const int n = std::min(g, taps.count - base);
    for (int k = 0; k < n; ++k) {
      const TexelTap& tk = t[base + k];
      prod[k] = Fetch::at(tex.level(tk.level), tk.x, tk.y) * tk.w;
    }
    acc += tree_sum(prod, n);
  }
  return {acc[0], acc[1], acc[2], acc[3]};
}

}  // namespace

Rgba TexelBlend::blend(const FilterTaps& taps, const Texture& tex) const {
  const int g = std::clamp(cfg_.taps_per_cycle, 1, 32);
  return tex.format() == TexelFormat::Rgba8 ? blend_taps<FetchRgba8>(taps, tex, g)
                                            : blend_taps<FetchRgba32f>(taps, tex, g);
}

TimingSpec TexelBlend::timing(const TechTable& tech) const {
  const int levels = std::bit_width(static_cast<unsigned>(std::max(cfg_.taps_per_cycle, 1))) - 1;
  OpCounts path;
  path.mem = 1;
  path.mul = 1;
  path.add = static_cast<uint64_t>(levels) + 1;  // tree + accumulator
  TimingSpec t;
  t.latency = std::max<uint32_t>(1, static_cast<uint32_t>(std::ceil(tech.path_latency(path))));
  t.ii = 1;
  t.lanes = 1;
  OpCounts units;  // taps_per_cycle read ports and RGBA multipliers, tree + accumulator adders
  units.mem = static_cast<uint64_t>(cfg_.taps_per_cycle);
  units.mul = 4 * static_cast<uint64_t>(cfg_.taps_per_cycle);
  units.add = 4 * static_cast<uint64_t>(cfg_.taps_per_cycle);
  t.area = tech.area_of(units);
  return t;
}

}  // namespace texsim
