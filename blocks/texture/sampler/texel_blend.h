#pragma once
// Texel blend: the weighted-sum datapath Σ w·texel over a fragment's taps, with texel reads
// (docs/derivations/filters.md §5). Arithmetic: float32 products and a float32 adder tree per group
// of `taps_per_cycle` taps, the group sums accumulated in tap order.
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

// Texel blend (docs/derivations/filters.md §5): reads the taps' texels and forms the weighted RGBA
// sum.
class TexelBlend {
 public:
  struct Config {
    // Multiply-accumulate lanes: taps blended per cycle (8 = one trilinear probe per cycle,
    // 4 = one bilinear probe). Key: taps_per_cycle (1..32, a power of two).
    int taps_per_cycle = 8;
    static Config from_toml(const ConfigReader& r);
  };

  TexelBlend() = default;
  explicit TexelBlend(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Σ w_k · texel_k over taps.tap[0 .. count); a border tap's texel is taps.border. Counts one
  // memory read, 4 mul and 4 add per tap.
  Rgba blend(const FilterTaps& taps, const Texture& tex, OpCounts& ops) const {
    ops += ops_per_item() * static_cast<uint64_t>(taps.count > 0 ? taps.count : 0);
    return blend(taps, tex);
  }
  // The same without counting (the count is ops_per_item() times the number of taps).
  Rgba blend(const FilterTaps& taps, const Texture& tex) const;

  // The same for a linear probe given as one quad (bilinear) or two (trilinear, finer level
  // first): equal to blend() of the taps the quads stand for. Needs taps_per_cycle >= 4·n (all
  // taps in one group); quads_in_one_group(n) says whether it holds.
  [[gnu::always_inline]] Rgba blend_quads(const TexelQuad* q, int n, const Texture& tex) const;
  bool quads_in_one_group(int n) const { return cfg_.taps_per_cycle >= 4 * n; }

  // Cycles one fragment occupies the datapath: ⌈count / taps_per_cycle⌉ (at least 1).
  uint32_t issue_cycles(const FilterTaps& taps) const {
    const int g = cfg_.taps_per_cycle > 1 ? cfg_.taps_per_cycle : 1;
    const int c = (taps.count + g - 1) / g;
    return static_cast<uint32_t>(c > 1 ? c : 1);
  }
  // Item: one tap.
  static OpCounts ops_per_item() {
    OpCounts o;
    o.mem = 1;  // one texel read
    o.mul = 4;  // w · RGBA
    o.add = 4;  // RGBA accumulate (tree levels + group accumulation: one add per product)
    return o;
  }
  // Latency: texel read, multiply, log2(taps_per_cycle) adder levels, accumulate. ii = 1 group.
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "blend"; }
  std::string arithmetic() const { return "float32 multiply-accumulate"; }

 private:
  Config cfg_;
};

// ---- the per-fragment datapath, in the header so the texture unit inlines it ----------

