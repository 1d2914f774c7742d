#include "blocks/texture/layered/layered_address_gen.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "blocks/texture/layered/cube_seam.h"
#include "blocks/texture/memory/storage_format.h"

namespace texsim {

int LayeredAddressGen::select_layer(float a, int layers) {
  if (!std::isfinite(a) || layers <= 1) return 0;
  const float hi = static_cast<float>(layers - 1);
  // Clamp first (in float: huge layers stay in range), then round half to even.
  const float c = std::clamp(a, -1.0f, hi + 1.0f);
  return static_cast<int>(std::clamp<int64_t>(TexelAddressGen::round_half_even(c), 0, layers - 1));
}

TexelTap* LayeredAddressGen::emit(const Texture& tex, int slice, int32_t mip, float u, float v,
                                  float w, bool cube, TexelTap* t) const {
  using namespace texel_address_detail;
  const TexelAddressGen::Config& cfg = base_.config();
  const int32_t level = tex.slice_level(slice, mip);
  if (cfg.filter == FilterMode::Nearest) {
    const Texture::Level& lv = tex.level(level);
    const float scale = std::ldexp(1.0f, cfg.sub_texel_bits);
    const int b = cfg.sub_texel_bits;
    const int64_t xf = to_fixed(u * static_cast<float>(lv.width), scale);
    const int64_t yf = to_fixed(v * static_cast<float>(lv.height), scale);
    // A seamless cube's nearest texel is on the face (s, t ∈ [0, 1]; s = 1 is the last texel).
    const AddressMode mu = cube && seamless_ ? AddressMode::Clamp : cfg.address_u;
    const AddressMode mv = cube && seamless_ ? AddressMode::Clamp : cfg.address_v;
    // Vulkan allows no ConstOffset on a cube image: a cube ignores the sampler's offsets.
    const int ou = cube ? 0 : cfg.offset_u, ov = cube ? 0 : cfg.offset_v;
    *t = {level, TexelAddressGen::address((xf >> b) + ou, lv.width, mu),
          TexelAddressGen::address((yf >> b) + ov, lv.height, mv), w};
    return t + 1;
  }
  if (cube && seamless_)
    return emit_cube_linear(tex, slice / kCubeFaces, slice % kCubeFaces, mip, u, v, w, t);
  const TexelQuad q = base_.linear_quad(tex, level, u, v, w);
  t[0] = {level, q.x0, q.y0, q.w[0]};
  t[1] = {level, q.x1, q.y0, q.w[1]};
  t[2] = {level, q.x0, q.y1, q.w[2]};
  t[3] = {level, q.x1, q.y1, q.w[3]};
  return t + 4;
}

TexelTap* LayeredAddressGen::emit_cube_linear(const Texture& tex, int cube, int face, int32_t mip,
                                              float s, float t, float w, TexelTap* out) const {
  using namespace texel_address_detail;
  const TexelAddressGen::Config& cfg = base_.config();
  const int n = tex.level(tex.slice_level(cube * kCubeFaces + face, mip)).width;
  const int b = cfg.sub_texel_bits;
  const float scale = std::ldexp(1.0f, b), frac = std::ldexp(1.0f, -b);
  const int64_t mask = (int64_t{1} << b) - 1;
  // The same fixed-point coordinates as TexelAddressGen::linear_quad; the neighbours i and
  // i + 1 are in [−1, n] (s, t ∈ [0, 1]), so one step off the face at most.
  const int64_t xf = to_fixed(s * static_cast<float>(n) - 0.5f, scale);
  const int64_t yf = to_fixed(t * static_cast<float>(n) - 0.5f, scale);
  const float a = static_cast<float>(xf & mask) * frac;
  const float be = static_cast<float>(yf & mask) * frac;
  const int x0 = static_cast<int>(xf >> b);
  const int y0 = static_cast<int>(yf >> b);
  const float wt[4] = {(1 - a) * (1 - be) * w, a * (1 - be) * w, (1 - a) * be * w, a * be * w};
  const int xs[4] = {x0, x0 + 1, x0, x0 + 1};
  const int ys[4] = {y0, y0, y0 + 1, y0 + 1};
  std::array<CubeTexel, 3> r;
  for (int k = 0; k < 4; ++k) {
    const int m = CubeSeam::resolve(face, xs[k], ys[k], n, r);
    // A corner's three texels share its weight (the spec allows their average).
    const float wk = m == 3 ? wt[k] * (1.0f / 3.0f) : wt[k];
    for (int j = 0; j < m; ++j) {
      const auto ju = static_cast<size_t>(j);
      *out++ = {tex.slice_level(cube * kCubeFaces + r[ju].face, mip), r[ju].x, r[ju].y, wk};
    }
  }
  return out;
}

void LayeredAddressGen::finish(const Texture& tex, FilterTaps& out, TexelTap* t) const {
  out.count = static_cast<int>(t - out.tap.data());
  out.border_taps = 0;
  if (!base_.config().uses_border()) return;
  int n = 0;
  for (int k = 0; k < out.count; ++k) {
    const TexelTap& tp = out.tap[static_cast<size_t>(k)];
    n += tp.x == kBorderTexel || tp.y == kBorderTexel;
  }
  out.border_taps = n;
  if (n > 0) out.border = border_texel(tex.storage(), base_.config().border);
}

int LayeredAddressGen::cube_taps(const Texture& tex, const CubeFaceCoord& c, int cube,
                                 const LodResult& lod, FilterTaps& out) const {
  const TexelAddressGen::LevelSelect sel = base_.select_levels(lod.lambda, tex.mips());
  const int n = cube_probes(lod);
  const float au = n > 1 && std::isfinite(lod.axis_u) ? lod.axis_u : 0.0f;
  const float av = n > 1 && std::isfinite(lod.axis_v) ? lod.axis_v : 0.0f;
  const float inv_n = 1.0f / static_cast<float>(n);
  const int slice = cube * kCubeFaces + c.face;
  const bool tri = base_.config().filter == FilterMode::Trilinear;
  TexelTap* t = out.tap.data();
  for (int k = 0; k < n; ++k) {
    const float off = static_cast<float>(k) - 0.5f * static_cast<float>(n - 1);
    const float s = std::clamp(c.s + off * au, 0.0f, 1.0f);
    const float tt = std::clamp(c.t + off * av, 0.0f, 1.0f);
    t = emit(tex, slice, sel.d_hi, s, tt, (tri ? 1.0f - sel.delta : 1.0f) * inv_n, true, t);
    if (tri) t = emit(tex, slice, sel.d_lo, s, tt, sel.delta * inv_n, true, t);
  }
  finish(tex, out, t);
  int edge = 0;
  const int mips = tex.mips();
  for (int k = 0; k < out.count; ++k) edge += out.tap[static_cast<size_t>(k)].level / mips != slice;
  return edge;
}

void LayeredAddressGen::array_taps(const Texture& tex, double u, double v, int layer,
                                   const LodResult& lod, FilterTaps& out) const {
  using texel_address_detail::finite_or_zero;
  const TexelAddressGen::LevelSelect sel = base_.select_levels(lod.lambda, tex.mips());
  const int n = static_cast<int>(TexelAddressGen::issue_cycles(lod));
  const float au = n > 1 ? finite_or_zero(lod.axis_u) : 0.0f;
  const float av = n > 1 ? finite_or_zero(lod.axis_v) : 0.0f;
  const float uf = finite_or_zero(static_cast<float>(u));
  const float vf = finite_or_zero(static_cast<float>(v));
  const float inv_n = 1.0f / static_cast<float>(n);
  const bool tri = base_.config().filter == FilterMode::Trilinear;
  TexelTap* t = out.tap.data();
  for (int k = 0; k < n; ++k) {
    const float off = static_cast<float>(k) - 0.5f * static_cast<float>(n - 1);
    const float pu = uf + off * au, pv = vf + off * av;
    t = emit(tex, layer, sel.d_hi, pu, pv, (tri ? 1.0f - sel.delta : 1.0f) * inv_n, false, t);
    if (tri) t = emit(tex, layer, sel.d_lo, pu, pv, sel.delta * inv_n, false, t);
  }
  finish(tex, out, t);
}

OpCounts LayeredAddressGen::ops_per_edge_tap() {
  OpCounts o;
  o.cmp = 2;  // outside in x, in y
  o.add = 2;  // the folded coordinates (a table gives the face and the orientation)
  return o;
}

}  // namespace texsim
