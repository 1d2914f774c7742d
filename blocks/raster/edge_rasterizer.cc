#include "blocks/raster/edge_rasterizer.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<EdgeRasterizer>);

namespace {

constexpr int64_t kLimit = int64_t{1} << EdgeRasterizer::kCoordBits;

// floor(a / 2^s) and ceil(a / 2^s) for any sign (arithmetic shift rounds towards -inf).
int64_t floor_shift(int64_t a, int s) { return a >> s; }
int64_t ceil_shift(int64_t a, int s) { return -((-a) >> s); }

// Snaps c·2^bits to the nearest integer (ties to even); false if beyond the guard band.
bool snap(double c, int bits, int64_t& out) {
  const double scaled = std::nearbyint(std::ldexp(c, bits));
  if (!(std::fabs(scaled) < static_cast<double>(kLimit))) return false;
  out = static_cast<int64_t>(scaled);
  return true;
}

}  // namespace

const char* reject_reason(RasterReject r) {
  switch (r) {
    case RasterReject::None:
      return "rasterised";
    case RasterReject::NotFinite:
      return "a vertex coordinate or w is not finite";
    case RasterReject::NonPositiveW:
      return "a vertex has w <= 0 (behind the eye; clip first)";
    case RasterReject::OutOfRange:
      return "a vertex or the scissor is beyond the guard band (clip first)";
    case RasterReject::Degenerate:
      return "zero area after snapping";
  }
  return "?";
}

EdgeRasterizer::Config EdgeRasterizer::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"subpixel_bits"});
  Config c;
  c.subpixel_bits =
      static_cast<int>(r.get_int("subpixel_bits", c.subpixel_bits, 0, kMaxSubpixelBits));
  return c;
}

EdgeRasterizer::Setup EdgeRasterizer::setup(const ScreenVertex v[3], const Scissor& sc) const {
  Setup st;
  st.bits = cfg_.subpixel_bits;
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(v[i].x) || !std::isfinite(v[i].y) || !std::isfinite(v[i].w)) {
      st.reject = RasterReject::NotFinite;
      return st;
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (!(v[i].w > 0)) {
      st.reject = RasterReject::NonPositiveW;
      return st;
    }
  }
  std::array<int64_t, 3> x{}, y{};
  for (int i = 0; i < 3; ++i) {
    if (!snap(v[i].x, st.bits, x[i]) || !snap(v[i].y, st.bits, y[i])) {
      st.reject = RasterReject::OutOfRange;
      return st;
    }
  }
  for (int32_t c : {sc.x0, sc.y0, sc.x1, sc.y1}) {
    if (!(std::abs(static_cast<int64_t>(c)) << st.bits < kLimit)) {
      st.reject = RasterReject::OutOfRange;
      return st;
    }
  }
  const int64_t area2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
  if (area2 == 0) return st;  // Degenerate
  if (area2 < 0) st.perm = {0, 2, 1};
  st.area2 = area2 < 0 ? -area2 : area2;
  for (int i = 0; i < 3; ++i) {
    st.vx[i] = x[st.perm[i]];
    st.vy[i] = y[st.perm[i]];
    st.inv_w[i] = 1.0 / v[st.perm[i]].w;
  }
  for (int e = 0; e < 3; ++e) {
    const int a = (e + 1) % 3, b = (e + 2) % 3;
    st.dx[e] = st.vx[b] - st.vx[a];
    st.dy[e] = st.vy[b] - st.vy[a];
    // Positive orientation with y down: a top edge runs to +x, a left edge runs up.
    const bool top_left = st.dy[e] < 0 || (st.dy[e] == 0 && st.dx[e] > 0);
    st.bias[e] = top_left ? 0 : -1;
  }
  const auto [xmin, xmax] = std::minmax({x[0], x[1], x[2]});
  const auto [ymin, ymax] = std::minmax({y[0], y[1], y[2]});
  st.x0 = static_cast<int32_t>(std::max<int64_t>(ceil_shift(xmin, st.bits), sc.x0));
  st.x1 = static_cast<int32_t>(std::min<int64_t>(floor_shift(xmax, st.bits), sc.x1 - int64_t{1}));
  st.y0 = static_cast<int32_t>(std::max<int64_t>(ceil_shift(ymin, st.bits), sc.y0));
  st.y1 = static_cast<int32_t>(std::min<int64_t>(floor_shift(ymax, st.bits), sc.y1 - int64_t{1}));
  st.reject = RasterReject::None;
  return st;
}

