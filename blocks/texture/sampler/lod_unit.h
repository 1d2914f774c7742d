#pragma once
// LOD unit: scale factor, anisotropy ratio and LOD λ of one fragment from its derivatives, as
// the front of a texture filter pipe computes them (docs/derivations/filters.md §1, Vulkan "Scale
// Factor Operation, LOD Operation"). Arithmetic: float32 throughout; log2 is a table look-up.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/sample_op.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

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

// LOD unit (docs/derivations/filters.md §1): isotropic ρ or the Vulkan anisotropic rule N =
// min(⌈ρmax/ρmin⌉, maxAniso), λ = log2(ρmax/N), then bias and clamp.
class LodUnit {
 public:
  struct Config {
    AnisoMode aniso = AnisoMode::Isotropic;
    int max_aniso = 16;  // 1..16 (FilterTaps holds 16 probes × 8 taps)
    float lod_bias = 0;  // sampler bias, added to the fragment's own lod_bias
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
  // The fragment's operation (f.op, Vulkan "LOD Operation") picks λ_base: the derivatives
  // (implicit LOD; explicit gradients, which are the derivative fields), or f.lod (explicit
  // LOD: one probe, and a NaN lod gives λ_base = 0). The fragment's lod_bias is the shader's
  // Bias operand, which SPIR-V allows with implicit LOD only; every operation takes the
  // sampler's bias, then the [min_lod, max_lod] clamp.
  LodResult eval(const Fragment& f, int tex_w, int tex_h, OpCounts& ops) const {
    ops += ops_;
    return eval(f, tex_w, tex_h);
  }
  // The same without counting: a caller that counts fragments multiplies ops_per_item()
  // by their number instead (the count does not depend on the data).
  LodResult eval(const Fragment& f, int tex_w, int tex_h) const;
  // λ of a fragment on a 3-D texture whose level 0 is tex_w × tex_h × tex_d (docs/texture-
  // types.md §7): eval's isotropic arithmetic (float32 squares, log2, the operation's λ_base,
  // bias and clamp) on the footprint's three-dimensional extent, ρ = max(|(∂u, ∂v, ∂r)/∂x ⊙
  // (w, h, d)|, the same along y), ∂r in f.dwdx, f.dwdy. One probe: the 3-D path is isotropic.
  LodResult eval_volume(const Fragment& f, int tex_w, int tex_h, int tex_d) const;

  // Item: one fragment. Operations of the datapath (the same for every fragment: the hardware
  // evaluates every path and selects).
  const OpCounts& ops_per_item() const { return ops_; }
  // The operations fragment of operation `op` uses of that datapath: an explicit LOD skips the
  // derivative front (the bias add, the clamp and the select of λ_base remain).
  OpCounts ops_for(SampleOp op) const;
  // Critical path (latency) and area of a fully pipelined unit (one fragment per cycle).
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const { return "lod"; }
  std::string arithmetic() const { return "float32, log2 by table"; }

