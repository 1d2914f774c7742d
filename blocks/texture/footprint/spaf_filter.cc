#include "blocks/texture/footprint/spaf_filter.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <type_traits>

#include "blocks/base/block.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

static_assert(Block<SpafFilter>);

namespace {

// Set-up and accumulation types of a datapath T: double for the double datapath, else float32.
template <class T>
using SetupOf = std::conditional_t<std::is_same_v<T, double>, double, float>;

template <class T>
T to_t(double x) {
  if constexpr (is_fixed_v<T>)
    return T(x);
  else
    return static_cast<T>(x);
}

// d = E·(−k), k = ‖n‖₁/‖n‖₂: the texel centre's Euclidean distance to the edge (positive
// outside), rounded once into the cut-off's signed input format SIn.
template <class SIn, class T>
SIn edge_distance(T e, T negk) {
  if constexpr (is_fixed_v<T> && is_fixed_v<SIn>) {
    return vd_detail::mul<SIn>(e, negk);
  } else if constexpr (is_fixed_v<T>) {
    return static_cast<SIn>(to_double(e) * to_double(negk));
  } else {
    const T p = e * negk;
    return vd_detail::quantize<SIn>(static_cast<long double>(p));
  }
}

// Coverage of a texel from its cut edges (|E| < ½), accumulated edge by edge.
// Masks: AND of the table's sub-texel masks, popcount / bits.
struct MaskCoverage {
  const SpafFilter* sp;
  double deu[4], dev[4];
  uint64_t full;
  float inv_bits;
  uint64_t start() const { return full; }
  template <class T>
  void cut(uint64_t& m, int k, T e) const {
    m &= sp->mask(deu[k], dev[k], to_double(e));
  }
  static bool empty(uint64_t m) { return m == 0; }
  float coverage(uint64_t m) const { return static_cast<float>(std::popcount(m)) * inv_bits; }
  static uint32_t slots(int) { return 1; }
};

// V(d): the product over cut edges of W(d)/W(−½) in the cut-off's format.
template <class T, class Fmt>
struct VdCoverage {
  using Out = typename Fmt::Out;
  SubtexelCutoff::Fraction<Fmt> frac;
  T negk[4];
  uint32_t units;  // cut-off units per lane
  Out start() const { return frac.one(); }
  void cut(Out& c, int k, T e) const {
    c = vd_detail::mul<Out>(c, frac(edge_distance<typename Fmt::SIn>(e, negk[k])));
  }
  static bool empty(Out c) { return !(c > vd_detail::quantize<Out>(0.0L)); }
  static float coverage(Out c) { return static_cast<float>(to_double(c)); }
  // A texel occupies its lane until its cut edges have passed the lane's cut-off units.
  uint32_t slots(int cut_edges) const {
    return std::max<uint32_t>(1, (static_cast<uint32_t>(cut_edges) + units - 1) / units);
  }
};

}  // namespace

SpafFilter::Config SpafFilter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"mask_side", "slope_steps", "offset_steps", "half_px", "gaussian", "alpha",
                    "texel_budget", "lanes", "address_u", "address_v", "coverage", "vd", "arith"});
  Config c;
  c.mask_side = static_cast<int>(r.get_int("mask_side", c.mask_side, 1, 8));
  c.slope_steps = static_cast<int>(r.get_int("slope_steps", c.slope_steps, 4, 4096));
  if (c.slope_steps % 2 != 0) r.fail("slope_steps", "must be even (one half per sign of dev)");
  c.offset_steps = static_cast<int>(r.get_int("offset_steps", c.offset_steps, 2, 4096));
  c.half_px = r.get_double("half_px", c.half_px);
  if (!(c.half_px > 0) || !(c.half_px <= 8)) r.fail("half_px", "must be in (0, 8]");
  c.gaussian = r.get_bool("gaussian", c.gaussian);
  c.alpha = r.get_double("alpha", c.alpha);
  if (!(c.alpha >= 0) || !(c.alpha <= 64)) r.fail("alpha", "must be in [0, 64]");
  c.texel_budget = static_cast<int>(r.get_int("texel_budget", c.texel_budget, 16, 1 << 20));
  c.lanes = static_cast<int>(r.get_int("lanes", c.lanes, 1, 64));
  c.address_u = footprint_address_mode(r, "address_u");
  c.address_v = footprint_address_mode(r, "address_v");
  c.coverage =
      static_cast<Coverage>(r.get_choice("coverage", static_cast<int>(c.coverage), {"mask", "vd"}));
  if (c.coverage == Coverage::Vd) {
    c.vd = SubtexelCutoff::Config::from_toml(r.sub("vd"));
  } else if (r.table().contains("vd")) {
    r.fail("vd", "is only used with coverage = \"vd\"");
  }
  c.arith = kArith.at(r.get_choice("arith", kArith.index_of(c.arith), kArith.key_list()));
  return c;
}

