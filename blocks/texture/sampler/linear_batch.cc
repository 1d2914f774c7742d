// The batched linear sampler (linear_batch.h), compiled once per SIMD target by Highway's
// foreach_target and dispatched at run time. Each step below names the scalar block it mirrors;
// operations are written in the scalar code's order so every float32 result is the same.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "blocks/texture/sampler/linear_batch.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
//
#include <hwy/highway.h>

#include "blocks/texture/sampler/linear_batch.h"

#ifndef TEXSIM_LINEAR_BATCH_ONCE
#define TEXSIM_LINEAR_BATCH_ONCE
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace texsim::linear_batch_detail {

constexpr size_t kMaxLevels = 32;

// Everything the SIMD part needs: the fragments (read straight from the caller's array) and
// the uniform parameters of the material and texture.
struct Input {
  const Fragment* frags = nullptr;
  size_t count = 0;
  uint32_t tex_id = 0;     // fragments on another texture are left to the scalar path
  float sampler_bias = 0;  // LodUnit::Config::lod_bias
  // Uniforms.
  float tex_w = 0, tex_h = 0;  // level 0 size
  bool isotropic = true;
  float max_aniso = 16;
  float min_lod = 0, max_lod = 0;
  bool trilinear = false;
  int32_t top_level = 0;  // q = levels − 1
  int mip_bits = 8, sub_bits = 8;
  float mip_scale = 256, mip_frac = 1.0f / 256, fix_scale = 256, frac_scale = 1.0f / 256;
  AddressMode address_u = AddressMode::Wrap, address_v = AddressMode::Wrap;
  alignas(64) int32_t level_w[kMaxLevels];
  alignas(64) int32_t level_h[kMaxLevels];
  alignas(64) int32_t level_first[kMaxLevels];
  const int32_t* texels = nullptr;  // the texture's RGBA8 store, one 32-bit word per texel
  float* colours = nullptr;         // count RGBA colours out (LinearBatch::rgba or the caller's)
  // Cache lines (line_shift > 0): each level's byte address and, for the tiled layout, the
  // texels per row of tiles.
  int line_shift = 0;
  TexelLayout layout = TexelLayout::Linear;
  alignas(64) int32_t level_base[kMaxLevels];
  alignas(64) int32_t level_tile_row[kMaxLevels];
};

}  // namespace texsim::linear_batch_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace texsim::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using linear_batch_detail::Input;

