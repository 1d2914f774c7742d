// Lockstep of the whole rectangle-scan rasteriser (rtl_model/rtl/rect_scan_raster.v: stepper,
// auxiliary outline memory and texturing control wired together) against RectScanRasterizer
// (blocks/raster/rect_scan/). Per triangle the host writes the C++ model's outline planes into
// the memory (OutlineMemory::draw) and loads the rectangle, the closing edges and the row-start
// edge values; a transaction is then one visited pixel (RectScanEvent): x, y, row start,
// texture, end of row and the comparator's hits, on the cycle the C++ model's fast clock puts
// it (rows started plus pixels visited after the load) and with the stepper's and control's
// op counts. Triangles: random ones on a 64×48 screen (both axes, every slope, both coverage
// conventions) and the bunny scene's faces along their constant-depth lines. CI runs 10^5
// pixel events; $TEXSIM_RTL_VECTORS sets another count.
#include <Vrect_scan_raster.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/raster/guard_band_clipper.h"
#include "blocks/raster/rect_scan/coordinate_counters.h"
#include "blocks/raster/rect_scan/outline_comparator.h"
#include "blocks/raster/rect_scan/rect_scan_rasterizer.h"
#include "blocks/raster/rect_scan/row_start_counter.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/scene/scene.h"
#include "rtl_model/params/rtl_params.h"
#include "testbench/rtl/lockstep.h"

namespace texsim::rtl {
namespace {

using Model = Vrect_scan_raster;

struct Triangle {
  ScreenVertex v[3];
  RowLine line;
  Scissor sc;
  RectScanCoverage coverage;
};

constexpr int32_t kCols = 1 << rtl_params::kRectScanMemMajorBits;
constexpr int32_t kRows = 1 << rtl_params::kRectScanMemMinorBits;

class RasterBench {
 public:
  RasterBench(int64_t perturb, size_t perturb_word, uint64_t perturb_at)
      : sb_("rect_scan_raster", 0),
        h_("rect_scan_raster"),
        perturb_(perturb),
        word_(perturb_word),
        at_(perturb_at) {
    h_.reset();
    first_ops_ = RowStartCounter().ops_per_item();
    first_ops_.cmp += TexturingControl().ops_per_item().cmp;
    step_ops_ = LineStepper().ops_per_item() + CoordinateCounters().ops_per_item();
    step_ops_.cmp += TexturingControl().ops_per_item().cmp + OutlineComparator().ops_per_item().cmp;
  }
  // Runs one triangle; false when it does not fit the memory window (not run).
  bool run(const Triangle& t);
  Scoreboard finish() {
    for (int i = 0; i < (1 << 16) && sb_.pending() > 0; ++i) clock();
    sb_.finish();
    return sb_;
  }
  uint64_t issued() const { return issued_; }
  uint64_t textured() const { return textured_; }

 private:
  void clock() {
    h_.step();
    Model& top = h_.top();
    if (top.out_valid) {
      sb_.observe(h_.cycle(),
                  {static_cast<int16_t>(top.out_x), static_cast<int16_t>(top.out_y),
                   top.out_row_start, top.out_texture, top.out_end_of_row, top.out_hits},
                  h_.ops());
    }
  }
  void write_memory(const RectScanResult& r, const EdgeRasterizer::Setup& st);
  void load(const RectScanResult& r, const EdgeRasterizer::Setup& st, const Triangle& t);

