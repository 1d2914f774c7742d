#include "blocks/texel_address_gen.h"

#include <algorithm>
#include <cmath>

namespace texsim {

const char* to_string(FilterMode m) {
  switch (m) {
    case FilterMode::Nearest: return "nearest";
    case FilterMode::Bilinear: return "bilinear";
    case FilterMode::Trilinear: return "trilinear";
  }
  return "?";
}

namespace {

// Float texel coordinate to fixed point with `scale` = 2^bits, round to nearest even (the
// float→fixed converter of the datapath). |x| is limited to 2^30 texels first: beyond that a
// float32 coordinate has no fraction bits left, and the limit keeps the integer in range.
// x·2^bits is exact (at most 2^46), so this equals rounding ldexp(x, bits).
inline int64_t to_fixed(float x, float scale) {
  constexpr float kLimit = 1073741824.0f;  // 2^30
  x = std::clamp(x, -kLimit, kLimit);
  return TexelAddressGen::round_half_even(x * scale);
}

float finite_or_zero(float x) { return std::isfinite(x) ? x : 0.0f; }

bool is_pow2(int64_t n) { return (n & (n - 1)) == 0; }

// Euclidean i mod m (m > 0); a power-of-two m, the usual texture size, is a mask.
int64_t mod_pos(int64_t i, int64_t m) {
  if (is_pow2(m)) return i & (m - 1);
  const int64_t r = i % m;
  return r < 0 ? r + m : r;
}

int32_t wrap(int64_t i, int32_t size) { return static_cast<int32_t>(mod_pos(i, size)); }

int32_t clamp_edge(int64_t i, int32_t size) {
  return static_cast<int32_t>(std::clamp<int64_t>(i, 0, size - 1));
}

// Vulkan MIRRORED_REPEAT: (size − 1) − mirror((i mod 2·size) − size),
// mirror(n) = n for n ≥ 0, −(1 + n) otherwise.
int32_t mirror(int64_t i, int32_t size) {
  const int64_t n = mod_pos(i, 2 * static_cast<int64_t>(size)) - size;
  const int64_t m = n >= 0 ? n : -(1 + n);
  return static_cast<int32_t>((size - 1) - m);
}

// The two neighbours i and i + 1 of a linear filter, addressed. Wrap derives i + 1 from i
// (one modulo instead of two), as the hardware's incrementer does.
[[gnu::always_inline]] inline void address_pair(int64_t i, int32_t size, AddressMode mode, int32_t& a, int32_t& b) {
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
  }
  a = b = 0;
}

}  // namespace

TexelAddressGen::TexelAddressGen(const Config& c) : cfg_(c) {
  fix_scale_ = std::ldexp(1.0f, cfg_.sub_texel_bits);
  frac_scale_ = std::ldexp(1.0f, -cfg_.sub_texel_bits);
  mip_scale_ = std::ldexp(1.0f, cfg_.mipmap_bits);
  mip_frac_ = std::ldexp(1.0f, -cfg_.mipmap_bits);
  for (int a = 0; a < 2; ++a) {
    ops_setup_[a] = count_setup(a != 0);
    ops_probe_[a] = count_probe(a != 0);
  }
}

TexelAddressGen::Config TexelAddressGen::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"mode", "address", "address_u", "address_v", "sub_texel_bits", "mipmap_bits"});
  Config c;
  c.filter = static_cast<FilterMode>(
      r.get_choice("mode", static_cast<int>(c.filter), {"nearest", "bilinear", "trilinear"}));
  const std::vector<std::string_view> modes = {"wrap", "clamp", "mirror"};  // AddressMode order
  if (r.table().contains("address")) {
    // One key for both axes; giving an axis as well would leave it ambiguous which wins.
    for (std::string_view k : {"address_u", "address_v"}) {
      if (r.table().contains(k)) r.fail(k, "cannot be given together with 'address'");
    }
    c.address_u = c.address_v = static_cast<AddressMode>(r.get_choice("address", 0, modes));
  } else {
    c.address_u = static_cast<AddressMode>(r.get_choice("address_u", 0, modes));
    c.address_v = static_cast<AddressMode>(r.get_choice("address_v", 0, modes));
  }
  c.sub_texel_bits = static_cast<int>(r.get_int("sub_texel_bits", c.sub_texel_bits, 1, 16));
  c.mipmap_bits = static_cast<int>(r.get_int("mipmap_bits", c.mipmap_bits, 1, 16));
  return c;
}

int32_t TexelAddressGen::address(int64_t i, int32_t size, AddressMode mode) {
  switch (mode) {
    case AddressMode::Wrap: return wrap(i, size);
    case AddressMode::Clamp: return clamp_edge(i, size);
    case AddressMode::Mirror: return mirror(i, size);
  }
  return 0;
}