namespace {

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using MF = hn::Mask<DF>;

// TexelAddressGen::round_half_even for |x| < 2^31: below 2^23 add and subtract ±2^23, above
// it x is an integer already.
HWY_INLINE VI round_half_even(DF df, VF x) {
  const VF k = hn::Set(df, 8388608.0f);
  const VF c = hn::CopySign(k, x);
  const VF r = hn::IfThenElse(hn::Lt(hn::Abs(x), k), hn::Sub(hn::Add(x, c), c), x);
  return hn::ConvertTo(DI(), r);
}

// std::clamp(x, lo, hi) for non-NaN x: lo when x < lo, else hi when hi < x, else x.
HWY_INLINE VF clamp(VF x, VF lo, VF hi) {
  return hn::IfThenElse(hn::Lt(x, lo), lo, hn::IfThenElse(hn::Lt(hi, x), hi, x));
}

// texel_address_detail::address_pair for power-of-two sizes (wrap, mirror) or any (clamp).
HWY_INLINE void address_pair(DI di, VI i, VI size, AddressMode mode, VI& a, VI& b) {
  const VI one = hn::Set(di, 1);
  const VI zero = hn::Zero(di);
  const VI last = hn::Sub(size, one);
  switch (mode) {
    case AddressMode::Wrap: {
      a = hn::And(i, last);
      const VI next = hn::Add(a, one);
      b = hn::IfThenElse(hn::Eq(next, size), zero, next);
      return;
    }
    case AddressMode::Clamp:
      a = hn::Min(hn::Max(i, zero), last);
      b = hn::Min(hn::Max(hn::Add(i, one), zero), last);
      return;
    case AddressMode::Mirror: {
      // (size − 1) − m, m = n ≥ 0 ? n : −(1 + n) = ~n, n = (i mod 2·size) − size.
      const VI mask2 = hn::Sub(hn::Add(size, size), one);
      const auto mirror = [&](VI j) {
        const VI n = hn::Sub(hn::And(j, mask2), size);
        const VI m = hn::IfThenElse(hn::Lt(n, zero), hn::Not(n), n);
        return hn::Sub(last, m);
      };
      a = mirror(i);
      b = mirror(hn::Add(i, one));
      return;
    }
    case AddressMode::Border:
    case AddressMode::MirrorClamp:
      a = b = i;  // refused by serves(): the one-by-one kernel's
      return;
  }
}

// TexelAddressGen::linear_quad on per-lane levels: writes the quad's texels and weights (× w).
struct Quad {
  VI x0, x1, y0, y1;
  VF w[4];
  MF fits;  // fixed-point coordinates within int32
};

// A level's entries of the per-level tables, per lane. The lanes of a vector are neighbouring
// fragments and nearly always on one level: then one scalar read each instead of a gather.
struct LevelInfo {
  VI level, w, h, first;
  bool uniform;
  int32_t l0;  // the level of lane 0
  VI of(const int32_t* table) const {
    const DI di;
    return uniform ? hn::Set(di, table[l0]) : hn::GatherIndex(di, table, level);
  }
};

HWY_INLINE LevelInfo level_info(const Input& in, VI level) {
  const DI di;
  LevelInfo li;
  li.level = level;
  li.l0 = hn::GetLane(level);
  li.uniform = hn::AllTrue(di, hn::Eq(level, hn::Set(di, li.l0)));
  li.w = li.of(in.level_w);
  li.h = li.of(in.level_h);
  li.first = li.of(in.level_first);
  return li;
}

HWY_INLINE Quad linear_quad(const Input& in, const LevelInfo& li, VF u, VF v, VF w,
                            bool unit_weight) {
  const DF df;
  const DI di;
  const VI wl = li.w, hl = li.h;
  const VF half = hn::Set(df, 0.5f), limit = hn::Set(df, 1073741824.0f);  // 2^30
  const VF scale = hn::Set(df, in.fix_scale);
  VF xs = hn::Sub(hn::Mul(u, hn::ConvertTo(df, wl)), half);
  VF ys = hn::Sub(hn::Mul(v, hn::ConvertTo(df, hl)), half);
  xs = hn::Mul(clamp(xs, hn::Neg(limit), limit), scale);
  ys = hn::Mul(clamp(ys, hn::Neg(limit), limit), scale);
  Quad q;
  const VF int_limit = hn::Set(df, 2147483648.0f);  // 2^31
  q.fits = hn::And(hn::Lt(hn::Abs(xs), int_limit), hn::Lt(hn::Abs(ys), int_limit));
  const VI xf = round_half_even(df, xs), yf = round_half_even(df, ys);
  const VI mask = hn::Set(di, (int32_t{1} << in.sub_bits) - 1);
  const VF fs = hn::Set(df, in.frac_scale);
  const VF a = hn::Mul(hn::ConvertTo(df, hn::And(xf, mask)), fs);
  const VF be = hn::Mul(hn::ConvertTo(df, hn::And(yf, mask)), fs);
  address_pair(di, hn::ShiftRightSame(xf, in.sub_bits), wl, in.address_u, q.x0, q.x1);
  address_pair(di, hn::ShiftRightSame(yf, in.sub_bits), hl, in.address_v, q.y0, q.y1);
  const VF one = hn::Set(df, 1.0f);
  const VF wi0 = hn::Sub(one, a), wj0 = hn::Sub(one, be);
  q.w[0] = hn::Mul(wi0, wj0);
  q.w[1] = hn::Mul(a, wj0);
  q.w[2] = hn::Mul(wi0, be);
  q.w[3] = hn::Mul(a, be);
  if (!unit_weight) {
    for (VF& x : q.w) x = hn::Mul(x, w);
  }
  return q;
}

// FetchRgba8::at · w for one texel per lane: the 32-bit word, channels c·(1/255), times w.
struct Texel {
  VF r, g, b, a;
};
// The channels of one texel word per lane, c·(1/255), times w (FetchRgba8::at · w).
HWY_INLINE Texel product(VI word, VF w) {
  const DF df;
  const DI di;
  const VI byte = hn::Set(di, 0xff);
  const VF k = hn::Set(df, 1.0f / 255.0f);
  const auto channel = [&](int shift) {
    const VI c = hn::And(hn::ShiftRightSame(word, shift), byte);
    return hn::Mul(hn::Mul(hn::ConvertTo(df, c), k), w);
  };
  return {channel(0), channel(8), channel(16), channel(24)};
}
HWY_INLINE Texel add(const Texel& p, const Texel& q) {
  return {hn::Add(p.r, q.r), hn::Add(p.g, q.g), hn::Add(p.b, q.b), hn::Add(p.a, q.a)};
}

// The quad's four RGBA8 words in tap order. A row's two texels are neighbours in the store
// (x1 = x0 + 1) except at a wrap or a clamped edge, so each row is one 8-byte load per lane:
// two scalar loads per fragment where gathers took four (and gathers are slow on AMD Zen).
HWY_INLINE void quad_words(const Input& in, const LevelInfo& li, const Quad& q, VI* word) {
  const DI di;
  constexpr size_t kLanes = hn::MaxLanes(DI());
  HWY_ALIGN int32_t row0[kLanes], row1[kLanes], dx[kLanes];
  HWY_ALIGN int32_t pair0[2 * kLanes], pair1[2 * kLanes];
  hn::Store(hn::Add(li.first, hn::Add(hn::Mul(q.y0, li.w), q.x0)), di, row0);
  hn::Store(hn::Add(li.first, hn::Add(hn::Mul(q.y1, li.w), q.x0)), di, row1);
  hn::Store(hn::Sub(q.x1, q.x0), di, dx);
  const int32_t* const t = in.texels;
  for (size_t k = 0; k < hn::Lanes(di); ++k) {
    const int32_t* const a = t + row0[k];
    const int32_t* const b = t + row1[k];
    if (HWY_LIKELY(dx[k] == 1)) {
      std::memcpy(pair0 + 2 * k, a, 8);
      std::memcpy(pair1 + 2 * k, b, 8);
    } else {
      pair0[2 * k] = a[0];
      pair0[2 * k + 1] = a[dx[k]];
      pair1[2 * k] = b[0];
      pair1[2 * k + 1] = b[dx[k]];
    }
  }
  hn::LoadInterleaved2(di, pair0, word[0], word[1]);
  hn::LoadInterleaved2(di, pair1, word[2], word[3]);
}

// The adder tree of one quad: (p0 + p1) + (p2 + p3).
HWY_INLINE Texel quad_sum(const Input& in, const LevelInfo& li, const Quad& q) {
  VI word[4];
  quad_words(in, li, q, word);
  const Texel p0 = product(word[0], q.w[0]);
  const Texel p1 = product(word[1], q.w[1]);
  const Texel p2 = product(word[2], q.w[2]);
  const Texel p3 = product(word[3], q.w[3]);
  return add(add(p0, p1), add(p2, p3));
}

// Texture::spread_bits for 16-bit values: the bits moved to the even positions.
HWY_INLINE VI spread_bits(DI di, VI v) {
  v = hn::And(hn::Or(v, hn::ShiftLeft<8>(v)), hn::Set(di, 0x00ff00ff));
  v = hn::And(hn::Or(v, hn::ShiftLeft<4>(v)), hn::Set(di, 0x0f0f0f0f));
  v = hn::And(hn::Or(v, hn::ShiftLeft<2>(v)), hn::Set(di, 0x33333333));
  return hn::And(hn::Or(v, hn::ShiftLeft<1>(v)), hn::Set(di, 0x55555555));
}

// Texture::row_index and col_index of the texture's layout.
HWY_INLINE VI row_index(const Input& in, const LevelInfo& li, VI y) {
  const DI di;
  switch (in.layout) {
    case TexelLayout::Linear:
      return hn::Mul(y, li.w);
    case TexelLayout::Tiled4x4:
      return hn::Add(hn::Mul(hn::ShiftRight<2>(y), li.of(in.level_tile_row)),
                     hn::ShiftLeft<2>(hn::And(y, hn::Set(di, 3))));
    case TexelLayout::Morton:
      return hn::ShiftLeft<1>(spread_bits(di, y));
  }
  return y;
}
HWY_INLINE VI col_index(const Input& in, VI x) {
  const DI di;
  switch (in.layout) {
    case TexelLayout::Linear:
      return x;
    case TexelLayout::Tiled4x4:
      return hn::Add(hn::ShiftLeft<4>(hn::ShiftRight<2>(x)), hn::And(x, hn::Set(di, 3)));
    case TexelLayout::Morton:
      return spread_bits(di, x);
  }
  return x;
}

// The cache lines of a quad's four taps (tap order), as the texture unit's cache model
// computes them: (level address + texel index · 4) >> line_shift.
HWY_INLINE void quad_lines(const Input& in, const LevelInfo& li, const Quad& q, VI* line) {
  const VI base = li.of(in.level_base);
  const VI r0 = row_index(in, li, q.y0), r1 = row_index(in, li, q.y1);
  const VI c0 = col_index(in, q.x0), c1 = col_index(in, q.x1);
  const auto at = [&](VI r, VI c) {
    return hn::ShiftRightSame(hn::Add(base, hn::ShiftLeft<2>(hn::Add(r, c))), in.line_shift);
  };
  line[0] = at(r0, c0);
  line[1] = at(r0, c1);
  line[2] = at(r1, c0);
  line[3] = at(r1, c1);
}

// Bit k set when line k differs from lines 0 .. k − 1.
HWY_INLINE VI first_use(DI di, const VI* line, int n) {
  VI bits = hn::Set(di, 1);
  for (int k = 1; k < n; ++k) {
    auto fresh = hn::Ne(line[k], line[0]);
    for (int j = 1; j < k; ++j) fresh = hn::And(fresh, hn::Ne(line[k], line[j]));
    bits = hn::Or(bits, hn::IfThenElseZero(fresh, hn::Set(di, 1 << k)));
  }
  return bits;
}

// One vector of fragments as the scalar blocks convert them (LodUnit::eval,
// TexelAddressGen::taps): derivatives and coordinates to float32, bias = sampler + fragment.
// `ok`: the lanes the batch takes — on its texture, with finite float32 derivatives and bias
// (a double that overflows float32 goes to the scalar path too, which has its own rules).
struct Lanes {
  VF u, v, dudx, dvdx, dudy, dvdy, bias;
  MF ok;
};

// The batch's fragments as float32 columns (the scalar blocks' conversions), read in one
// sequential pass: gathering fields straight from the 88-byte fragments stalled on every new
// cache line (the hardware prefetchers do not follow gathers), most of the batch's time on
// AMD Zen 4.
struct Columns {
  static constexpr size_t kPadded = LinearBatch::kMax + 16;
  alignas(64) float u[kPadded], v[kPadded];
  alignas(64) float dudx[kPadded], dvdx[kPadded], dudy[kPadded], dvdy[kPadded];
  alignas(64) float bias[kPadded];
  alignas(64) int32_t tex[kPadded];
  bool one_frame = true;  // every fragment on the first one's frame
};

// Fills c with fragments 0 .. count and zeros up to the next whole vector (lanes past the end
// are not done). Not vectorised: a vectorised loop would gather the strided fields again.
#if defined(__clang__)
#define TEXSIM_NO_TREE_VECTORIZE
#else
#define TEXSIM_NO_TREE_VECTORIZE [[gnu::optimize("no-tree-vectorize")]]
#endif
TEXSIM_NO_TREE_VECTORIZE HWY_NOINLINE void load_columns(const Input& in, Columns& c) {
  const size_t padded = hwy::RoundUpTo(in.count, hn::Lanes(DF()));
  const uint32_t frame = in.count > 0 ? in.frags[0].frame : 0;
  bool one_frame = true;
  for (size_t k = 0; k < in.count; ++k) {
    const Fragment& f = in.frags[k];
    one_frame &= f.frame == frame;
    c.u[k] = static_cast<float>(f.u);
    c.v[k] = static_cast<float>(f.v);
    c.dudx[k] = static_cast<float>(f.dudx);
    c.dvdx[k] = static_cast<float>(f.dvdx);
    c.dudy[k] = static_cast<float>(f.dudy);
    c.dvdy[k] = static_cast<float>(f.dvdy);
    // A fragment with an explicit operation (Fragment::op) is left to the one-by-one path: a
    // non-finite bias takes its lane out of the batch.
    // So is one that picks a sampler or has constant offsets of its own.
    const bool own = (f.op | f.sampler | f.offset_u | f.offset_v) == 0;
    c.bias[k] = own ? f.lod_bias : std::numeric_limits<float>::quiet_NaN();
    c.tex[k] = static_cast<int32_t>(f.tex);
  }
  c.one_frame = one_frame;
  for (size_t k = in.count; k < padded; ++k) {
    c.u[k] = c.v[k] = c.dudx[k] = c.dvdx[k] = c.dudy[k] = c.dvdy[k] = c.bias[k] = 0;
    c.tex[k] = 0;
  }
}

HWY_INLINE Lanes load_lanes(const Input& in, const Columns& c, size_t i) {
  const DF df;
  const DI di;
  Lanes l;
  const VF u = hn::Load(df, c.u + i);
  const VF v = hn::Load(df, c.v + i);
  l.u = hn::IfThenElseZero(hn::IsFinite(u), u);  // finite_or_zero
  l.v = hn::IfThenElseZero(hn::IsFinite(v), v);
  l.dudx = hn::Load(df, c.dudx + i);
  l.dvdx = hn::Load(df, c.dvdx + i);
  l.dudy = hn::Load(df, c.dudy + i);
  l.dvdy = hn::Load(df, c.dvdy + i);
  l.bias = hn::Add(hn::Set(df, in.sampler_bias), hn::Load(df, c.bias + i));
  const VI tex = hn::Load(di, c.tex + i);
  const VI lane = hn::Add(hn::Iota(di, 0), hn::Set(di, static_cast<int32_t>(i)));
  l.ok = hn::RebindMask(df, hn::And(hn::Eq(tex, hn::Set(di, static_cast<int32_t>(in.tex_id))),
                                    hn::Lt(lane, hn::Set(di, static_cast<int32_t>(in.count)))));
  l.ok = hn::And(l.ok, hn::And(hn::And(hn::IsFinite(l.dudx), hn::IsFinite(l.dvdx)),
                               hn::And(hn::IsFinite(l.dudy), hn::IsFinite(l.dvdy))));
  l.ok = hn::And(l.ok, hn::IsFinite(l.bias));
  return l;
}

// LodUnit::eval's ρ² for lanes whose inputs are finite; `ok` loses the lanes the scalar
// path must take (ρ² overflow, anisotropic N > 1).
HWY_INLINE VF lod_rho2(const Input& in, const Lanes& l, MF& ok) {
  const DF df;
  const VF mux = hn::Mul(l.dudx, hn::Set(df, in.tex_w));
  const VF mvx = hn::Mul(l.dvdx, hn::Set(df, in.tex_h));
  const VF muy = hn::Mul(l.dudy, hn::Set(df, in.tex_w));
  const VF mvy = hn::Mul(l.dvdy, hn::Set(df, in.tex_h));
  const VF px2 = hn::Add(hn::Mul(mux, mux), hn::Mul(mvx, mvx));
  const VF py2 = hn::Add(hn::Mul(muy, muy), hn::Mul(mvy, mvy));
  // std::max(px2, py2) returns px2 unless px2 < py2.
  const VF rmax2 = hn::IfThenElse(hn::Lt(px2, py2), py2, px2);
  ok = hn::And(ok, hn::IsFinite(rmax2));
  if (!in.isotropic) {
    // N = 1 exactly when η ≤ 1: ρmax² = 0, or ρmin² = 0 with maxAniso 1, or min(√(ρmax²/ρmin²),
    // maxAniso) ≤ 1.
    const VF rmin2 = hn::IfThenElse(hn::Lt(py2, px2), py2, px2);
    const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), max_aniso = hn::Set(df, in.max_aniso);
    const VF ratio = hn::Sqrt(hn::Div(rmax2, hn::IfThenElse(hn::Eq(rmin2, zero), one, rmin2)));
    const VF eta =
        hn::IfThenElse(hn::Eq(rmax2, zero), one,
                       hn::IfThenElse(hn::Eq(rmin2, zero), max_aniso,
                                      hn::IfThenElse(hn::Lt(max_aniso, ratio), max_aniso, ratio)));
    ok = hn::And(ok, hn::Le(eta, one));
  }
  return rmax2;
}

