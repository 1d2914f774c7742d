#include "pipeline/texture/coord_method.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/texture/coords/uv_approximation.h"
#include "blocks/texture/coords/uv_approximation_triangle.h"
#include "blocks/texture/coords/uv_constant_depth.h"
#include "blocks/texture/coords/uv_heckbert_direct.h"
#include "blocks/texture/coords/uv_incremental_adder.h"
#include "blocks/texture/derivs/derivatives_analytic.h"
#include "blocks/texture/derivs/derivatives_forward_diff.h"
#include "blocks/texture/derivs/derivatives_iterative.h"
#include "blocks/texture/derivs/derivatives_quad.h"

namespace texsim {

namespace {

// The fixed-point widths of the study: a 32-bit datapath, a 48-bit one and a 60-bit one,
// each with enough integer bits (sign + 15/19/23) for coordinates of a 4096-texel plane
// and pixel indices of an 8192-pixel row.
using FixedA = Fixed<16, 16>;
using FixedB = Fixed<20, 28>;
using FixedC = Fixed<24, 36>;

template <template <class> class Impl, class Base, class... Args>
std::unique_ptr<Base> make_for_format(const std::string& format, Args&&... args) {
  if (format == "float") return std::make_unique<Impl<float>>(args...);
  if (format == "double") return std::make_unique<Impl<double>>(args...);
  if (format == FixedA::name()) return std::make_unique<Impl<FixedA>>(args...);
  if (format == FixedB::name()) return std::make_unique<Impl<FixedB>>(args...);
  if (format == FixedC::name()) return std::make_unique<Impl<FixedC>>(args...);
  throw InputError("number format '" + format + "'", "unknown (known: float, double, " +
                                                         FixedA::name() + ", " + FixedB::name() +
                                                         ", " + FixedC::name() + ")");
}

uint32_t lat(const TimingSpec& t) { return t.ii == 0 ? 0 : t.latency; }

enum class CoordKind {
  Heckbert,
  HeckbertRcp,
  Incremental,
  IncrementalK4,
  IncrementalBidir,
  Affine,
  Quadratic,
  Cubic,
  Biquadratic,
  Bicubic,
  ConstantDepth,
  Affine16,
  Quadratic32
};

CoordKind coord_kind(const std::string& m) {
  const auto& names = CoordGenerator::method_names();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == m) return static_cast<CoordKind>(i);
  }
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw InputError("coordinate method '" + m + "'", "unknown (known: " + known + ")");
}

template <class T>
class CoordGenImpl final : public CoordGenerator {
 public:
  CoordGenImpl(const std::string& method, Datapath dp)
      : method_(method), format_(format_name<T>()), kind_(coord_kind(method)) {
    UvHeckbertDirect::Config hc;
    hc.datapath = dp;
    hc.form = kind_ == CoordKind::HeckbertRcp ? UvHeckbertDirect::Form::Reciprocal
                                              : UvHeckbertDirect::Form::Divide;
    hd_ = UvHeckbertDirect(hc);
    UvIncrementalAdder::Config ic;
    ic.datapath = dp;
    ic.form = kind_ == CoordKind::IncrementalK4      ? UvIncrementalAdder::Form::KLane
              : kind_ == CoordKind::IncrementalBidir ? UvIncrementalAdder::Form::Bidirectional
                                                     : UvIncrementalAdder::Form::Sequential;
    ic.lanes = 4;
    inc_ = UvIncrementalAdder(ic);
    UvApproximation::Config ac;
    ac.datapath = dp;
    ac.order = kind_ == CoordKind::Affine || kind_ == CoordKind::Affine16
                   ? UvApproximation::Order::Affine
               : kind_ == CoordKind::Cubic ? UvApproximation::Order::Cubic
                                           : UvApproximation::Order::Quadratic;
    ac.segment = kind_ == CoordKind::Affine16 ? 16 : kind_ == CoordKind::Quadratic32 ? 32 : 0;
    ap_ = UvApproximation(ac);
    UvApproximationTriangle::Config tc;
    tc.datapath = dp;
    tc.order = kind_ == CoordKind::Bicubic ? UvApproximationTriangle::Order::Bicubic
                                           : UvApproximationTriangle::Order::Biquadratic;
    at_ = UvApproximationTriangle(tc);
    UvConstantDepth::Config cc;
    cc.datapath = dp;
    cd_ = UvConstantDepth(cc);
  }
  const std::string& method() const override { return method_; }
  const std::string& format() const override { return format_; }

