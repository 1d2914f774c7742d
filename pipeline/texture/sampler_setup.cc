#include "pipeline/texture/sampler_setup.h"

#include <cmath>
#include <iterator>

#include "blocks/base/input_error.h"
#include "blocks/texture/sampler/sampler_modes.h"

namespace texsim {

namespace {

const std::vector<std::string_view> kLodKeys = {"aniso", "max_aniso", "lod_bias", "min_lod",
                                                "max_lod"};
const std::vector<std::string_view> kFilterKeys = {
    "mode",        "address", "address_u", "address_v", "sub_texel_bits",
    "mipmap_bits", "border",  "seamless",  "reduction", "compare"};

// Vulkan's valid usage of unnormalizedCoordinates (VkSamplerCreateInfo).
void check_unnormalized(const SamplerSetup& s, const ConfigReader& r) {
  const auto refuse = [&](std::string_view key, const std::string& why) {
    r.fail(r.table().contains(key) ? key : "unnormalized",
           "unnormalized coordinates need " + why + " (Vulkan unnormalizedCoordinates)");
  };
  if (s.filter.filter == FilterMode::Trilinear)
    refuse("mode", "mode \"nearest\" or \"bilinear\" (mipmap mode nearest)");
  for (const auto& [key, mode] :
       {std::pair<std::string_view, AddressMode>{"address_u", s.filter.address_u},
        {"address_v", s.filter.address_v}}) {
    if (mode != AddressMode::Clamp && mode != AddressMode::Border)
      refuse(r.table().contains("address") ? "address" : key, "address \"clamp\" or \"border\"");
  }
  if (s.lod.aniso != AnisoMode::Isotropic) refuse("aniso", "aniso = \"isotropic\"");
  if (s.filter.compare != CompareOp::None) refuse("compare", "compare = \"none\"");
  if (s.lod.min_lod != 0 || !r.table().contains("max_lod") || s.lod.max_lod != 0)
    refuse(s.lod.min_lod != 0 ? "min_lod" : "max_lod", "min_lod = 0 and max_lod = 0");
}

}  // namespace

SamplerSetup SamplerSetup::from_toml(const std::string& name, const ConfigReader& r) {
  if (r.table().contains("offset")) {
    r.fail("offset",
           "a constant offset belongs to the sample instruction, not the sampler: give it in the "
           "material's `operation` (offset = [i, j]) or in the trace records");
  }
  std::vector<std::string_view> for_filter = kLodKeys, for_lod = kFilterKeys;
  for_filter.push_back("unnormalized");
  for_lod.push_back("unnormalized");
  SamplerSetup s;
  s.name = name;
  s.filter = TexelAddressGen::Config::from_toml(r.for_block(r.block(), for_filter));
  s.lod = LodUnit::Config::from_toml(r.for_block(r.block(), for_lod));
  s.filter.unnormalized = r.get_bool("unnormalized", false);
  if (s.filter.unnormalized) check_unnormalized(s, r);
  return s;
}

std::string unnormalized_refusal(const Fragment& f) {
  if (f.op == static_cast<uint8_t>(SampleOp::kSample)) {
    return "operation 'sample' (implicit LOD) cannot use an unnormalised sampler (Vulkan allows "
           "explicit LOD 0 only: op \"lod\" with lod 0)";
  }
  if (f.op == static_cast<uint8_t>(SampleOp::kSampleLod) && f.lod != 0)
    return "explicit LOD " + std::to_string(f.lod) + ": an unnormalised sampler reads LOD 0 only";
  if (f.op == static_cast<uint8_t>(SampleOp::kGather) ||
      f.op == static_cast<uint8_t>(SampleOp::kSampleGrad)) {
    return "operation '" + std::string(kSampleOpNames[f.op]) +
           "' cannot use an unnormalised sampler (Vulkan allows explicit LOD 0 only)";
  }
  if (f.offset_u != 0 || f.offset_v != 0 || f.offset_w != 0)
    return "constant offsets cannot be used with an unnormalised sampler";
  return {};
}

std::string unnormalized_refusal(TextureType type) {
  if (type == TextureType::Tex2D) return {};
  return std::string("a ") + to_string(type) +
         " texture cannot be read with an unnormalised sampler (Vulkan: 1-D or 2-D image views "
         "of one layer only)";
}

TraceSampler to_trace_sampler(const SamplerSetup& s) {
  const TexelAddressGen::Config& f = s.filter;
  TraceSampler t;
  t.name = s.name;
  t.mode = static_cast<uint8_t>(f.filter);
  t.address_u = static_cast<uint8_t>(f.address_u);
  t.address_v = static_cast<uint8_t>(f.address_v);
  t.address_w = static_cast<uint8_t>(f.address_w);
  for (int c = 0; c < 4; ++c) t.border[c] = f.border[c];
  t.compare = static_cast<uint8_t>(f.compare);
  t.reduction = static_cast<uint8_t>(f.reduction);
  t.aniso = static_cast<uint8_t>(s.lod.aniso);
  t.max_aniso = static_cast<uint8_t>(s.lod.max_aniso);
  t.lod_bias = s.lod.lod_bias;
  t.min_lod = s.lod.min_lod;
  t.max_lod = s.lod.max_lod;
  t.unnormalized = f.unnormalized ? 1 : 0;
  t.seamless = f.seamless_cube ? 1 : 0;
  t.sub_texel_bits = static_cast<uint8_t>(f.sub_texel_bits);
  t.mipmap_bits = static_cast<uint8_t>(f.mipmap_bits);
  return t;
}

SamplerSetup from_trace_sampler(const TraceSampler& t, size_t id, const std::string& where) {
  // The trace codes are the enums' orders (the name tables of trace_file.h and the scene's).
  static_assert(std::size(kTraceCompareNames) == std::size(kCompareOpNames));
  static_assert(std::size(kTraceReductionNames) == std::size(kReductionNames));
  const auto fail = [&](const std::string& why) {
    throw InputError(where,
                     "sampler table entry " + std::to_string(id) + " ('" + t.name + "'): " + why);
  };
  if (const std::string why = check_sampler(t); !why.empty()) fail(why);
  SamplerSetup s;
  s.name = t.name;
  TexelAddressGen::Config& f = s.filter;
  f.filter = static_cast<FilterMode>(t.mode);
  f.address_u = static_cast<AddressMode>(t.address_u);
  f.address_v = static_cast<AddressMode>(t.address_v);
  f.address_w = static_cast<AddressMode>(t.address_w);
  f.border = Rgba(t.border[0], t.border[1], t.border[2], t.border[3]);
  f.compare = static_cast<CompareOp>(t.compare);
  f.reduction = static_cast<Reduction>(t.reduction);
  f.unnormalized = t.unnormalized != 0;
  f.seamless_cube = t.seamless != 0;
  f.sub_texel_bits = t.sub_texel_bits;
  f.mipmap_bits = t.mipmap_bits;
  s.lod.aniso = static_cast<AnisoMode>(t.aniso);
  s.lod.max_aniso = t.max_aniso;
  s.lod.lod_bias = t.lod_bias;
  s.lod.min_lod = t.min_lod;
  s.lod.max_lod = t.max_lod;
  if (f.compare != CompareOp::None && f.reduction != Reduction::WeightedAverage)
    fail("a depth comparison needs the reduction weighted_average");
  if (f.unnormalized) {
    const std::string vk = " (Vulkan unnormalizedCoordinates)";
    if (f.filter == FilterMode::Trilinear)
      fail("unnormalized coordinates need mode nearest or bilinear" + vk);
    for (const AddressMode a : {f.address_u, f.address_v}) {
      if (a != AddressMode::Clamp && a != AddressMode::Border)
        fail("unnormalized coordinates need address clamp or border" + vk);
    }
    if (s.lod.aniso != AnisoMode::Isotropic)
      fail("unnormalized coordinates need aniso isotropic" + vk);
    if (f.compare != CompareOp::None) fail("unnormalized coordinates need compare none" + vk);
    if (s.lod.min_lod != 0 || s.lod.max_lod != 0)
      fail("unnormalized coordinates need min_lod = 0 and max_lod = 0" + vk);
  }
  return s;
}

std::shared_ptr<const SamplerTable> sampler_table_of(const std::vector<TraceSampler>& table,
                                                     const std::string& where) {
  if (table.empty()) return nullptr;
  auto out = std::make_shared<SamplerTable>();
  out->reserve(table.size());
  for (size_t k = 0; k < table.size(); ++k)
    out->push_back(from_trace_sampler(table[k], k + 1, where));
  return out;
}

OperationSetup OperationSetup::from_toml(const ConfigReader& r) {
  r.reject_unknown({"op", "lod", "component", "compare_ref", "offset"});
  OperationSetup o;
  o.op = static_cast<SampleOp>(r.get_choice(
      "op", 0,
      std::vector<std::string_view>(std::begin(kSampleOpNames), std::end(kSampleOpNames))));
  const auto finite = [&](std::string_view key, const toml::node& n) {
    const std::optional<double> v = n.value<double>();
    if (!v || !std::isfinite(*v)) r.fail_at(n, std::string(key) + ": expected a finite number");
    return static_cast<float>(*v);
  };
  if (const toml::node* n = r.table().get("lod")) {
    if (o.op != SampleOp::kSampleLod) r.fail("lod", "only with op = \"lod\"");
    o.lod = finite("lod", *n);
  }
  if (r.table().contains("component")) {
    if (o.op != SampleOp::kGather) r.fail("component", "only with op = \"gather\"");
    o.component = static_cast<uint8_t>(r.get_choice("component", 0, {"r", "g", "b", "a"}));
  }
  if (const toml::node* n = r.table().get("compare_ref")) {
    if (const toml::array* a = n->as_array()) {
      if (a->size() != 3) r.fail("compare_ref", "expected a number or [a, b, c] (a + b·u + c·v)");
      for (size_t k = 0; k < 3; ++k) o.ref[k] = finite("compare_ref", *a->get(k));
    } else {
      o.ref[0] = finite("compare_ref", *n);
    }
  }
  if (const toml::node* n = r.table().get("offset")) {
    const toml::array* a = n->as_array();
    if (!a || a->size() != 2) r.fail("offset", "expected two integers [i, j]");
    int8_t* out[2] = {&o.offset_u, &o.offset_v};
    for (size_t k = 0; k < 2; ++k) {
      const toml::node& e = *a->get(k);
      const std::optional<int64_t> v = e.is_integer() ? e.value<int64_t>() : std::nullopt;
      using C = TexelAddressGen::Config;
      if (!v || *v < C::kMinTexelOffset || *v > C::kMaxTexelOffset)
        r.fail_at(e, "offset: each component must be an integer in [-8, 7]");
      *out[k] = static_cast<int8_t>(*v);
    }
  }
  return o;
}

}  // namespace texsim