// The scalar path's λ → fixed-point d' for one lane: ½·log2f(ρ²) + bias, clamped to
// [min_lod, max_lod] and [0, q], times 2^m, rounded to nearest even (LodUnit::eval,
// TexelAddressGen::select_levels, restated for one lane; test_linear_batch compares the
// results with those blocks near every tie). It keeps the lanes the interval leaves undecided
// in the batch: rare at 8 mipmap bits, but 60 % of ordinary lanes at 16.
int32_t scalar_dfix(const Input& in, float rmax2, float bias) {
  const float lambda = std::clamp(0.5f * std::log2(rmax2) + bias, in.min_lod, in.max_lod);
  const float d = std::clamp(lambda, 0.0f, static_cast<float>(in.top_level));
  return static_cast<int32_t>(TexelAddressGen::round_half_even(d * in.mip_scale));
}

#if HWY_TARGET != HWY_SCALAR
// d' in fixed point without libm: log2 ρ² in double (exponent + a series for the mantissa,
// |error| < 1e-12), then the interval the scalar float32 path can land in: the C library's
// log2f within 4 ulp of the exact value (glibc's is within 1; test_linear_batch checks it over
// the float range) and the float32 addition of the bias within 2 ulp. Where the whole interval
// rounds to one fixed-point value, that value is the scalar path's; the other lanes
// (`unsure`) take the scalar path's own arithmetic.
template <class DD>
HWY_INLINE hn::Vec<DD> dfix_half(DD dd, hn::Vec<DD> e, hn::Vec<DD> m, hn::Vec<DD> bias,
                                 const Input& in, hn::Mask<DD>& sure) {
  using VD = hn::Vec<DD>;
  const VD one = hn::Set(dd, 1.0);
  const VD sv = hn::Div(hn::Sub(m, one), hn::Add(m, one));  // |s| <= 0.1716
  const VD z = hn::Mul(sv, sv);
  // ln m = 2s (1 + z/3 + z²/5 + … + z⁷/15): the first omitted term is below 1e-13.
  VD poly = hn::Set(dd, 1.0 / 15);
  for (double k : {13.0, 11.0, 9.0, 7.0, 5.0, 3.0, 1.0})
    poly = hn::Add(hn::Mul(poly, z), hn::Set(dd, 1.0 / k));
  const VD y = hn::Add(e, hn::Mul(hn::Mul(hn::Add(sv, sv), poly), hn::Set(dd, 1.4426950408889634)));
  const VD unit = hn::Set(dd, 1.0);
  const VD ey =
      hn::Add(hn::Mul(hn::Set(dd, 0x1p-21), hn::Max(hn::Abs(y), unit)), hn::Set(dd, 1e-9));
  const VD half = hn::Set(dd, 0.5);
  VD lo = hn::Add(hn::Mul(half, hn::Sub(y, ey)), bias);
  VD hi = hn::Add(hn::Mul(half, hn::Add(y, ey)), bias);
  const VD eb = hn::Mul(hn::Set(dd, 0x1p-22), hn::Max(hn::Max(hn::Abs(lo), hn::Abs(hi)), unit));
  lo = hn::Sub(lo, eb);
  hi = hn::Add(hi, eb);
  const auto clamp_d = [&](VD x) {
    x = hn::Min(hn::Max(x, hn::Set(dd, in.min_lod)), hn::Set(dd, in.max_lod));
    x = hn::Min(hn::Max(x, hn::Zero(dd)), hn::Set(dd, static_cast<double>(in.top_level)));
    return hn::Mul(x, hn::Set(dd, static_cast<double>(in.mip_scale)));
  };
  const VD xl = hn::Add(clamp_d(lo), half), xh = hn::Add(clamp_d(hi), half);
  const VD kl = hn::Floor(xl), kh = hn::Floor(xh);
  // One integer for the whole interval, and no tie (x + ½ an integer) at its low end.
  sure = hn::And(hn::Eq(kl, kh), hn::Lt(kl, xl));
  return kl;
}