  StageConfig stage(const TechTable& t) const override {
    StageConfig s;
    s.name = "coords." + method_;
    switch (kind_) {
      case CoordKind::Heckbert:
      case CoordKind::HeckbertRcp:
        s.timing = hd_.timing(t);
        break;
      case CoordKind::Incremental:
      case CoordKind::IncrementalK4:
      case CoordKind::IncrementalBidir:
        s.timing = inc_.timing(t);
        break;
      case CoordKind::Affine:
      case CoordKind::Quadratic:
      case CoordKind::Cubic:
      case CoordKind::Affine16:
      case CoordKind::Quadratic32:
        s.timing = ap_.timing(t);
        break;
      case CoordKind::Biquadratic:
      case CoordKind::Bicubic:
        s.timing = at_.timing(t);
        break;
      case CoordKind::ConstantDepth:
        s.timing = cd_.timing(t);
        break;
    }
    return s;
  }

  OpCounts pixel_ops() const override {
    switch (kind_) {
      case CoordKind::Heckbert:
      case CoordKind::HeckbertRcp:
        return hd_.ops_per_item();
      case CoordKind::Incremental:
      case CoordKind::IncrementalK4:
      case CoordKind::IncrementalBidir:
        return inc_.ops_per_item();
      case CoordKind::Affine:
      case CoordKind::Quadratic:
      case CoordKind::Cubic:
      case CoordKind::Affine16:
      case CoordKind::Quadratic32:
        return ap_.ops_per_item();
      case CoordKind::Biquadratic:
      case CoordKind::Bicubic:
        return at_.ops_per_item();
      case CoordKind::ConstantDepth:
        return cd_.ops_per_item();
    }
    return {};
  }

