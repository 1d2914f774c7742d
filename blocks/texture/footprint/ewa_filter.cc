#include "blocks/texture/footprint/ewa_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "blocks/base/block.h"
#include "blocks/texture/footprint/gaussian_weight.h"
#include "blocks/texture/footprint/weight_map.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

static_assert(Block<EwaFilter>);

const char* to_string(EwaFilter::Weight w) {
  switch (w) {
    case EwaFilter::Weight::Lut:
      return "lut";
    case EwaFilter::Weight::Exp:
      return "exp";
    case EwaFilter::Weight::Pow8:
      return "pow8";
    case EwaFilter::Weight::Map:
      return "map";
    case EwaFilter::Weight::Uniform:
      return "uniform";
    case EwaFilter::Weight::Thesis:
      return "thesis";
  }
  return "?";
}

EwaFilter::Config EwaFilter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"weight", "lut_size", "lut_bits", "alpha", "radius_px", "max_aniso",
                    "texel_budget", "reconstruction", "minor_texels", "mip", "scan", "arith",
                    "address_u", "address_v", "lanes", "weight_map", "edge", "vd"});
  Config c;
  c.weight = static_cast<Weight>(r.get_choice("weight", static_cast<int>(c.weight),
                                              {"lut", "exp", "pow8", "map", "uniform", "thesis"}));
  c.lut_size = static_cast<int>(r.get_int("lut_size", c.lut_size, 2, 1 << 16));
  c.lut_bits = static_cast<int>(r.get_int("lut_bits", c.lut_bits, 0, 30));
  c.alpha = r.get_double("alpha", c.alpha);
  if (!(c.alpha > 0) || !(c.alpha <= 64)) r.fail("alpha", "must be in (0, 64]");
  c.radius_px = r.get_double("radius_px", c.radius_px);
  if (!(c.radius_px > 0) || !(c.radius_px <= 16)) r.fail("radius_px", "must be in (0, 16]");
  c.max_aniso = r.get_double("max_aniso", c.max_aniso);
  if (!(c.max_aniso >= 1) || !(c.max_aniso <= 256)) r.fail("max_aniso", "must be in [1, 256]");
  c.texel_budget = static_cast<int>(r.get_int("texel_budget", c.texel_budget, 16, 1 << 20));
  c.reconstruction = r.get_double("reconstruction", c.reconstruction);
  if (!(c.reconstruction >= 0) || !(c.reconstruction <= 16)) {
    r.fail("reconstruction", "must be in [0, 16]");
  }
  c.minor_texels = r.get_double("minor_texels", c.minor_texels);
  if (!(c.minor_texels >= 0.25) || !(c.minor_texels <= 64)) {
    r.fail("minor_texels", "must be in [0.25, 64]");
  }
  c.mip = static_cast<Mip>(r.get_choice("mip", static_cast<int>(c.mip), {"nearest", "linear"}));
  c.scan = static_cast<Scan>(r.get_choice("scan", static_cast<int>(c.scan), {"box", "row_span"}));
  c.arith = kArith.at(r.get_choice("arith", kArith.index_of(c.arith), kArith.key_list()));
  c.address_u = footprint_address_mode(r, "address_u");
  c.address_v = footprint_address_mode(r, "address_v");
  c.lanes = static_cast<int>(r.get_int("lanes", c.lanes, 1, 64));
  if (c.weight != Weight::Map && r.table().contains("weight_map")) {
    r.fail("weight_map", "is only used with weight = \"map\"");
  }
  c.edge = static_cast<Edge>(r.get_choice("edge", static_cast<int>(c.edge), {"none", "vd"}));
  if (c.edge == Edge::Vd) {
    c.vd = SubtexelCutoff::Config::from_toml(r.sub("vd"));
  } else if (r.table().contains("vd")) {
    r.fail("vd", "is only used with edge = \"vd\"");
  }
  return c;
}

EwaFilter::EwaFilter() : EwaFilter(Config{}) {}

EwaFilter::EwaFilter(const Config& c) : cfg_(c) {
  if (cfg_.weight == Weight::Map) {
    WeightMap::Config m;
    m.alpha = cfg_.alpha;
    map_ = std::make_shared<const WeightMap>(m);
  }
  build_lut();
}

EwaFilter::EwaFilter(const Config& c, std::shared_ptr<const WeightMap> map)
    : cfg_(c), map_(std::move(map)) {
  if (cfg_.weight == Weight::Map && !map_) {
    WeightMap::Config m;
    m.alpha = cfg_.alpha;
    map_ = std::make_shared<const WeightMap>(m);
  }
  build_lut();
}

EwaFilter::~EwaFilter() = default;
EwaFilter::EwaFilter(const EwaFilter&) = default;
EwaFilter& EwaFilter::operator=(const EwaFilter&) = default;

