#include "testbench/conformance/vulkan_conformance.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "blocks/base/sample_op.h"

namespace texsim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Per-channel interval of values one candidate (a texel set with weight ranges) can produce.
struct Box {
  double lo[4], hi[4];
  int level;
  long long i0, j0;       // unwrapped integer coordinates (linear: of the i0/j0 texel)
  double a0, a1, b0, b1;  // α, β ranges (nearest: unused)
};

// Vulkan "Wrapping Operation", stated as in the spec; -1 stands for a border texel.
long long wrap(long long i, long long size, AddressMode m) {
  auto mod = [](long long a, long long b) { return ((a % b) + b) % b; };
  switch (m) {
    case AddressMode::Wrap:
      return mod(i, size);
    case AddressMode::Clamp:
      return std::min(std::max(i, 0LL), size - 1);
    case AddressMode::Mirror: {
      const long long n = mod(i, 2 * size) - size;
      const long long mirror = n >= 0 ? n : -(1 + n);
      return (size - 1) - mirror;
    }
    case AddressMode::Border:
      return i < 0 || i >= size ? -1 : i;
    case AddressMode::MirrorClamp: {
      const long long mirror = i >= 0 ? i : -(1 + i);
      return std::min(mirror, size - 1);
    }
  }
  return 0;
}

// "Texel Replacement": a border texel is the sampler's border colour, then "Conversion to
// RGBA" as for any texel of the image's format: the channels it lacks are 0 (colour) and 1
// (alpha); a normalised format's channels hold only its range.
double border_channel(const Texture& tex, const VkSamplerState& s, int c) {
  const StorageFormatInfo& f = format_info(tex.storage());
  if (c >= f.channels) return c == 3 ? 1.0 : 0.0;
  const double b = s.border[c];
  switch (f.coding) {
    case ChannelCoding::Unorm:
    case ChannelCoding::Srgb:  // the border colour is linear: no sRGB decoding
      return std::clamp(b, 0.0, 1.0);
    case ChannelCoding::Snorm:
      return std::clamp(b, -1.0, 1.0);
    default:
      return b;
  }
}