  Scoreboard sb_;
  RtlHarness<Model> h_;
  int64_t perturb_;
  size_t word_;
  uint64_t at_;
  OpCounts ops_, first_ops_, step_ops_;
  uint64_t issued_ = 0, textured_ = 0;
  std::vector<std::pair<int32_t, int32_t>> marked_;  // memory words written non-zero
};

void RasterBench::write_memory(const RectScanResult& r, const EdgeRasterizer::Setup& st) {
  Model& top = h_.top();
  const RectScanFrame& f = r.frame;
  auto write = [&](int32_t cm, int32_t rm, uint8_t w) {
    top.mem_we = 1;
    top.mem_major = static_cast<uint8_t>(cm);
    top.mem_minor = static_cast<uint16_t>(rm);
    top.mem_wdata = w;
    clock();
    top.mem_we = 0;
  };
  for (const auto& [cm, rm] : marked_) write(cm, rm, 0);  // the last triangle's marks
  marked_.clear();
  OutlineMemory mem(r.line, f.major0, f.major1, f.mem_lo, f.mem_hi);
  mem.draw(st);
  for (int32_t minor = f.mem_lo; minor <= f.mem_hi; ++minor) {
    for (int32_t major = f.major0; major <= f.major1; ++major) {
      const uint8_t w = mem.read(major, minor);
      if (w == 0) continue;
      marked_.emplace_back(major - f.major0, minor - f.mem_lo);
      write(major - f.major0, minor - f.mem_lo, w);
    }
  }
}

void RasterBench::load(const RectScanResult& r, const EdgeRasterizer::Setup& st,
                       const Triangle& t) {
  Model& top = h_.top();
  const RectScanFrame& f = r.frame;
  TexturingControl bkt;
  bkt.load(st, r.line, f.box_lo, f.box_hi, t.coverage);
  top.x_major = r.line.x_major;
  top.neg = r.line.sign < 0;
  top.delta_minor = static_cast<uint16_t>(r.line.delta_minor);
  top.major0 = static_cast<uint16_t>(f.major0);
  top.major1 = static_cast<uint16_t>(f.major1);
  top.t_lo = static_cast<uint16_t>(f.t_lo);
  top.t_hi = static_cast<uint16_t>(f.t_hi);
  top.mem_lo = static_cast<uint16_t>(f.mem_lo);
  top.mem_hi = static_cast<uint16_t>(f.mem_hi);
  top.minor_lo = static_cast<uint16_t>(f.box_lo);
  top.minor_hi = static_cast<uint16_t>(f.box_hi);
  top.closing = static_cast<uint8_t>(bkt.closing(0) | bkt.closing(1) << 1 | bkt.closing(2) << 2);
  top.outline = t.coverage == RectScanCoverage::Outline;
  // Edge values with their biases at the first row's start, and their change per row.
  const int32_t x = r.line.x_major ? f.major0 : f.t_lo, y = r.line.x_major ? f.t_lo : f.major0;
  uint64_t ev[3], row[3];
  for (int e = 0; e < 3; ++e) {
    ev[e] = static_cast<uint64_t>(EdgeRasterizer::edge_value(st, e, x, y) + st.bias[e]);
    const int64_t d = r.line.x_major ? st.dx[e] : -st.dy[e];
    row[e] = static_cast<uint64_t>(d * (int64_t{1} << st.bits));
  }
  top.ev0 = ev[0];
  top.ev1 = ev[1];
  top.ev2 = ev[2];
  top.ev_row0 = row[0];
  top.ev_row1 = row[1];
  top.ev_row2 = row[2];
}

bool RasterBench::run(const Triangle& t) {
  const RectScanRasterizer rs = [&] {
    RectScanRasterizer::Config c;
    c.coverage = t.coverage;
    return RectScanRasterizer(c);
  }();
  std::vector<RectScanEvent> events;
  const RectScanEventSink sink = [&](const RectScanEvent& e) { events.push_back(e); };
  const RectScanResult r = rs.rasterize(t.v, t.line, t.sc, &sink);
  if (events.empty()) return true;
  const RectScanFrame& f = r.frame;
  if (f.major1 - f.major0 >= kCols || f.mem_hi - f.mem_lo >= kRows) return false;
  const EdgeRasterizer::Setup st = [&] {
    EdgeRasterizer::Config ec;
    ec.subpixel_bits = rs.config().subpixel_bits;
    return EdgeRasterizer(ec).setup(t.v, t.sc);
  }();
  Model& top = h_.top();
  while (!top.in_ready) clock();
  write_memory(r, st);
  load(r, st, t);
  const uint64_t cycle0 = h_.cycle();
  uint64_t fast = 0;
  for (const RectScanEvent& e : events) {
    fast += e.row_start ? 2 : 1;  // a row's start cycle, then its pixels
    ops_ += e.row_start ? first_ops_ : step_ops_;
    OutWords w{e.x, e.y, e.row_start, e.texture, e.end_of_row, e.hits};
    if (perturb_ != 0 && issued_ == at_) w[word_] += perturb_;
    std::ostringstream in;
    in << "pixel (" << e.x << "," << e.y << ") rows " << f.t_lo << ".." << f.t_hi;
    sb_.expect(in.str(), cycle0 + fast, w, ops_);
    ++issued_;
    textured_ += e.texture;
  }
  top.in_valid = 1;
  clock();
  top.in_valid = 0;
  return true;
}

const Scissor kScreen{0, 0, 64, 48};

Triangle random_triangle(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> ux(-4, 68), uy(-4, 52), uk(-1, 1);
  const LineStepper ls(rtl_params::kRectScanLine);
  Triangle t{{{ux(rng), uy(rng), 1}, {ux(rng), uy(rng), 1}, {ux(rng), uy(rng), 1}},
             ls.line_for_slope(rng() % 2 == 0, uk(rng)),
             kScreen,
             rng() % 2 == 0 ? RectScanCoverage::TopLeft : RectScanCoverage::Outline};
  return t;
}

// The bunny scene's faces, each along its constant-depth lines (as a scene run draws them).
std::vector<Triangle> scene_triangles(size_t most) {
  const Scene s = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/bunny.toml");
  const Scissor sc{0, 0, s.width, s.height};
  const RectScanRasterizer rs;
  std::vector<Triangle> out;
  for (const ScenePrimitive& p : s.primitives) {
    const PlaneProjection map(s, p);
    if (map.culled()) continue;
    std::vector<ScreenVertex> poly;
    for (const glm::dvec2& v : map.screen_polygon()) poly.push_back({v.x, v.y, 1});
    if (poly.size() < 3) continue;
    const ProjectiveMap m = map.texel_map(1, 1);
    const RowLine line =
        rs.line_for_denominator(static_cast<double>(m.G), static_cast<double>(m.H));
    const std::vector<ScreenVertex> q = within_guard_band(poly, sc, 8);
    for (size_t i = 1; i + 1 < q.size() && out.size() < most; ++i)
      out.push_back({{q[0], q[i], q[i + 1]}, line, sc, RectScanCoverage::TopLeft});
    if (out.size() >= most) break;
  }
  return out;
}

Scoreboard run_raster(uint64_t pixels, size_t scene_tris, int64_t perturb = 0, size_t word = 0,
                      uint64_t at = 0) {
  RasterBench b(perturb, word, at);
  std::mt19937_64 rng(2802);
  uint64_t skipped = 0, triangles = 0;
  for (const Triangle& t : scene_triangles(scene_tris)) {
    skipped += b.run(t) ? 0 : 1;
    ++triangles;
  }
  const uint64_t scene_pixels = b.issued();
  while (b.issued() < pixels) {
    skipped += b.run(random_triangle(rng)) ? 0 : 1;
    ++triangles;
  }
  Scoreboard sb = b.finish();
  std::cout << sb.summary() << " (" << triangles << " triangles, " << skipped
            << " too large for the memory window; " << scene_pixels << " pixel events from "
            << scene_tris << " bunny faces; " << b.textured() << " textured)\n"
            << sb.report();
  EXPECT_LT(skipped * 20, triangles);
  return sb;
}

TEST(RtlLockstep, RectScanRasterMatchesCppPerPixelEvent) {
  const Scoreboard sb = run_raster(lockstep_vectors(), 3000);
  EXPECT_EQ(sb.mismatches(), 0u) << sb.report();
  EXPECT_GE(sb.compared(), lockstep_vectors());
}

// Negative controls: one LSB of one pixel's x, and one event's texture decision.
TEST(RtlLockstep, RectScanRasterScoreboardCatchesOneLsbAndOneEvent) {
  const Scoreboard a = run_raster(20000, 200, 1, 0, 12345);
  EXPECT_EQ(a.mismatches(), 1u);
  EXPECT_NE(a.report().find("transaction 12345 "), std::string::npos) << a.report();
  const Scoreboard b = run_raster(20000, 200, 1, 3, 15000);
  EXPECT_EQ(b.mismatches(), 1u);
  EXPECT_NE(b.report().find("transaction 15000 "), std::string::npos) << b.report();
}

}  // namespace
}  // namespace texsim::rtl