namespace texel_blend_detail {

// GCC/Clang vector extension: four float lanes, each one IEEE float32 operation exactly as in
// the component-wise Rgba arithmetic, kept in one register; and the integer views used to
// widen RGBA8 bytes (two interleaves with zero, which compile to unpack instructions).
typedef float F4 __attribute__((vector_size(16)));
typedef int32_t I4 __attribute__((vector_size(16)));
typedef uint8_t U8x16 __attribute__((vector_size(16)));
typedef uint16_t U16x8 __attribute__((vector_size(16)));

// Texel fetch and conversion to float; RGBA8 channels are c · (1/255) as in Texture::texel.
struct FetchRgba8 {
  static const uint8_t* data(const Texture& tex, int level) { return tex.rgba8(level); }
  static F4 at(const uint8_t* texels, size_t index) {
    // The texel's 4 bytes in the low lane (a plain 32-bit load), R in the lowest byte.
    static_assert(std::endian::native == std::endian::little, "RGBA8 load assumes little-endian");
    int32_t rgba;
    std::memcpy(&rgba, texels + index * 4, sizeof rgba);
    const I4 word = {rgba, 0, 0, 0};
    U8x16 b;
    std::memcpy(&b, &word, sizeof b);
    const U8x16 z8 = {};
    const U8x16 b16 =
        __builtin_shufflevector(b, z8, 0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
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
  static const float* data(const Texture& tex, int level) { return tex.rgba32f(level); }
  static F4 at(const float* texels, size_t index) {
    F4 v;
    std::memcpy(&v, texels + index * 4, sizeof v);
    return v;
  }
};

// Binary adder tree over prod[0 .. n), as the hardware sums its lanes: pairs, an odd last
// element passed up unchanged.
inline F4 tree_sum(F4* prod, int n) {
  for (int width = n; width > 1; width = (width + 1) / 2) {
    for (ptrdiff_t k = 0; k < width / 2; ++k) prod[k] = prod[2 * k] + prod[2 * k + 1];
    if (width & 1) prod[width / 2] = prod[width - 1];
  }
  return prod[0];
}

// w · texel of taps [first, first + n); the level's texels and width are looked up once per
// run of taps on one level (a probe's taps share a level). With kBorder, a border tap
// (kBorderTexel) takes the border colour instead of a texel.
template <class Fetch, bool kBorder = false>
struct Products {
  const Texture& tex;
  F4 border = {0.0f, 0.0f, 0.0f, 0.0f};
  int32_t level = -1;
  decltype(Fetch::data(std::declval<const Texture&>(), 0)) texels = nullptr;
  size_t width = 0;

  F4 operator()(const TexelTap& t) {
    if constexpr (kBorder) {
      if (t.x == kBorderTexel || t.y == kBorderTexel) return border * t.w;
    }
    if (t.level != level) {
      level = t.level;
      const Texture::Level& lv = tex.level(level);
      texels = Fetch::data(tex, level);
      width = static_cast<size_t>(lv.width);
    }
    const size_t index = static_cast<size_t>(t.y) * width + static_cast<size_t>(t.x);
    return Fetch::at(texels, index) * t.w;
  }
};

template <class Fetch, bool kBorder = false>
inline Rgba blend_taps(const FilterTaps& taps, const Texture& tex, int g) {
  F4 acc = {0.0f, 0.0f, 0.0f, 0.0f};
  Products<Fetch, kBorder> product{tex};
  if constexpr (kBorder)
    product.border = F4{taps.border.r, taps.border.g, taps.border.b, taps.border.a};
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

// w · texel of a quad's four taps, in tap order.
template <class Fetch>
[[gnu::always_inline]] inline void quad_products(const TexelQuad& q, const Texture& tex, F4* p) {
  const Texture::Level& lv = tex.level(q.level);
  const auto texels = Fetch::data(tex, q.level);
  const auto width = static_cast<size_t>(lv.width);
  const size_t r0 = static_cast<size_t>(q.y0) * width, r1 = static_cast<size_t>(q.y1) * width;
  const auto x0 = static_cast<size_t>(q.x0), x1 = static_cast<size_t>(q.x1);
  p[0] = Fetch::at(texels, r0 + x0) * q.w[0];
  p[1] = Fetch::at(texels, r0 + x1) * q.w[1];
  p[2] = Fetch::at(texels, r1 + x0) * q.w[2];
  p[3] = Fetch::at(texels, r1 + x1) * q.w[3];
}

// The adder trees of blend_taps for 4 and 8 taps in one group.
template <class Fetch>
[[gnu::always_inline]] inline Rgba blend_quads(const TexelQuad* q, int n, const Texture& tex) {
  F4 acc = {0.0f, 0.0f, 0.0f, 0.0f};
  F4 p[8];
  quad_products<Fetch>(q[0], tex, p);
  if (n == 1) {
    acc += (p[0] + p[1]) + (p[2] + p[3]);
  } else {
    quad_products<Fetch>(q[1], tex, p + 4);
    acc += ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
  }
  return {acc[0], acc[1], acc[2], acc[3]};
}

}  // namespace texel_blend_detail

inline Rgba TexelBlend::blend(const FilterTaps& taps, const Texture& tex) const {
  using namespace texel_blend_detail;
  const int g = std::clamp(cfg_.taps_per_cycle, 1, 32);
  if (taps.border_taps > 0) {
    // The same sums, the border taps' products taken from the border colour.
    return tex.format() == TexelFormat::Rgba8 ? blend_taps<FetchRgba8, true>(taps, tex, g)
                                              : blend_taps<FetchRgba32f, true>(taps, tex, g);
  }
  return tex.format() == TexelFormat::Rgba8 ? blend_taps<FetchRgba8>(taps, tex, g)
                                            : blend_taps<FetchRgba32f>(taps, tex, g);
}

inline Rgba TexelBlend::blend_quads(const TexelQuad* q, int n, const Texture& tex) const {
  using namespace texel_blend_detail;
  return tex.format() == TexelFormat::Rgba8
             ? texel_blend_detail::blend_quads<FetchRgba8>(q, n, tex)
             : texel_blend_detail::blend_quads<FetchRgba32f>(q, n, tex);
}

}  // namespace texsim
