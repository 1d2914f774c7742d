// The shared parts of the anisotropic footprint filters (EWA, multi-probe, Feline, SPAF):
// addressing-mode costs, the footprint set-up and the bilinear fallback.
#include "blocks/texture/footprint/footprint_types.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

OpCounts address_mode_ops(AddressMode m) { return TexelAddressGen::ops_address(m); }

AddressMode footprint_address_mode(const ConfigReader& r, std::string_view key) {
  const toml::node* n = r.table().get(key);
  if (n && n->value<std::string>() == "border") {
    r.fail(key,
           "border addressing is the lod/filter path's only: a footprint filter has no border "
           "colour (use wrap, clamp, mirror or mirror_clamp)");
  }
  constexpr AddressMode kModes[] = {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror,
                                    AddressMode::MirrorClamp};
  return kModes[r.get_choice(key, 0, {"wrap", "clamp", "mirror", "mirror_clamp"})];
}

OpCounts footprint_setup_ops() {
  OpCounts o;
  // Derivatives to texels (×w0·R, ×h0·R): 4 mul. Σ = J·Jᵀ: 6 mul, 3 add. Eigenvalues:
  // (Σuu ± Σvv)/2: 2 add; d² + Σuv²: 2 mul, 1 add; √; λ± = t ± s: 2 add; λ₋ ≥ 0: 1 cmp.
  // Clamp: maxA²·λ₋ and the compare: 1 mul, 1 cmp; λ₊/maxA²: 1 mul; δ: 1 add;
  // δ/(2s): rcp, mul; λ₊ − Σuu, λ₊ − Σvv: 2 add; three k·(…): 3 mul; three updates: 3 add;
  // select clamped/unclamped Σ: 3 cmp. Non-finite input test: 1 cmp.
  o.mul = 4 + 6 + 2 + 1 + 1 + 1 + 3;
  o.add = 3 + 2 + 1 + 2 + 1 + 2 + 3;
  o.sqrt = 1;
  o.rcp = 1;
  o.cmp = 1 + 1 + 3 + 1;
  return o;
}

template <class S>
Footprint footprint_setup(const Fragment& f, int w0, int h0, double radius_px, double max_aniso,
                          OpCounts& ops) {
  ops += footprint_setup_ops();
  Footprint fp;
  if (!std::isfinite(f.dudx) || !std::isfinite(f.dvdx) || !std::isfinite(f.dudy) ||
      !std::isfinite(f.dvdy)) {
    fp.bad_input = true;  // a point footprint: magnification at level 0
    return fp;
  }
  const S sw = static_cast<S>(static_cast<double>(w0) * radius_px);
  const S sh = static_cast<S>(static_cast<double>(h0) * radius_px);
  const S ux = static_cast<S>(f.dudx) * sw, uy = static_cast<S>(f.dudy) * sw;
  const S vx = static_cast<S>(f.dvdx) * sh, vy = static_cast<S>(f.dvdy) * sh;
  S suu = ux * ux + uy * uy, suv = ux * vx + uy * vy, svv = vx * vx + vy * vy;
  const S half = static_cast<S>(0.5);
  const S t = (suu + svv) * half, d = (suu - svv) * half;
  const S s = std::sqrt(d * d + suv * suv);
  if (!std::isfinite(suu) || !std::isfinite(svv) || !std::isfinite(suv) || !std::isfinite(s)) {
    fp.overflow = true;
    return fp;
  }
  const S lp = t + s;
  S lm = std::max(t - s, S(0));
  fp.aniso = lm > 0 ? std::sqrt(static_cast<double>(lp) / static_cast<double>(lm))
                    : (lp > 0 ? std::numeric_limits<double>::infinity() : 1.0);
  const S a2 = static_cast<S>(max_aniso * max_aniso);
  if (lp > a2 * lm) {
    // λ₊ > λ₋ here, so s > 0.
    const S target = lp / a2;
    const S k = (target - lm) / (S(2) * s);
    suu += k * (lp - suu);
    svv += k * (lp - svv);
    suv -= k * suv;
    lm = target;
    fp.clamped = true;
  }
  fp.suu = static_cast<double>(suu);
  fp.suv = static_cast<double>(suv);
  fp.svv = static_cast<double>(svv);
  fp.major2 = static_cast<double>(lp);
  fp.minor2 = static_cast<double>(lm);
  return fp;
}

template Footprint footprint_setup<float>(const Fragment&, int, int, double, double, OpCounts&);
template Footprint footprint_setup<double>(const Fragment&, int, int, double, double, OpCounts&);

Rgba bilinear_fallback(const Texture& tex, int level, double u, double v, AddressMode au,
                       AddressMode av, std::vector<TexelRef>* fetched, OpCounts& ops) {
  const int w = tex.width(level), h = tex.height(level);
  constexpr double kLimit = 1073741824.0;  // 2^30 texels: keeps the integer part in range
  const double x = std::clamp(u * w - 0.5, -kLimit, kLimit);
  const double y = std::clamp(v * h - 0.5, -kLimit, kLimit);
  const double fx = std::floor(x), fy = std::floor(y);
  const float a = static_cast<float>(x - fx), b = static_cast<float>(y - fy);
  const auto i = static_cast<int64_t>(fx), j = static_cast<int64_t>(fy);
  const int32_t x0 = TexelAddressGen::address(i, w, au),
                x1 = TexelAddressGen::address(i + 1, w, au);
  const int32_t y0 = TexelAddressGen::address(j, h, av),
                y1 = TexelAddressGen::address(j + 1, h, av);
  if (fetched) {
    fetched->push_back({level, x0, y0});
    fetched->push_back({level, x1, y0});
    fetched->push_back({level, x0, y1});
    fetched->push_back({level, x1, y1});
  }
  // Coordinates: 2 mul, 2 add; floor: 2 cmp; addresses of both neighbours on each axis;
  // weights (1−a)(1−b) …: 2 add, 4 mul; four reads and multiply-accumulates.
  OpCounts o;
  o.mul = 2 + 4 + 16;
  o.add = 2 + 2 + 12;
  o.cmp = 2;
  o.mem = 4;
  ops += o;
  ops += address_mode_ops(au) * 2;
  ops += address_mode_ops(av) * 2;
  return (1 - a) * (1 - b) * tex.texel(level, x0, y0) + a * (1 - b) * tex.texel(level, x1, y0) +
         (1 - a) * b * tex.texel(level, x0, y1) + a * b * tex.texel(level, x1, y1);
}

}  // namespace texsim