SpafFilter::SpafFilter(const Config& c) : cfg_(c), cut_(c.vd) {
  cfg_.mask_side = std::clamp(cfg_.mask_side, 1, 8);
  cfg_.slope_steps = std::max(2, cfg_.slope_steps & ~1);
  cfg_.offset_steps = std::max(2, cfg_.offset_steps);
  cfg_.vd.lanes = std::max<uint32_t>(1, cfg_.vd.lanes);
  cut_ = SubtexelCutoff(cfg_.vd);
  const int half = cfg_.slope_steps / 2;
  table_.resize(static_cast<size_t>(cfg_.slope_steps) * static_cast<size_t>(cfg_.offset_steps));
  // Each entry is the exact mask at the centre of its (slope, E) cell.
  for (int s = 0; s < cfg_.slope_steps; ++s) {
    const double deu = -1.0 + 2.0 * ((s % half) + 0.5) / half;
    const double dev = (s < half ? 1.0 : -1.0) * (1.0 - std::fabs(deu));
    for (int e = 0; e < cfg_.offset_steps; ++e) {
      const double ev = -0.5 + (e + 0.5) / cfg_.offset_steps;
      table_[static_cast<size_t>(s) * static_cast<size_t>(cfg_.offset_steps) +
             static_cast<size_t>(e)] = exact_mask(deu, dev, ev);
    }
  }
}

uint64_t SpafFilter::table_bytes() const {
  return table_.size() * static_cast<uint64_t>((mask_bits() + 7) / 8);
}

uint64_t SpafFilter::exact_mask(double deu, double dev, double e) const {
  const int n = cfg_.mask_side;
  uint64_t m = 0;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const double ox = (x + 0.5) / n - 0.5, oy = (y + 0.5) / n - 0.5;
      if (e + ox * deu + oy * dev >= 0) m |= uint64_t{1} << (y * n + x);
    }
  }
  return m;
}

int SpafFilter::slope_index(double deu, double dev) const {
  // The normal lies on the L1 diamond |deu| + |dev| = 1: deu ∈ [−1, 1] and the sign of dev
  // name it without an angle.
  const int half = cfg_.slope_steps / 2;
  const int i = std::clamp(static_cast<int>((deu + 1.0) * 0.5 * half), 0, half - 1);
  return dev >= 0 ? i : i + half;
}

uint64_t SpafFilter::mask(double deu, double dev, double e) const {
  const int s = slope_index(deu, dev);
  const int k =
      std::clamp(static_cast<int>((e + 0.5) * cfg_.offset_steps), 0, cfg_.offset_steps - 1);
  return table_[static_cast<size_t>(s) * static_cast<size_t>(cfg_.offset_steps) +
                static_cast<size_t>(k)];
}

double SpafFilter::vd_coverage(double deu, double dev, double e) const {
  // E is normalised by ‖n‖₁; the Euclidean distance is E·‖n‖₁/‖n‖₂ = E/‖(deu, dev)‖₂.
  const double negk = -1.0 / std::hypot(deu, dev);
  return visit_vd_format(cfg_.vd.format, [&](auto fmt) {
    using Fmt = decltype(fmt);
    const SubtexelCutoff::Fraction<Fmt> frac(cut_);
    return to_double(frac(edge_distance<typename Fmt::SIn>(e, negk)));
  });
}