 private:
  static OpCounts count_ops(const Config& c);
  Config cfg_;
  OpCounts ops_;  // per fragment, fixed by the configuration
};

// In the header so the texture unit inlines it into its per-fragment path.
inline LodResult LodUnit::eval(const Fragment& f, int tex_w, int tex_h) const {
  LodResult r;
  const bool implicit = f.op == static_cast<uint8_t>(SampleOp::kSample);
  const float bias = cfg_.lod_bias + (implicit ? f.lod_bias : 0.0f);
  if (f.op == static_cast<uint8_t>(SampleOp::kSampleLod)) {
    float lambda = (std::isnan(f.lod) ? 0.0f : f.lod) + bias;
    if (std::isnan(lambda)) lambda = 0;  // inf + (-inf) bias
    r.lambda = std::clamp(lambda, cfg_.min_lod, cfg_.max_lod);
    return r;
  }
  const float w = static_cast<float>(tex_w), h = static_cast<float>(tex_h);

  float lambda_base = 0;  // fallback for non-finite derivatives: level 0 before bias
  const bool finite = std::isfinite(f.dudx) && std::isfinite(f.dvdx) && std::isfinite(f.dudy) &&
                      std::isfinite(f.dvdy);
  if (finite) {
    // Derivatives in texels of level 0 (float32 from here on).
    const float mux = static_cast<float>(f.dudx) * w, mvx = static_cast<float>(f.dvdx) * h;
    const float muy = static_cast<float>(f.dudy) * w, mvy = static_cast<float>(f.dvdy) * h;
    const float px2 = mux * mux + mvx * mvx;
    const float py2 = muy * muy + mvy * mvy;
    const float rmax2 = std::max(px2, py2);
    if (std::isinf(rmax2)) {
      // Overflow of float32 squares (|derivative| > ~1.8e19 texels): the most minified λ.
      lambda_base = std::numeric_limits<float>::infinity();
    } else if (cfg_.aniso == AnisoMode::Isotropic) {
      // ρ = sqrt(rmax2); log2 ρ = ½ log2 ρ². ρ = 0 gives -inf, clamped to min_lod below.
      lambda_base = 0.5f * std::log2(rmax2);
    } else {
      const float rmin2 = std::min(px2, py2);
      const float max_aniso = static_cast<float>(cfg_.max_aniso);
      float eta = 1.0f;
      if (rmax2 == 0.0f) {
        eta = 1.0f;  // footprint is a point
      } else if (rmin2 == 0.0f) {
        eta = max_aniso;  // footprint is a line segment
      } else {
        eta = std::min(std::sqrt(rmax2 / rmin2), max_aniso);
      }
      const int n = std::clamp(static_cast<int>(std::ceil(eta)), 1, cfg_.max_aniso);
      r.probes = n;
      lambda_base = 0.5f * std::log2(rmax2) - std::log2(static_cast<float>(n));
      if (n > 1) {
        // Vulkan picks the x axis when ρx > ρy, else y.
        const bool x_major = px2 > py2;
        const float inv_n = 1.0f / static_cast<float>(n);
        r.axis_u = static_cast<float>(x_major ? f.dudx : f.dudy) * inv_n;
        r.axis_v = static_cast<float>(x_major ? f.dvdx : f.dvdy) * inv_n;
      }
    }
  }
  float lambda = lambda_base + bias;
  if (std::isnan(lambda)) lambda = 0;  // only if bias itself is non-finite
  r.lambda = std::clamp(lambda, cfg_.min_lod, cfg_.max_lod);
  return r;
}

inline LodResult LodUnit::eval_volume(const Fragment& f, int tex_w, int tex_h, int tex_d) const {
  if (f.op == static_cast<uint8_t>(SampleOp::kSampleLod)) return eval(f, tex_w, tex_h);
  LodResult r;
  const float bias =
      cfg_.lod_bias + (f.op == static_cast<uint8_t>(SampleOp::kSample) ? f.lod_bias : 0.0f);
  float lambda_base = 0;  // non-finite derivatives: level 0 before bias, as eval
  const double dx[3] = {f.dudx, f.dvdx, f.dwdx}, dy[3] = {f.dudy, f.dvdy, f.dwdy};
  const float size[3] = {static_cast<float>(tex_w), static_cast<float>(tex_h),
                         static_cast<float>(tex_d)};
  bool finite = true;
  for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(dx[k]) && std::isfinite(dy[k]);
  if (finite) {
    float px2 = 0, py2 = 0;  // in texels of level 0, float32 from here on
    for (int k = 0; k < 3; ++k) {
      const float a = static_cast<float>(dx[k]) * size[k], b = static_cast<float>(dy[k]) * size[k];
      px2 += a * a;
      py2 += b * b;
    }
    // ρ = 0 gives −∞ (min_lod wins the clamp); a float32 overflow +∞ (the most minified λ).
    lambda_base = 0.5f * std::log2(std::max(px2, py2));
  }
  float lambda = lambda_base + bias;
  if (std::isnan(lambda)) lambda = 0;
  r.lambda = std::clamp(lambda, cfg_.min_lod, cfg_.max_lod);
  return r;
}

}  // namespace texsim
