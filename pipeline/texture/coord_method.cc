#include "pipeline/texture/coord_method.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/raster/guard_band_clipper.h"
#include "blocks/texture/coords/uv_approximation.h"
#include "blocks/texture/coords/uv_approximation_triangle.h"
#include "blocks/texture/coords/uv_constant_depth.h"
#include "blocks/texture/coords/uv_heckbert_direct.h"
#include "blocks/texture/coords/uv_incremental_adder.h"
#include "blocks/texture/derivs/derivatives_analytic.h"
#include "blocks/texture/derivs/derivatives_forward_diff.h"
#include "blocks/texture/derivs/derivatives_iterative.h"
#include "blocks/texture/derivs/derivatives_quad.h"
#include "rtl_model/number/number_format.h"

namespace texsim {

std::vector<RowSpan> triangle_rows(const double x[3], const double y[3], int32_t w, int32_t h) {
  const std::vector<ScreenVertex> tri = {{x[0], y[0], 1}, {x[1], y[1], 1}, {x[2], y[2], 1}};
  return rasterize_convex(EdgeRasterizer(), tri, Scissor{0, 0, w, h});
}

namespace {

// The block in the number format a scene names, from the one registry of number formats
// (rtl_model/number/number_format.h: kCoordFormats). The fixed-point formats have enough
// integer bits (sign + 15/19/23) for coordinates of a 4096-texel plane and pixel indices of
// an 8192-pixel row.
static_assert(std::is_same_v<number_format_t<NumberFormat::S16_16>, Fixed<16, 16>>);
static_assert(std::is_same_v<number_format_t<NumberFormat::S20_28>, Fixed<20, 28>>);
static_assert(std::is_same_v<number_format_t<NumberFormat::S24_36>, Fixed<24, 36>>);

template <template <class> class Impl, class Base, class... Args>
std::unique_ptr<Base> make_for_format(const std::string& format, Args&&... args) {
  const std::vector<std::string_view> keys = kCoordFormats.key_list();
  const auto it = std::find(keys.begin(), keys.end(), format);
  if (it == keys.end()) {
    std::string known;
    for (std::string_view k : keys) known += (known.empty() ? "" : ", ") + std::string(k);
    throw InputError("number format '" + format + "'", "unknown (known: " + known + ")");
  }
  const NumberFormat f = kCoordFormats.at(static_cast<int>(it - keys.begin()));
  return kCoordFormats.visit(f, [&](auto v) -> std::unique_ptr<Base> {
    return std::make_unique<Impl<decltype(v)>>(args...);
  });
}

// Impl<T, Block> as a template of T alone, for make_for_format.
template <template <class, class> class Impl, class Block>
struct ImplOf {
  template <class T>
  using type = Impl<T, Block>;
};

uint32_t lat(const TimingSpec& t) { return t.ii == 0 ? 0 : t.latency; }

// Set-up work of a block beside its per-pixel datapath: per row (or line) and per triangle.
// A block whose row set-up is empty shares another's and counts no rows.
struct SetupCost {
  OpCounts row, triangle;
  uint32_t row_lat = 0, triangle_lat = 0;
  bool counts_rows = false;
};

// Blocks with a per-triangle set-up (named, so that a block losing it fails to compile).
template <class Block>
constexpr bool kTriangleSetup = false;
template <>
constexpr bool kTriangleSetup<UvApproximationTriangle> = true;
template <>
constexpr bool kTriangleSetup<UvConstantDepth> = true;
template <>
constexpr bool kTriangleSetup<DerivativesIterative> = true;

template <class Block>
SetupCost setup_cost(const Block& b, const TechTable& t) {
  SetupCost s;
  s.row = b.row_setup_ops();
  s.row_lat = lat(b.row_setup_timing(t));
  s.counts_rows = s.row.total() > 0;
  if constexpr (kTriangleSetup<Block>) {
    s.triangle = b.triangle_setup_ops();
    s.triangle_lat = lat(b.triangle_setup_timing(t));
  }
  return s;
}

// Appends a generator's fragments and their front-end costs: a row's first pixel carries the
// row set-up, the triangle's first pixel the triangle set-up.
struct CoordEmitter {
  std::vector<CoordFragment>& out;
  std::vector<ItemCost>& costs;
  const SetupCost& setup;
  uint64_t pixels = 0;
  void operator()(int32_t x, int32_t y, const CoordSample& s, bool row_start) {
    ItemCost c;
    if (row_start) c.extra_ii += setup.row_lat;
    if (pixels == 0) c.extra_ii += setup.triangle_lat;
    out.push_back({x, y, s});
    costs.push_back(c);
    ++pixels;
  }
};

// Runs `eval(span, out)` over the given spans; returns the spans walked.
template <class Eval>
uint64_t walk_spans(const std::vector<RowSpan>& spans, CoordEmitter& emit, Eval&& eval) {
  std::vector<CoordSample> buf;
  uint64_t walked = 0;
  for (const RowSpan& r : spans) {
    if (r.n <= 0) continue;
    buf.assign(static_cast<size_t>(r.n), CoordSample{});
    eval(r, buf.data());
    for (int32_t k = 0; k < r.n; ++k) emit(r.x0 + k, r.y, buf[static_cast<size_t>(k)], k == 0);
    ++walked;
  }
  return walked;
}

// Traversal of each coordinate block over a triangle's pixels; returns the rows (or lines,
// or segments) walked. Blocks that evaluate raster rows from the map share the first form.
template <class T, class Block>
uint64_t walk(const Block& b, const CoordTriangle& tri, const MapCoeffs<T>& mc,
              CoordEmitter& emit) {
  return walk_spans(tri.rows, emit,
                    [&](const RowSpan& r, CoordSample* o) { b.eval_row(mc, r, o); });
}

// Each segment is a span with its own set-up.
template <class T>
uint64_t walk(const UvApproximation& b, const CoordTriangle& tri, const MapCoeffs<T>& mc,
              CoordEmitter& emit) {
  std::vector<RowSpan> segments;
  for (const RowSpan& r : tri.rows) {
    for (const RowSpan& g : b.segments(r)) segments.push_back(g);
  }
  return walk_spans(segments, emit,
                    [&](const RowSpan& r, CoordSample* o) { b.eval_row(mc, r, o); });
}

template <class T>
uint64_t walk(const UvApproximationTriangle& b, const CoordTriangle& tri, const MapCoeffs<T>& mc,
              CoordEmitter& emit) {
  UvApproximationTriangle::Triangle tr;
  for (int k = 0; k < 3; ++k) {
    tr.x[k] = tri.x[k];
    tr.y[k] = tri.y[k];
  }
  const auto st = b.setup_triangle(mc, tr);
  return walk_spans(tri.rows, emit,
                    [&](const RowSpan& r, CoordSample* o) { b.eval_row(st, r, o); });
}

// Walks the triangle's pixels along constant-depth lines: pixel (major, minor) lies on line
// j = minor - round(k·major), whose exact course is minor = k·major + j (the rectangle-scan
// rasterizer's traversal, every line the same digital line shifted by one pixel).
template <class T>
uint64_t walk(const UvConstantDepth& b, const CoordTriangle& tri, const MapCoeffs<T>& mc,
              CoordEmitter& emit) {
  const bool xm = b.x_major(tri.map);
  const long double k = b.slope(tri.map);
  struct P {
    int64_t j;
    int32_t major, minor;
  };
  std::vector<P> ps;
  for (const RowSpan& r : tri.rows) {
    for (int32_t i = 0; i < r.n; ++i) {
      const int32_t x = r.x0 + i, y = r.y;
      const int32_t major = xm ? x : y, minor = xm ? y : x;
      // A NaN or infinite slope (a map the block rejects) must not convert out of range.
      const long double line = std::floor(k * major + 0.5L);
      const int64_t rounded = std::fabs(line) < 0x1p62L ? static_cast<int64_t>(line) : 0;
      ps.push_back({minor - rounded, major, minor});
    }
  }
  std::sort(ps.begin(), ps.end(),
            [](const P& a, const P& c) { return a.j != c.j ? a.j < c.j : a.major < c.major; });
  const auto st = b.setup_triangle(mc);
  std::vector<CoordSample> buf;
  uint64_t lines = 0;
  size_t i = 0;
  while (i < ps.size()) {
    size_t e = i + 1;
    while (e < ps.size() && ps[e].j == ps[i].j && ps[e].major == ps[e - 1].major + 1) ++e;
    const UvConstantDepth::SlopedSpan l{ps[i].major, static_cast<double>(ps[i].j),
                                        static_cast<int32_t>(e - i)};
    buf.assign(e - i, CoordSample{});
    b.eval_row(mc, st, l, buf.data());
    for (size_t q = i; q < e; ++q) {
      const int32_t x = xm ? ps[q].major : ps[q].minor, y = xm ? ps[q].minor : ps[q].major;
      emit(x, y, buf[q - i], q == i);
    }
    ++lines;
    i = e;
  }
  return lines;
}

// One coordinate block in number format T.
template <class T, class Block>
class CoordGenImpl final : public CoordGenerator {
 public:
  CoordGenImpl(std::string method, const Block& block)
      : method_(std::move(method)), format_(format_name<T>()), block_(block) {}
  const std::string& method() const override { return method_; }
  const std::string& format() const override { return format_; }

