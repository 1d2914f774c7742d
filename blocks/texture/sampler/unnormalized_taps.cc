#include "blocks/texture/sampler/unnormalized_taps.h"

#include "blocks/texture/memory/storage_format.h"

namespace texsim {

void UnnormalizedTaps::taps(const TexelAddressGen::Config& c, const Texture& tex, double u,
                            double v, FilterTaps& out) {
  using namespace texel_address_detail;  // NOLINT(google-build-using-namespace)
  const Texture::Level& lv = tex.level(0);
  const int32_t wl = lv.width, hl = lv.height;
  const int b = c.sub_texel_bits;
  const auto scale = static_cast<float>(int64_t{1} << b);
  const float uf = finite_or_zero(static_cast<float>(u));
  const float vf = finite_or_zero(static_cast<float>(v));
  if (c.filter == FilterMode::Nearest) {
    out.tap[0] = {0, TexelAddressGen::address(to_fixed(uf, scale) >> b, wl, c.address_u),
                  TexelAddressGen::address(to_fixed(vf, scale) >> b, hl, c.address_v), 1.0f};
    out.count = 1;
  } else {
    // i0 = ⌊u − ½⌋, α = frac(u − ½) with b fraction bits (the linear quad without u·width).
    const int64_t xf = to_fixed(uf - 0.5f, scale), yf = to_fixed(vf - 0.5f, scale);
    const int64_t mask = (int64_t{1} << b) - 1;
    const float a = static_cast<float>(xf & mask) / scale;
    const float be = static_cast<float>(yf & mask) / scale;
    int32_t x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    address_pair(xf >> b, wl, c.address_u, x0, x1);
    address_pair(yf >> b, hl, c.address_v, y0, y1);
    out.tap[0] = {0, x0, y0, (1.0f - a) * (1.0f - be)};
    out.tap[1] = {0, x1, y0, a * (1.0f - be)};
    out.tap[2] = {0, x0, y1, (1.0f - a) * be};
    out.tap[3] = {0, x1, y1, a * be};
    out.count = 4;
  }
  out.border_taps = 0;
  for (int k = 0; k < out.count; ++k) {
    const TexelTap& t = out.tap[static_cast<size_t>(k)];
    out.border_taps += t.x == kBorderTexel || t.y == kBorderTexel;
  }
  if (out.border_taps > 0) out.border = border_texel(tex.storage(), c.border);
}

OpCounts UnnormalizedTaps::ops_per_item(const TexelAddressGen::Config& c) {
  // One integer coordinate per axis (nearest) or two (linear).
  const uint64_t coords = c.filter == FilterMode::Nearest ? 1 : 2;
  OpCounts o = TexelAddressGen::ops_address(c.address_u) * coords +
               TexelAddressGen::ops_address(c.address_v) * coords;
  if (c.filter != FilterMode::Nearest) {
    o.add += 2 + 2 + 2;  // u − ½, v − ½; i0 + 1, j0 + 1; 1 − α, 1 − β
    o.mul += 4;          // the four weights
  }
  return o;
}

}  // namespace texsim
