#pragma once
// Texel address generator: mip level selection, texel coordinates, address modes and filter
// weights of the nearest, bilinear and trilinear filters, with anisotropic probes
// (docs/derivations/filters.md §2–§4). One block for the three filters: they share one datapath
// (nearest is its 1-tap degenerate case, trilinear runs it on two levels), selected by
// Config::filter. Arithmetic: float32 coordinates, converted to fixed point with `sub_texel_bits`
// fraction bits (round to nearest even); LOD to fixed point with `mipmap_bits` fraction bits;
// weights are products of those fixed-point fractions (exact in float32) and 1/N.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/sampler_modes.h"

namespace texsim {

// x or y of a tap that reads the border colour (CLAMP_TO_BORDER, outside the level): no
// texel is read and no memory is accessed for it.
inline constexpr int32_t kBorderTexel = -1;

// One texel to read: coordinates already addressed (inside the level, or kBorderTexel in
// either coordinate for a border tap), and its weight.
struct TexelTap {
  int32_t level;
  int32_t x, y;
  float w;
};
// The 2x2 texels of a linear filter on one level, addressed, and their weights in tap order
// (x0,y0) (x1,y0) (x0,y1) (x1,y1): four taps in a form the texture unit keeps in registers.
struct TexelQuad {
  int32_t level;
  int32_t x0, x1, y0, y1;
  float w[4];
};
// All taps of one fragment: up to maxAniso (16) probes × 8 taps. border_taps counts the taps
// that read the border colour (then `border` holds it, in the texture's format conversion).
struct FilterTaps {
  std::array<TexelTap, 128> tap;
  int count = 0;
  int border_taps = 0;
  Rgba border{0.0f};
};

// Nearest = VK_FILTER_NEAREST + VK_SAMPLER_MIPMAP_MODE_NEAREST; Bilinear = VK_FILTER_LINEAR +
// MIPMAP_MODE_NEAREST; Trilinear = VK_FILTER_LINEAR + MIPMAP_MODE_LINEAR. The same filter
// serves magnification and minification.
enum class FilterMode { Nearest, Bilinear, Trilinear };
const char* to_string(FilterMode m);

// Texel address generator (docs/derivations/filters.md §2–§4): levels, texel coordinates,
// wrap/clamp/mirror/border/mirror-clamp, texel offsets and weights of nearest/bilinear/trilinear
// taps, per anisotropic probe.
class TexelAddressGen {
 public:
  struct Config {
    FilterMode filter = FilterMode::Bilinear;
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    AddressMode address_w = AddressMode::Wrap;  // r of a 3-D texture (no other type reads it)
    int sub_texel_bits = 8;  // fraction bits of texel coordinates (Vulkan subTexelPrecisionBits)
    int mipmap_bits = 8;     // fraction bits of the LOD (Vulkan mipmapPrecisionBits)
    // CLAMP_TO_BORDER's colour (VkBorderColor FLOAT_*, or FLOAT_CUSTOM_EXT), linear RGBA.
    Rgba border{0.0f};
    // Constant texel offset (OpImageSample*'s ConstOffset), added to the integer texel
    // coordinates before wrapping; Vulkan's minTexelOffset..maxTexelOffset = -8..7.
    int offset_u = 0, offset_v = 0;
    static constexpr int kMinTexelOffset = -8, kMaxTexelOffset = 7;
    // Cube textures: seamless filtering across face edges (Vulkan's default), or each face
    // addressed on its own with address_u/address_v (VK_EXT_non_seamless_cube_map).
    bool seamless_cube = true;
    // Min/max reduction and depth comparison (sampler_modes.h), which the texel reducer
    // applies in place of the blend. Keys: reduction ("weighted_average"|"min"|"max"),
    // compare ("none"|"never"|"less"|…|"always"; not with a min/max reduction).
    Reduction reduction = Reduction::WeightedAverage;
    CompareOp compare = CompareOp::None;
    // Vulkan unnormalizedCoordinates (a scene sampler's `unnormalized`): u, v in texels on
    // level 0; the texture unit takes such a sampler's taps from UnnormalizedTaps.
    bool unnormalized = false;
    bool reduces() const {
      return reduction != Reduction::WeightedAverage || compare != CompareOp::None;
    }
    // The texture unit's functional path: float32 (LodUnit, the taps, TexelBlend) or the
    // fixed-point sampler the RTL matches (FixedSampler; the material must be one it covers).
    bool fixed_arithmetic = false;
    // Keys: mode ("nearest"|"bilinear"|"trilinear"); address ("wrap"|"clamp"|"mirror"|
    // "border"|"mirror_clamp") for every axis, or address_u, address_v, address_w (3-D r)
    // separately (not both forms at once); sub_texel_bits (1..16), mipmap_bits (1..16); border
    // ("transparent_black"|"opaque_black"|"opaque_white"|[r, g, b, a]); offset ([i, j]);
    // seamless (bool, cube textures); arithmetic ("float"|"fixed").
    static Config from_toml(const ConfigReader& r);
    bool uses_border() const {
      return address_u == AddressMode::Border || address_v == AddressMode::Border;
    }
  };