// Every texel set and weight range the spec allows on `level`: integer coordinates from both
// sides of the coordinate's error interval; weights within one sub-texel LSB of the exact
// fraction (truncation and rounding both allowed).
void level_boxes(const Texture& tex, int level, const VkSampleQuery& q, const VkSamplerState& s,
                 const VkFilterPrecision& p, std::vector<Box>& out) {
  out.clear();
  const long long w = tex.width(level), h = tex.height(level);
  const double lsb = std::ldexp(1.0, -p.sub_texel_bits);
  // The offset joins the unwrapped integer coordinates ("Texel Coordinate Offset"), then wrap.
  auto texel = [&](long long i, long long j, int c) {
    const long long x = wrap(i + s.offset_u, w, s.address_u);
    const long long y = wrap(j + s.offset_v, h, s.address_v);
    if (x < 0 || y < 0) return border_channel(tex, s, c);
    const Rgba t = tex.texel(level, static_cast<int>(x), static_cast<int>(y));
    return static_cast<double>(t[c]);
  };
  // Unnormalised coordinates are texel coordinates already ("Unnormalized Texel Coordinate
  // Operations").
  const double xs = s.unnormalized ? q.u : q.u * static_cast<double>(w);
  const double ys = s.unnormalized ? q.v : q.v * static_cast<double>(h);
  const double ex = std::fabs(xs) * p.coord_rel_eps + 1e-9;
  const double ey = std::fabs(ys) * p.coord_rel_eps + 1e-9;
  if (s.filter == VkSamplerState::Filter::Nearest) {
    // i = ⌊u·width⌋; the coordinate may carry only sub_texel_bits fraction bits.
    const auto i_lo = static_cast<long long>(std::floor(xs - ex - lsb));
    const auto i_hi = static_cast<long long>(std::floor(xs + ex + lsb));
    const auto j_lo = static_cast<long long>(std::floor(ys - ey - lsb));
    const auto j_hi = static_cast<long long>(std::floor(ys + ey + lsb));
    for (long long i = i_lo; i <= i_hi; ++i) {
      for (long long j = j_lo; j <= j_hi; ++j) {
        Box b{};
        b.level = level;
        b.i0 = i;
        b.j0 = j;
        for (int c = 0; c < 4; ++c) b.lo[c] = b.hi[c] = texel(i, j, c);
        out.push_back(b);
      }
    }
    return;
  }
  // Linear: i0 = ⌊u·width − ½⌋, α = frac(u·width − ½) kept to sub_texel_bits.
  const double x = xs - 0.5, y = ys - 0.5;
  const auto i_lo = static_cast<long long>(std::floor(x - ex));
  const auto i_hi = static_cast<long long>(std::floor(x + ex));
  const auto j_lo = static_cast<long long>(std::floor(y - ey));
  const auto j_hi = static_cast<long long>(std::floor(y + ey));
  for (long long i0 = i_lo; i0 <= i_hi; ++i0) {
    for (long long j0 = j_lo; j0 <= j_hi; ++j0) {
      Box b{};
      b.level = level;
      b.i0 = i0;
      b.j0 = j0;
      const double fi = static_cast<double>(i0), fj = static_cast<double>(j0);
      b.a0 = std::clamp(x - ex - fi - lsb, 0.0, 1.0);
      b.a1 = std::clamp(x + ex - fi + lsb, 0.0, 1.0);
      b.b0 = std::clamp(y - ey - fj - lsb, 0.0, 1.0);
      b.b1 = std::clamp(y + ey - fj + lsb, 0.0, 1.0);
      for (int c = 0; c < 4; ++c) {
        const double t00 = texel(i0, j0, c), t10 = texel(i0 + 1, j0, c);
        const double t01 = texel(i0, j0 + 1, c), t11 = texel(i0 + 1, j0 + 1, c);
        // Bilinear in (α, β): its extremes over the weight box are at the corners.
        b.lo[c] = kInf;
        b.hi[c] = -kInf;
        for (double a : {b.a0, b.a1}) {
          for (double be : {b.b0, b.b1}) {
            const double f =
                (1 - a) * (1 - be) * t00 + a * (1 - be) * t10 + (1 - a) * be * t01 + a * be * t11;
            b.lo[c] = std::min(b.lo[c], f);
            b.hi[c] = std::max(b.hi[c], f);
          }
        }
      }
      out.push_back(b);
    }
  }
}

// Judges candidates one by one and keeps the closest miss, for the reason string.
class CandidateJudge {
 public:
  CandidateJudge(const Rgba& result, double color_eps) : result_(result), color_eps_(color_eps) {}

  const Rgba& result() const { return result_; }
  // The colour tolerance around x.
  double tol(double x) const { return color_eps_ * std::max(1.0, std::fabs(x)); }

  // Whether the result is inside a candidate's per-channel ranges. A candidate whose channels
  // are each reachable but not together (`conflict` ≥ 0) misses by a nominal eps. When this is
  // the closest miss so far, describe(buf, size, channel, lo, hi, is_conflict) explains it.
  template <class Describe>
  bool judge(const double* lo, const double* hi, Describe&& describe, int conflict) {
    double miss = 0;
    int worst_c = 0;
    for (int c = 0; c < 4; ++c) {
      const double r = result_[c];
      const double m = std::max({0.0, (lo[c] - tol(r)) - r, r - (hi[c] + tol(r))});
      if (m > miss) {
        miss = m;
        worst_c = c;
      }
    }
    const bool is_conflict = miss == 0 && conflict >= 0;
    if (is_conflict) {
      miss = color_eps_;
      worst_c = conflict;
    }
    if (miss < best_) {
      best_ = miss;
      if (miss > 0) {
        describe(best_desc_, sizeof best_desc_, worst_c, lo[worst_c], hi[worst_c], is_conflict);
      }
    }
    return miss == 0;
  }