void EwaFilter::build_lut() {
  // Entry i holds the weight at the middle of its interval [i/N, (i+1)/N) of Q, so the
  // piecewise-constant table is unbiased (Greene & Heckbert index by the left end).
  const int n = std::max(cfg_.lut_size, 2);
  lut_.resize(static_cast<size_t>(n));
  const double scale = cfg_.lut_bits > 0 ? std::ldexp(1.0, cfg_.lut_bits) : 0.0;
  for (int i = 0; i < n; ++i) {
    const double q = (i + 0.5) / n;
    double w = std::exp(-cfg_.alpha * q);
    if (cfg_.lut_bits > 0)
      w = std::nearbyint(w * scale) / scale;
    else
      w = static_cast<double>(static_cast<float>(w));
    lut_[static_cast<size_t>(i)] = w;
  }
}

double EwaFilter::weight_of(double q) const {
  if (!(q < 1.0)) return 0.0;
  q = std::max(q, 0.0);
  switch (cfg_.weight) {
    case Weight::Lut: {
      const int n = static_cast<int>(lut_.size());
      const int i = std::min(static_cast<int>(q * n), n - 1);
      return lut_[static_cast<size_t>(i)];
    }
    case Weight::Exp:
      return GaussianWeight::weight_exp<GaussianWeightFormat<double>>(2.0 * cfg_.alpha * q);
    case Weight::Pow8:
      return GaussianWeight::weight_pow8<GaussianWeightFormat<double>>(2.0 * cfg_.alpha * q);
    case Weight::Map:
      return map_ ? map_->function(q) : 0.0;
    case Weight::Uniform:
      return 1.0;
    case Weight::Thesis:
      return 0.0;
  }
  return 0.0;
}

double EwaFilter::thesis_weight(double alpha, double ux, double vx, double uy, double vy, double U,
                                double V) {
  const EllipseQuadratic<double> e =
      GaussianWeight::setup<double>(GaussianAxes::SeedLiteral, ux, vx, uy, vy);
  return GaussianWeight::weight_pow8<GaussianWeightFormat<double>>(2.0 * alpha *
                                                                   GaussianWeight::q_of(e, U, V));
}

namespace {

// Operations of the per-footprint level selection and of one budget iteration.
OpCounts level_select_ops() {
  OpCounts o;
  o.lut = 1;  // log2 λ₋ (the ½ is an exponent decrement)
  o.add = 3;  // − log2 minor_texels, + lod bias, fraction
  o.cmp = 2;  // floor, clamp to the pyramid
  return o;
}
OpCounts budget_iteration_ops() {
  OpCounts o;
  o.mul = 3 + 2 + 1;  // Σ to the level (per-axis scale factors), 2·h, box product
  o.add = 2 + 2;      // reconstruction, +1 per side
  o.sqrt = 2;         // box half-widths √Σuu, √Σvv
  o.cmp = 1;          // against the budget
  return o;
}
OpCounts level_setup_ops() {
  OpCounts o;
  o.mul = 2 + 3 + 2;      // det, a/b/c, centre u·w, v·h
  o.add = 1 + 2 + 4 + 1;  // det, centre −½, box bounds, U0 = i0 − uc
  o.rcp = 1;              // 1/det
  o.cmp = 1 + 4;          // det > 0, bound conversions
  return o;
}
OpCounts row_ops(EwaFilter::Scan scan) {
  OpCounts o;
  o.add = 1 + 2 + 2;  // V = j − vc; Q0 = (aU0 + bV)U0 + cV²; dQ0 = a(2U0 + 1) + bV
  o.mul = 5 + 2;
  if (scan == EwaFilter::Scan::RowSpan) {
    // disc = (bV)² − 4a(cV² − 1) (bV, cV² shared with Q0): 2 mul, 2 add; √disc; the two
    // ends (−bV ± √disc)·(1/2a): 2 add, 2 mul; conversion and clip to the box: 4 cmp.
    o.mul += 2 + 2;
    o.add += 2 + 2;
    o.sqrt = 1;
    o.cmp = 4 + 1;  // + empty-row test
  }
  return o;
}
OpCounts normalise_ops() {
  OpCounts o;
  o.cmp = 1;  // Σw > 0
  o.rcp = 1;
  o.mul = 4;
  return o;
}

// Weight-function operations per texel (the GaussianWeight unit's function part, with the
// α scale folded into its multiplier).
OpCounts weight_ops(EwaFilter::Weight w) {
  OpCounts o;
  switch (w) {
    case EwaFilter::Weight::Lut:
      o.mul = 1;  // index Q·N (a bit slice for power-of-two N in fixed point)
      o.lut = 1;
      break;
    case EwaFilter::Weight::Exp:
      o.cmp = 1;
      o.mul = 1;
      o.lut = 1;
      break;
    case EwaFilter::Weight::Pow8:
      o.cmp = 2;
      o.add = 1;
      o.mul = 1 + 3;
      break;
    case EwaFilter::Weight::Thesis: {
      // q′ = (aU + bV)U + cV² from the set-up's a, b, c, then × 2α and the power 8.
      GaussianWeight::Config g;
      g.axes = GaussianAxes::SeedLiteral;
      o = GaussianWeight(g).ops_per_item();
      o.mul += 1;
      break;
    }
    case EwaFilter::Weight::Map:  // WeightMap::ops_per_item, added where used
    case EwaFilter::Weight::Uniform:
      break;
  }
  return o;
}

template <class T>
using AccOf = std::conditional_t<std::is_same_v<T, double>, double, float>;
template <class T>
using SetupOf = std::conditional_t<std::is_same_v<T, double>, double, float>;

template <class T>
T to_t(double x) {
  if constexpr (is_fixed_v<T>)
    return T(x);
  else
    return static_cast<T>(x);
}

// One level's scan: Σ_l (level texels², reconstruction included) → weighted sum.
template <class T>
struct LevelScan {
  using S = SetupOf<T>;
  using Acc = AccOf<T>;