namespace {

// One fragment through SpafFilter's datapath in T, stage by stage (SpafFilter::filter_t):
// level and box, per-level edge and Q set-up in S, the fixed datapath's range guard, the
// stepping start in T, then the scan with a coverage unit.
template <class T>
struct SpafRun {
  using S = SetupOf<T>;
  using Acc = SetupOf<T>;

  const SpafFilter& sp;
  const Texture& tex;
  std::vector<TexelRef>* fetched;
  OpCounts& ops;
  FilterOutput out{};
  int w0 = 0, h0 = 0, q_top = 0, level = 0, wl = 0, hl = 0;
  double u = 0, v = 0, ax = 0, ay = 0, bx = 0, by = 0, det = 0;
  int64_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  // Per-level set-up in S: edge normals, E at the centre, −k (V(d) coverage), Q coefficients.
  S deu[4]{}, dev[4]{}, ec[4]{}, negk[4]{};
  S qa = 0, qb = 0, qc = 0, uc = 0, vc = 0, U0 = 0, V0 = 0;
  // Stepping start in T.
  T deut[4]{}, devt[4]{}, erow0[4]{};
  T q0{}, dq0{}, dqv0{}, bt{}, two_a{}, two_c{};

  const SpafFilter::Config& cfg() const { return sp.config(); }

  FilterOutput fallback() {
    out.stats.fallback = true;
    out.stats.level = level;
    out.colour =
        bilinear_fallback(tex, level, u, v, cfg().address_u, cfg().address_v, fetched, ops);
    out.stats.texels += 4;
    return out;
  }

  // Position and the footprint's half-axes in level-0 texels (non-finite: replaced).
  void read_fragment(const Fragment& f) {
    w0 = tex.width(0);
    h0 = tex.height(0);
    q_top = tex.levels() - 1;
    u = f.u;
    v = f.v;
    if (!std::isfinite(u) || !std::isfinite(v)) {
      out.stats.bad_input = true;
      u = std::isfinite(u) ? u : 0.0;
      v = std::isfinite(v) ? v : 0.0;
    }
    const double h = cfg().half_px;
    ax = f.dudx * w0 * h;
    ay = f.dvdx * h0 * h;
    bx = f.dudy * w0 * h;
    by = f.dvdy * h0 * h;
    if (!std::isfinite(ax) || !std::isfinite(ay) || !std::isfinite(bx) || !std::isfinite(by)) {
      out.stats.bad_input = true;
      ax = ay = bx = by = 0;
    }
    det = ax * by - ay * bx;
  }

  // The bounding box of the quadrilateral at level l (sets i0..j1); returns its texel count.
  double box(int l) {
    const double sx = static_cast<double>(tex.width(l)) / w0,
                 sy = static_cast<double>(tex.height(l)) / h0;
    const double ex = (std::fabs(ax) + std::fabs(bx)) * sx,
                 ey = (std::fabs(ay) + std::fabs(by)) * sy;
    constexpr double kLimit = 1073741824.0;
    const double cu = std::clamp(u * tex.width(l) - 0.5, -kLimit, kLimit);
    const double cv = std::clamp(v * tex.height(l) - 0.5, -kLimit, kLimit);
    const double exc = std::min(ex, kLimit), eyc = std::min(ey, kLimit);
    i0 = static_cast<int64_t>(std::ceil(cu - exc - 0.5));
    i1 = static_cast<int64_t>(std::floor(cu + exc + 0.5));
    j0 = static_cast<int64_t>(std::ceil(cv - eyc - 0.5));
    j1 = static_cast<int64_t>(std::floor(cv + eyc + 0.5));
    OpCounts it;  // scale, extents, bounds, count, compare
    it.mul = 4 + 1;
    it.add = 2 + 4 + 2;
    it.cmp = 4 + 1;
    ops += it;
    return static_cast<double>(i1 - i0 + 1) * static_cast<double>(j1 - j0 + 1);
  }

