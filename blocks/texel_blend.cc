#include "blocks/texel_blend.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <utility>

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

// GCC/Clang vector extension: four float lanes, each one IEEE float32 operation exactly as in
// the component-wise Rgba arithmetic, kept in one register; and the integer views used to
// widen RGBA8 bytes (two interleaves with zero, which compile to unpack instructions).
typedef float F4 __attribute__((vector_size(16)));
typedef int32_t I4 __attribute__((vector_size(16)));
typedef uint8_t U8x16 __attribute__((vector_size(16)));
typedef uint16_t U16x8 __attribute__((vector_size(16)));

// Texel fetch and conversion to float; RGBA8 channels are c · (1/255) as in Texture::texel.
struct FetchRgba8 {
  static const uint8_t* data(const Texture::Level& lv) { return lv.rgba8.data(); }
  static F4 at(const uint8_t* texels, size_t index) {
    // The texel's 4 bytes in the low lane (a plain 32-bit load), R in the lowest byte.
    static_assert(std::endian::native == std::endian::little, "RGBA8 load assumes little-endian");
    int32_t rgba;
    std::memcpy(&rgba, texels + index * 4, sizeof rgba);
    const I4 word = {rgba, 0, 0, 0};
    U8x16 b;
    std::memcpy(&b, &word, sizeof b);
    const U8x16 z8 = {};
    const U8x16 b16 = __builtin_shufflevector(b, z8, 0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21,
                                              6, 22, 7, 23);
    U16x8 h;
    std::memcpy(&h, &b16, sizeof h);
    const U16x8 z16 = {};
    const U16x8 h32 = __builtin_shufflevector(h, z16, 0, 8, 1, 9, 2, 10, 3, 11);
    I4 c;
    std::memcpy(&c, &h32, sizeof c);
    constexpr float k = 1.0f / 255.0f;
    return __builtin_convertvector(c, F4) * k;
  }
};
struct FetchRgba32f {
  static const float* data(const Texture::Level& lv) { return lv.rgba32f.data(); }
  static F4 at(const float* texels, size_t index) {
    F4 v;
    std::memcpy(&v, texels + index * 4, sizeof v);
    return v;
  }
};

// Binary adder tree over prod[0 .. n), as the hardware sums its lanes: pairs, an odd last
// element passed up unchanged.
F4 tree_sum(F4* prod, int n) {
  for (int width = n; width > 1; width = (width + 1) / 2) {
    for (int k = 0; k < width / 2; ++k) prod[k] = prod[2 * k] + prod[2 * k + 1];
    if (width & 1) prod[width / 2] = prod[width - 1];
  }
  return prod[0];
}

// w · texel of taps [first, first + n); the level's texels and width are looked up once per
// run of taps on one level (a probe's taps share a level).
template <class Fetch>
struct Products {
  const Texture& tex;
  int32_t level = -1;
  decltype(Fetch::data(std::declval<const Texture::Level&>())) texels = nullptr;
  size_t width = 0;

  F4 operator()(const TexelTap& t) {
    if (t.level != level) {
      level = t.level;
      const Texture::Level& lv = tex.level(level);
      texels = Fetch::data(lv);
      width = static_cast<size_t>(lv.width);
    }
    const size_t index = static_cast<size_t>(t.y) * width + static_cast<size_t>(t.x);
    return Fetch::at(texels, index) * t.w;
  }
};

template <class Fetch>
Rgba blend_taps(const FilterTaps& taps, const Texture& tex, int g) {
  F4 acc = {0.0f, 0.0f, 0.0f, 0.0f};
  Products<Fetch> product{tex};
  const TexelTap* t = taps.tap.data();
  if (taps.count == 4 && g >= 4) {
    // One bilinear probe in one group: the tree is ((p0 + p1) + (p2 + p3)).
    const F4 p0 = product(t[0]), p1 = product(t[1]), p2 = product(t[2]), p3 = product(t[3]);
    acc += (p0 + p1) + (p2 + p3);
  } else if (taps.count == 8 && g >= 8) {
    // One trilinear probe in one group.
    const F4 p0 = product(t[0]), p1 = product(t[1]), p2 = product(t[2]), p3 = product(t[3]);
    const F4 p4 = product(t[4]), p5 = product(t[5]), p6 = product(t[6]), p7 = product(t[7]);
    acc += ((p0 + p1) + (p2 + p3)) + ((p4 + p5) + (p6 + p7));
  } else {
    F4 prod[32];
    for (int base = 0; base < taps.count; base += g) {
      const int n = std::min(g, taps.count - base);
      for (int k = 0; k < n; ++k) prod[k] = product(t[base + k]);
      acc += tree_sum(prod, n);
    }
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