  const EwaFilter& filt;
  const Texture& tex;
  std::vector<TexelRef>* fetched;
  OpCounts& ops;
  FilterStats& st;

  // The level's ellipse Q(U, V) = a·U² + b·U·V + c·V² ≤ 1 around the centre (uc, vc) in texels,
  // its bounding box and, with the edge cut-off, the band Q > qband near the boundary.
  struct Ellipse {
    int wl = 0, hl = 0;
    S as = 0, bs = 0, cs = 0, uc = 0, vc = 0, inv2a = 0;
    int64_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
    T a{}, b{}, cc{}, qband{}, gy_step{};
  };
  // Weight-map transform (x, y) = M·(U, V), per-footprint constants.
  // With the seed's formula (5) the transform is of absolute texel coordinates (u, v) = (i, j)
  // plus the constants (kx, ky) = (Kx·S, Ky·S) (`absolute`). With weight = Thesis, `thesis`
  // holds the seed's θ/L/d quadratic form.
  struct MapTransform {
    S xu = 0, xv = 0, yu = 0, yv = 0, kx = 0, ky = 0;
    bool absolute = false;
    EllipseQuadratic<S> thesis;
  };
  // Per-kind step counts of one scan (operations are multiplied out once at the end: they
  // depend only on how many rows, box texels, inside texels and edge texels there were).
  struct Steps {
    uint64_t rows = 0, visits = 0, insides = 0, edges = 0;
  };

  // Σ⁻¹ and the box; false if Σ is singular or its inverse not finite.
  bool ellipse(int level, double u, double v, double suu, double suv, double svv,
               Ellipse& e) const {
    const S det =
        static_cast<S>(suu) * static_cast<S>(svv) - static_cast<S>(suv) * static_cast<S>(suv);
    if (!(det > 0) || !std::isfinite(det)) return false;
    const S rdet = S(1) / det;
    e.as = static_cast<S>(svv) * rdet;
    e.bs = S(-2) * static_cast<S>(suv) * rdet;
    e.cs = static_cast<S>(suu) * rdet;
    if (!std::isfinite(e.as) || !std::isfinite(e.bs) || !std::isfinite(e.cs)) return false;
    e.wl = tex.width(level);
    e.hl = tex.height(level);
    constexpr S kLimit = static_cast<S>(1073741824.0);  // 2^30 texels
    e.uc = std::clamp(static_cast<S>(u) * static_cast<S>(e.wl) - S(0.5), -kLimit, kLimit);
    e.vc = std::clamp(static_cast<S>(v) * static_cast<S>(e.hl) - S(0.5), -kLimit, kLimit);
    const S hu = std::sqrt(static_cast<S>(suu)), hv = std::sqrt(static_cast<S>(svv));
    e.i0 = static_cast<int64_t>(std::ceil(e.uc - hu));
    e.i1 = static_cast<int64_t>(std::floor(e.uc + hu));
    e.j0 = static_cast<int64_t>(std::ceil(e.vc - hv));
    e.j1 = static_cast<int64_t>(std::floor(e.vc + hv));
    e.a = to_t<T>(static_cast<double>(e.as));
    e.b = to_t<T>(static_cast<double>(e.bs));
    e.cc = to_t<T>(static_cast<double>(e.cs));
    e.qband = e.gy_step = to_t<T>(0.0);
    return true;
  }