  StageConfig stage(const TechTable& t) const override {
    StageConfig s;
    s.name = "coords." + method_;
    s.timing = block_.timing(t);
    return s;
  }

  OpCounts pixel_ops() const override { return block_.ops_per_item(); }

  void generate(const CoordTriangle& tri, const TechTable& t, std::vector<CoordFragment>& out,
                std::vector<ItemCost>& costs, OpCounts& ops,
                CoordGeneratorStats& stats) const override {
    const SetupCost setup = setup_cost(block_, t);
    CoordEmitter emit{out, costs, setup};
    const uint64_t walked = walk(block_, tri, to_coeffs<T>(tri.map), emit);
    const uint64_t rows = setup.counts_rows ? walked : 0;
    const bool any = emit.pixels > 0;
    const OpCounts here = block_.ops_per_item() * emit.pixels + setup.row * rows +
                          (any ? setup.triangle : OpCounts{});
    ops += here;
    stats.fragments += emit.pixels;
    stats.rows += rows;
    stats.triangles += any ? 1 : 0;
    stats.divisions += here.div + here.rcp;
  }

 private:
  std::string method_, format_;
  Block block_;
};

// Per-triangle state of a derivative block: none, or the iterative block's set-up.
template <class T, class Block>
struct DerivRows {
  DerivRows(const Block& block, const MapCoeffs<T>& coeffs) : b(block), mc(coeffs) {}
  void eval(const RowSpan& r, CoordDerivs* o) const { b.eval_row(mc, r, o); }
  const Block& b;
  const MapCoeffs<T>& mc;
};

template <class T>
struct DerivRows<T, DerivativesIterative> {
  DerivRows(const DerivativesIterative& block, const MapCoeffs<T>& coeffs)
      : b(block), mc(coeffs), st(block.setup_triangle(coeffs)) {}
  void eval(const RowSpan& r, CoordDerivs* o) const { b.eval_row(mc, st, r, o); }
  const DerivativesIterative& b;
  const MapCoeffs<T>& mc;
  DerivativesIterative::Setup<T> st;
};

// Derivatives from 2x2 quads: the helper pixels of partly covered quads still run the
// coordinate datapath (charged as the incremental adder's pixel operations).
template <class Block>
constexpr bool kRunsHelperPixels = false;
template <>
constexpr bool kRunsHelperPixels<DerivativesQuad> = true;

// One derivative block in number format T.
template <class T, class Block>
class DerivGenImpl final : public DerivGenerator {
 public:
  DerivGenImpl(std::string method, const Block& block)
      : method_(std::move(method)), format_(format_name<T>()), block_(block) {}
  const std::string& method() const override { return method_; }
  const std::string& format() const override { return format_; }