  // Level: start where the shorter derivative (one pixel) spans 1–2 texels, as EWA's minor
  // axis rule, then go coarser until the box fits the budget. Control decisions, in double.
  // False: a zero-area quadrilateral (no inside) or a box still too large at the top level
  // (a footprint far larger than the texture): both take the bilinear sample.
  bool select_level() {
    const double shorter = std::min(std::hypot(ax, ay), std::hypot(bx, by)) / cfg().half_px;
    level = 0;
    if (shorter > 1) level = std::min(q_top, static_cast<int>(std::floor(std::log2(shorter))));
    while (box(level) > cfg().texel_budget && level < q_top) ++level;
    out.stats.level = level;
    return std::fabs(det) > 0 && !(box(level) > cfg().texel_budget * 4.0);
  }

  // Per-level set-up in S: corners relative to the centre (P0 → P1 → P2 → P3 → P0), edge
  // normals and the edge values at the centre. False: an edge of zero length after rounding
  // (a quadrilateral too thin for S has no inside).
  bool edge_setup() {
    wl = tex.width(level);
    hl = tex.height(level);
    const double sxl = static_cast<double>(wl) / w0, syl = static_cast<double>(hl) / h0;
    uc = static_cast<S>(u * wl - 0.5);
    vc = static_cast<S>(v * hl - 0.5);
    const S lax = static_cast<S>(ax * sxl), lay = static_cast<S>(ay * syl);
    const S lbx = static_cast<S>(bx * sxl), lby = static_cast<S>(by * syl);
    const S ox[4] = {-lax - lbx, lax - lbx, lax + lbx, -lax + lbx};
    const S oy[4] = {-lay - lby, lay - lby, lay + lby, -lay + lby};
    for (int k = 0; k < 4; ++k) {
      const S du = ox[(k + 1) % 4] - ox[k], dv = oy[(k + 1) % 4] - oy[k];
      const S l1 = std::fabs(du) + std::fabs(dv);
      const S rl1 = S(1) / l1;
      if (!(l1 > 0) || !std::isfinite(rl1)) return false;
      deu[k] = dv * rl1;
      dev[k] = -du * rl1;
      // E at the centre. The seed's normal (ΔV, −ΔU) points inside for one orientation only:
      // flip it so that the centre is inside (E > 0) whatever the sign of det J.
      ec[k] = -(ox[k] * deu[k] + oy[k] * dev[k]);
      if (ec[k] < 0) {
        deu[k] = -deu[k];
        dev[k] = -dev[k];
        ec[k] = -ec[k];
      }
      negk[k] =
          cfg().coverage == SpafFilter::Coverage::Vd ? -(l1 / std::sqrt(du * du + dv * dv)) : S(0);
    }
    gaussian_setup(lax, lay, lbx, lby);
    return true;
  }

  // Gaussian weight: Q of the R = 1 px ellipse, Σ = J·Jᵀ at this level (level texels), with
  // det Σ = (det J)² (no cancellation in suu·svv − suv²).
  void gaussian_setup(S lax, S lay, S lbx, S lby) {
    const S r = static_cast<S>(1.0 / cfg().half_px);
    const S jux = lax * r, jvx = lay * r, juy = lbx * r, jvy = lby * r;
    const S suu = jux * jux + juy * juy, suv = jux * jvx + juy * jvy, svv = jvx * jvx + jvy * jvy;
    const S jdet = jux * jvy - juy * jvx;
    const S sdet = jdet * jdet;
    const S rs = sdet > 0 && std::isfinite(S(1) / sdet) ? S(1) / sdet : S(0);
    qa = svv * rs;
    qb = S(-2) * suv * rs;
    qc = suu * rs;
    // Box corner (i0, j0) relative to the centre: the stepping starts there.
    U0 = static_cast<S>(i0) - uc;
    V0 = static_cast<S>(j0) - vc;
  }