HWY_INLINE VI level_fixed(const Input& in, VF rmax2, VF bias, MF ok) {
  const DF df;
  const DI di;
  const hn::Half<DF> dh;
  const hn::Rebind<double, decltype(dh)> dd;
  const hn::Rebind<int32_t, decltype(dd)> dih;
  // ρ² = 2^e · m, m in [√½, √2) (exact in float32 for a normal ρ²).
  const VI bits = hn::BitCast(di, rmax2);
  VI e = hn::Sub(hn::ShiftRight<23>(bits), hn::Set(di, 127));
  VF m = hn::BitCast(df, hn::Or(hn::And(bits, hn::Set(di, 0x7fffff)), hn::Set(di, 0x3f800000)));
  const auto big = hn::Gt(m, hn::Set(df, 1.41421356f));
  m = hn::IfThenElse(big, hn::Mul(m, hn::Set(df, 0.5f)), m);
  e = hn::Add(e, hn::IfThenElseZero(hn::RebindMask(di, big), hn::Set(di, 1)));
  const VF ef = hn::ConvertTo(df, e);
  hn::Mask<decltype(dd)> sure_lo, sure_hi;
  const auto klo = dfix_half(dd, hn::PromoteTo(dd, hn::LowerHalf(dh, ef)),
                             hn::PromoteTo(dd, hn::LowerHalf(dh, m)),
                             hn::PromoteTo(dd, hn::LowerHalf(dh, bias)), in, sure_lo);
  const auto khi = dfix_half(dd, hn::PromoteTo(dd, hn::UpperHalf(dh, ef)),
                             hn::PromoteTo(dd, hn::UpperHalf(dh, m)),
                             hn::PromoteTo(dd, hn::UpperHalf(dh, bias)), in, sure_hi);
  VI dfix = hn::Combine(di, hn::DemoteTo(dih, khi), hn::DemoteTo(dih, klo));
  const auto sure_d = [&](hn::Mask<decltype(dd)> s) {
    return hn::DemoteTo(dih, hn::IfThenElseZero(s, hn::Set(dd, 1.0)));
  };
  const VI sure = hn::Combine(di, sure_d(sure_hi), sure_d(sure_lo));
  // Zero and subnormal ρ² (log2 −inf, or no implicit bit) are the scalar arithmetic's too.
  const MF normal = hn::Ge(rmax2, hn::Set(df, 0x1p-126f));
  const MF unsure = hn::AndNot(hn::And(normal, hn::RebindMask(df, hn::Ne(sure, hn::Zero(di)))), ok);
  if (!hn::AllFalse(df, unsure)) {
    HWY_ALIGN float r[hn::MaxLanes(df)], b[hn::MaxLanes(df)];
    HWY_ALIGN int32_t d[hn::MaxLanes(df)], u[hn::MaxLanes(df)];
    hn::Store(rmax2, df, r);
    hn::Store(bias, df, b);
    hn::Store(dfix, di, d);
    hn::Store(hn::VecFromMask(di, hn::RebindMask(di, unsure)), di, u);
    for (size_t k = 0; k < hn::Lanes(df); ++k) {
      if (u[k]) d[k] = scalar_dfix(in, r[k], b[k]);
    }
    dfix = hn::Load(di, d);
  }
  return dfix;
}
#else
HWY_INLINE VI level_fixed(const Input& in, VF rmax2, VF bias, MF ok) {
  const DI di;
  if (hn::AllFalse(DF(), ok)) return hn::Zero(di);
  return hn::Set(di, scalar_dfix(in, hn::GetLane(rmax2), hn::GetLane(bias)));
}
#endif

}  // namespace

