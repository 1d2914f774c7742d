#include "blocks/texture/sampler/fixed_sampler.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "blocks/texture/sampler/bilinear_lerp.h"

namespace texsim {

namespace {

constexpr int64_t kCoordMax = (int64_t{1} << (FixedSampler::kCoordBits - 1)) - 1;

int64_t saturate(int64_t x, int64_t lo, int64_t hi) { return std::clamp(x, lo, hi); }

// Euclidean i mod m (m > 0).
int64_t mod_pos(int64_t i, int64_t m) {
  const int64_t r = i % m;
  return r < 0 ? r + m : r;
}

int32_t address_one(int64_t i, int32_t size, AddressMode mode) {
  switch (mode) {
    case AddressMode::Wrap:
      return static_cast<int32_t>(mod_pos(i, size));
    case AddressMode::Clamp:
      return static_cast<int32_t>(std::clamp<int64_t>(i, 0, size - 1));
    case AddressMode::Mirror: {
      const int64_t n = mod_pos(i, 2 * int64_t{size}) - size;
      return static_cast<int32_t>((size - 1) - (n >= 0 ? n : -(1 + n)));
    }
    case AddressMode::MirrorClamp:
      return static_cast<int32_t>(std::min<int64_t>(i >= 0 ? i : -(1 + i), size - 1));
    case AddressMode::Border:
      break;  // not covered (FixedSampler::covers)
  }
  return 0;
}

// The neighbours i and i + 1 of a linear filter; wrap derives i + 1 from i, as the C++ unit.
void address_pair(int64_t i, int32_t size, AddressMode mode, int32_t& a, int32_t& b) {
  a = address_one(i, size, mode);
  if (mode == AddressMode::Wrap)
    b = a + 1 == size ? 0 : a + 1;
  else
    b = address_one(i + 1, size, mode);
}

// Texel coordinate of level size `size` at normalised `c` (s15.32): c·size − ½, rounded half to
// even to `sub` fraction bits; integer part and fraction.
void texel_coord(int64_t c, int32_t size, int sub, int64_t& i, uint32_t& frac) {
  const int64_t x = c * size - (int64_t{1} << (FixedSampler::kCoordFrac - 1));
  const int64_t xf = FixedSampler::round_half_even(x, FixedSampler::kCoordFrac - sub);
  i = xf >> sub;
  frac = static_cast<uint32_t>(xf & ((int64_t{1} << sub) - 1));
}

// Derivative in texels of level 0, s15.16, from s15.32 normalised: floor, saturated.
uint64_t texel_square(int64_t d, int32_t size) {
  const int64_t t = saturate((d * size) >> (FixedSampler::kCoordFrac - FixedSampler::kDerivFrac),
                             INT32_MIN, INT32_MAX);
  const auto a = static_cast<uint64_t>(t < 0 ? -t : t);
  return a * a;
}

}  // namespace

const std::array<uint32_t, 257>& FixedSampler::log2_table() {
  static const std::array<uint32_t, 257> t = [] {
    std::array<uint32_t, 257> a{};
    for (size_t i = 0; i < a.size(); ++i) {
      const double l = std::log2(1.0 + static_cast<double>(i) / 256.0);
      a[i] = static_cast<uint32_t>(std::llround(std::ldexp(l, kLodFrac)));
    }
    return a;
  }();
  return t;
}

bool FixedSampler::covers(const TexelAddressGen::Config& a, const LodUnit::Config& l,
                          std::string* why) {
  std::string w;
  if (a.filter == FilterMode::Nearest) w = "nearest filter";
  if (a.uses_border()) w = "border addressing";
  if (a.reduces()) w = "min/max reduction or depth comparison";
  if (l.aniso != AnisoMode::Isotropic) w = "anisotropic LOD";
  if (why != nullptr) *why = w;
  return w.empty();
}

bool FixedSampler::covers_texture(const Texture& tex, std::string* why) {
  std::string w;
  if (tex.levels() > kMaxLevels) w = "more than " + std::to_string(kMaxLevels) + " levels";
  if (tex.format() != TexelFormat::Rgba8 || tex.storage() != StorageFormat::Rgba8Unorm)
    w = "texel storage other than rgba8 unorm";
  if (tex.compressed()) w = "compressed texture";
  if (tex.shape().type != TextureType::Tex2D) w = "layered or cube texture";
  if (why != nullptr) *why = w;
  return w.empty();
}

int32_t FixedSampler::to_lod(float x) {
  if (std::isnan(x)) return 0;
  const double s =
      std::clamp(std::ldexp(static_cast<double>(x), kLodFrac), -2147483648.0, 2147483647.0);
  return static_cast<int32_t>(std::nearbyint(s));
}

FixedSampler::Config FixedSampler::config_of(const TexelAddressGen::Config& a,
                                             const LodUnit::Config& l) {
  Config c;
  c.trilinear = a.filter == FilterMode::Trilinear;
  c.address_u = a.address_u;
  c.address_v = a.address_v;
  c.sub_bits = a.sub_texel_bits;
  c.mip_bits = a.mipmap_bits;
  c.offset_u = a.offset_u;
  c.offset_v = a.offset_v;
  c.bias = to_lod(l.lod_bias);
  c.min_lod = to_lod(l.min_lod);
  c.max_lod = to_lod(l.max_lod);
  return c;
}

FixedSampler::TextureDesc FixedSampler::describe(const Texture& tex) {
  TextureDesc d;
  d.w0 = tex.level(0).width;
  d.h0 = tex.level(0).height;
  d.levels = std::min(tex.levels(), kMaxLevels);
  d.layout = tex.layout();
  for (int l = 0; l < d.levels; ++l)
    d.base[static_cast<size_t>(l)] = static_cast<uint32_t>(tex.level(l).offset / 4);
  return d;
}

std::vector<uint32_t> FixedSampler::memory_image(const Texture& tex) {
  const TextureDesc d = describe(tex);
  std::vector<uint32_t> mem;
  for (int l = 0; l < d.levels; ++l) {
    const Texture::Level& lv = tex.level(l);
    const uint8_t* p = tex.rgba8(l);
    for (int y = 0; y < lv.height; ++y) {
      for (int x = 0; x < lv.width; ++x) {
        const size_t at = d.base[static_cast<size_t>(l)] + Texture::texel_index(d.layout, lv, x, y);
        if (mem.size() <= at) mem.resize(at + 1);
        const size_t i =
            (static_cast<size_t>(y) * static_cast<size_t>(lv.width) + static_cast<size_t>(x)) * 4;
        mem[at] = uint32_t{p[i]} | uint32_t{p[i + 1]} << 8 | uint32_t{p[i + 2]} << 16 |
                  uint32_t{p[i + 3]} << 24;
      }
    }
  }
  return mem;
}

int64_t FixedSampler::to_coord(double x) {
  const auto f = static_cast<float>(x);
  if (!std::isfinite(f)) return 0;
  const double s = std::clamp(std::ldexp(static_cast<double>(f), kCoordFrac),
                              -static_cast<double>(kCoordMax), static_cast<double>(kCoordMax));
  return static_cast<int64_t>(std::nearbyint(s));
}

FixedSampler::Input FixedSampler::to_input(const Fragment& f) {
  return {to_coord(f.u),    to_coord(f.v),    to_coord(f.dudx),
          to_coord(f.dvdx), to_coord(f.dudy), to_coord(f.dvdy)};
}

int32_t FixedSampler::lambda(const Input& in, const TextureDesc& t) const {
  const uint64_t px2 = texel_square(in.dudx, t.w0) + texel_square(in.dvdx, t.h0);
  const uint64_t py2 = texel_square(in.dudy, t.w0) + texel_square(in.dvdy, t.h0);
  const uint64_t r2 = std::max(px2, py2);
  int64_t log2v = kLog2Zero;
  if (r2 != 0) {
    const int p = 63 - std::countl_zero(r2);
    const uint64_t norm = r2 << (63 - p);  // leading one at bit 63
    const auto idx = static_cast<size_t>((norm >> (63 - kLog2Index)) & 255);
    const int64_t r = static_cast<int64_t>((norm >> (63 - kLog2Index - kLog2Interp)) & 4095);
    const auto& tab = log2_table();
    const int64_t l0 = tab[idx], l1 = tab[idx + 1];
    log2v = (int64_t{p - 2 * kDerivFrac} << kLodFrac) + l0 + (((l1 - l0) * r) >> kLog2Interp);
  }
  const int64_t lam = (log2v >> 1) + cfg_.bias;
  return static_cast<int32_t>(std::clamp<int64_t>(lam, cfg_.min_lod, cfg_.max_lod));
}

FixedSampler::Result FixedSampler::sample(const Input& in, const TextureDesc& t,
                                          const Memory& mem) const {
  return sample(in, t, mem, nullptr);
}

FixedSampler::Result FixedSampler::sample(const Input& in, const TextureDesc& t, const Memory& mem,
                                          std::array<LerpInput, 2>* lerps) const {
  Result r;
  const int m = cfg_.mip_bits;
  const int64_t q = std::max(t.levels, 1) - 1;
  const int64_t d = std::clamp<int64_t>(lambda(in, t), 0, q << kLodFrac);
  const int64_t dfix = round_half_even(d, kLodFrac - m);
  const int64_t one = int64_t{1} << m;
  if (cfg_.trilinear) {
    r.level_hi = static_cast<int32_t>(dfix >> m);
    r.level_lo = static_cast<int32_t>(std::min<int64_t>(r.level_hi + 1, q));
    r.delta = static_cast<uint32_t>(dfix & (one - 1));
  } else {
    const int64_t n = ((dfix + (one >> 1) + one - 1) >> m) - 1;
    r.level_hi = r.level_lo = static_cast<int32_t>(std::clamp<int64_t>(n, 0, q));
  }
  std::array<uint32_t, 2> colour{};
  const BilinearLerp lerp({8, cfg_.sub_bits});
  for (int k = 0; k < 2; ++k) {
    const int32_t level = k == 0 ? r.level_hi : r.level_lo;
    const int32_t wl = std::max(1, t.w0 >> level), hl = std::max(1, t.h0 >> level);
    int64_t i = 0, j = 0;
    uint32_t fx = 0, fy = 0;
    texel_coord(in.u, wl, cfg_.sub_bits, i, fx);
    texel_coord(in.v, hl, cfg_.sub_bits, j, fy);
    int32_t x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    address_pair(i + cfg_.offset_u, wl, cfg_.address_u, x0, x1);
    address_pair(j + cfg_.offset_v, hl, cfg_.address_v, y0, y1);
    Texture::Level lv;
    lv.width = wl;
    lv.height = hl;
    const uint32_t base = t.base[static_cast<size_t>(level)];
    auto at = [&](int32_t x, int32_t y) {
      return static_cast<uint32_t>(base + Texture::texel_index(t.layout, lv, x, y));
    };
    const std::array<uint32_t, 4> a = {at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1)};
    std::array<uint64_t, 4> quad{};
    for (size_t n = 0; n < 4; ++n) {
      r.addr[static_cast<size_t>(4 * k) + n] = a[n];
      quad[n] = a[n] < mem.size() ? mem[a[n]] : 0;
    }
    colour[static_cast<size_t>(k)] = static_cast<uint32_t>(lerp.lerp(quad, fx, fy));
    if (lerps) (*lerps)[static_cast<size_t>(k)] = {quad, fx, fy};
  }
  if (!cfg_.trilinear) {
    r.rgba = colour[0];
    return r;
  }
  // Per channel hi·2^M + (lo − hi)·δ, rounded half up once.
  for (int c = 0; c < 4; ++c) {
    const int64_t hi = (colour[0] >> (8 * c)) & 255, lo = (colour[1] >> (8 * c)) & 255;
    const int64_t v = ((hi << m) + (lo - hi) * static_cast<int64_t>(r.delta) + (one >> 1)) >> m;
    r.rgba |= static_cast<uint32_t>(v) << (8 * c);
  }
  return r;
}