  // Every value the stepping datapath holds (E; Q, its steps and products at the box corner)
  // is bounded from the box: |E| ≤ max E(centre) + Ub + Vb, and with Ub, Vb the box's
  // extents from the centre plus one step, |Q|, |dQ| ≤ 3·Qb, Qb = (a·Ub + |b|·Vb)·Ub + c·Vb².
  // False beyond the format's range: the fixed datapath does not scan (bilinear fallback).
  bool fixed_guard() {
    ops += sp.fixed_guard_ops();
    const S ub = std::max(std::fabs(U0), std::fabs(static_cast<S>(i1) - uc)) + S(1);
    const S vb = std::max(std::fabs(V0), std::fabs(static_cast<S>(j1) - vc)) + S(1);
    const S qbound = cfg().gaussian ? (qa * ub + std::fabs(qb) * vb) * ub + qc * vb * vb : S(0);
    const S ebound = std::max(std::max(ec[0], ec[1]), std::max(ec[2], ec[3])) + ub + vb;
    const S limit = static_cast<S>(std::ldexp(1.0, T::kIntBits - 3));  // a quarter of the range
    return qbound < limit && ebound < limit;
  }

  // Stepping datapath in T: E_k = ec_k + U·deu_k + V·dev_k and Q = (aU + bV)U + cV² at the
  // box corner, then additions only: along a row E += deu, Q += dQ, dQ += 2a; down a row
  // E += dev, Q_row += dQv, dQv += 2c, dQ_row += b.
  void stepping_start() {
    const T one = to_t<T>(1.0);
    const T Ut = to_t<T>(static_cast<double>(U0)), Vt = to_t<T>(static_cast<double>(V0));
    for (int k = 0; k < 4; ++k) {
      deut[k] = to_t<T>(static_cast<double>(deu[k]));
      devt[k] = to_t<T>(static_cast<double>(dev[k]));
      erow0[k] = to_t<T>(static_cast<double>(ec[k])) + deut[k] * Ut + devt[k] * Vt;
    }
    const T at = to_t<T>(static_cast<double>(qa)), ct = to_t<T>(static_cast<double>(qc));
    bt = to_t<T>(static_cast<double>(qb));
    q0 = (at * Ut + bt * Vt) * Ut + ct * Vt * Vt;
    dq0 = at * (Ut + Ut + one) + bt * Vt;
    dqv0 = bt * Ut + ct * (Vt + Vt + one);
    two_a = at + at;
    two_c = ct + ct;
  }

  // Per-kind step counts of the scan (operations multiplied out at the end).
  struct Steps {
    uint64_t rows = 0, visits = 0, partials = 0, insides = 0;
  };

  // One texel at E values e and Q value q: the edge units, coverage, weight and MAC.
  template <class Cov>
  void texel(const Cov& cov, const T (&e)[4], T q, int64_t i, int32_t y, Steps& n,
             glm::vec<4, Acc>& sum, Acc& wsum) {
    const T zero = to_t<T>(0.0), half = to_t<T>(0.5), mhalf = to_t<T>(-0.5);
    // The four edge units test in parallel; a texel out on any edge goes no further.
    bool out_side = false;
    int cuts = 0, cut_k[4];
    for (int k = 0; k < 4; ++k) {
      if (e[k] <= mhalf)
        out_side = true;
      else if (e[k] < half)
        cut_k[cuts++] = k;
    }
    if (out_side) {
      out.stats.visited += 1;
      return;
    }
    out.stats.visited += cov.slots(cuts);
    auto c = cov.start();
    for (int m = 0; m < cuts; ++m) cov.cut(c, cut_k[m], e[cut_k[m]]);
    n.partials += static_cast<uint64_t>(cuts);
    if (cov.empty(c)) return;
    float w = cov.coverage(c);
    if (cfg().gaussian) {
      const T qq = q < zero ? zero : q;  // the exp table's index clamp
      w *= static_cast<float>(std::exp(-cfg().alpha * to_double(qq)));
    }
    ++n.insides;
    const int32_t x = TexelAddressGen::address(i, wl, cfg().address_u);
    if (fetched) fetched->push_back({level, x, y});
    ++out.stats.texels;
    const Acc wa = static_cast<Acc>(w);
    sum += wa * glm::vec<4, Acc>(tex.texel(level, x, y));
    wsum += wa;
  }