void FilterLinearBatch(const Input& in, LinearBatch& out) {
  const DF df;
  const DI di;
  const size_t lanes = hn::Lanes(df);
  const VI zero_i = hn::Zero(di);
  const VI top = hn::Set(di, in.top_level);
  const int m = in.mip_bits;
  const VI one_fix = hn::Set(di, int32_t{1} << m);
  Columns cols;
  load_columns(in, cols);
  // The fragments after the batch (in a trace, the next batch) are brought into the cache
  // while this one computes, a vector's worth at a time: load_columns otherwise waited for
  // memory. A prefetch past the end of the caller's array does not fault.
  const char* const next = reinterpret_cast<const char*>(in.frags + in.count);
  size_t done = 0;
  for (size_t i = 0; i < in.count; i += lanes) {
    for (size_t b = i * sizeof(Fragment); b < (i + lanes) * sizeof(Fragment); b += 64)
      __builtin_prefetch(next + b);
    const Lanes l = load_lanes(in, cols, i);
    MF ok = l.ok;
    const VF rmax2 = lod_rho2(in, l, ok);
    // TexelAddressGen::select_levels: d' = clamp(λ, 0, q) to fixed point with m fraction bits.
    const VI dfix = level_fixed(in, rmax2, l.bias, ok);
    const VF u = l.u, v = l.v;
    Texel sum;
    VI level_hi, level_lo;
    Quad q0, q1;
    LevelInfo li0, li1;
    if (in.trilinear) {
      // (Clamped so lanes left to the scalar path, whose λ may be NaN, read in range.)
      level_hi = hn::Min(hn::Max(hn::ShiftRightSame(dfix, m), zero_i), top);
      level_lo = hn::Min(hn::Add(level_hi, hn::Set(di, 1)), top);
      const VF delta = hn::Mul(hn::ConvertTo(df, hn::And(dfix, hn::Sub(one_fix, hn::Set(di, 1)))),
                               hn::Set(df, in.mip_frac));
      li0 = level_info(in, level_hi);
      li1 = level_info(in, level_lo);
      q0 = linear_quad(in, li0, u, v, hn::Sub(hn::Set(df, 1.0f), delta), false);
      q1 = linear_quad(in, li1, u, v, delta, false);
      ok = hn::And(ok, hn::And(q0.fits, q1.fits));
      sum = add(quad_sum(in, li0, q0), quad_sum(in, li1, q1));
    } else {
      // Vulkan's nearest(d') = ⌈d' + ½⌉ − 1, clamped to [0, q].
      const VI half = hn::Set(di, (int32_t{1} << m) >> 1);
      const VI up = hn::Add(hn::Add(dfix, half), hn::Sub(one_fix, hn::Set(di, 1)));
      level_hi = hn::Sub(hn::ShiftRightSame(up, m), hn::Set(di, 1));
      level_hi = hn::Min(hn::Max(level_hi, zero_i), top);
      level_lo = level_hi;
      li0 = level_info(in, level_hi);
      q0 = linear_quad(in, li0, u, v, hn::Set(df, 1.0f), true);
      ok = hn::And(ok, q0.fits);
      sum = quad_sum(in, li0, q0);
    }
    // TexelBlend's accumulator starts at 0.
    const VF z = hn::Zero(df);
    if (i + lanes <= in.count || in.colours == out.rgba) {
      hn::StoreInterleaved4(hn::Add(z, sum.r), hn::Add(z, sum.g), hn::Add(z, sum.b),
                            hn::Add(z, sum.a), df, in.colours + 4 * i);
    } else {  // the last, partial vector: not past the caller's array
      hn::StoreInterleaved4(hn::Add(z, sum.r), hn::Add(z, sum.g), hn::Add(z, sum.b),
                            hn::Add(z, sum.a), df, out.rgba + 4 * i);
      std::memcpy(in.colours + 4 * i, out.rgba + 4 * i, (in.count - i) * 4 * sizeof(float));
    }
    hn::Store(hn::VecFromMask(di, hn::RebindMask(di, ok)), di, out.done + i);
    done += hn::CountTrue(df, ok);
    hn::Store(level_hi, di, out.level[0] + i);
    hn::Store(q0.x0, di, out.x0[0] + i);
    hn::Store(q0.x1, di, out.x1[0] + i);
    hn::Store(q0.y0, di, out.y0[0] + i);
    hn::Store(q0.y1, di, out.y1[0] + i);
    if (in.line_shift > 0) {
      VI line[8];
      quad_lines(in, li0, q0, line);
      if (in.trilinear) quad_lines(in, li1, q1, line + 4);
      const int taps = in.trilinear ? 8 : 4;
      for (int k = 0; k < taps; ++k) hn::Store(line[k], di, out.line[k] + i);
      hn::Store(first_use(di, line, taps), di, out.first_use + i);
    }
    if (in.trilinear) {
      hn::Store(level_lo, di, out.level[1] + i);
      hn::Store(q1.x0, di, out.x0[1] + i);
      hn::Store(q1.x1, di, out.x1[1] + i);
      hn::Store(q1.y0, di, out.y0[1] + i);
      hn::Store(q1.y1, di, out.y1[1] + i);
    }
  }
  out.all_done = done == in.count;  // (lanes past the count are never done)
  out.one_frame = cols.one_frame;
}

}  // namespace texsim::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace texsim {