  void generate(const CoordTriangle& tri, const TechTable& t, std::vector<CoordFragment>& out,
                std::vector<ItemCost>& costs, OpCounts& ops,
                CoordGeneratorStats& stats) const override {
    const MapCoeffs<T> mc = to_coeffs<T>(tri.map);
    OpCounts pix, row, trio;
    uint32_t row_lat = 0, tri_lat = 0;
    uint64_t pixels = 0, rows = 0;
    std::vector<CoordSample> buf;
    bool first = true;
    auto emit = [&](int32_t x, int32_t y, const CoordSample& s, bool row_start) {
      ItemCost c;
      if (row_start) c.extra_ii += row_lat;
      if (first) c.extra_ii += tri_lat;
      first = false;
      out.push_back({x, y, s});
      costs.push_back(c);
      ++pixels;
    };
    auto run_rows = [&](auto&& eval) {
      for (const RowSpan& r : tri.rows) {
        if (r.n <= 0) continue;
        buf.assign(static_cast<size_t>(r.n), CoordSample{});
        eval(r, buf.data());
        for (int32_t k = 0; k < r.n; ++k) emit(r.x0 + k, r.y, buf[k], k == 0);
        ++rows;
      }
    };
    switch (kind_) {
      case CoordKind::Heckbert:
      case CoordKind::HeckbertRcp:
        pix = hd_.ops_per_item();
        run_rows([&](const RowSpan& r, CoordSample* o) { hd_.eval_row(mc, r, o); });
        rows = 0;  // no row set-up
        break;
      case CoordKind::Incremental:
      case CoordKind::IncrementalK4:
      case CoordKind::IncrementalBidir:
        pix = inc_.ops_per_item();
        row = inc_.row_setup_ops();
        row_lat = lat(inc_.row_setup_timing(t));
        run_rows([&](const RowSpan& r, CoordSample* o) { inc_.eval_row(mc, r, o); });
        break;
      case CoordKind::Affine:
      case CoordKind::Quadratic:
      case CoordKind::Cubic:
      case CoordKind::Affine16:
      case CoordKind::Quadratic32:
        pix = ap_.ops_per_item();
        row = ap_.row_setup_ops();
        row_lat = lat(ap_.row_setup_timing(t));
        // Each segment is a span with its own set-up.
        for (const RowSpan& r : tri.rows) {
          for (const RowSpan& g : ap_.segments(r)) {
            if (g.n <= 0) continue;
            buf.assign(static_cast<size_t>(g.n), CoordSample{});
            ap_.eval_row(mc, g, buf.data());
            for (int32_t k = 0; k < g.n; ++k) emit(g.x0 + k, g.y, buf[k], k == 0);
            ++rows;
          }
        }
        break;
      case CoordKind::Biquadratic:
      case CoordKind::Bicubic: {
        pix = at_.ops_per_item();
        row = at_.row_setup_ops();
        trio = at_.triangle_setup_ops();
        row_lat = lat(at_.row_setup_timing(t));
        tri_lat = lat(at_.triangle_setup_timing(t));
        UvApproximationTriangle::Triangle tr;
        for (int k = 0; k < 3; ++k) {
          tr.x[k] = tri.x[k];
          tr.y[k] = tri.y[k];
        }
        const auto st = at_.setup_triangle(mc, tr);
        run_rows([&](const RowSpan& r, CoordSample* o) { at_.eval_row(st, r, o); });
        break;
      }
      case CoordKind::ConstantDepth:
        pix = cd_.ops_per_item();
        row = cd_.row_setup_ops();
        trio = cd_.triangle_setup_ops();
        row_lat = lat(cd_.row_setup_timing(t));
        tri_lat = lat(cd_.triangle_setup_timing(t));
        rows = constant_depth(tri, mc, emit, buf);
        break;
    }
    const bool any = pixels > 0;
    ops += pix * pixels + row * rows + (any ? trio : OpCounts{});
    stats.fragments += pixels;
    stats.rows += rows;
    stats.triangles += any ? 1 : 0;
    const OpCounts here = pix * pixels + row * rows + (any ? trio : OpCounts{});
    stats.divisions += here.div + here.rcp;
  }

 private:
  // Walks the triangle's pixels along constant-depth lines: pixel (major, minor) lies on line
  // j = minor - round(k·major), whose exact course is minor = k·major + j (the rectangle-scan
  // rasterizer's traversal, every line the same digital line shifted by one pixel).
  template <class Emit>
  uint64_t constant_depth(const CoordTriangle& tri, const MapCoeffs<T>& mc, Emit& emit,
                          std::vector<CoordSample>& buf) const {
    const bool xm = cd_.x_major(tri.map);
    const long double k = cd_.slope(tri.map);
    struct P {
      int64_t j;
      int32_t major, minor;
    };
    std::vector<P> ps;
    for (const RowSpan& r : tri.rows) {
      for (int32_t i = 0; i < r.n; ++i) {
        const int32_t x = r.x0 + i, y = r.y;
        const int32_t major = xm ? x : y, minor = xm ? y : x;
        const auto rounded = static_cast<int64_t>(std::floor(k * major + 0.5L));
        ps.push_back({minor - rounded, major, minor});
      }
    }
    std::sort(ps.begin(), ps.end(),
              [](const P& a, const P& b) { return a.j != b.j ? a.j < b.j : a.major < b.major; });
    const auto st = cd_.setup_triangle(mc);
    uint64_t lines = 0;
    size_t i = 0;
    while (i < ps.size()) {
      size_t e = i + 1;
      while (e < ps.size() && ps[e].j == ps[i].j && ps[e].major == ps[e - 1].major + 1) ++e;
      const UvConstantDepth::SlopedSpan l{ps[i].major, static_cast<double>(ps[i].j),
                                          static_cast<int32_t>(e - i)};
      buf.assign(e - i, CoordSample{});
      cd_.eval_row(mc, st, l, buf.data());
      for (size_t q = i; q < e; ++q) {
        const int32_t x = xm ? ps[q].major : ps[q].minor, y = xm ? ps[q].minor : ps[q].major;
        emit(x, y, buf[q - i], q == i);
      }
      ++lines;
      i = e;
    }
    return lines;
  }