  double best() const { return best_; }
  const char* best_desc() const { return best_desc_; }

 private:
  const Rgba& result_;
  double color_eps_;
  double best_ = kInf;
  char best_desc_[320] = "";
};

// Mipmap mode nearest: any candidate of any level in [level_lo, level_hi].
bool judge_nearest_mip(const Texture& tex, const VkSampleQuery& q, const VkSamplerState& s,
                       const VkFilterPrecision& p, int level_lo, int level_hi,
                       CandidateJudge& judge) {
  std::vector<Box> a;
  for (int L = level_lo; L <= level_hi; ++L) {
    level_boxes(tex, L, q, s, p, a);
    for (const Box& x : a) {
      const bool ok = judge.judge(
          x.lo, x.hi,
          [&](char* buf, size_t n, int c, double lo, double hi, bool) {
            std::snprintf(buf, n,
                          "level %d, i0=%lld j0=%lld, alpha in [%.5f, %.5f], beta in [%.5f, "
                          "%.5f]: channel %d allowed [%.6f, %.6f]",
                          x.level, x.i0, x.j0, x.a0, x.a1, x.b0, x.b1, c, lo, hi);
          },
          -1);
      if (ok) return true;
    }
  }
  return false;
}

// Ranges of (1 − δ)·A + δ·B for δ in [d0, d1], A in x's and B in y's, into lo and hi. The result
// must equal it for one δ shared by all channels: per channel the feasible δ form an interval
// (both bounds are linear in δ); returns the first channel whose interval leaves none in
// common with [d0, d1] and the earlier channels', or -1.
int blend_ranges(const Box& x, const Box& y, double d0, double d1, const CandidateJudge& judge,
                 double* lo, double* hi) {
  double g0 = d0, g1 = d1;
  int conflict = -1;
  for (int c = 0; c < 4; ++c) {
    lo[c] = std::min((1 - d0) * x.lo[c] + d0 * y.lo[c], (1 - d1) * x.lo[c] + d1 * y.lo[c]);
    hi[c] = std::max((1 - d0) * x.hi[c] + d0 * y.hi[c], (1 - d1) * x.hi[c] + d1 * y.hi[c]);
    const double r = judge.result()[c], t = judge.tol(r);
    // r ≥ A_lo + δ (B_lo − A_lo) − t  and  r ≤ A_hi + δ (B_hi − A_hi) + t.
    const double kl = y.lo[c] - x.lo[c], cl = r - x.lo[c] + t;
    const double kh = y.hi[c] - x.hi[c], ch = r - x.hi[c] - t;
    double e0 = 0, e1 = 1;
    if (kl > 0)
      e1 = std::min(e1, cl / kl);
    else if (kl < 0)
      e0 = std::max(e0, cl / kl);
    else if (cl < 0)
      e1 = -1;
    if (kh > 0)
      e0 = std::max(e0, ch / kh);
    else if (kh < 0)
      e1 = std::min(e1, ch / kh);
    else if (ch > 0)
      e1 = -1;
    const double n0 = std::max(g0, e0), n1 = std::min(g1, e1);
    if (n0 > n1 && conflict < 0) conflict = c;
    g0 = n0;
    g1 = n1;
  }
  return conflict;
}

