#include "blocks/texture/sampler/texel_address_gen.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<TexelAddressGen>);

const char* to_string(FilterMode m) {
  switch (m) {
    case FilterMode::Nearest:
      return "nearest";
    case FilterMode::Bilinear:
      return "bilinear";
    case FilterMode::Trilinear:
      return "trilinear";
  }
  return "?";
}

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

namespace {

// `border`: a VkBorderColor FLOAT_* name or a custom float colour [r, g, b, a] (finite).
// Integer border colours (INT_*, INT_CUSTOM_EXT) need an integer format, which texsim has not.
Rgba border_from_toml(const ConfigReader& r) {
  const toml::node* n = r.table().get("border");
  if (!n) return Rgba(0.0f);
  if (n->is_string()) {
    const int k = r.get_choice("border", 0, {"transparent_black", "opaque_black", "opaque_white"});
    return k == 0 ? Rgba(0.0f) : (k == 1 ? Rgba(0.0f, 0.0f, 0.0f, 1.0f) : Rgba(1.0f));
  }
  const toml::array* a = n->as_array();
  if (!a || a->size() != 4) {
    r.fail("border",
           "expected \"transparent_black\", \"opaque_black\", \"opaque_white\" or a custom "
           "float colour [r, g, b, a]");
  }
  Rgba c(0.0f);
  for (size_t k = 0; k < 4; ++k) {
    const toml::node& e = *a->get(k);
    const std::optional<double> v = e.value<double>();
    if (!v || !std::isfinite(*v)) r.fail_at(e, "border: each channel must be a finite number");
    c[static_cast<int>(k)] = static_cast<float>(*v);
  }
  return c;
}

// `offset`: [i, j], integers in minTexelOffset..maxTexelOffset.
void offset_from_toml(const ConfigReader& r, int& ou, int& ov) {
  const toml::node* n = r.table().get("offset");
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a || a->size() != 2) r.fail("offset", "expected two integers [i, j]");
  int* out[2] = {&ou, &ov};
  for (size_t k = 0; k < 2; ++k) {
    const toml::node& e = *a->get(k);
    const std::optional<int64_t> v = e.is_integer() ? e.value<int64_t>() : std::nullopt;
    using C = TexelAddressGen::Config;
    if (!v || *v < C::kMinTexelOffset || *v > C::kMaxTexelOffset) {
      r.fail_at(e, "offset: each component must be an integer in [" +
                       std::to_string(C::kMinTexelOffset) + ", " +
                       std::to_string(C::kMaxTexelOffset) +
                       "] (Vulkan minTexelOffset..maxTexelOffset)");
    }
    *out[k] = static_cast<int>(*v);
  }
}

}  // namespace

TexelAddressGen::Config TexelAddressGen::Config::from_toml(const ConfigReader& r) {
  if (r.table().contains("border_int")) {
    r.fail("border_int",
           "integer border colours need an integer texture format, and texsim has none; give a "
           "float 'border'");
  }
  r.reject_unknown({"mode", "address", "address_u", "address_v", "address_w", "sub_texel_bits",
                    "mipmap_bits", "border", "offset", "seamless", "reduction", "compare",
                    "arithmetic"});
  Config c;
  c.filter = static_cast<FilterMode>(
      r.get_choice("mode", static_cast<int>(c.filter), {"nearest", "bilinear", "trilinear"}));
  const std::vector<std::string_view> modes = {"wrap", "clamp", "mirror", "border",
                                               "mirror_clamp"};  // AddressMode order
  if (r.table().contains("address")) {
    // One key for both axes; giving an axis as well would leave it ambiguous which wins.
    for (std::string_view k : {"address_u", "address_v", "address_w"}) {
      if (r.table().contains(k)) r.fail(k, "cannot be given together with 'address'");
    }
    c.address_u = c.address_v = c.address_w =
        static_cast<AddressMode>(r.get_choice("address", 0, modes));
  } else {
    c.address_u = static_cast<AddressMode>(r.get_choice("address_u", 0, modes));
    c.address_v = static_cast<AddressMode>(r.get_choice("address_v", 0, modes));
    c.address_w = static_cast<AddressMode>(r.get_choice("address_w", 0, modes));
  }
  c.sub_texel_bits = static_cast<int>(r.get_int("sub_texel_bits", c.sub_texel_bits, 1, 16));
  c.mipmap_bits = static_cast<int>(r.get_int("mipmap_bits", c.mipmap_bits, 1, 16));
  c.border = border_from_toml(r);
  offset_from_toml(r, c.offset_u, c.offset_v);
  c.seamless_cube = r.get_bool("seamless", c.seamless_cube);
  c.reduction = static_cast<Reduction>(
      r.get_choice("reduction", 0, {kReductionNames[0], kReductionNames[1], kReductionNames[2]}));
  c.compare = static_cast<CompareOp>(r.get_choice(
      "compare", 0,
      std::vector<std::string_view>(std::begin(kCompareOpNames), std::end(kCompareOpNames))));
  // Vulkan: a comparing sampler's reduction is the weighted average.
  if (c.compare != CompareOp::None && c.reduction != Reduction::WeightedAverage)
    r.fail("compare", "a depth comparison needs reduction = \"weighted_average\"");
  c.fixed_arithmetic = r.get_choice("arithmetic", 0, {"float", "fixed"}) == 1;
  return c;
}