HWY_EXPORT(FilterLinearBatch);

namespace {
bool pow2(int n) { return n > 0 && (n & (n - 1)) == 0; }

// Whether every texel address of `tex` is below 2^31, so the batch computes addresses in int32
// (each layout's index grows with x and y: the last texel of a level has its largest).
bool lines_fit_int32(const Texture& tex) {
  for (int l = 0; l < tex.levels(); ++l) {
    if (tex.address(l, tex.width(l) - 1, tex.height(l) - 1) + 4 > (uint64_t{1} << 31)) return false;
  }
  return true;
}
}  // namespace

LinearBatchSampler::LinearBatchSampler(const LodUnit::Config& lod,
                                       const TexelAddressGen::Config& addr)
    : lod_(lod), addr_(addr) {
  if (addr.filter == FilterMode::Nearest)
    throw std::invalid_argument("LinearBatchSampler: the filter must be bilinear or trilinear");
}

bool LinearBatchSampler::serves(const Texture& tex) const {
  // 8-bit RGBA texels of 4 bytes in memory: the batch's lines are computed at 4 bytes a texel
  // (an R8 or RG8 texture keeps the 8-bit store but takes 1 or 2 bytes in memory).
  if (tex.format() != TexelFormat::Rgba8 || tex.bytes_per_texel() != 4) return false;
  if (tex.levels() < 1 || tex.levels() > static_cast<int>(linear_batch_detail::kMaxLevels))
    return false;
  // Border and mirror-clamp addressing and texel offsets are the one-by-one kernel's
  // (bit-identical results either way; docs/derivations/filters.md §2).
  for (AddressMode m : {addr_.address_u, addr_.address_v}) {
    if (m == AddressMode::Border || m == AddressMode::MirrorClamp) return false;
  }
  if (addr_.offset_u != 0 || addr_.offset_v != 0) return false;
  uint64_t texels = 0;
  for (int l = 0; l < tex.levels(); ++l) {
    const int w = tex.width(l), h = tex.height(l);
    if (addr_.address_u != AddressMode::Clamp && !pow2(w)) return false;
    if (addr_.address_v != AddressMode::Clamp && !pow2(h)) return false;
    texels += static_cast<uint64_t>(w) * static_cast<uint64_t>(h);
  }
  return texels < (uint64_t{1} << 31);
}

