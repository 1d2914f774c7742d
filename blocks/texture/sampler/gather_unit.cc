#include "blocks/texture/sampler/gather_unit.h"

#include <cmath>
#include <stdexcept>

namespace texsim {

TexelQuad GatherUnit::quad(const TexelAddressGen::Config& c, const Texture& tex, double u, double v,
                           int du, int dv) {
  using namespace texel_address_detail;
  const Texture::Level& lv = tex.level(0);
  const int32_t wl = lv.width, hl = lv.height;
  const int b = c.sub_texel_bits;
  const float fix_scale = std::ldexp(1.0f, b);
  const float uf = finite_or_zero(static_cast<float>(u));
  const float vf = finite_or_zero(static_cast<float>(v));
  // i0 = ⌊u·width − ½⌋ on the fixed-point coordinate, as TexelAddressGen::linear_quad.
  const int64_t xf = to_fixed(uf * static_cast<float>(wl) - 0.5f, fix_scale);
  const int64_t yf = to_fixed(vf * static_cast<float>(hl) - 0.5f, fix_scale);
  TexelQuad q;
  q.level = 0;
  address_pair((xf >> b) + c.offset_u + du, wl, c.address_u, q.x0, q.x1);
  address_pair((yf >> b) + c.offset_v + dv, hl, c.address_v, q.y0, q.y1);
  q.w[0] = q.w[1] = q.w[2] = q.w[3] = 1.0f;
  return q;
}

Rgba GatherUnit::gather(const TexelQuad& q, const Texture& tex, int component, const Rgba& border,
                        int* border_taps) {
  if (component < 0 || component > 3)
    throw std::invalid_argument("gather component " + std::to_string(component) +
                                " is not 0..3 (r, g, b, a)");
  int n = 0;
  auto at = [&](int32_t x, int32_t y) {
    if (x == kBorderTexel || y == kBorderTexel) {
      ++n;
      return border[component];
    }
    return tex.texel(q.level, x, y)[component];
  };
  const Rgba out(at(q.x0, q.y1), at(q.x1, q.y1), at(q.x1, q.y0), at(q.x0, q.y0));
  if (border_taps) *border_taps += n;
  return out;
}

OpCounts GatherUnit::ops_per_item(const TexelAddressGen::Config& c) {
  OpCounts o;
  o.mul = 2;                                           // u·width, v·height
  o.add = 2;                                           // − ½
  o.cmp = 2;                                           // the float→fixed converters' range clamp
  o.add += 2 + 2;                                      // the offsets; i1 = i0 + 1
  o += TexelAddressGen::ops_address(c.address_u) * 2;  // i0, i1
  o += TexelAddressGen::ops_address(c.address_v) * 2;  // j0, j1
  o.mem = 4;                                           // four texel reads
  o.cmp += 4;                                          // component select per texel
  return o;
}

}  // namespace texsim