  // Edge cut-off: only texels with Q > qband can lie within half a texel of the boundary
  // (|∇√Q| ≤ 1/minor radius, so d > −½ needs √Q > 1 − ½/minor radius).
  void edge_band(double suu, double suv, double svv, Ellipse& e) const {
    ops += filt.ops_edge_setup();
    const S th = (static_cast<S>(suu) + static_cast<S>(svv)) * S(0.5);
    const S dh = (static_cast<S>(suu) - static_cast<S>(svv)) * S(0.5);
    const S lmin = th - std::sqrt(dh * dh + static_cast<S>(suv) * static_cast<S>(suv));
    const S am = std::sqrt(std::max(lmin, S(0)));
    const S t = am > S(0.5) ? S(1) - S(0.5) / am : S(0);
    e.qband = to_t<T>(static_cast<double>(t * t));
    e.gy_step = e.b;
  }

  // Operations at the start of each row.
  OpCounts per_row_ops(bool cutoff) const {
    const EwaFilter::Config& c = filt.config();
    OpCounts per_row = row_ops(c.scan) + address_mode_ops(c.address_v);
    if (cutoff) {
      OpCounts g;  // row start of ∂Q/∂V = bU0 + 2cV
      g.mul = 2;
      g.add = 1;
      per_row += g;
    }
    if (c.weight == EwaFilter::Weight::Map) {
      // Row start of the transform (x, y) = M·(U0, V).
      OpCounts m;
      // With the seed's formula: (Kx·S) + (−Vy·S)·u + (Vx·S)·v and likewise y.
      const WeightMap::Transform tr = filt.weight_map() ? filt.weight_map()->config().transform
                                                        : WeightMap::Transform::Cholesky;
      const bool jac = tr == WeightMap::Transform::Jacobian;
      const bool seed = tr == WeightMap::Transform::Seed;
      m.mul = jac || seed ? 4 : 3;
      m.add = seed ? 4 : (jac ? 2 : 1);
      per_row += m;
    }
    return per_row;
  }

  MapTransform map_transform(const Ellipse& e, const Fragment& f) const {
    const EwaFilter::Config& c = filt.config();
    const WeightMap* map = filt.weight_map();
    MapTransform m;
    // The fragment's own J at this level, scaled by R (the thesis's derivatives).
    const S R = static_cast<S>(c.radius_px);
    const S jux = static_cast<S>(f.dudx) * static_cast<S>(e.wl) * R;
    const S juy = static_cast<S>(f.dudy) * static_cast<S>(e.wl) * R;
    const S jvx = static_cast<S>(f.dvdx) * static_cast<S>(e.hl) * R;
    const S jvy = static_cast<S>(f.dvdy) * static_cast<S>(e.hl) * R;
    if (c.weight == EwaFilter::Weight::Thesis) {
      GaussianWeight::Config g;
      g.axes = GaussianAxes::SeedLiteral;
      ops += GaussianWeight(g).setup_ops();
      m.thesis = GaussianWeight::setup<S>(GaussianAxes::SeedLiteral, jux, jvx, juy, jvy);
      return m;
    }
    if (c.weight != EwaFilter::Weight::Map || !map) return m;
    ops += map->setup_ops();
    if (map->config().transform == WeightMap::Transform::Seed) {
      const SeedTransform t = SeedTransform::from(
          static_cast<double>(jux), static_cast<double>(jvx), static_cast<double>(juy),
          static_cast<double>(jvy), static_cast<double>(e.uc), static_cast<double>(e.vc));
      m.absolute = true;
      m.kx = static_cast<S>(t.kxs);
      m.ky = static_cast<S>(t.kys);
      m.xu = static_cast<S>(t.xu);
      m.xv = static_cast<S>(t.xv);
      m.yu = static_cast<S>(t.yu);
      m.yv = static_cast<S>(t.yv);
    } else if (map->config().transform == WeightMap::Transform::Cholesky) {
      const S ra = std::sqrt(e.as);
      m.xu = ra;
      m.xv = e.bs / (S(2) * ra);
      m.yu = 0;
      m.yv = std::sqrt(std::max(e.cs - m.xv * m.xv, S(0)));
    } else {
      // (x, y) = J⁻¹(U, V).
      const S jdet = jux * jvy - juy * jvx;
      const S rj = jdet != S(0) && std::isfinite(jdet) ? S(1) / jdet : S(0);
      m.xu = jvy * rj;
      m.xv = -juy * rj;
      m.yu = -jvx * rj;
      m.yv = jux * rj;
    }
    return m;
  }

