#include "blocks/texture/sampler/srgb_decoder.h"

#include <algorithm>

#include "blocks/base/derive_timing.h"
#include "blocks/texture/memory/storage_format.h"

namespace texsim {

const char* to_string(SrgbDecode d) {
  return d == SrgbDecode::BeforeFilter ? "before_filter" : "after_filter";
}

Rgba SrgbDecoder::decode_filtered(const Rgba& c) {
  return {srgb_eotf(c.r), srgb_eotf(c.g), srgb_eotf(c.b), c.a};
}

OpCounts SrgbDecoder::ops_per_item() const {
  OpCounts o;
  if (where_ == SrgbDecode::BeforeFilter) {
    o.lut = 3;  // R, G, B codes through the 256-entry table; alpha is linear
    return o;
  }
  // Per colour channel: (x + 0.055) / 1.055 folded into one add and the scale inside log2's
  // argument, log2, × 2.4, exp2, x / 12.92 on the linear segment, the compare and select.
  o.add = 3;
  o.mul = 6;
  o.lut = 6;
  o.cmp = 3;
  return o;
}

TimingSpec SrgbDecoder::timing(const TechTable& tech) const {
  OpCounts units, path;
  if (where_ == SrgbDecode::BeforeFilter) {
    units.lut = 3 * static_cast<uint64_t>(std::max(lanes_, 1));
    path.lut = 1;
  } else {
    units = ops_per_item();
    path.add = 1;
    path.lut = 2;
    path.mul = 1;
    path.cmp = 1;
  }
  return derive_timing(tech, units, path, Datapath::Spatial);
}

}  // namespace texsim