  template <class Cov>
  FilterOutput scan(const Cov& cov) {
    const bool gaussian = cfg().gaussian;
    glm::vec<4, Acc> sum(0);
    Acc wsum = 0;
    Steps n;
    T erow[4] = {erow0[0], erow0[1], erow0[2], erow0[3]};
    T qrow = q0, dqrow = dq0, dqv = dqv0;
    for (int64_t j = j0; j <= j1; ++j) {
      ++n.rows;
      const int32_t y = TexelAddressGen::address(j, hl, cfg().address_v);
      T e[4] = {erow[0], erow[1], erow[2], erow[3]};
      T q = qrow, dq = dqrow;
      for (int64_t i = i0; i <= i1; ++i) {
        ++n.visits;
        texel(cov, e, q, i, y, n, sum, wsum);
        for (int k = 0; k < 4; ++k) e[k] = e[k] + deut[k];
        if (gaussian) {
          q = q + dq;
          dq = dq + two_a;
        }
      }
      for (int k = 0; k < 4; ++k) erow[k] = erow[k] + devt[k];
      if (gaussian) {
        qrow = qrow + dqv;
        dqv = dqv + two_c;
        dqrow = dqrow + bt;
      }
    }
    ops += sp.per_row_ops() * n.rows;
    ops += sp.ops_per_item() * n.visits;
    ops += sp.per_partial_edge_ops() * n.partials;
    ops += sp.per_inside_ops() * n.insides;
    OpCounts norm;
    norm.cmp = 1;
    norm.rcp = 1;
    norm.mul = 4;
    ops += norm;
    if (!normalisable(wsum)) return fallback();
    out.colour = Rgba(sum * (Acc(1) / wsum));
    return out;
  }
};

}  // namespace

template <class T>
FilterOutput SpafFilter::filter_t(const Texture& tex, const Fragment& f,
                                  std::vector<TexelRef>* fetched, OpCounts& ops) const {
  SpafRun<T> run{*this, tex, fetched, ops};
  ops += setup_ops();
  run.read_fragment(f);
  if (!run.select_level() || !run.edge_setup()) return run.fallback();
  if constexpr (is_fixed_v<T>) {
    if (!run.fixed_guard()) return run.fallback();
  }
  run.stepping_start();
  if (cfg_.coverage == Coverage::Mask) {
    MaskCoverage mc{this, {}, {}, 0, 1.0f / static_cast<float>(mask_bits())};
    for (int k = 0; k < 4; ++k) {
      mc.deu[k] = static_cast<double>(run.deu[k]);
      mc.dev[k] = static_cast<double>(run.dev[k]);
    }
    const int bits = mask_bits();
    mc.full = bits == 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
    return run.scan(mc);
  }
  return visit_vd_format(cfg_.vd.format, [&](auto fmt) {
    using Fmt = decltype(fmt);
    VdCoverage<T, Fmt> vcov{SubtexelCutoff::Fraction<Fmt>(cut_), {}, cfg_.vd.lanes};
    for (int k = 0; k < 4; ++k) vcov.negk[k] = to_t<T>(static_cast<double>(run.negk[k]));
    return run.scan(vcov);
  });
}

template FilterOutput SpafFilter::filter_t<float>(const Texture&, const Fragment&,
                                                  std::vector<TexelRef>*, OpCounts&) const;
template FilterOutput SpafFilter::filter_t<double>(const Texture&, const Fragment&,
                                                   std::vector<TexelRef>*, OpCounts&) const;
template FilterOutput SpafFilter::filter_t<SpafFixed>(const Texture&, const Fragment&,
                                                      std::vector<TexelRef>*, OpCounts&) const;