  // Scans texels ia..ib of row j (V = j − vc) with Q stepped incrementally; adds to the sums.
  void scan_row(int level, int64_t j, int64_t ia, int64_t ib, const Ellipse& e,
                const MapTransform& mt, bool cutoff, const SubtexelCutoff& cut, Steps& n,
                glm::vec<4, Acc>& sum, Acc& wsum) const {
    const EwaFilter::Config& c = filt.config();
    const WeightMap* map = filt.weight_map();
    const T one = to_t<T>(1.0), zero = to_t<T>(0.0), two_a = e.a + e.a;
    const S Vs = static_cast<S>(j) - e.vc;
    const int32_t y = TexelAddressGen::address(j, e.hl, c.address_v);
    const S U0s = static_cast<S>(ia) - e.uc;
    const T U0 = to_t<T>(static_cast<double>(U0s)), V = to_t<T>(static_cast<double>(Vs));
    T q = (e.a * U0 + e.b * V) * U0 + e.cc * V * V;
    T dq = e.a * (U0 + U0 + one) + e.b * V;
    S mx = mt.xu * U0s + mt.xv * Vs, my = mt.yu * U0s + mt.yv * Vs;
    if (mt.absolute) {  // the seed's formula (5) in absolute texel coordinates (u, v) = (i, j)
      const S ui = static_cast<S>(ia), vj = static_cast<S>(j);
      mx = mt.kx + mt.xu * ui + mt.xv * vj;
      my = mt.ky + mt.yu * ui + mt.yv * vj;
    }
    S Us = U0s;                                           // the texel's U for the Thesis weight
    T gy = cutoff ? e.b * U0 + (e.cc + e.cc) * V : zero;  // ∂Q/∂V, stepped by b along the row
    n.visits += static_cast<uint64_t>(ib - ia + 1);
    for (int64_t i = ia; i <= ib; ++i) {
      ++st.visited;
      if (q < one) {
        const T qq = q < zero ? zero : q;
        float w = 0;
        if (c.weight == EwaFilter::Weight::Map && map) {
          w = map->read(static_cast<float>(mx), static_cast<float>(my), st.map_reads);
        } else if (c.weight == EwaFilter::Weight::Thesis) {
          const S qt = S(2) * static_cast<S>(c.alpha) * GaussianWeight::q_of(mt.thesis, Us, Vs);
          w = static_cast<float>(GaussianWeight::weight_pow8<GaussianWeightFormat<S>>(qt));
        } else {
          w = static_cast<float>(filt.weight_of(to_double(qq)));
        }
        if (cutoff && q > e.qband) {
          // d = (√Q − 1)/|∇√Q| = 2(Q − √Q)/|∇Q|: the distance to the tangent of the boundary
          // at the texel's radial projection onto it (exact on the axes and for circles).
          ++n.edges;
          const S qs = static_cast<S>(to_double(qq));
          const S gx = static_cast<S>(to_double(dq - e.a));  // ∂Q/∂U = 2aU + bV = dQ − a
          const S gv = static_cast<S>(to_double(gy));
          const S d = EwaFilter::boundary_distance(qs, gx, gv);
          w *= static_cast<float>(cut.fraction(static_cast<double>(d)));
        }
        ++n.insides;
        const int32_t x = TexelAddressGen::address(i, e.wl, c.address_u);
        if (fetched) fetched->push_back({level, x, y});
        ++st.texels;
        const Rgba t = tex.texel(level, x, y);
        const Acc wa = static_cast<Acc>(w);
        sum += wa * glm::vec<4, Acc>(t);
        wsum += wa;
      }
      q = q + dq;
      dq = dq + two_a;
      if (cutoff) gy = gy + e.gy_step;
      mx += mt.xu;
      my += mt.yu;
      Us += S(1);
    }
  }

  // Returns Σw; `sum` gets Σ w·texel.
  Acc run(int level, double u, double v, double suu, double suv, double svv, const Fragment& f,
          glm::vec<4, Acc>& sum) const {
    const EwaFilter::Config& c = filt.config();
    ops += level_setup_ops();
    sum = glm::vec<4, Acc>(0);
    Ellipse e;
    if (!ellipse(level, u, v, suu, suv, svv, e)) return Acc(0);
    const bool span = c.scan == EwaFilter::Scan::RowSpan;
    const bool cutoff = c.edge == EwaFilter::Edge::Vd;
    const SubtexelCutoff cut = filt.cutoff();
    if (cutoff) edge_band(suu, suv, svv, e);
    e.inv2a = span ? S(1) / (S(2) * e.as) : S(0);
    if (span) ops.rcp += 1;
    const OpCounts per_row = per_row_ops(cutoff);
    const MapTransform mt = map_transform(e, f);
    Acc wsum = 0;
    Steps n;
    for (int64_t j = e.j0; j <= e.j1; ++j) {
      ++n.rows;
      int64_t ia = e.i0, ib = e.i1;
      if (span) {
        const S Vs = static_cast<S>(j) - e.vc;
        const S bv = e.bs * Vs;
        const S disc = bv * bv - S(4) * e.as * (e.cs * Vs * Vs - S(1));
        if (!(disc > 0)) continue;
        const S r = std::sqrt(disc);
        ia = std::max(ia, static_cast<int64_t>(std::ceil(e.uc + (-bv - r) * e.inv2a)));
        ib = std::min(ib, static_cast<int64_t>(std::floor(e.uc + (-bv + r) * e.inv2a)));
        if (ia > ib) continue;
        st.visited += 1;  // one slot per row for the span set-up
      }
      scan_row(level, j, ia, ib, e, mt, cutoff, cut, n, sum, wsum);
    }
    ops += per_row * n.rows;
    ops += filt.ops_per_item() * n.visits;
    ops += filt.ops_per_inside() * n.insides;
    ops += (cutoff ? filt.ops_per_edge_texel() : OpCounts{}) * n.edges;
    return wsum;
  }
};

}  // namespace

