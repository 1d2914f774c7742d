#pragma once
// LOD unit: scale factor, anisotropy ratio and LOD λ of one fragment from its derivatives, as
// the front of a texture filter pipe computes them (docs/filters.md §1, Vulkan "Scale Factor
// Operation, LOD Operation"). Arithmetic: float32 throughout; log2 is a table look-up.
#include <cstdint>

#include "blocks/config_reader.h"
#include "blocks/op_counts.h"
#include "blocks/tech_table.h"
#include "blocks/timing_spec.h"
#include "traces/fragment.h"

namespace texsim {

enum class AnisoMode { Isotropic, Vulkan };

// Output of the LOD unit for one fragment. `lambda` is Vulkan's λ: after bias and the
// [min_lod, max_lod] clamp, before the clamp to the pyramid (the filter's level selection does
// that, as it knows the texture). `probes` = N ≥ 1; (axis_u, axis_v) is the step between
// neighbouring probes along the major axis in normalised coordinates (0 when N = 1).
struct LodResult {
  float lambda = 0;
  int probes = 1;
  float axis_u = 0, axis_v = 0;
};

// LOD unit (docs/filters.md §1): isotropic ρ or the Vulkan anisotropic rule N = min(⌈ρmax/ρmin⌉,
// maxAniso), λ = log2(ρmax/N), then bias and clamp.
class LodUnit {
 public:
  struct Config {
    AnisoMode aniso = AnisoMode::Isotropic;
    int max_aniso = 16;    // 1..16 (FilterTaps holds 16 probes × 8 taps)
    float lod_bias = 0;    // sampler bias, added to the fragment's own lod_bias
    float min_lod = 0;
    float max_lod = 1000;
    // Keys: aniso ("isotropic"|"vulkan"), max_aniso, lod_bias, min_lod, max_lod.
    static Config from_toml(const ConfigReader& r);
  };

  LodUnit() : LodUnit(Config{}) {}
  explicit LodUnit(const Config& c) : cfg_(c), ops_(count_ops(c)) {}
  const Config& config() const { return cfg_; }

  // λ, probe count and probe step for fragment `f` on a texture whose level 0 is
  // tex_w × tex_h. Adds this fragment's operations to `ops`. Never returns NaN: non-finite
  // derivatives give λ_base = 0 (then bias and clamp as usual) and one probe.
  LodResult eval(const Fragment& f, int tex_w, int tex_h, OpCounts& ops) const {
    ops += ops_;
    return eval(f, tex_w, tex_h);
  }
  // The same without counting: a caller that counts fragments multiplies ops_per_fragment()
  // by their number instead (the count does not depend on the data).
  LodResult eval(const Fragment& f, int tex_w, int tex_h) const;

  // Operations per fragment of the datapath (the same for every fragment: the hardware
  // evaluates every path and selects).
  const OpCounts& ops_per_fragment() const { return ops_; }
  // Critical path (latency) and area of a fully pipelined unit (one fragment per cycle).
  TimingSpec timing(const TechTable& tech) const;

 private:
  static OpCounts count_ops(const Config& c);
  Config cfg_;
  OpCounts ops_;  // per fragment, fixed by the configuration
};

}  // namespace texsim