  std::string method_, format_;
  CoordKind kind_;
  UvHeckbertDirect hd_;
  UvIncrementalAdder inc_;
  UvApproximation ap_;
  UvApproximationTriangle at_;
  UvConstantDepth cd_;
};

enum class DerivKind { Analytic, Quad, HeckbertFd, AcceleratedFd, Iterative };

DerivKind deriv_kind(const std::string& m) {
  const auto& names = DerivGenerator::method_names();
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == m) return static_cast<DerivKind>(i);
  }
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw InputError("derivative method '" + m + "'", "unknown (known: " + known + ")");
}

template <class T>
class DerivGenImpl final : public DerivGenerator {
 public:
  DerivGenImpl(const std::string& method, Datapath dp)
      : method_(method), format_(format_name<T>()), kind_(deriv_kind(method)) {
    DerivativesAnalytic::Config a;
    a.datapath = dp;
    an_ = DerivativesAnalytic(a);
    DerivativesQuad::Config q;
    q.datapath = dp;
    qd_ = DerivativesQuad(q);
    DerivativesForwardDiff::Config f;
    f.datapath = dp;
    f.form = kind_ == DerivKind::AcceleratedFd ? DerivativesForwardDiff::Form::Accelerated
                                               : DerivativesForwardDiff::Form::Classic;
    fd_ = DerivativesForwardDiff(f);
    DerivativesIterative::Config i;
    i.datapath = dp;
    it_ = DerivativesIterative(i);
    UvIncrementalAdder::Config ic;
    ic.datapath = dp;
    helper_ = UvIncrementalAdder(ic);
  }
  const std::string& method() const override { return method_; }
  const std::string& format() const override { return format_; }

  StageConfig stage(const TechTable& t) const override {
    StageConfig s;
    s.name = "derivs." + method_;
    switch (kind_) {
      case DerivKind::Analytic:
        s.timing = an_.timing(t);
        break;
      case DerivKind::Quad:
        s.timing = qd_.timing(t);
        break;
      case DerivKind::HeckbertFd:
      case DerivKind::AcceleratedFd:
        s.timing = fd_.timing(t);
        break;
      case DerivKind::Iterative:
        s.timing = it_.timing(t);
        break;
    }
    return s;
  }

  OpCounts pixel_ops() const override {
    switch (kind_) {
      case DerivKind::Analytic:
        return an_.ops_per_item();
      case DerivKind::Quad:
        return qd_.ops_per_item();
      case DerivKind::HeckbertFd:
      case DerivKind::AcceleratedFd:
        return fd_.ops_per_item();
      case DerivKind::Iterative:
        return it_.ops_per_item();
    }
    return {};
  }