OpCounts EwaFilter::ops_per_item() const {
  OpCounts o;
  o.cmp = 1;  // Q < 1
  o.add = 2;  // Q += dQ, dQ += 2a
  if (cfg_.weight == Weight::Map && map_) o += map_->ops_per_step();
  if (cfg_.edge == Edge::Vd) o.add += 1;  // ∂Q/∂V += b
  return o;
}

OpCounts EwaFilter::ops_edge_setup() const {
  OpCounts o;
  if (cfg_.edge != Edge::Vd) return o;
  // λ₋ of Σ_l: (Σuu ± Σvv)/2 (2 add, 2 mul), d² + Σuv² (2 mul, 1 add), √, t − s (1 add);
  // minor radius √λ₋; band 1 − ½/r (rcp, 1 add, r > ½ 1 cmp), squared (1 mul); 2c (1 add).
  o.add = 2 + 1 + 1 + 1 + 1;
  o.mul = 2 + 2 + 1;
  o.sqrt = 2;
  o.rcp = 1;
  o.cmp = 1;
  return o;
}

OpCounts EwaFilter::ops_per_edge_texel() const {
  OpCounts o;
  if (cfg_.edge != Edge::Vd) return o;
  // ∂Q/∂U = dQ − a (1 add); |∇Q|² (2 mul, 1 add), ∇Q ≠ 0 (1 cmp); √Q (1 sqrt); 1/|∇Q|
  // (1 sqrt, 1 rcp); Q − √Q (1 add); d = 2(Q − √Q)/|∇Q| (1 mul, the 2 an exponent
  // increment); the cut-off and its fraction; weight × fraction (1 mul).
  o.add = 1 + 1 + 1;
  o.mul = 2 + 1 + 1;
  o.cmp = 1;
  o.sqrt = 2;
  o.rcp = 1;
  o += cutoff().ops_per_item() + SubtexelCutoff::fraction_extra_ops();
  return o;
}

OpCounts EwaFilter::ops_per_inside() const {
  OpCounts o = weight_ops(cfg_.weight);
  if (cfg_.weight == Weight::Map && map_) o += map_->ops_per_item();
  o += address_mode_ops(cfg_.address_u);
  o.mem += 1;                             // texel read
  o.mul += 4;                             // w·RGBA
  o.add += 4 + 1;                         // RGBA accumulate, Σw
  if (cfg_.edge == Edge::Vd) o.cmp += 1;  // Q > band
  return o;
}

