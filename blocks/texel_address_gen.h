#pragma once
// Texel address generator: mip level selection, texel coordinates, address modes and filter
// weights of the nearest, bilinear and trilinear filters, with anisotropic probes
// (docs/filters.md §2–§4). One block for the three filters: they share one datapath (nearest
// is its 1-tap degenerate case, trilinear runs it on two levels), selected by Config::filter.
// Arithmetic: float32 coordinates, converted to fixed point with `sub_texel_bits` fraction
// bits (round to nearest even); LOD to fixed point with `mipmap_bits` fraction bits; weights
// are products of those fixed-point fractions (exact in float32) and 1/N.
#include <array>
#include <cmath>
#include <cstdint>

#include "blocks/config_reader.h"
#include "blocks/lod_unit.h"
#include "blocks/op_counts.h"
#include "blocks/tech_table.h"
#include "blocks/texture_memory.h"
#include "blocks/timing_spec.h"

namespace texsim {

// One texel to read: coordinates already addressed (inside the level), and its weight.
struct TexelTap {
  int32_t level;
  int32_t x, y;
  float w;
};
// All taps of one fragment: up to maxAniso (16) probes × 8 taps.
struct FilterTaps {
  std::array<TexelTap, 128> tap;
  int count = 0;
};

// Nearest = VK_FILTER_NEAREST + VK_SAMPLER_MIPMAP_MODE_NEAREST; Bilinear = VK_FILTER_LINEAR +
// MIPMAP_MODE_NEAREST; Trilinear = VK_FILTER_LINEAR + MIPMAP_MODE_LINEAR. The same filter
// serves magnification and minification.
enum class FilterMode { Nearest, Bilinear, Trilinear };
const char* to_string(FilterMode m);

// Texel address generator (docs/filters.md §2–§4): levels, texel coordinates, wrap/clamp/mirror
// and weights of nearest/bilinear/trilinear taps, per anisotropic probe.
class TexelAddressGen {
 public:
  struct Config {
    FilterMode filter = FilterMode::Bilinear;
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    int sub_texel_bits = 8;  // fraction bits of texel coordinates (Vulkan subTexelPrecisionBits)
    int mipmap_bits = 8;     // fraction bits of the LOD (Vulkan mipmapPrecisionBits)
    // Keys: mode ("nearest"|"bilinear"|"trilinear"); address ("wrap"|"clamp"|"mirror") for
    // both axes, or address_u and address_v separately (not both forms at once);
    // sub_texel_bits (1..16), mipmap_bits (1..16).
    static Config from_toml(const ConfigReader& r);
  };

  // Mip level(s) chosen for one fragment (Vulkan "Image Level(s) Selection").
  struct LevelSelect {
    int32_t d_hi = 0;   // the level for nearest mipmap mode; the finer level for linear
    int32_t d_lo = 0;   // coarser level (linear mode); = d_hi otherwise
    float delta = 0;    // weight of d_lo, a multiple of 2^-mipmap_bits (linear mode)
  };

  TexelAddressGen() : TexelAddressGen(Config{}) {}
  explicit TexelAddressGen(const Config& c);
  const Config& config() const { return cfg_; }

  // Writes the taps of one fragment at normalised (u, v) into `out` (out.count set).
  // Probes: lod.probes (clamped to 1..16) at (u, v) + (k − (N−1)/2)·(axis_u, axis_v),
  // k = 0..N−1, each weighted 1/N. Non-finite u or v are treated as 0.
  void taps(const Texture& tex, double u, double v, const LodResult& lod, FilterTaps& out,
            OpCounts& ops) const {
    const bool aniso = issue_cycles(lod) > 1;
    ops += ops_setup_[aniso];
    ops += ops_probe_[aniso] * issue_cycles(lod);
    taps(tex, u, v, lod, out);
  }
  // The same without counting: the count depends only on the probe number N, so a caller
  // may count fragments and probes and multiply ops_setup() and ops_per_probe() at the end.
  void taps(const Texture& tex, double u, double v, const LodResult& lod, FilterTaps& out) const;

  // Level selection from λ on a pyramid of `levels` levels.
  LevelSelect select_levels(float lambda, int levels) const;
  // Vulkan's wrapping of one integer texel coordinate into [0, size).
  static int32_t address(int64_t i, int32_t size, AddressMode mode);

  // The float→fixed converters' rounding: nearest integer, ties to even (= std::llrint in the
  // default rounding mode, without the library call). Below 2^23 adding and subtracting 2^23
  // rounds to an integer in float32 arithmetic; larger floats are integers already.
  static int64_t round_half_even(float x) {
    constexpr float k = 8388608.0f;  // 2^23
    if (std::fabs(x) < k) {
      const float c = std::copysign(k, x);
      return static_cast<int64_t>((x + c) - c);
    }
    return std::llrint(x);  // integers, and NaN (never reached from the datapath)
  }

  // Taps per probe and issue slots (cycles at ii = 1) one fragment occupies.
  int taps_per_probe() const;
  static uint32_t issue_cycles(const LodResult& lod) {
    return static_cast<uint32_t>(lod.probes < 1 ? 1 : (lod.probes > 16 ? 16 : lod.probes));
  }
  // Operations per fragment (level selection) and per probe; an anisotropic fragment
  // (N > 1) adds 1/N per fragment and the probe offset and 1/N weighting per probe.
  const OpCounts& ops_setup(bool anisotropic) const { return ops_setup_[anisotropic]; }
  const OpCounts& ops_per_probe(bool anisotropic) const { return ops_probe_[anisotropic]; }
  // Per-probe pipeline: latency of the critical path, ii = 1 probe per cycle, area of one
  // probe's datapath (with the anisotropic offset/weight stage).
  TimingSpec timing(const TechTable& tech) const;

 private:
  static OpCounts ops_address(AddressMode m);
  OpCounts ops_level() const;
  OpCounts count_setup(bool anisotropic) const;
  OpCounts count_probe(bool anisotropic) const;
  TexelTap* emit_nearest(const Texture& tex, int32_t level, float u, float v, float w,
                         TexelTap* out) const;
  TexelTap* emit_linear(const Texture& tex, int32_t level, float u, float v, float w,
                        TexelTap* out) const;
  Config cfg_;
  // Fixed by the configuration, so computed once: the converters' scale factors (powers of
  // two, so the products are exact and equal to ldexp) and the operation counts.
  float fix_scale_ = 256.0f;        // 2^sub_texel_bits
  float frac_scale_ = 1.0f / 256;   // 2^-sub_texel_bits
  float mip_scale_ = 256.0f;        // 2^mipmap_bits
  float mip_frac_ = 1.0f / 256;     // 2^-mipmap_bits
  OpCounts ops_setup_[2], ops_probe_[2];  // [anisotropic]
};

}  // namespace texsim
