#include "blocks/spaf_filter.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "blocks/texel_address_gen.h"

namespace texsim {

SpafFilter::Config SpafFilter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"mask_side", "slope_steps", "offset_steps", "half_px", "gaussian", "alpha",
                    "texel_budget", "lanes", "address_u", "address_v"});
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
  const std::vector<std::string_view> modes = {"wrap", "clamp", "mirror"};
  c.address_u = static_cast<AddressMode>(r.get_choice("address_u", 0, modes));
  c.address_v = static_cast<AddressMode>(r.get_choice("address_v", 0, modes));
  return c;
}

SpafFilter::SpafFilter(const Config& c) : cfg_(c) {
  cfg_.mask_side = std::clamp(cfg_.mask_side, 1, 8);
  cfg_.slope_steps = std::max(2, cfg_.slope_steps & ~1);
  cfg_.offset_steps = std::max(2, cfg_.offset_steps);
  const int half = cfg_.slope_steps / 2;
  table_.resize(static_cast<size_t>(cfg_.slope_steps) * static_cast<size_t>(cfg_.offset_steps));
  // Each entry is the exact mask at the centre of its (slope, E) cell.
  for (int s = 0; s < cfg_.slope_steps; ++s) {
    const double deu = -1.0 + 2.0 * ((s % half) + 0.5) / half;
    const double dev = (s < half ? 1.0 : -1.0) * (1.0 - std::fabs(deu));
    for (int e = 0; e < cfg_.offset_steps; ++e) {
      const double ev = -0.5 + (e + 0.5) / cfg_.offset_steps;
      table_[static_cast<size_t>(s) * static_cast<size_t>(cfg_.offset_steps) + static_cast<size_t>(e)] =
          exact_mask(deu, dev, ev);
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
  const int k = std::clamp(static_cast<int>((e + 0.5) * cfg_.offset_steps), 0, cfg_.offset_steps - 1);
  return table_[static_cast<size_t>(s) * static_cast<size_t>(cfg_.offset_steps) + static_cast<size_t>(k)];
}

FilterOutput SpafFilter::filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                                OpCounts& ops) const {
  FilterOutput out;
  FilterStats& st = out.stats;
  ops += setup_ops();
  const int w0 = tex.width(0), h0 = tex.height(0), q_top = tex.levels() - 1;
  double u = f.u, v = f.v;
  if (!std::isfinite(u) || !std::isfinite(v)) {
    st.bad_input = true;
    u = std::isfinite(u) ? u : 0.0;
    v = std::isfinite(v) ? v : 0.0;
  }
  double ax = f.dudx * w0 * cfg_.half_px, ay = f.dvdx * h0 * cfg_.half_px;
  double bx = f.dudy * w0 * cfg_.half_px, by = f.dvdy * h0 * cfg_.half_px;
  if (!std::isfinite(ax) || !std::isfinite(ay) || !std::isfinite(bx) || !std::isfinite(by)) {
    st.bad_input = true;
    ax = ay = bx = by = 0;
  }
  const double det = ax * by - ay * bx;
  auto fallback = [&](int level) {
    st.fallback = true;
    st.level = level;
    out.colour = bilinear_fallback(tex, level, u, v, cfg_.address_u, cfg_.address_v, fetched, ops);
    st.texels += 4;
    return out;
  };
  // Level: start where the shorter derivative (one pixel) spans 1–2 texels, as EWA's minor
  // axis rule, then go coarser until the box fits the budget.
  const double shorter = std::min(std::hypot(ax, ay), std::hypot(bx, by)) / cfg_.half_px;
  int level = 0;
  if (shorter > 1) level = std::min(q_top, static_cast<int>(std::floor(std::log2(shorter))));
  auto box = [&](int l, int64_t& i0, int64_t& i1, int64_t& j0, int64_t& j1) {
    const double sx = static_cast<double>(tex.width(l)) / w0, sy = static_cast<double>(tex.height(l)) / h0;
    const double ex = (std::fabs(ax) + std::fabs(bx)) * sx, ey = (std::fabs(ay) + std::fabs(by)) * sy;
    constexpr double kLimit = 1073741824.0;
    const double uc = std::clamp(u * tex.width(l) - 0.5, -kLimit, kLimit);
    const double vc = std::clamp(v * tex.height(l) - 0.5, -kLimit, kLimit);
    const double exc = std::min(ex, kLimit), eyc = std::min(ey, kLimit);
    i0 = static_cast<int64_t>(std::ceil(uc - exc - 0.5));
    i1 = static_cast<int64_t>(std::floor(uc + exc + 0.5));
    j0 = static_cast<int64_t>(std::ceil(vc - eyc - 0.5));
    j1 = static_cast<int64_t>(std::floor(vc + eyc + 0.5));
    OpCounts it;  // scale, extents, bounds, count, compare
    it.mul = 4 + 1;
    it.add = 2 + 4 + 2;
    it.cmp = 4 + 1;
    ops += it;
    return static_cast<double>(i1 - i0 + 1) * static_cast<double>(j1 - j0 + 1);
  };
  int64_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  while (box(level, i0, i1, j0, j1) > cfg_.texel_budget && level < q_top) ++level;
  st.level = level;
  if (!(std::fabs(det) > 0) || box(level, i0, i1, j0, j1) > cfg_.texel_budget * 4.0) {
    // A zero-area quadrilateral has no inside; a box still too large at the top level (a
    // footprint far larger than the texture) is not scanned: both take the bilinear sample.
    return fallback(level);
  }
  const int wl = tex.width(level), hl = tex.height(level);
  const double sx = static_cast<double>(wl) / w0, sy = static_cast<double>(hl) / h0;
  const double uc = u * wl - 0.5, vc = v * hl - 0.5;
  const double lax = ax * sx, lay = ay * sy, lbx = bx * sx, lby = by * sy;
  // Corners and edges (P0 → P1 → P2 → P3 → P0).
  const double px[4] = {uc - lax - lbx, uc + lax - lbx, uc + lax + lbx, uc - lax + lbx};
  const double py[4] = {vc - lay - lby, vc + lay - lby, vc + lay + lby, vc - lay + lby};
  double deu[4], dev[4];
  for (int k = 0; k < 4; ++k) {
    const double du = px[(k + 1) % 4] - px[k], dv = py[(k + 1) % 4] - py[k];
    const double l1 = std::fabs(du) + std::fabs(dv);
    deu[k] = dv / l1;
    dev[k] = -du / l1;
    // The seed's normal (ΔV, −ΔU) points inside for one orientation only: flip it so that the
    // centre is inside (E > 0) whatever the sign of det J.
    if ((uc - px[k]) * deu[k] + (vc - py[k]) * dev[k] < 0) {
      deu[k] = -deu[k];
      dev[k] = -dev[k];
    }
  }
  // Gaussian weight: Q of the R = 1 px ellipse (Σ = J·Jᵀ at this level, in level texels).
  const double r = 1.0 / cfg_.half_px;
  const double jux = lax * r, jvx = lay * r, juy = lbx * r, jvy = lby * r;
  const double suu = jux * jux + juy * juy, suv = jux * jvx + juy * jvy, svv = jvx * jvx + jvy * jvy;
  const double sdet = suu * svv - suv * suv;
  const double qa = sdet > 0 ? svv / sdet : 0, qb = sdet > 0 ? -2 * suv / sdet : 0, qc = sdet > 0 ? suu / sdet : 0;
  const OpCounts visit = per_visit_ops(), partial = per_partial_edge_ops(), inside = per_inside_ops();
  const int bits = mask_bits();
  const uint64_t full = bits == 64 ? ~uint64_t{0} : (uint64_t{1} << bits) - 1;
  glm::vec4 sum(0);
  float wsum = 0;
  uint64_t visits = 0, partials = 0, insides = 0;  // operations multiplied out at the end
  for (int64_t j = j0; j <= j1; ++j) {
    const int32_t y = TexelAddressGen::address(j, hl, cfg_.address_v);
    for (int64_t i = i0; i <= i1; ++i) {
      ++st.visited;
      ++visits;
      uint64_t m = full;
      bool out_side = false;
      for (int k = 0; k < 4 && !out_side; ++k) {
        const double e = (static_cast<double>(i) - px[k]) * deu[k] + (static_cast<double>(j) - py[k]) * dev[k];
        if (e <= -0.5) {
          out_side = true;
        } else if (e < 0.5) {
          ++partials;
          m &= mask(deu[k], dev[k], e);
        }
      }
      if (out_side || m == 0) continue;
      const float cover = static_cast<float>(std::popcount(m)) / static_cast<float>(bits);
      float w = cover;
      if (cfg_.gaussian) {
        const double U = static_cast<double>(i) - uc, V = static_cast<double>(j) - vc;
        const double q = (qa * U + qb * V) * U + qc * V * V;
        w *= static_cast<float>(std::exp(-cfg_.alpha * q));
      }
      ++insides;
      const int32_t x = TexelAddressGen::address(i, wl, cfg_.address_u);
      if (fetched) fetched->push_back({level, x, y});
      ++st.texels;
      sum += w * tex.texel(level, x, y);
      wsum += w;
    }
  }
  ops += visit * visits;
  ops += partial * partials;
  ops += inside * insides;
  OpCounts norm;
  norm.cmp = 1;
  norm.rcp = 1;
  norm.mul = 4;
  ops += norm;
  if (!(wsum > 0)) return fallback(level);
  out.colour = sum * (1.0f / wsum);
  return out;
}

uint32_t SpafFilter::issue_cycles(const FilterStats& s) const {
  const auto lanes = static_cast<uint32_t>(std::max(cfg_.lanes, 1));
  return std::max<uint32_t>(1, (s.visited + lanes - 1) / lanes);
}

OpCounts SpafFilter::setup_ops() const {
  OpCounts o;
  // Derivatives to texels: 4 mul; shorter side: 4 mul, 2 add, 2 sqrt, cmp; log2 (table);
  // corners: 8 add; four edges: 2 add (ΔU, ΔV), |ΔU| + |ΔV| (2 cmp, 1 add), rcp, 2 mul,
  // orientation test (2 add, 2 mul, cmp, select); slope index per edge (1 mul, 1 add, 2 cmp);
  // Gaussian set-up: Σ (6 mul, 3 add), det (2 mul, 1 add), rcp, 3 mul.
  o.mul = 4 + 4 + 4 * (2 + 2 + 1) + 6 + 2 + 3;
  o.add = 2 + 8 + 4 * (2 + 1 + 2 + 1) + 3 + 1;
  o.sqrt = 2;
  o.rcp = 4 + 1;
  o.lut = 1;
  o.cmp = 1 + 4 * (2 + 2 + 2);
  return o;
}

OpCounts SpafFilter::per_visit_ops() const {
  OpCounts o;
  o.add = 4 + 2;  // four edge values stepped, Q stepped (dQ, Q)
  o.cmp = 8;      // E ≤ −½ and E < ½ per edge
  return o;
}

OpCounts SpafFilter::per_partial_edge_ops() const {
  OpCounts o;
  o.mul = 1;  // E index (E + ½)·steps
  o.add = 1;
  o.lut = 1;  // mask table read
  o.cmp = 1;  // AND into the running mask
  return o;
}

OpCounts SpafFilter::per_inside_ops() const {
  OpCounts o;
  o.lut = 1;  // popcount (an adder tree over ≤ 64 bits; one table-sized unit)
  o.mul = 1;  // coverage = popcount / bits (a shift for powers of two; counted)
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
  OpCounts path;  // set-up: scale, edge ΔU, L1 norm, rcp, normal, orientation; texel: edge
                  // step, compare, table, AND, popcount, weight, read, MAC; normalisation
  path.mul = 1 + 1 + 1 + 2 + 1 + 1;
  path.add = 1 + 1 + 1 + 1 + 1 + 1;
  path.rcp = 2;
  path.cmp = 1 + 2 + 1 + 1;
  path.lut = 1 + 1 + (cfg_.gaussian ? 1 : 0);
  path.mem = 1;
  TimingSpec t;
  t.latency = static_cast<uint32_t>(std::ceil(tech.path_latency(path)));
  t.ii = 1;
  t.lanes = static_cast<uint32_t>(std::max(cfg_.lanes, 1));
  OpCounts lane = per_visit_ops() + per_partial_edge_ops() * 4 + per_inside_ops();
  lane.mem = 0;
  t.area = tech.area_of(setup_ops()) + tech.area_of(lane) * static_cast<double>(t.lanes);
  return t;
}

}  // namespace texsim