uint32_t FixedSampler::lod_latency(const TechTable& tech) { return LodUnit().timing(tech).latency; }

uint32_t FixedSampler::address_latency(const TechTable& tech) {
  TexelAddressGen::Config c;
  c.filter = FilterMode::Trilinear;
  return TexelAddressGen(c).timing(tech).latency;
}

uint32_t FixedSampler::lerp_latency(const TechTable& tech) {
  return BilinearLerp().timing(tech).latency;
}

uint32_t FixedSampler::mip_latency(const TechTable& tech) {
  OpCounts path;
  path.add = 2;
  path.mul = 1;
  return static_cast<uint32_t>(std::lround(tech.path_latency(path)));
}

uint32_t FixedSampler::latency(const TechTable& tech) {
  return lod_latency(tech) + address_latency(tech) + kMemLatency + lerp_latency(tech) +
         mip_latency(tech);
}

OpCounts FixedSampler::ops_per_item(const TexelAddressGen::Config& a,
                                    const LodUnit::Config& l) const {
  const TexelAddressGen gen(a);
  OpCounts o = LodUnit(l).ops_per_item() + gen.ops_setup(false) + gen.ops_per_item(false);
  o += BilinearLerp::ops_per_item();
  if (cfg_.trilinear) {
    o += BilinearLerp::ops_per_item();
    o.add += uint64_t{2} * BilinearLerp::kChannels;
    o.mul += BilinearLerp::kChannels;
  }
  return o;
}

}  // namespace texsim