void TexelAddressGen::count_border(const Texture& tex, FilterTaps& out) const {
  int n = 0;
  for (int k = 0; k < out.count; ++k) {
    n += out.tap[static_cast<size_t>(k)].x == kBorderTexel ||
         out.tap[static_cast<size_t>(k)].y == kBorderTexel;
  }
  out.border_taps = n;
  if (n == 0) return;
  out.border = border_texel(tex.storage(), cfg_.border);
  // An sRGB texture decoded after the filter sums encoded values: its (linear) border colour
  // enters the sum encoded, so a fragment of border taps only decodes back to it.
  if (tex.srgb_after_filter())
    for (int k = 0; k < 3; ++k) out.border[k] = srgb_oetf(out.border[k]);
}

int TexelAddressGen::taps_per_probe() const {
  switch (cfg_.filter) {
    case FilterMode::Nearest:
      return 1;
    case FilterMode::Bilinear:
      return 4;
    case FilterMode::Trilinear:
      return 8;
  }
  return 1;
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
    case AddressMode::Border:
      o.cmp = 2;  // 0 ≤ i, i < size: the tap's border flag (no texel read when set)
      break;
    case AddressMode::MirrorClamp:
      // mirror(i): −(1 + i) is the bitwise complement (1 add) selected by the sign (1 cmp);
      // min(size − 1, ·) (1 cmp).
      o.add = 1;
      o.cmp = 2;
      break;
  }
  return o;
}

OpCounts TexelAddressGen::ops_level() const {
  OpCounts o;
  const bool linear = cfg_.filter != FilterMode::Nearest;
  const uint64_t coords = linear ? 2 : 1;                    // i0, i1 (and j0, j1) or one i (and j)
  o.mul += 2;                                                // u·width, v·height
  if (linear) o.add += 2;                                    // − ½
  o.add += 2;                                                // round to fixed point
  if (linear) o.add += 2;                                    // i1 = i0 + 1, j1 = j0 + 1
  if (cfg_.offset_u != 0 || cfg_.offset_v != 0) o.add += 2;  // i0 + offset, j0 + offset
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
    o.lut += 1;           // 1/N
    if (tri) o.mul += 2;  // (1 − δ)/N, δ/N
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
  const double lat =
      tech.path_latency(setup) + tech.path_latency(pos) + tech.path_latency(coord) + std::max(a, b);
  // One probe per cycle (ii = 1); a fragment takes issue_cycles() slots.
  return derive_timing(tech, ops_setup(true) + ops_per_item(true), lat, Datapath::Spatial);
}

std::string TexelAddressGen::name() const {
  return std::string("filter.") + to_string(cfg_.filter);
}

std::string TexelAddressGen::arithmetic() const {
  return "float32 coordinates; weights in u0." + std::to_string(cfg_.sub_texel_bits) +
         ", mip fraction u0." + std::to_string(cfg_.mipmap_bits);
}

}  // namespace texsim