void LinearBatchSampler::filter(const Fragment* f, size_t n, const Texture& tex, LinearBatch& out,
                                uint32_t line_shift, Rgba* colours) const {
  if (n > LinearBatch::kMax) throw std::invalid_argument("LinearBatchSampler: batch too large");
  static_assert(std::endian::native == std::endian::little, "RGBA8 words assume little-endian");
  linear_batch_detail::Input in;
  in.frags = f;
  in.count = n;
  in.tex_id = f[0].tex;
  in.sampler_bias = lod_.lod_bias;
  in.tex_w = static_cast<float>(tex.width(0));
  in.tex_h = static_cast<float>(tex.height(0));
  in.isotropic = lod_.aniso == AnisoMode::Isotropic || lod_.max_aniso <= 1;
  in.max_aniso = static_cast<float>(lod_.max_aniso);
  in.min_lod = lod_.min_lod;
  in.max_lod = lod_.max_lod;
  in.trilinear = addr_.filter == FilterMode::Trilinear;
  in.top_level = tex.levels() - 1;
  in.mip_bits = addr_.mipmap_bits;
  in.sub_bits = addr_.sub_texel_bits;
  in.mip_scale = std::ldexp(1.0f, addr_.mipmap_bits);
  in.mip_frac = std::ldexp(1.0f, -addr_.mipmap_bits);
  in.fix_scale = std::ldexp(1.0f, addr_.sub_texel_bits);
  in.frac_scale = std::ldexp(1.0f, -addr_.sub_texel_bits);
  in.address_u = addr_.address_u;
  in.address_v = addr_.address_v;
  for (int l = 0; l < tex.levels(); ++l) {
    in.level_w[l] = tex.width(l);
    in.level_h[l] = tex.height(l);
    in.level_first[l] = static_cast<int32_t>(tex.level(l).first);
  }
  in.texels = reinterpret_cast<const int32_t*>(tex.rgba8(0));
  static_assert(sizeof(Rgba) == 4 * sizeof(float), "an Rgba is four packed floats");
  in.colours = colours ? reinterpret_cast<float*>(colours) : out.rgba;
  out.has_lines = line_shift > 0 && lines_fit_int32(tex);
  if (out.has_lines) {
    in.line_shift = static_cast<int>(line_shift);
    in.layout = tex.layout();
    for (int l = 0; l < tex.levels(); ++l) {
      in.level_base[l] = static_cast<int32_t>(tex.base() + tex.level(l).offset);
      in.level_tile_row[l] = ((tex.width(l) + 3) / 4) * 16;
    }
  }
  HWY_DYNAMIC_DISPATCH(FilterLinearBatch)(in, out);
}

const char* LinearBatchSampler::target() {
  // Highway's better targets are the lower bits: the best supported one of those compiled in.
  const int64_t targets = hwy::SupportedTargets() & HWY_TARGETS;
  return hwy::TargetName(targets & -targets);
}

}  // namespace texsim
#endif