  void generate(const CoordTriangle& tri, const TechTable& t, std::vector<CoordDerivs>& out,
                std::vector<ItemCost>& costs, OpCounts& ops) const override {
    const MapCoeffs<T> mc = to_coeffs<T>(tri.map);
    OpCounts pix, row, trio;
    uint32_t row_lat = 0, tri_lat = 0;
    uint64_t pixels = 0, rows = 0;
    DerivativesIterative::Setup<T> st;
    switch (kind_) {
      case DerivKind::Analytic:
        pix = an_.ops_per_item();
        break;
      case DerivKind::Quad:
        pix = qd_.ops_per_item();
        break;
      case DerivKind::HeckbertFd:
      case DerivKind::AcceleratedFd:
        pix = fd_.ops_per_item();
        break;
      case DerivKind::Iterative:
        pix = it_.ops_per_item();
        row = it_.row_setup_ops();
        trio = it_.triangle_setup_ops();
        row_lat = lat(it_.row_setup_timing(t));
        tri_lat = lat(it_.triangle_setup_timing(t));
        st = it_.setup_triangle(mc);
        break;
    }
    std::vector<CoordDerivs> buf;
    bool first = true;
    std::unordered_set<int64_t> quads;
    for (const RowSpan& r : tri.rows) {
      if (r.n <= 0) continue;
      buf.assign(static_cast<size_t>(r.n), CoordDerivs{});
      switch (kind_) {
        case DerivKind::Analytic:
          an_.eval_row(mc, r, buf.data());
          break;
        case DerivKind::Quad:
          qd_.eval_row(mc, r, buf.data());
          break;
        case DerivKind::HeckbertFd:
        case DerivKind::AcceleratedFd:
          fd_.eval_row(mc, r, buf.data());
          break;
        case DerivKind::Iterative:
          it_.eval_row(mc, st, r, buf.data());
          break;
      }
      for (int32_t k = 0; k < r.n; ++k) {
        ItemCost c;
        if (k == 0) c.extra_ii += row_lat;
        if (first) c.extra_ii += tri_lat;
        first = false;
        out.push_back(buf[k]);
        costs.push_back(c);
        if (kind_ == DerivKind::Quad) {
          quads.insert((static_cast<int64_t>((r.x0 + k) >> 1) << 32) ^ ((r.y >> 1) & 0xffffffff));
        }
      }
      pixels += static_cast<uint64_t>(r.n);
      ++rows;
    }
    if (kind_ != DerivKind::Iterative) rows = 0;
    ops += pix * pixels + row * rows + (pixels > 0 ? trio : OpCounts{});
    if (kind_ == DerivKind::Quad) {
      // Helper pixels of partly covered quads still run the coordinate datapath.
      const uint64_t helpers = 4 * quads.size() - pixels;
      ops += helper_.ops_per_item() * helpers;
    }
  }

 private:
  std::string method_, format_;
  DerivKind kind_;
  DerivativesAnalytic an_;
  DerivativesQuad qd_;
  DerivativesForwardDiff fd_;
  DerivativesIterative it_;
  UvIncrementalAdder helper_;
};

template <class T>
class EllipseGenImpl final : public EllipseGenerator {
 public:
  EllipseGenImpl(const std::string& form, Datapath dp) {
    EllipseSetup::Config c;
    c.datapath = dp;
    if (form == "determinant") {
      c.f_form = EllipseSetup::FForm::Determinant;
    } else if (form == "ac-b2") {
      c.f_form = EllipseSetup::FForm::AcMinusB2;
    } else {
      throw InputError("ellipse form '" + form + "'", "unknown (known: determinant, ac-b2)");
    }
    es_ = EllipseSetup(c);
  }
  StageConfig stage(const TechTable& t) const override {
    StageConfig s;
    s.name = "ellipse";
    s.timing = es_.timing(t);
    return s;
  }
  OpCounts pixel_ops() const override { return es_.ops_per_item(); }
  EllipseCoeffs eval(const CoordDerivs& d) const override { return es_.eval<T>(d); }

 private:
  EllipseSetup es_;
};

}  // namespace

const std::vector<std::string>& coord_format_names() {
  static const std::vector<std::string> n = {"float", "double", FixedA::name(), FixedB::name(),
                                             FixedC::name()};
  return n;
}

const std::vector<std::string>& CoordGenerator::method_names() {
  static const std::vector<std::string> n = {
      "heckbert",       "heckbert-rcp", "incremental", "incremental-k4", "incremental-bidir",
      "affine",         "quadratic",    "cubic",       "biquadratic",    "bicubic",
      "constant-depth", "affine-16",    "quadratic-32"};
  return n;
}

std::unique_ptr<CoordGenerator> CoordGenerator::create(const std::string& method,
                                                       const std::string& format, Datapath dp) {
  coord_kind(method);  // validate the method before the format
  return make_for_format<CoordGenImpl, CoordGenerator>(format, method, dp);
}