FilterOutput SpafFilter::filter(const Texture& tex, const Fragment& f,
                                std::vector<TexelRef>* fetched, OpCounts& ops) const {
  return kArith.visit(cfg_.arith,
                      [&](auto t) { return filter_t<decltype(t)>(tex, f, fetched, ops); });
}

uint32_t SpafFilter::issue_cycles(const FilterStats& s) const {
  return scan_issue_cycles(s, cfg_.lanes);
}

OpCounts SpafFilter::setup_ops() const {
  OpCounts o;
  // Derivatives to texels: 4 mul; shorter side: 4 mul, 2 add, 2 sqrt, cmp; log2 (table);
  // to the level: 4 mul; corners: 8 add; four edges: 2 add (ΔU, ΔV), |ΔU| + |ΔV| (2 cmp,
  // 1 add), rcp, 2 mul, E at the centre and orientation (2 mul, 1 add, cmp, negate 1 add,
  // select), slope index per edge (1 mul, 1 add, 2 cmp); box corner U0, V0: 2 add; E there per
  // edge: 2 mul, 2 add.
  o.mul = 4 + 4 + 4 + 4 * (2 + 2 + 1) + 4 * 2;
  o.add = 2 + 8 + 4 * (2 + 1 + 2 + 1) + 2 + 4 * 2;
  o.sqrt = 2;
  o.rcp = 4;
  o.lut = 1;
  o.cmp = 1 + 4 * (2 + 2 + 2);
  if (cfg_.gaussian) {
    // Σ (4 mul scale by 1/half_px, 6 mul, 3 add), det J (2 mul, 1 add) squared (1 mul), rcp,
    // a, b, c (3 mul); Q0 = (aU0 + bV0)U0 + cV0² (5 mul, 2 add), dQ0 = a(2U0 + 1) + bV0
    // (1 mul, 3 add), dQv0 = bU0 + c(2V0 + 1) (2 mul, 3 add), 2a, 2c (2 add).
    o.mul += 4 + 6 + 2 + 1 + 3 + 5 + 1 + 2;
    o.add += 3 + 1 + 2 + 3 + 3 + 2;
    o.rcp += 1;
  }
  if (cfg_.coverage == Coverage::Vd) {
    // Per edge k = ‖n‖₁/‖n‖₂: ΔU² + ΔV² (2 mul, 1 add), √, reciprocal, × ‖n‖₁ (1 mul).
    o.mul += uint64_t{4} * 3;
    o.add += uint64_t{4} * 1;
    o.sqrt += 4;
    o.rcp += 4;
  }
  return o;
}

OpCounts SpafFilter::fixed_guard_ops() const {
  OpCounts o;
  // Ub, Vb: two distances, |·|, max, +1 each (3 add, 3 cmp); Qb (4 mul, 2 add, |b| 1 cmp);
  // max E(centre) (3 cmp) + Ub + Vb (2 add); two compares against the limit.
  o.add = 2 * 3 + 2 + 2;
  o.mul = 4;
  o.cmp = 2 * 3 + 1 + 3 + 2;
  return o;
}

OpCounts SpafFilter::per_row_ops() const {
  OpCounts o = address_mode_ops(cfg_.address_v);
  o.add += 4;                     // E += dev per edge
  if (cfg_.gaussian) o.add += 3;  // Q_row += dQv, dQv += 2c, dQ_row += b
  return o;
}

OpCounts SpafFilter::ops_per_item() const {
  OpCounts o;
  o.add = 4;                      // four edge values stepped
  if (cfg_.gaussian) o.add += 2;  // Q stepped (dQ, Q)
  o.cmp = 8;                      // E ≤ −½ and E < ½ per edge
  return o;
}