  // Mip level(s) chosen for one fragment (Vulkan "Image Level(s) Selection").
  struct LevelSelect {
    int32_t d_hi = 0;  // the level for nearest mipmap mode; the finer level for linear
    int32_t d_lo = 0;  // coarser level (linear mode); = d_hi otherwise
    float delta = 0;   // weight of d_lo, a multiple of 2^-mipmap_bits (linear mode)
  };

  TexelAddressGen() : TexelAddressGen(Config{}) {}
  explicit TexelAddressGen(const Config& c);
  const Config& config() const { return cfg_; }

  // Writes the taps of one fragment at normalised (u, v) into `out` (out.count set).
  // Probes: lod.probes (clamped to 1..16) at (u, v) + (k − (N−1)/2)·(axis_u, axis_v),
  // k = 0..N−1, each weighted 1/N. Non-finite u or v are treated as 0.
  void taps(const Texture& tex, double u, double v, const LodResult& lod, FilterTaps& out,
            OpCounts& ops) const {
    const bool aniso = issue_cycles(lod) > 1;
    ops += ops_setup_[aniso];
    ops += ops_probe_[aniso] * issue_cycles(lod);
    taps(tex, u, v, lod, out);
  }
  // The same without counting: the count depends only on the probe number N, so a caller
  // may count fragments and probes and multiply ops_setup() and ops_per_item() at the end.
  void taps(const Texture& tex, double u, double v, const LodResult& lod, FilterTaps& out) const;

  // The quad of a linear filter at (u, v) (finite, normalised) on `level`, weights scaled by
  // w: the four taps taps() writes for one linear probe on one level.
  [[gnu::always_inline]] TexelQuad linear_quad(const Texture& tex, int32_t level, float u, float v,
                                               float w) const;
  // Level selection from λ on a pyramid of `levels` levels.
  [[gnu::always_inline]] LevelSelect select_levels(float lambda, int levels) const;
  // Vulkan's wrapping of one integer texel coordinate into [0, size), or kBorderTexel
  // (CLAMP_TO_BORDER outside the level).
  static int32_t address(int64_t i, int32_t size, AddressMode mode);

  // The float→fixed converters' rounding: nearest integer, ties to even (= std::llrint in the
  // default rounding mode, without the library call). Below 2^23 adding and subtracting 2^23
  // rounds to an integer in float32 arithmetic; larger floats are integers already.
  [[gnu::always_inline]] static int64_t round_half_even(float x) {
    constexpr float k = 8388608.0f;  // 2^23
    const float a = std::fabs(x);
    if (a < k) {
      const float c = std::copysign(k, x);
      return static_cast<int64_t>((x + c) - c);
    }
    if (a < 4611686018427387904.0f) return static_cast<int64_t>(x);  // an integer below 2^62
    return std::llrint(x);  // huge, and NaN (never reached from the datapath)
  }