const std::vector<std::string>& DerivGenerator::method_names() {
  static const std::vector<std::string> n = {"analytic", "quad", "heckbert-fd", "accelerated-fd",
                                             "iterative"};
  return n;
}

std::unique_ptr<DerivGenerator> DerivGenerator::create(const std::string& method,
                                                       const std::string& format, Datapath dp) {
  deriv_kind(method);
  return make_for_format<DerivGenImpl, DerivGenerator>(format, method, dp);
}

std::unique_ptr<EllipseGenerator> EllipseGenerator::create(const std::string& form,
                                                           const std::string& format, Datapath dp) {
  return make_for_format<EllipseGenImpl, EllipseGenerator>(format, form, dp);
}

CoordUnitConfig CoordUnitConfig::from_toml(const ConfigReader& r) {
  r.reject_unknown({"method", "derivs", "format", "datapath"});
  CoordUnitConfig c;
  auto choose = [&](std::string_view key, const std::vector<std::string>& names,
                    const std::string& def, bool allow_none) {
    std::vector<std::string_view> choices(names.begin(), names.end());
    if (allow_none) choices.push_back("none");
    int d = 0;
    for (size_t i = 0; i < choices.size(); ++i) {
      if (choices[i] == def) d = static_cast<int>(i);
    }
    return std::string(choices[static_cast<size_t>(r.get_choice(key, d, choices))]);
  };
  c.coords = choose("method", CoordGenerator::method_names(), c.coords, false);
  c.derivs = choose("derivs", DerivGenerator::method_names(), c.derivs, true);
  c.format = choose("format", coord_format_names(), c.format, false);
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

CoordUnit::CoordUnit(const CoordUnitConfig& c) : cfg_(c) {
  coords_ = CoordGenerator::create(c.coords, c.format, c.datapath);
  if (c.derivs != "none") derivs_ = DerivGenerator::create(c.derivs, c.format, c.datapath);
}

std::vector<StageConfig> CoordUnit::stages(const TechTable& t) const {
  std::vector<StageConfig> s{coords_->stage(t)};
  if (derivs_) s.push_back(derivs_->stage(t));
  return s;
}

void CoordUnit::generate(const CoordTriangle& tri, const TechTable& t,
                         std::vector<CoordUnitFragment>& out, std::vector<ItemCost>& costs,
                         OpCounts& coord_ops, OpCounts& deriv_ops) const {
  std::vector<CoordFragment> frags;
  std::vector<ItemCost> ccost;
  CoordGeneratorStats stats;
  coords_->generate(tri, t, frags, ccost, coord_ops, stats);
  std::vector<CoordDerivs> ders;
  std::vector<ItemCost> dcost;
  // Row index: where row y's derivatives start in `ders`, and its x0.
  std::unordered_map<int32_t, std::pair<size_t, int32_t>> row_at;
  if (derivs_) {
    derivs_->generate(tri, t, ders, dcost, deriv_ops);
    size_t base = 0;
    for (const RowSpan& r : tri.rows) {
      if (r.n <= 0) continue;
      row_at[r.y] = {base, r.x0};
      base += static_cast<size_t>(r.n);
    }
  }
  const size_t stages = derivs_ ? 2 : 1;
  for (size_t i = 0; i < frags.size(); ++i) {
    CoordUnitFragment f;
    f.x = frags[i].x;
    f.y = frags[i].y;
    f.uv = frags[i].uv;
    costs.push_back(ccost[i]);
    if (stages == 2) {
      const auto it = row_at.find(f.y);
      ItemCost dc;
      if (it != row_at.end()) {
        const size_t k = it->second.first + static_cast<size_t>(f.x - it->second.second);
        if (k < ders.size()) {
          f.d = ders[k];
          dc = dcost[k];
        }
      }
      costs.push_back(dc);
    }
    out.push_back(f);
  }
}

}  // namespace texsim