// Mipmap mode linear: d_hi = ⌊d'⌋, d_lo = min(d_hi + 1, q), δ = frac(d') to mipmap_bits
// (±1 LSB), for every d' in [dlo, dhi]; any pair of candidates of the two levels.
bool judge_linear_mip(const Texture& tex, const VkSampleQuery& q, const VkSamplerState& s,
                      const VkFilterPrecision& p, double dlo, double dhi, CandidateJudge& judge) {
  const int qmax = tex.levels() - 1;
  const double mip_lsb = std::ldexp(1.0, -p.mipmap_bits);
  std::vector<Box> a, b;
  for (int dh = static_cast<int>(std::floor(dlo)); dh <= static_cast<int>(std::floor(dhi)); ++dh) {
    const int dl = std::min(dh + 1, qmax);
    double d0 = std::clamp(dlo - dh - mip_lsb, 0.0, 1.0);
    double d1 = std::clamp(dhi - dh + mip_lsb, 0.0, 1.0);
    if (dh == qmax) d0 = d1 = 0;
    level_boxes(tex, dh, q, s, p, a);
    level_boxes(tex, dl, q, s, p, b);
    for (const Box& x : a) {
      for (const Box& y : b) {
        double lo[4], hi[4];
        const int conflict = blend_ranges(x, y, d0, d1, judge, lo, hi);
        const bool ok = judge.judge(
            lo, hi,
            [&](char* buf, size_t n, int c, double l, double h, bool no_common_delta) {
              if (no_common_delta) {
                std::snprintf(buf, n,
                              "levels %d/%d, delta in [%.5f, %.5f], i0=%lld/%lld j0=%lld/%lld: "
                              "every channel is reachable alone but no single delta reaches "
                              "all (channel %d leaves none)",
                              dh, dl, d0, d1, x.i0, y.i0, x.j0, y.j0, c);
              } else {
                std::snprintf(buf, n,
                              "levels %d/%d, delta in [%.5f, %.5f], i0=%lld/%lld j0=%lld/%lld, "
                              "alpha in [%.5f, %.5f]: channel %d allowed [%.6f, %.6f]",
                              dh, dl, d0, d1, x.i0, y.i0, x.j0, y.j0, x.a0, x.a1, c, l, h);
              }
            },
            conflict);
        if (ok) return true;
      }
    }
  }
  return false;
}

}  // namespace

void VulkanConformance::lod_interval(const Texture& tex, const VkSampleQuery& q, double& lo,
                                     double& hi) const {
  const double bias = s_.mip_lod_bias + q.shader_bias;
  if (s_.unnormalized) {  // valid usage: minLod = maxLod = 0, explicit LOD 0
    lo = hi = 0;
    return;
  }
  if (q.explicit_lod) {
    // The sampler's bias only (the instruction has no Bias operand), then the clamp.
    const double acc = std::ldexp(1.0, -p_.mipmap_bits);
    lo = std::isfinite(q.lod) ? q.lod + s_.mip_lod_bias - acc : -kInf;
    hi = std::isfinite(q.lod) ? q.lod + s_.mip_lod_bias + acc : kInf;
  } else if (!(std::isfinite(q.dudx) && std::isfinite(q.dvdx) && std::isfinite(q.dudy) &&
               std::isfinite(q.dvdy))) {
    lo = -kInf;
    hi = kInf;
  } else {
    const double w = tex.width(0), h = tex.height(0);
    const double mux = std::fabs(q.dudx) * w, mvx = std::fabs(q.dvdx) * h;
    const double muy = std::fabs(q.dudy) * w, mvy = std::fabs(q.dvdy) * h;
    // Scale factors: max(|m_u|, |m_v|) ≤ f ≤ √2 (|m_u| + |m_v|); ρmax = max(f_x, f_y).
    const double rho_lo = std::max(std::max(mux, mvx), std::max(muy, mvy));
    const double rho_hi = std::sqrt(2.0) * std::max(mux + mvx, muy + mvy);
    const double acc = std::ldexp(1.0, -p_.mipmap_bits);  // LOD accuracy
    lo = std::log2(rho_lo) - acc + bias;                  // log2(0) = −inf: magnification
    hi = std::log2(rho_hi) + acc + bias;
  }
  lo = std::clamp(lo, s_.min_lod, s_.max_lod);
  hi = std::clamp(hi, s_.min_lod, s_.max_lod);
}

