#pragma once
// BilinearLerp: the bilinear interpolation datapath in fixed point at a chosen sub-texel
// precision (docs/rtl/blocks.md), the functional core the RTL block rtl_model/rtl/bilinear_lerp.v
// matches bit for bit. TexelBlend (texel_blend.h) is the float32 weighted sum; this is the
// integer form a texture unit builds: texels of `texel_bits` per channel (four channels, R in
// the low bits), weights fx, fy of `sub_bits` fraction bits (the sub-texel position quantised),
//   top = t00·2^S + (t10 − t00)·fx,   bot = t01·2^S + (t11 − t01)·fx      (exact)
//   out = (top·2^S + (bot − top)·fy + 2^(2S−1)) >> 2S                    (one HalfUp rounding)
// so |out − exact bilinear value| ≤ 1/2 LSB for the quantised weights, and out never leaves
// [0, 2^T − 1] (a convex combination rounded once).
#include <array>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

class BilinearLerp {
 public:
  static constexpr int kChannels = 4;
  struct Config {
    int texel_bits = 8;  // bits per channel, 1..16. Key: texel_bits
    int sub_bits = 8;    // sub-texel precision (weight fraction bits), 1..16. Key: sub_bits
    static Config from_toml(const ConfigReader& r);
  };

  BilinearLerp() = default;
  explicit BilinearLerp(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // One channel: t00 at (x0, y0), t10 at (x0 + 1, y0), t01 at (x0, y0 + 1), t11 at
  // (x0 + 1, y0 + 1); fx, fy in [0, 2^sub_bits) are the weights of the +1 texels.
  static uint32_t lerp_channel(uint32_t t00, uint32_t t10, uint32_t t01, uint32_t t11, uint32_t fx,
                               uint32_t fy, int sub_bits) {
    const int64_t s = sub_bits;
    const int64_t top = (int64_t{t00} << s) + (int64_t{t10} - int64_t{t00}) * fx;
    const int64_t bot = (int64_t{t01} << s) + (int64_t{t11} - int64_t{t01}) * fx;
    const int64_t acc = (top << s) + (bot - top) * fy + (int64_t{1} << (2 * s - 1));
    return static_cast<uint32_t>(acc >> (2 * s));
  }
  // Four channels packed texel_bits apart in each of the quad's words (t00, t10, t01, t11).
  uint64_t lerp(const std::array<uint64_t, 4>& quad, uint32_t fx, uint32_t fy) const {
    const int t = cfg_.texel_bits;
    const uint64_t mask = (uint64_t{1} << t) - 1;
    uint64_t out = 0;
    for (int c = 0; c < kChannels; ++c) {
      auto ch = [&](int k) { return static_cast<uint32_t>((quad[k] >> (c * t)) & mask); };
      out |= uint64_t{lerp_channel(ch(0), ch(1), ch(2), ch(3), fx, fy, cfg_.sub_bits)} << (c * t);
    }
    return out;
  }
  // The same, counting ops_per_item().
  uint64_t lerp(const std::array<uint64_t, 4>& quad, uint32_t fx, uint32_t fy,
                OpCounts& ops) const {
    ops += ops_per_item();
    return lerp(quad, fx, fy);
  }

  // Item: one bilinear sample of four channels; per channel 3 multipliers and 6 adders
  // (two differences, two x-lerp sums, one difference, the y-lerp sum with the rounding
  // constant as its carry-in).
  static constexpr OpCounts ops_per_item() {
    OpCounts o;
    o.mul = uint64_t{3} * kChannels;
    o.add = uint64_t{6} * kChannels;
    return o;
  }
  // difference, ×fx, sum, difference, ×fy, sum: the channels work side by side.
  static constexpr OpCounts critical_path() {
    OpCounts o;
    o.add = 4;
    o.mul = 2;
    return o;
  }
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "bilinear lerp"; }
  std::string arithmetic() const;

 private:
  Config cfg_;
};

}  // namespace texsim