  // Taps per probe and issue slots (cycles at ii = 1) one fragment occupies.
  int taps_per_probe() const;
  static uint32_t issue_cycles(const LodResult& lod) {
    return static_cast<uint32_t>(lod.probes < 1 ? 1 : (lod.probes > 16 ? 16 : lod.probes));
  }
  // Operations per fragment (level selection) and per item, one probe; an anisotropic
  // fragment (N > 1) adds 1/N per fragment and the probe offset and 1/N weighting per probe.
  const OpCounts& ops_setup(bool anisotropic) const { return ops_setup_[anisotropic]; }
  const OpCounts& ops_per_item(bool anisotropic) const { return ops_probe_[anisotropic]; }
  const OpCounts& ops_per_item() const { return ops_per_item(false); }
  // Per-probe pipeline: latency of the critical path, ii = 1 probe per cycle, area of one
  // probe's datapath (with the anisotropic offset/weight stage).
  TimingSpec timing(const TechTable& tech) const;
  // Operations of one address mode on one integer coordinate (docs/derivations/filters.md §2).
  static OpCounts ops_address(AddressMode m);
  // Report name ("filter.<mode>") and number formats.
  std::string name() const;
  std::string arithmetic() const;

 private:
  OpCounts ops_level() const;
  OpCounts count_setup(bool anisotropic) const;
  OpCounts count_probe(bool anisotropic) const;
  [[gnu::always_inline]] TexelTap* emit_nearest(const Texture& tex, int32_t level, float u, float v,
                                                float w, TexelTap* out) const;
  // Counts the border taps of `out` and gives it the border colour in the texture's format.
  void count_border(const Texture& tex, FilterTaps& out) const;
  [[gnu::always_inline]] TexelTap* emit_linear(const Texture& tex, int32_t level, float u, float v,
                                               float w, TexelTap* out) const;
  Config cfg_;
  // Fixed by the configuration, so computed once: the converters' scale factors (powers of
  // two, so the products are exact and equal to ldexp) and the operation counts.
  float fix_scale_ = 256.0f;              // 2^sub_texel_bits
  float frac_scale_ = 1.0f / 256;         // 2^-sub_texel_bits
  float mip_scale_ = 256.0f;              // 2^mipmap_bits
  float mip_frac_ = 1.0f / 256;           // 2^-mipmap_bits
  OpCounts ops_setup_[2], ops_probe_[2];  // [anisotropic]
};

// ---- the per-fragment datapath, in the header so the texture unit inlines it ----------

namespace texel_address_detail {

// Float texel coordinate to fixed point with `scale` = 2^bits, round to nearest even (the
// float→fixed converter of the datapath). |x| is limited to 2^30 texels first: beyond that a
// float32 coordinate has no fraction bits left, and the limit keeps the integer in range.
// x·2^bits is exact (at most 2^46), so this equals rounding ldexp(x, bits).
[[gnu::always_inline]] inline int64_t to_fixed(float x, float scale) {
  constexpr float kLimit = 1073741824.0f;  // 2^30
  x = std::clamp(x, -kLimit, kLimit);
  return TexelAddressGen::round_half_even(x * scale);
}

inline float finite_or_zero(float x) { return std::isfinite(x) ? x : 0.0f; }

inline bool is_pow2(int64_t n) { return (n & (n - 1)) == 0; }

// Euclidean i mod m (m > 0); a power-of-two m, the usual texture size, is a mask.
inline int64_t mod_pos(int64_t i, int64_t m) {
  if (is_pow2(m)) return i & (m - 1);
  const int64_t r = i % m;
  return r < 0 ? r + m : r;
}

inline int32_t wrap(int64_t i, int32_t size) { return static_cast<int32_t>(mod_pos(i, size)); }

inline int32_t clamp_edge(int64_t i, int32_t size) {
  return static_cast<int32_t>(std::clamp<int64_t>(i, 0, size - 1));
}

// Vulkan MIRRORED_REPEAT: (size − 1) − mirror((i mod 2·size) − size),
// mirror(n) = n for n ≥ 0, −(1 + n) otherwise.
inline int32_t mirror(int64_t i, int32_t size) {
  const int64_t n = mod_pos(i, 2 * static_cast<int64_t>(size)) - size;
  const int64_t m = n >= 0 ? n : -(1 + n);
  return static_cast<int32_t>((size - 1) - m);
}

// Vulkan MIRROR_CLAMP_TO_EDGE: clamp(mirror(i), 0, size − 1).
inline int32_t mirror_clamp(int64_t i, int32_t size) {
  const int64_t m = i >= 0 ? i : -(1 + i);
  return static_cast<int32_t>(std::min<int64_t>(m, size - 1));
}

// Vulkan CLAMP_TO_BORDER: i itself inside the level, the border texel outside.
inline int32_t border(int64_t i, int32_t size) {
  return i >= 0 && i < size ? static_cast<int32_t>(i) : kBorderTexel;
}

// The two neighbours i and i + 1 of a linear filter, addressed. Wrap derives i + 1 from i
// (one modulo instead of two), as the hardware's incrementer does.
[[gnu::always_inline]] inline void address_pair(int64_t i, int32_t size, AddressMode mode,
                                                int32_t& a, int32_t& b) {
  switch (mode) {
    case AddressMode::Wrap:
      a = wrap(i, size);
      b = a + 1 == size ? 0 : a + 1;
      return;
    case AddressMode::Clamp:
      a = clamp_edge(i, size);
      b = clamp_edge(i + 1, size);
      return;
    case AddressMode::Mirror:
      a = mirror(i, size);
      b = mirror(i + 1, size);
      return;
    case AddressMode::Border:
      a = border(i, size);
      b = border(i + 1, size);
      return;
    case AddressMode::MirrorClamp:
      a = mirror_clamp(i, size);
      b = mirror_clamp(i + 1, size);
      return;
  }
  a = b = 0;
}

}  // namespace texel_address_detail

inline int32_t TexelAddressGen::address(int64_t i, int32_t size, AddressMode mode) {
  switch (mode) {
    case AddressMode::Wrap:
      return texel_address_detail::wrap(i, size);
    case AddressMode::Clamp:
      return texel_address_detail::clamp_edge(i, size);
    case AddressMode::Mirror:
      return texel_address_detail::mirror(i, size);
    case AddressMode::Border:
      return texel_address_detail::border(i, size);
    case AddressMode::MirrorClamp:
      return texel_address_detail::mirror_clamp(i, size);
  }
  return 0;
}

inline TexelAddressGen::LevelSelect TexelAddressGen::select_levels(float lambda, int levels) const {
  LevelSelect s;
  const int32_t q = std::max(levels, 1) - 1;
  if (std::isnan(lambda)) lambda = 0;
  // d' = clamp(λ, 0, q) (level_base = 0), then to fixed point with mipmap_bits fraction bits
  // (d'·2^m is exact: d' ≤ q < 2^31, m ≤ 16).
  const float d = std::clamp(lambda, 0.0f, static_cast<float>(q));
  const int m = cfg_.mipmap_bits;
  const int64_t one = int64_t{1} << m;
  const int64_t dfix = round_half_even(d * mip_scale_);
  if (cfg_.filter == FilterMode::Trilinear) {
    s.d_hi = static_cast<int32_t>(dfix >> m);
    s.d_lo = std::min(s.d_hi + 1, q);
    s.delta = static_cast<float>(dfix & (one - 1)) * mip_frac_;
  } else {
    // Vulkan's preferred nearest(d') = ⌈d' + 0.5⌉ − 1 (rounds halves down), in fixed point:
    // ⌈a / 2^m⌉ = (a + 2^m − 1) >> m.
    const int64_t half = one >> 1;
    s.d_hi = static_cast<int32_t>(((dfix + half + one - 1) >> m) - 1);
    s.d_hi = std::clamp(s.d_hi, 0, q);
    s.d_lo = s.d_hi;
    s.delta = 0;
  }
  return s;
}

inline TexelTap* TexelAddressGen::emit_nearest(const Texture& tex, int32_t level, float u, float v,
                                               float w, TexelTap* out) const {
  using namespace texel_address_detail;
  const Texture::Level& lv = tex.level(level);
  const int32_t wl = lv.width, hl = lv.height;
  const int b = cfg_.sub_texel_bits;
  // i = ⌊u·width⌋ on the fixed-point coordinate.
  const int64_t xf = to_fixed(u * static_cast<float>(wl), fix_scale_);
  const int64_t yf = to_fixed(v * static_cast<float>(hl), fix_scale_);
  // The constant offset joins the integer coordinate before wrapping.
  *out = {level, address((xf >> b) + cfg_.offset_u, wl, cfg_.address_u),
          address((yf >> b) + cfg_.offset_v, hl, cfg_.address_v), w};
  return out + 1;
}

inline TexelQuad TexelAddressGen::linear_quad(const Texture& tex, int32_t level, float u, float v,
                                              float w) const {
  using namespace texel_address_detail;
  const Texture::Level& lv = tex.level(level);
  const int32_t wl = lv.width, hl = lv.height;
  const int b = cfg_.sub_texel_bits;
  const int64_t mask = (int64_t{1} << b) - 1;
  // i0 = ⌊u·width − ½⌋, α = frac(u·width − ½) with b fraction bits.
  const int64_t xf = to_fixed(u * static_cast<float>(wl) - 0.5f, fix_scale_);
  const int64_t yf = to_fixed(v * static_cast<float>(hl) - 0.5f, fix_scale_);
  const float a = static_cast<float>(xf & mask) * frac_scale_;
  const float be = static_cast<float>(yf & mask) * frac_scale_;
  TexelQuad q;
  q.level = level;
  address_pair((xf >> b) + cfg_.offset_u, wl, cfg_.address_u, q.x0, q.x1);
  address_pair((yf >> b) + cfg_.offset_v, hl, cfg_.address_v, q.y0, q.y1);
  const float wi0 = 1.0f - a, wj0 = 1.0f - be;
  q.w[0] = wi0 * wj0 * w;
  q.w[1] = a * wj0 * w;
  q.w[2] = wi0 * be * w;
  q.w[3] = a * be * w;
  return q;
}

inline TexelTap* TexelAddressGen::emit_linear(const Texture& tex, int32_t level, float u, float v,
                                              float w, TexelTap* out) const {
  const TexelQuad q = linear_quad(tex, level, u, v, w);
  out[0] = {level, q.x0, q.y0, q.w[0]};
  out[1] = {level, q.x1, q.y0, q.w[1]};
  out[2] = {level, q.x0, q.y1, q.w[2]};
  out[3] = {level, q.x1, q.y1, q.w[3]};
  return out + 4;
}

inline void TexelAddressGen::taps(const Texture& tex, double u, double v, const LodResult& lod,
                                  FilterTaps& out) const {
  using texel_address_detail::finite_or_zero;
  const int n = static_cast<int>(issue_cycles(lod));
  const LevelSelect sel = select_levels(lod.lambda, tex.levels());
  const float uf = finite_or_zero(static_cast<float>(u));
  const float vf = finite_or_zero(static_cast<float>(v));
  TexelTap* t = out.tap.data();
  if (n == 1) {
    // One probe at (u, v) with weight 1.
    switch (cfg_.filter) {
      case FilterMode::Nearest:
        t = emit_nearest(tex, sel.d_hi, uf, vf, 1.0f, t);
        break;
      case FilterMode::Bilinear:
        t = emit_linear(tex, sel.d_hi, uf, vf, 1.0f, t);
        break;
      case FilterMode::Trilinear:
        t = emit_linear(tex, sel.d_hi, uf, vf, 1.0f - sel.delta, t);
        t = emit_linear(tex, sel.d_lo, uf, vf, sel.delta, t);
        break;
    }
  } else {
    const float au = finite_or_zero(lod.axis_u), av = finite_or_zero(lod.axis_v);
    const float inv_n = 1.0f / static_cast<float>(n);
    for (int k = 0; k < n; ++k) {
      // Probe k of N, centred on (u, v), one probe step apart (docs/derivations/filters.md §4).
      const float off = static_cast<float>(k) - 0.5f * static_cast<float>(n - 1);
      const float pu = uf + off * au;
      const float pv = vf + off * av;
      switch (cfg_.filter) {
        case FilterMode::Nearest:
          t = emit_nearest(tex, sel.d_hi, pu, pv, inv_n, t);
          break;
        case FilterMode::Bilinear:
          t = emit_linear(tex, sel.d_hi, pu, pv, inv_n, t);
          break;
        case FilterMode::Trilinear:
          t = emit_linear(tex, sel.d_hi, pu, pv, (1.0f - sel.delta) * inv_n, t);
          t = emit_linear(tex, sel.d_lo, pu, pv, sel.delta * inv_n, t);
          break;
      }
    }
  }
  out.count = static_cast<int>(t - out.tap.data());
  out.border_taps = 0;
  if (cfg_.uses_border()) count_border(tex, out);
}

}  // namespace texsim