template <class T>
FilterOutput EwaFilter::filter_t(const Texture& tex, const Fragment& f,
                                 std::vector<TexelRef>* fetched, OpCounts& ops) const {
  using S = SetupOf<T>;
  using Acc = AccOf<T>;
  FilterOutput out;
  FilterStats& st = out.stats;
  const int q_top = tex.levels() - 1;
  const int w0 = tex.width(0), h0 = tex.height(0);
  double u = f.u, v = f.v;
  if (!std::isfinite(u) || !std::isfinite(v)) {
    u = std::isfinite(u) ? u : 0.0;
    v = std::isfinite(v) ? v : 0.0;
    st.bad_input = true;
  }
  Footprint fp = footprint_setup<S>(f, w0, h0, cfg_.radius_px, cfg_.max_aniso, ops);
  st.bad_input = st.bad_input || fp.bad_input;

  // Level from the minor axis: λ = log2(√λ₋ / minor_texels) + bias; the finer level keeps
  // the minor radius at that level in [minor_texels, 2·minor_texels).
  ops += level_select_ops();
  double lambda = -std::numeric_limits<double>::infinity();
  if (fp.overflow) {
    lambda = q_top;
  } else if (fp.minor2 > 0) {
    lambda = 0.5 * std::log2(fp.minor2) - std::log2(cfg_.minor_texels) + f.lod_bias;
  }
  if (std::isnan(lambda)) lambda = 0;
  int l0 = static_cast<int>(std::clamp(std::floor(lambda), 0.0, static_cast<double>(q_top)));
  double frac = 0;
  if (cfg_.mip == Mip::Linear && l0 < q_top) frac = std::clamp(lambda - l0, 0.0, 1.0);

  // Σ at level l (level texels², with the reconstruction term) and its bounding box.
  double scale = 1.0;  // shrinks Σ at the top level when even that box exceeds the budget
  auto level_sigma = [&](int l, double& suu, double& suv, double& svv) {
    const double sx = static_cast<double>(tex.width(l)) / w0;
    const double sy = static_cast<double>(tex.height(l)) / h0;
    suu = fp.suu * sx * sx * scale + cfg_.reconstruction;
    suv = fp.suv * sx * sy * scale;
    svv = fp.svv * sy * sy * scale + cfg_.reconstruction;
  };
  auto box_count = [&](int l) {
    double suu, suv, svv;
    level_sigma(l, suu, suv, svv);
    ops += budget_iteration_ops();
    return (2.0 * std::sqrt(suu) + 1.0) * (2.0 * std::sqrt(svv) + 1.0);
  };
  const double budget = cfg_.texel_budget;
  double box = box_count(l0);
  while (box > budget && l0 < q_top) box = box_count(++l0);
  if (l0 == q_top) frac = 0;
  // Even the most minified level's box is too large (derivatives far beyond the texture size):
  // shrink the footprint by 2 per axis until it fits, so the texel count stays bounded.
  for (int guard = 0; guard < 200 && box > budget; ++guard) {
    scale *= 0.25;
    box = box_count(l0);
  }
  st.level = l0;

  const LevelScan<T> scan{*this, tex, fetched, ops, st};
  glm::vec<4, Acc> s0(0), s1(0);
  double suu, suv, svv;
  level_sigma(l0, suu, suv, svv);
  const Acc w0sum = scan.run(l0, u, v, suu, suv, svv, f, s0);
  Acc w1sum = 0;
  if (frac > 0) {
    level_sigma(l0 + 1, suu, suv, svv);
    w1sum = scan.run(l0 + 1, u, v, suu, suv, svv, f, s1);
  }
  // Normalise each level; a level whose weights are all zero gives way to the other one, and
  // if both are zero the bilinear sample at the centre of the finer level is the result.
  const bool ok0 = normalisable(w0sum), ok1 = normalisable(w1sum);
  ops += normalise_ops();
  if (frac > 0) ops += normalise_ops();
  if (!ok0 && !ok1) {
    st.fallback = true;
    out.colour = bilinear_fallback(tex, l0, u, v, cfg_.address_u, cfg_.address_v, fetched, ops);
    st.texels += 4;
    return out;
  }
  glm::vec<4, Acc> c0 = ok0 ? s0 * (Acc(1) / w0sum) : glm::vec<4, Acc>(0);
  glm::vec<4, Acc> c1 = ok1 ? s1 * (Acc(1) / w1sum) : glm::vec<4, Acc>(0);
  if (!ok0) c0 = c1;
  if (!ok1) c1 = c0;
  if (frac > 0) {
    OpCounts lerp;
    lerp.mul = 4;
    lerp.add = 8;
    ops += lerp;
    const Acc fr = static_cast<Acc>(frac);
    c0 = c0 + fr * (c1 - c0);
  }
  out.colour = Rgba(c0);
  return out;
}

template FilterOutput EwaFilter::filter_t<float>(const Texture&, const Fragment&,
                                                 std::vector<TexelRef>*, OpCounts&) const;
template FilterOutput EwaFilter::filter_t<double>(const Texture&, const Fragment&,
                                                  std::vector<TexelRef>*, OpCounts&) const;
template FilterOutput EwaFilter::filter_t<EwaQFixed>(const Texture&, const Fragment&,
                                                     std::vector<TexelRef>*, OpCounts&) const;

FilterOutput EwaFilter::filter(const Texture& tex, const Fragment& f,
                               std::vector<TexelRef>* fetched, OpCounts& ops) const {
  return kArith.visit(cfg_.arith,
                      [&](auto t) { return filter_t<decltype(t)>(tex, f, fetched, ops); });
}

uint32_t EwaFilter::issue_cycles(const FilterStats& s) const {
  return scan_issue_cycles(s, cfg_.lanes);
}

