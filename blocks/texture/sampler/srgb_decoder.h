#pragma once
// The sRGB decoder of the sampler: takes the colour channels of an sRGB texture (srgb8_a8) from
// the encoded values to linear ones through the sRGB EOTF (docs/formats.md#srgb-decode-placement).
// Where it sits is `[pipeline] srgb_decode`:
//  - before_filter (the Vulkan rule): each texel as it is read, a 256-entry table per colour
//    channel of each blend lane; the filter sums linear values.
//  - after_filter: once per fragment, on the filtered value (no longer an 8-bit code, so the
//    EOTF itself: a select between the linear segment and pow(x, 2.4) as exp2(2.4 · log2(x))).
//    The filter then sums encoded values, which is not what the specification asks for; the
//    formats study measures the error.
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

enum class SrgbDecode { BeforeFilter, AfterFilter };
const char* to_string(SrgbDecode d);

class SrgbDecoder {
 public:
  // taps_per_cycle: the blend's lanes (before the filter, one table set per lane).
  SrgbDecoder(SrgbDecode where, int taps_per_cycle) : where_(where), lanes_(taps_per_cycle) {}
  SrgbDecode where() const { return where_; }

  // After the filter: the filtered colour's RGB through the EOTF (clamped to [0, 1], NaN gives
  // 0, in double rounded once to float); alpha is linear and kept.
  static Rgba decode_filtered(const Rgba& c);

  // Item: a texel read (before_filter) or a fragment (after_filter).
  OpCounts ops_per_item() const;
  // Operations for `fragments` fragments that read `texels` texels of sRGB textures.
  OpCounts ops(uint64_t fragments, uint64_t texels) const {
    return ops_per_item() * (where_ == SrgbDecode::BeforeFilter ? texels : fragments);
  }
  // Before the filter: one table read (the blend's lanes side by side); after it: the EOTF's
  // chain add → log2 → mul → exp2 → select, one fragment per cycle.
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "srgb_decode"; }
  std::string arithmetic() const {
    return where_ == SrgbDecode::BeforeFilter ? "8-bit code table" : "float32 EOTF";
  }

 private:
  SrgbDecode where_;
  int lanes_;
};

}  // namespace texsim