  StageConfig stage(const TechTable& t) const override {
    StageConfig s;
    s.name = "derivs." + method_;
    s.timing = block_.timing(t);
    return s;
  }

  OpCounts pixel_ops() const override { return block_.ops_per_item(); }

  void generate(const CoordTriangle& tri, const TechTable& t, std::vector<CoordDerivs>& out,
                std::vector<ItemCost>& costs, OpCounts& ops) const override {
    const MapCoeffs<T> mc = to_coeffs<T>(tri.map);
    const SetupCost setup = setup_cost(block_, t);
    const DerivRows<T, Block> rows_of(block_, mc);
    uint64_t pixels = 0, rows = 0;
    std::vector<CoordDerivs> buf;
    std::unordered_set<int64_t> quads;
    for (const RowSpan& r : tri.rows) {
      if (r.n <= 0) continue;
      buf.assign(static_cast<size_t>(r.n), CoordDerivs{});
      rows_of.eval(r, buf.data());
      for (int32_t k = 0; k < r.n; ++k) {
        ItemCost c;
        if (k == 0) c.extra_ii += setup.row_lat;
        if (k == 0 && pixels == 0) c.extra_ii += setup.triangle_lat;
        out.push_back(buf[static_cast<size_t>(k)]);
        costs.push_back(c);
        if constexpr (kRunsHelperPixels<Block>)
          quads.insert((static_cast<int64_t>((r.x0 + k) >> 1) << 32) ^ ((r.y >> 1) & 0xffffffff));
      }
      pixels += static_cast<uint64_t>(r.n);
      ++rows;
    }
    if (!setup.counts_rows) rows = 0;
    ops += block_.ops_per_item() * pixels + setup.row * rows +
           (pixels > 0 ? setup.triangle : OpCounts{});
    if constexpr (kRunsHelperPixels<Block>)
      ops += helper_.ops_per_item() * (4 * quads.size() - pixels);
  }