OpCounts SpafFilter::per_partial_edge_ops() const {
  OpCounts o;
  if (cfg_.coverage == Coverage::Vd) {
    o = cut_.ops_per_item() + SubtexelCutoff::fraction_extra_ops();
    o.mul += 1;  // d = E·(−k)
    o.mul += 1;  // coverage product
    return o;
  }
  o.mul = 1;  // E index (E + ½)·steps
  o.add = 1;
  o.lut = 1;  // mask table read
  o.cmp = 1;  // AND into the running mask
  return o;
}

OpCounts SpafFilter::per_inside_ops() const {
  OpCounts o;
  if (cfg_.coverage == Coverage::Mask) {
    o.lut = 1;  // popcount (an adder tree over ≤ 64 bits; one table-sized unit)
    o.mul = 1;  // coverage = popcount / bits (a shift for powers of two; counted)
  }
  if (cfg_.gaussian) {
    o.mul += 2;  // −α·Q, coverage·w
    o.lut += 1;  // exp
  }
  o += address_mode_ops(cfg_.address_u);
  o.mem = 1;
  o.mul += 4;
  o.add += 4 + 1;
  return o;
}

TimingSpec SpafFilter::timing(const TechTable& tech) const {
  OpCounts path;  // set-up: scale, edge ΔU, L1 norm, rcp, normal, orientation, box-corner
                  // start; texel: edge step, compare, coverage, weight, read, MAC; normalisation
  path.mul = 1 + 1 + 1 + 2 + 1 + 1 + 2;
  path.add = 1 + 1 + 1 + 1 + 1 + 1 + 2;
  path.rcp = 2;
  path.cmp = 1 + 2 + 1;
  path.lut = cfg_.gaussian ? 1 : 0;
  path.mem = 1;
  if (cfg_.coverage == Coverage::Vd) {
    // ‖n‖₂ beside the L1 path (√ then its reciprocal in parallel with 1/‖n‖₁), then per cut
    // edge: d = E·(−k), the cut-off, × 1/W(−½) and select, and a two-level product tree.
    path.sqrt += 1;
    path.mul += 1 + 1 + 2;
    path.cmp += 1;
    path += cut_.critical_path();
  } else {
    path.lut += 1 + 1;  // mask table, popcount
    path.cmp += 1;      // AND
  }
  // Per lane: the edge and Q steppers, four edge units (mask table port or distance, ratio
  // and product), vd.lanes cut-off units, coverage, weight and MAC; one row stepper.
  OpCounts lane = ops_per_item() + per_inside_ops();
  if (cfg_.coverage == Coverage::Vd) {
    OpCounts edge = SubtexelCutoff::fraction_extra_ops();
    edge.mul += 2;  // distance, product (per_partial_edge_ops without the cut-off itself)
    lane += edge * 4 + cut_.ops_per_item() * cut_.config().lanes;
  } else {
    lane += per_partial_edge_ops() * 4;
  }
  lane.mem = 0;
  OpCounts shared = setup_ops() + per_row_ops();
  if (cfg_.arith == NumberFormat::S20_28HalfUp) shared += fixed_guard_ops();
  return derive_timing(tech, lane, path, Datapath::Spatial,
                       static_cast<uint32_t>(std::max(cfg_.lanes, 1)), shared);
}

std::string SpafFilter::arithmetic() const {
  std::string s;
  if (cfg_.arith == NumberFormat::Double) {
    s = "double set-up, edge functions, Q and accumulation";
  } else if (cfg_.arith == NumberFormat::S20_28HalfUp) {
    s = "float32 set-up; edge functions and Q in " + SpafFixed::name();
  } else {
    s = "float32 set-up, edge functions and Q";
  }
  if (cfg_.coverage == Coverage::Vd) {
    s += "; coverage from the " + cut_.name() + " cut-off per edge";
  } else {
    const std::string n = std::to_string(cfg_.mask_side);
    s += "; " + n + "x" + n + " sub-texel mask table, popcount";
  }
  if (cfg_.gaussian) s += "; Gaussian weight exp(-alpha Q)";
  s += cfg_.arith == NumberFormat::Double ? "" : "; float32 accumulation";
  return s;
}

}  // namespace texsim