TimingSpec EwaFilter::timing(const TechTable& tech) const {
  // Critical path: set-up (derivatives → Σ → eigenvalues → clamp), level (log2, budget
  // iteration), level set-up (det → 1/det → a, b, c → row start Q0), one texel (Q step,
  // compare, weight, read, multiply-accumulate), normalisation.
  OpCounts path;
  path.mul = 1 + 1 + 1 + 1 + 1;  // scale, square, d², k, k·(…)
  path.add = 1 + 1 + 1 + 1 + 1;  // sum, (Σuu−Σvv)/2, d²+Σuv², λ₊ − Σ, update
  path.sqrt = 1;
  path.rcp = 1;
  path.cmp = 2;
  OpCounts level;
  level.lut = 1;
  level.add = 2;
  level.cmp = 2;
  level.mul = 1;
  level.sqrt = 1;
  path += level;
  OpCounts lsetup;
  lsetup.mul = 2 + 2;  // det, a, then aU0, ·U0
  lsetup.add = 1 + 2;
  lsetup.rcp = 1;
  path += lsetup;
  OpCounts texel;
  texel.add = 1 + 1 + 1;  // Q step, accumulate, Σw
  texel.cmp = 1;
  texel.mul = 1;  // w·texel
  texel.mem = 1;
  switch (cfg_.weight) {
    case Weight::Lut:
      texel.mul += 1;
      texel.lut += 1;
      break;
    case Weight::Exp:
      texel.mul += 1;
      texel.lut += 1;
      texel.cmp += 1;
      break;
    case Weight::Pow8:
      texel.mul += 4;
      texel.add += 1;
      texel.cmp += 1;
      break;
    case Weight::Map:
      if (map_) texel += map_->read_critical_path();
      break;
    case Weight::Uniform:
      break;
    case Weight::Thesis:  // q′: aU, +bV, ·U (2 mul, 1 add), ·2α, power 8
      texel.mul += 2 + 1 + 4;
      texel.add += 1 + 1;
      texel.cmp += 1;
      break;
  }
  if (cfg_.edge == Edge::Vd) {
    // ∂Q/∂U → |∇Q|² → 1/|∇Q| → d → cut-off → × 1/W(−½), select → w × fraction.
    texel.add += 1 + 1;
    texel.mul += 1 + 1 + 1 + 1;
    texel.sqrt += 1;
    texel.rcp += 1;
    texel.cmp += 1;
    texel += cutoff().critical_path();
  }
  path += texel;
  path.rcp += 1;
  path.mul += 1;
  path.cmp += 1;
  OpCounts units = footprint_setup_ops() + level_select_ops() + budget_iteration_ops() +
                   level_setup_ops() + row_ops(cfg_.scan) + normalise_ops();
  OpCounts lane = ops_per_item() + ops_per_inside();
  lane.mem = 0;
  if (cfg_.edge == Edge::Vd) {
    // Per lane the distance datapath and vd.lanes cut-off units; the band set-up once.
    const SubtexelCutoff cut = cutoff();
    units += ops_edge_setup();
    OpCounts dist = ops_per_edge_texel();
    const OpCounts c = cut.ops_per_item();
    dist.add -= c.add;
    dist.mul -= c.mul;
    dist.cmp -= c.cmp;
    dist.lut -= c.lut;
    lane += dist + c * cut.config().lanes;
  }
  return derive_timing(tech, lane, path, Datapath::Spatial,
                       static_cast<uint32_t>(std::max(cfg_.lanes, 1)), units);
}

std::string EwaFilter::arithmetic() const {
  std::string q;
  if (cfg_.arith == NumberFormat::Double) {
    q = "double set-up, Q and accumulation";
  } else if (cfg_.arith == NumberFormat::S18_30) {
    q = "float32 set-up, Q in " + EwaQFixed::name() + ", float32 accumulation";
  } else {
    q = "float32 set-up and Q, float32 accumulation";
  }
  switch (cfg_.weight) {
    case Weight::Lut:
      q += "; weights from a " + std::to_string(cfg_.lut_size) + "-entry table (" +
           (cfg_.lut_bits > 0 ? "u0." + std::to_string(cfg_.lut_bits) : std::string("float")) + ")";
      break;
    case Weight::Exp:
      q += "; weights exp(-alpha Q) computed";
      break;
    case Weight::Pow8:
      q += "; weights (1 - alpha Q/8)^8 computed";
      break;
    case Weight::Map:
      q += "; weights read from a " + (map_ ? map_->name() : std::string("?")) + " map";
      break;
    case Weight::Uniform:
      q += "; uniform weights";
      break;
    case Weight::Thesis:
      q += "; weights (1 - q'/16)^8 computed with the seed's theta/L/d rule";
      break;
  }
  if (cfg_.edge == Edge::Vd) {
    q += "; " + cutoff().name() + " edge cut-off, boundary distance in " +
         (cfg_.arith == NumberFormat::Double ? "double" : "float32");
  }
  return q;
}

}  // namespace texsim