int64_t EdgeRasterizer::edge_value(const Setup& st, int e, int32_t x, int32_t y) {
  const int a = (e + 1) % 3;
  const int64_t px = static_cast<int64_t>(x) * (int64_t{1} << st.bits);
  const int64_t py = static_cast<int64_t>(y) * (int64_t{1} << st.bits);
  return st.dx[e] * (py - st.vy[a]) - st.dy[e] * (px - st.vx[a]);
}

bool EdgeRasterizer::covers(const Setup& st, int32_t x, int32_t y) {
  if (!st.ok()) return false;
  for (int e = 0; e < 3; ++e) {
    if (!inside(st, e, edge_value(st, e, x, y))) return false;
  }
  return true;
}

std::vector<RowSpan> EdgeRasterizer::rasterize(const ScreenVertex v[3], const Scissor& sc,
                                               EdgeRasterStats* stats) const {
  std::vector<RowSpan> rows;
  const Setup st = setup(v, sc);
  if (stats) {
    ++stats->triangles;
    if (!st.ok()) ++stats->rejected;
  }
  scan(
      st,
      [&](int32_t x, int32_t y, const std::array<int64_t, 3>&) {
        if (!rows.empty() && rows.back().y == y && rows.back().x0 + rows.back().n == x) {
          ++rows.back().n;
        } else {
          rows.push_back({x, y, 1});
        }
      },
      stats);
  return rows;
}

std::array<double, 3> EdgeRasterizer::perspective_weights(const Setup& st,
                                                          const std::array<int64_t, 3>& e) {
  std::array<double, 3> b{};
  for (int i = 0; i < 3; ++i) b[i] = static_cast<double>(e[i]) * st.inv_w[i];
  const double r = 1.0 / (b[0] + b[1] + b[2]);
  std::array<double, 3> w{};
  for (int i = 0; i < 3; ++i) w[st.perm[i]] = b[i] * r;
  return w;
}

OpCounts EdgeRasterizer::ops_per_item() const {
  OpCounts o;
  o.add = 3;  // E_e += step_x
  o.cmp = 3;  // sign tests with the top-left bias
  return o;
}

OpCounts EdgeRasterizer::row_ops() const {
  OpCounts o;
  o.add = 3;
  return o;
}

OpCounts EdgeRasterizer::triangle_setup_ops() const {
  // Snap (round) six coordinates; six edge deltas; area: 2 mul 1 add; first value of each
  // edge: two differences, 2 mul, one subtraction; guard band 6, orientation 1, top-left 3,
  // box min/max and scissor 8 compares; 1/w of the three vertices.
  OpCounts o;
  o.add = 6 + 6 + 1 + 3 * 3;
  o.mul = 2 + 3 * 2;
  o.cmp = 6 + 1 + 3 + 8;
  o.rcp = 3;
  return o;
}

OpCounts EdgeRasterizer::interpolation_ops() const {
  OpCounts o;
  o.mul = 3 + 3;  // b_i = E_i·(1/w_i), weight_i = b_i·r
  o.add = 2;      // Σ b
  o.rcp = 1;      // r = 1/Σ b
  return o;
}

TimingSpec EdgeRasterizer::timing(const TechTable& t) const {
  OpCounts path;
  path.add = 1;
  path.cmp = 1;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial, 1,
                       row_ops() + triangle_setup_ops());
}

std::string EdgeRasterizer::arithmetic() const {
  return "vertices snapped to " + std::to_string(cfg_.subpixel_bits) +
         " sub-pixel bits (round to nearest even), edge functions exact in int64 (±2^30 guard "
         "band), perspective-correct weights in double";
}

}  // namespace texsim