ConformanceVerdict VulkanConformance::check(const Texture& tex, const VkSampleQuery& q,
                                            const Rgba& result) const {
  ConformanceVerdict v;
  if (!std::isfinite(q.u) || !std::isfinite(q.v)) {
    v.pass = true;
    v.judged = false;
    v.reason = "not judged: non-finite coordinates (undefined in the spec)";
    return v;
  }
  for (int c = 0; c < 4; ++c) {
    if (std::isnan(result[c])) {
      v.reason = "result channel " + std::to_string(c) + " is NaN";
      v.miss = kInf;
      return v;
    }
  }
  lod_interval(tex, q, v.lambda_lo, v.lambda_hi);
  const int qmax = tex.levels() - 1;
  const double dlo = std::clamp(v.lambda_lo, 0.0, static_cast<double>(qmax));
  const double dhi = std::clamp(v.lambda_hi, 0.0, static_cast<double>(qmax));

  CandidateJudge judge(result, p_.color_eps);
  bool ok = false;
  if (s_.mipmap_mode == VkSamplerState::MipmapMode::Nearest) {
    // nearest(d') = ⌈d' + ½⌉ − 1 (preferred) or ⌊d' + ½⌋ (alternative): take both, d' carried
    // with mipmap_bits fraction bits (±1 LSB: the clamp to [min_lod, max_lod] comes before
    // that conversion, so a clamped λ is rounded too).
    const double mip_lsb = std::ldexp(1.0, -p_.mipmap_bits);
    v.level_lo = std::clamp(static_cast<int>(std::ceil(dlo - mip_lsb + 0.5)) - 1, 0, qmax);
    v.level_hi = std::clamp(static_cast<int>(std::floor(dhi + mip_lsb + 0.5)), 0, qmax);
    ok = judge_nearest_mip(tex, q, s_, p_, v.level_lo, v.level_hi, judge);
  } else {
    v.level_lo = static_cast<int>(std::floor(dlo));
    v.level_hi = std::min(static_cast<int>(std::floor(dhi)) + 1, qmax);
    ok = judge_linear_mip(tex, q, s_, p_, dlo, dhi, judge);
  }
  v.pass = ok;
  if (ok) {
    v.reason = "ok";
    return v;
  }
  v.miss = judge.best();
  char buf[640];
  std::snprintf(buf, sizeof buf,
                "result (%.6f, %.6f, %.6f, %.6f) outside every allowed value; lambda in "
                "[%.4f, %.4f], levels %d..%d; closest candidate misses by %.3g: %s",
                static_cast<double>(result[0]), static_cast<double>(result[1]),
                static_cast<double>(result[2]), static_cast<double>(result[3]), v.lambda_lo,
                v.lambda_hi, v.level_lo, v.level_hi, judge.best(), judge.best_desc());
  v.reason = buf;
  return v;
}

VkSamplerState vk_sampler_of(const TexelAddressGen::Config& a, const LodUnit::Config& l) {
  VkSamplerState v;
  v.filter = a.filter == FilterMode::Nearest ? VkSamplerState::Filter::Nearest
                                             : VkSamplerState::Filter::Linear;
  v.mipmap_mode = a.filter == FilterMode::Trilinear ? VkSamplerState::MipmapMode::Linear
                                                    : VkSamplerState::MipmapMode::Nearest;
  v.address_u = a.address_u;
  v.address_v = a.address_v;
  v.mip_lod_bias = l.lod_bias;
  v.min_lod = l.min_lod;
  v.max_lod = l.max_lod;
  for (int c = 0; c < 4; ++c) v.border[c] = a.border[c];
  v.offset_u = a.offset_u;
  v.offset_v = a.offset_v;
  v.unnormalized = a.unnormalized;
  return v;
}

VkSampleQuery vk_query_of(const Fragment& f) {
  VkSampleQuery q{f.u, f.v, f.dudx, f.dvdx, f.dudy, f.dvdy, f.lod_bias};
  q.explicit_lod = f.op == static_cast<uint8_t>(SampleOp::kSampleLod);
  q.lod = f.lod;
  return q;
}

}  // namespace texsim
