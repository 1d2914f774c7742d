#include "blocks/texture/sampler/texel_reduce.h"

#include <algorithm>
#include <cmath>

#include "blocks/texture/memory/storage_format.h"

namespace texsim {

namespace {

Rgba tap_texel(const FilterTaps& taps, const TexelTap& t, const Texture& tex) {
  if (t.x == kBorderTexel || t.y == kBorderTexel) return taps.border;
  return tex.texel(t.level, t.x, t.y);
}

}  // namespace

Rgba TexelReduce::minmax(const FilterTaps& taps, const Texture& tex, Reduction r) {
  bool any = false;
  Rgba out(0.0f);
  for (int k = 0; k < taps.count; ++k) {
    const TexelTap& t = taps.tap[static_cast<size_t>(k)];
    if (t.w == 0.0f) continue;  // not among the texels the weighted average would use
    const Rgba c = tap_texel(taps, t, tex);
    if (!any) {
      out = c;
      any = true;
      continue;
    }
    for (int ch = 0; ch < 4; ++ch)
      out[ch] = r == Reduction::Max ? std::max(out[ch], c[ch]) : std::min(out[ch], c[ch]);
  }
  return out;
}

float TexelReduce::reference(const Texture& tex, float reference) {
  const StorageFormatInfo& fi = format_info(tex.storage());
  if (fi.depth && fi.coding == ChannelCoding::Unorm && !std::isnan(reference))
    return std::clamp(reference, 0.0f, 1.0f);
  return reference;
}

Rgba TexelReduce::compare(const FilterTaps& taps, const Texture& tex, CompareOp op,
                          float reference_in) {
  const float ref = reference(tex, reference_in);
  float sum = 0.0f;
  for (int k = 0; k < taps.count; ++k) {
    const TexelTap& t = taps.tap[static_cast<size_t>(k)];
    if (compare_passes(op, ref, tap_texel(taps, t, tex).r)) sum += t.w;
  }
  return Rgba(sum, sum, sum, 1.0f);
}

OpCounts TexelReduce::ops_per_tap(Reduction r, CompareOp op) {
  OpCounts o;
  o.mem = 1;
  if (op != CompareOp::None) {
    o.cmp = 1;
    o.mul = 1;
    o.add = 1;
  } else if (r != Reduction::WeightedAverage) {
    o.cmp = 4 + 1;  // min/max per channel; the zero-weight test
  } else {
    o.mul = 4;
    o.add = 4;
  }
  return o;
}

}  // namespace texsim