TexelAddressGen::LevelSelect TexelAddressGen::select_levels(float lambda, int levels) const {
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

int TexelAddressGen::taps_per_probe() const {
  switch (cfg_.filter) {
    case FilterMode::Nearest: return 1;
    case FilterMode::Bilinear: return 4;
    case FilterMode::Trilinear: return 8;
  }
  return 1;
}

[[gnu::always_inline]] inline TexelTap* TexelAddressGen::emit_nearest(const Texture& tex, int32_t level, float u, float v,
                                               float w, TexelTap* out) const {
  const Texture::Level& lv = tex.level(level);
  const int32_t wl = lv.width, hl = lv.height;
  const int b = cfg_.sub_texel_bits;
  // i = ⌊u·width⌋ on the fixed-point coordinate.
  const int64_t xf = to_fixed(u * static_cast<float>(wl), fix_scale_);
  const int64_t yf = to_fixed(v * static_cast<float>(hl), fix_scale_);
  *out = {level, address(xf >> b, wl, cfg_.address_u), address(yf >> b, hl, cfg_.address_v), w};
  return out + 1;
}

[[gnu::always_inline]] inline TexelTap* TexelAddressGen::emit_linear(const Texture& tex, int32_t level, float u, float v,
                                              float w, TexelTap* out) const {
  const Texture::Level& lv = tex.level(level);
  const int32_t wl = lv.width, hl = lv.height;
  const int b = cfg_.sub_texel_bits;
  const int64_t mask = (int64_t{1} << b) - 1;
  // i0 = ⌊u·width − ½⌋, α = frac(u·width − ½) with b fraction bits.
  const int64_t xf = to_fixed(u * static_cast<float>(wl) - 0.5f, fix_scale_);
  const int64_t yf = to_fixed(v * static_cast<float>(hl) - 0.5f, fix_scale_);
  const float a = static_cast<float>(xf & mask) * frac_scale_;
  const float be = static_cast<float>(yf & mask) * frac_scale_;
  int32_t x0, x1, y0, y1;
  address_pair(xf >> b, wl, cfg_.address_u, x0, x1);
  address_pair(yf >> b, hl, cfg_.address_v, y0, y1);
  const float wi0 = 1.0f - a, wj0 = 1.0f - be;
  out[0] = {level, x0, y0, wi0 * wj0 * w};
  out[1] = {level, x1, y0, a * wj0 * w};
  out[2] = {level, x0, y1, wi0 * be * w};
  out[3] = {level, x1, y1, a * be * w};
  return out + 4;
}

void TexelAddressGen::taps(const Texture& tex, double u, double v, const LodResult& lod,
                           FilterTaps& out) const {
  const int n = static_cast<int>(issue_cycles(lod));
  const LevelSelect sel = select_levels(lod.lambda, tex.levels());
  const float uf = finite_or_zero(static_cast<float>(u));
  const float vf = finite_or_zero(static_cast<float>(v));
  TexelTap* t = out.tap.data();
  if (n == 1) {
    // One probe at (u, v) with weight 1.
    switch (cfg_.filter) {
      case FilterMode::Nearest: t = emit_nearest(tex, sel.d_hi, uf, vf, 1.0f, t); break;
      case FilterMode::Bilinear: t = emit_linear(tex, sel.d_hi, uf, vf, 1.0f, t); break;
      case FilterMode::Trilinear:
        t = emit_linear(tex, sel.d_hi, uf, vf, 1.0f - sel.delta, t);
        t = emit_linear(tex, sel.d_lo, uf, vf, sel.delta, t);
        break;
    }
  } else {
    const float au = finite_or_zero(lod.axis_u), av = finite_or_zero(lod.axis_v);
    const float inv_n = 1.0f / static_cast<float>(n);
    for (int k = 0; k < n; ++k) {
      // Probe k of N, centred on (u, v), one probe step apart (docs/filters.md §4).
      const float off = static_cast<float>(k) - 0.5f * static_cast<float>(n - 1);
      const float pu = uf + off * au;
      const float pv = vf + off * av;
      switch (cfg_.filter) {
        case FilterMode::Nearest: t = emit_nearest(tex, sel.d_hi, pu, pv, inv_n, t); break;
        case FilterMode::Bilinear: t = emit_linear(tex, sel.d_hi, pu, pv, inv_n, t); break;
        case FilterMode::Trilinear:
          t = emit_linear(tex, sel.d_hi, pu, pv, (1.0f - sel.delta) * inv_n, t);
          t = emit_linear(tex, sel.d_lo, pu, pv, sel.delta * inv_n, t);
          break;
      }
    }
  }
  out.count = static_cast<int>(t - out.tap.data());
}

// ---- operation counts and timing ----------------------------------------------------------

OpCounts TexelAddressGen::ops_address(AddressMode m) {
  OpCounts o;
  switch (m) {
    case AddressMode::Wrap:
      // i mod size for any size: q = ⌊i·(1/size)⌋, r = i − q·size, fix-up compare.
      o.mul = 2;
      o.add = 1;
      o.cmp = 1;
      break;
    case AddressMode::Clamp:
      o.cmp = 2;  // max(0, ·), min(size − 1, ·)
      break;
    case AddressMode::Mirror:
      // t = i mod 2·size (as wrap), n = t − size, mirror(n) (select + negate), (size−1) − m.
      o.mul = 2;
      o.add = 4;
      o.cmp = 2;
      break;
  }
  return o;
}

OpCounts TexelAddressGen::ops_level() const {
  OpCounts o;
  const bool linear = cfg_.filter != FilterMode::Nearest;
  const uint64_t coords = linear ? 2 : 1;  // i0, i1 (and j0, j1) or one i (and j)
  o.mul += 2;                              // u·width, v·height
  if (linear) o.add += 2;                  // − ½
  o.add += 2;                              // round to fixed point
  if (linear) o.add += 2;                  // i1 = i0 + 1, j1 = j0 + 1
  o += ops_address(cfg_.address_u) * coords;
  o += ops_address(cfg_.address_v) * coords;
  if (linear) {
    o.add += 2;  // 1 − α, 1 − β
    o.mul += 4;  // w_i · w_j
  }
  return o;
}

OpCounts TexelAddressGen::count_setup(bool anisotropic) const {
  OpCounts o;
  const bool tri = cfg_.filter == FilterMode::Trilinear;
  o.cmp += 2;  // d' = clamp(λ, 0, q)
  o.add += 1;  // d' to fixed point
  if (tri) {
    o.add += 1;  // d_lo = d_hi + 1
    o.cmp += 1;  // min(d_lo, q)
    o.add += 1;  // 1 − δ
  } else {
    o.add += 1;  // ⌈d' + ½⌉ − 1
  }
  o.cmp += tri ? 4 : 2;  // level sizes max(1, size >> d) per level used
  if (anisotropic) {
    o.lut += 1;                 // 1/N
    if (tri) o.mul += 2;        // (1 − δ)/N, δ/N
  }
  return o;
}

OpCounts TexelAddressGen::count_probe(bool anisotropic) const {
  const bool tri = cfg_.filter == FilterMode::Trilinear;
  OpCounts o = ops_level() * (tri ? 2 : 1);
  if (anisotropic) {
    o.add += 1;  // probe offset counter k − (N−1)/2
    o.mul += 2;  // offset · axis
    o.add += 2;  // + (u, v)
  }
  // Per-tap scaling by the level weight and/or 1/N.
  if (tri || anisotropic) o.mul += static_cast<uint64_t>(taps_per_probe());
  return o;
}

TimingSpec TexelAddressGen::timing(const TechTable& tech) const {
  const bool tri = cfg_.filter == FilterMode::Trilinear;
  const bool linear = cfg_.filter != FilterMode::Nearest;
  // Level selection: clamp (2 cmp), to fixed (add), rule (add; linear: add + min), sizes (cmp).
  OpCounts setup;
  setup.cmp = 2 + 1 + (tri ? 1 : 0);
  setup.add = 2;
  // Probe position: offset · axis + u.
  OpCounts pos;
  pos.mul = 1;
  pos.add = 1;
  // Coordinate: scale, − ½ (linear), round to fixed.
  OpCounts coord;
  coord.mul = 1;
  coord.add = linear ? 2 : 1;
  // Branch A: i1 = i0 + 1, then the slower of the two address modes.
  OpCounts au = ops_address(cfg_.address_u), av = ops_address(cfg_.address_v);
  double a = std::max(tech.path_latency(au), tech.path_latency(av));
  if (linear) a += tech.lat(OpKind::Add);
  // Branch B: 1 − α, w_i·w_j, then the level/probe weight.
  double b = 0;
  if (linear) b = tech.lat(OpKind::Add) + tech.lat(OpKind::Mul);
  b += tech.lat(OpKind::Mul);  // × level weight or 1/N (present in the pipe, bypassed if 1)
  const double lat = tech.path_latency(setup) + tech.path_latency(pos) +
                     tech.path_latency(coord) + std::max(a, b);
  TimingSpec t;
  t.latency = std::max<uint32_t>(1, static_cast<uint32_t>(std::ceil(lat)));
  t.ii = 1;  // one probe per cycle; a fragment takes issue_cycles() slots
  t.lanes = 1;
  t.area = tech.area_of(ops_setup(true) + ops_per_probe(true));
  return t;
}

}  // namespace texsim