 private:
  std::string method_, format_;
  Block block_;
  UvIncrementalAdder helper_;  // its pixel operations only
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

// ----- The methods: name -> block, with the block settings the method fixes -----

// A method's block, read from a table by the block's own Config::from_toml; `fixed` names the
// keys the method sets (given in the table they are an error), `preset` sets them.
template <class Gen>
using GenFactory = std::function<std::unique_ptr<Gen>(const std::string& format)>;

template <class Gen>
struct Method {
  std::string_view name;
  std::string_view block;  // the block's name in messages
  std::function<GenFactory<Gen>(const ConfigReader& r, const Method& m)> read;
};

template <template <class, class> class Impl, class Gen, class Block>
Method<Gen> method(std::string_view name, std::string_view block,
                   const std::vector<std::string_view>& fixed,
                   std::function<void(typename Block::Config&)> preset = {}) {
  auto read = [fixed, preset](const ConfigReader& r, const Method<Gen>& m) -> GenFactory<Gen> {
    for (std::string_view key : fixed) {
      if (r.table().contains(key)) r.fail(key, "is set by method '" + std::string(m.name) + "'");
    }
    typename Block::Config c = Block::Config::from_toml(r);
    if (preset) preset(c);
    return [c, name = std::string(m.name)](const std::string& format) {
      return make_for_format<ImplOf<Impl, Block>::template type, Gen>(format, name, Block(c));
    };
  };
  return {name, block, read};
}

template <class Block>
Method<CoordGenerator> coords(std::string_view name, std::string_view block,
                              const std::vector<std::string_view>& fixed = {},
                              std::function<void(typename Block::Config&)> preset = {}) {
  return method<CoordGenImpl, CoordGenerator, Block>(name, block, fixed, std::move(preset));
}

template <class Block>
Method<DerivGenerator> derivs(std::string_view name, std::string_view block,
                              const std::vector<std::string_view>& fixed = {},
                              std::function<void(typename Block::Config&)> preset = {}) {
  return method<DerivGenImpl, DerivGenerator, Block>(name, block, fixed, std::move(preset));
}

// The coordinate methods, in the order reports and studies list them.
const std::vector<Method<CoordGenerator>>& coord_methods() {
  using Hd = UvHeckbertDirect;
  using Inc = UvIncrementalAdder;
  using Ap = UvApproximation;
  using Tri = UvApproximationTriangle;
  static const std::vector<Method<CoordGenerator>> m = {
      coords<Hd>("heckbert", "uv_heckbert_direct", {"form"}),
      coords<Hd>("heckbert-rcp", "uv_heckbert_direct", {"form"},
                 [](Hd::Config& c) { c.form = Hd::Form::Reciprocal; }),
      coords<Inc>("incremental", "uv_incremental_adder", {"form"}),
      coords<Inc>("incremental-k4", "uv_incremental_adder", {"form"},
                  [](Inc::Config& c) { c.form = Inc::Form::KLane; }),
      coords<Inc>("incremental-bidir", "uv_incremental_adder", {"form"},
                  [](Inc::Config& c) { c.form = Inc::Form::Bidirectional; }),
      coords<Inc>("incremental-direct", "uv_incremental_adder", {"form"},
                  [](Inc::Config& c) { c.form = Inc::Form::DirectN; }),
      coords<Ap>("affine", "uv_approximation", {"order", "segment"},
                 [](Ap::Config& c) { c.order = Ap::Order::Affine; }),
      coords<Ap>("quadratic", "uv_approximation", {"order", "segment"},
                 [](Ap::Config& c) { c.order = Ap::Order::Quadratic; }),
      coords<Ap>("cubic", "uv_approximation", {"order", "segment"},
                 [](Ap::Config& c) { c.order = Ap::Order::Cubic; }),
      coords<Tri>("biquadratic", "uv_approximation_triangle", {"order"},
                  [](Tri::Config& c) { c.order = Tri::Order::Biquadratic; }),
      coords<Tri>("bicubic", "uv_approximation_triangle", {"order"},
                  [](Tri::Config& c) { c.order = Tri::Order::Bicubic; }),
      coords<UvConstantDepth>("constant-depth", "uv_constant_depth"),
      coords<Ap>("affine-16", "uv_approximation", {"order", "segment"},
                 [](Ap::Config& c) {
                   c.order = Ap::Order::Affine;
                   c.segment = 16;
                 }),
      coords<Ap>("quadratic-32", "uv_approximation", {"order", "segment"},
                 [](Ap::Config& c) {
                   c.order = Ap::Order::Quadratic;
                   c.segment = 32;
                 }),
  };
  return m;
}

const std::vector<Method<DerivGenerator>>& deriv_methods() {
  using Fd = DerivativesForwardDiff;
  static const std::vector<Method<DerivGenerator>> m = {
      derivs<DerivativesAnalytic>("analytic", "derivatives_analytic"),
      derivs<DerivativesQuad>("quad", "derivatives_quad"),
      derivs<Fd>("heckbert-fd", "derivatives_forward_diff", {"form"}),
      derivs<Fd>("accelerated-fd", "derivatives_forward_diff", {"form"},
                 [](Fd::Config& c) { c.form = Fd::Form::Accelerated; }),
      derivs<DerivativesIterative>("iterative", "derivatives_iterative"),
  };
  return m;
}

template <class Gen>
std::vector<std::string> names_of(const std::vector<Method<Gen>>& methods) {
  std::vector<std::string> n;
  n.reserve(methods.size());
  for (const auto& m : methods) n.emplace_back(m.name);
  return n;
}

template <class Gen>
const Method<Gen>& find_method(const std::vector<Method<Gen>>& methods, const std::string& name,
                               const char* what) {
  std::string known;
  for (const auto& m : methods) {
    if (m.name == name) return m;
    known += (known.empty() ? "" : ", ") + std::string(m.name);
  }
  throw InputError(std::string(what) + " '" + name + "'", "unknown (known: " + known + ")");
}

// A method's block with its defaults and `dp`, as a table holding only `datapath` gives it.
template <class Gen>
GenFactory<Gen> default_block(const Method<Gen>& m, Datapath dp) {
  const toml::table t{{"datapath", datapath_name(dp)}};
  return m.read(ConfigReader(t, "<defaults>", std::string(m.block)), m);
}

}  // namespace

const std::vector<std::string>& coord_format_names() {
  static const std::vector<std::string> n(kCoordFormats.keys.begin(), kCoordFormats.keys.end());
  return n;
}

const std::vector<std::string>& CoordGenerator::method_names() {
  static const std::vector<std::string> n = names_of(coord_methods());
  return n;
}

std::unique_ptr<CoordGenerator> CoordGenerator::create(const std::string& method,
                                                       const std::string& format, Datapath dp) {
  // The method is checked before the format.
  return default_block(find_method(coord_methods(), method, "coordinate method"), dp)(format);
}

const std::vector<std::string>& DerivGenerator::method_names() {
  static const std::vector<std::string> n = names_of(deriv_methods());
  return n;
}

std::unique_ptr<DerivGenerator> DerivGenerator::create(const std::string& method,
                                                       const std::string& format, Datapath dp) {
  return default_block(find_method(deriv_methods(), method, "derivative method"), dp)(format);
}

std::unique_ptr<EllipseGenerator> EllipseGenerator::create(const std::string& form,
                                                           const std::string& format, Datapath dp) {
  return make_for_format<EllipseGenImpl, EllipseGenerator>(format, form, dp);
}

CoordUnitConfig CoordUnitConfig::from_toml(const ConfigReader& r) {
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
  // The rest of the table is the coordinate block's: its own from_toml reads (and checks) it.
  const auto& cm = find_method(coord_methods(), c.coords, "coordinate method");
  c.coord_block = cm.read(
      r.for_block(r.block() + "[" + std::string(cm.block) + "]", {"method", "derivs", "format"}),
      cm);
  if (c.derivs != "none")
    c.deriv_block =
        default_block(find_method(deriv_methods(), c.derivs, "derivative method"), c.datapath);
  return c;
}

CoordUnit::CoordUnit(const CoordUnitConfig& c) : cfg_(c) {
  coords_ = c.coord_block ? c.coord_block(c.format)
                          : CoordGenerator::create(c.coords, c.format, c.datapath);
  if (c.derivs == "none") return;
  derivs_ = c.deriv_block ? c.deriv_block(c.format)
                          : DerivGenerator::create(c.derivs, c.format, c.datapath);
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
