#include "blocks/raster/rect_scan/rect_scan_rasterizer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/raster/rect_scan/coordinate_counters.h"
#include "blocks/raster/rect_scan/outline_comparator.h"
#include "blocks/raster/rect_scan/row_start_counter.h"

namespace texsim {

static_assert(Block<RectScanRasterizer>);

namespace {

using Frame = RectScanFrame;

Frame make_frame(const EdgeRasterizer::Setup& st, const RowLine& line) {
  Frame f;
  f.major0 = line.x_major ? st.x0 : st.y0;
  f.major1 = line.x_major ? st.x1 : st.y1;
  f.box_lo = line.x_major ? st.y0 : st.x0;
  f.box_hi = line.x_major ? st.y1 : st.x1;
  // Row index of a point: minor - k'·(major - major0); inside pixels are within 1/2 of the
  // vertices' range because |d(n) - k'·n| <= 1/2 (the rectangle's top row, the seed's r).
  const double k = line.slope(), s = std::ldexp(1.0, -st.bits);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i < 3; ++i) {
    const double major = static_cast<double>(line.x_major ? st.vx[i] : st.vy[i]) * s;
    const double minor = static_cast<double>(line.x_major ? st.vy[i] : st.vx[i]) * s;
    const double t = minor - k * (major - f.major0);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  const auto d_end = static_cast<int32_t>(line.offset(f.major1 - f.major0));
  const int32_t d_min = std::min(0, d_end), d_max = std::max(0, d_end);
  // Only rows that meet the box (a triangle far larger than the scissor stays bounded).
  f.t_lo = std::max(static_cast<int32_t>(std::floor(lo - 0.5)), f.box_lo - d_max);
  f.t_hi = std::min(static_cast<int32_t>(std::ceil(hi + 0.5)), f.box_hi - d_min);
  f.mem_lo = f.t_lo + d_min;
  f.mem_hi = f.t_hi + d_max;
  return f;
}

// Records one textured pixel in the result's runs and pixel list.
void emit(RectScanResult& res, const RowLine& line, int32_t t, int32_t major, int32_t minor) {
  const int32_t x = line.x_major ? major : minor, y = line.x_major ? minor : major;
  res.pixels.emplace_back(x, y);
  if (!res.runs.empty() && res.runs.back().t == t &&
      res.runs.back().major0 + res.runs.back().n == major) {
    ++res.runs.back().n;
    return;
  }
  const double h = t - line.slope() * res.major_start;
  res.runs.push_back({t, major, 1, h});
}

// A row's departure from the exact outline convention, put down to its first cause.
void count_hazards(const ParityControl& pc, uint64_t extra, uint64_t missed, ParityHazards& h) {
  h.extra_pixels += extra;
  h.missed_pixels += missed;
  if (extra + missed == 0) return;
  if (pc.saw_vertex_run()) {
    ++h.vertex_rows;
  } else if (pc.saw_touching_run()) {
    ++h.touching_rows;
  } else if (pc.saw_long_run()) {
    ++h.run_rows;
  } else {
    ++h.missed_crossing_rows;
  }
}

}  // namespace

RectScanRasterizer::Config RectScanRasterizer::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown(
      {"subpixel_bits", "slope_bits", "fast_clock_mhz", "memory_clock_mhz", "coverage"});
  Config c;
  c.subpixel_bits = static_cast<int>(
      r.get_int("subpixel_bits", c.subpixel_bits, 0, EdgeRasterizer::kMaxSubpixelBits));
  c.slope_bits =
      static_cast<int>(r.get_int("slope_bits", c.slope_bits, 1, LineStepper::kMaxSlopeBits));
  c.fast_clock_mhz = r.get_double("fast_clock_mhz", c.fast_clock_mhz);
  c.memory_clock_mhz = r.get_double("memory_clock_mhz", c.memory_clock_mhz);
  if (!(c.fast_clock_mhz > 0) || c.fast_clock_mhz > TechTable::kMaxClockMhz) {
    r.fail("fast_clock_mhz", "must be in (0, 1e5]");
  }
  if (!(c.memory_clock_mhz > 0) || c.memory_clock_mhz > TechTable::kMaxClockMhz) {
    r.fail("memory_clock_mhz", "must be in (0, 1e5]");
  }
  c.coverage = static_cast<RectScanCoverage>(
      r.get_choice("coverage", 0, {"top_left", "outline", "outline_parity"}));
  return c;
}

RowLine RectScanRasterizer::line_for_denominator(double g, double h) const {
  LineStepper::Config lc;
  lc.slope_bits = cfg_.slope_bits;
  return LineStepper(lc).line_for_denominator(g, h);
}

RowLine RectScanRasterizer::line_for_slope(bool x_major, double k) const {
  LineStepper::Config lc;
  lc.slope_bits = cfg_.slope_bits;
  return LineStepper(lc).line_for_slope(x_major, k);
}

RectScanResult RectScanRasterizer::rasterize(const ScreenVertex v[3], const RowLine& line,
                                             const Scissor& sc,
                                             const RectScanEventSink* events) const {
  RectScanResult res;
  res.line = line;
  EdgeRasterizer::Config ec;
  ec.subpixel_bits = cfg_.subpixel_bits;
  const EdgeRasterizer::Setup st = EdgeRasterizer(ec).setup(v, sc);
  res.reject = st.reject;
  if (!st.ok() || st.box_empty()) return res;
  // Preparation: the rectangle, the outline in the auxiliary memory, the registers.
  const Frame f = make_frame(st, line);
  res.frame = f;
  res.major_start = f.major0;
  OutlineMemory mem(line, f.major0, f.major1, f.mem_lo, f.mem_hi);
  RectScanStats& s = res.stats;
  // The per-edge planes; with the parity rule they are only the oracle of its hazards.
  s.outline_marks = mem.draw(st);
  s.memory_words = mem.words();
  LineStepper::Config lc;
  lc.slope_bits = cfg_.slope_bits;
  LineStepper li(lc);
  RowStartCounter start;
  CoordinateCounters counters(line.x_major);
  OutlineComparator bp;
  bp.set_foreground(7);
  TexturingControl bkt;
  // With the parity rule БКТ's per-edge flags (top-left) are the oracle of its hazards.
  bkt.load(
      st, line, f.box_lo, f.box_hi,
      cfg_.coverage == RectScanCoverage::OutlineParity ? RectScanCoverage::TopLeft : cfg_.coverage);
  start.load(f.major0, f.t_lo);
  const bool parity = cfg_.coverage == RectScanCoverage::OutlineParity;
  SeedOutlineMemory seed;
  ParityControl pc;
  if (parity) s.outline_marks = seed.draw(st, line, f.major0);
  // Rows until БКТ's end of triangle (the row index passes the last row of the rectangle).
  for (; start.minor() <= f.t_hi; start.next_row()) {
    const int32_t t = start.minor();
    counters.load(start.major0(), t);
    li.start_row(line);
    ++s.rows_scanned;
    const uint64_t textured_before = s.pixels_textured;
    TexturingControl::Decision d = bkt.start_row(counters.major(), counters.minor());
    if (parity) pc.start_row();
    uint64_t extra = 0, missed = 0;
    uint8_t hits = 0;
    for (;;) {
      ++s.pixels_visited;
      bool texture = d.texture, end = d.end_of_row;
      if (parity) {
        const int32_t x = line.x_major ? counters.major() : counters.minor();
        const int32_t y = line.x_major ? counters.minor() : counters.major();
        const uint8_t word = seed.read(x, y);
        const bool in_box = counters.minor() >= f.box_lo && counters.minor() <= f.box_hi;
        texture = pc.on_pixel(word, seed.is_end_vertex(x, y), seed.is_vertex(x, y)) && in_box;
        end = pc.end_of_row();
        // What the seed means: the triangle's inside (top-left) and the outline drawn.
        const bool meant = d.texture || (word != 0 && in_box);
        extra += texture && !meant;
        missed += meant && !texture;
      }
      if (events) {
        const int32_t x = line.x_major ? counters.major() : counters.minor();
        const int32_t y = line.x_major ? counters.minor() : counters.major();
        (*events)({x, y, counters.major() == f.major0, texture, end, hits});
      }
      if (texture) {
        ++s.pixels_textured;
        emit(res, line, t, counters.major(), counters.minor());
      } else {
        ++s.background_pixels;
      }
      if (end || counters.major() >= f.major1) break;
      counters.step(li.step(line));
      hits = bp.compare(mem.read(counters.major(), counters.minor()));
      d = bkt.on_pixel(hits, counters.major(), counters.minor());
    }
    s.rows_textured += s.pixels_textured > textured_before;
    if (parity) {
      // The oracle finishes the row on its own (copies: nothing of it is counted as scanned),
      // for the pixels the parity rule's early end of row missed.
      LineStepper li2 = li;
      CoordinateCounters c2 = counters;
      TexturingControl b2 = bkt;
      for (TexturingControl::Decision d2 = d; c2.major() < f.major1;) {
        c2.step(li2.step(line));
        d2 = b2.on_pixel(bp.planes(mem.peek(c2.major(), c2.minor())), c2.major(), c2.minor());
        const int32_t x = line.x_major ? c2.major() : c2.minor();
        const int32_t y = line.x_major ? c2.minor() : c2.major();
        missed += d2.texture ||
                  (seed.peek(x, y) != 0 && c2.minor() >= f.box_lo && c2.minor() <= f.box_hi);
      }
      count_hazards(pc, extra, missed, s.hazards);
    }
  }
  if (parity) s.memory_words = seed.words();
  s.steps = li.steps();
  s.minor_steps = li.minor_steps();
  s.memory_reads = parity ? seed.reads() : mem.reads();
  s.comparator_hits = bp.hits();
  s.crossings = parity ? pc.crossings() : bkt.crossings();
  s.vertex_hits = bkt.vertex_hits();
  s.fast_cycles = s.background_pixels + s.rows_scanned;
  s.memory_cycles = s.pixels_textured;
  s.prep_cycles = s.outline_marks;
  s.time_ns = 1e3 * (static_cast<double>(s.fast_cycles) / cfg_.fast_clock_mhz +
                     static_cast<double>(s.memory_cycles + s.prep_cycles) / cfg_.memory_clock_mhz);
  return res;
}

OpCounts RectScanRasterizer::ops_per_item() const {
  return LineStepper().ops_per_item() + CoordinateCounters().ops_per_item() +
         OutlineComparator().ops_per_item() + TexturingControl().ops_per_item();
}

OpCounts RectScanRasterizer::row_ops() const {
  return RowStartCounter().ops_per_item() + TexturingControl().row_ops();
}

OpCounts RectScanRasterizer::triangle_setup_ops() const {
  // The edge set-up of EdgeRasterizer (snapping, orientation, box), the slope quantisation,
  // the rectangle's rows from the vertices (3 × (mul, add), min/max) and its window.
  OpCounts o = EdgeRasterizer().triangle_setup_ops() + LineStepper().setup_ops();
  o.mul += 3;
  o.add += 3 + 4;
  o.cmp += 4 + 4;
  return o;
}

TimingSpec RectScanRasterizer::timing(const TechTable& t) const {
  // Along one step: the counters' add, the memory read, the comparator and БКТ's decision.
  OpCounts path;
  path.add = 1;
  path.mem = 1;
  path.cmp = 2;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial, 1,
                       row_ops() + triangle_setup_ops());
}

std::string RectScanRasterizer::arithmetic() const {
  return "integer: vertices on 2^-" + std::to_string(cfg_.subpixel_bits) +
         " pixel, int64 edge values (preparation and row starts), Bresenham rows with ΔX = 2^" +
         std::to_string(cfg_.slope_bits) + "; clocks " + std::to_string(cfg_.fast_clock_mhz) +
         " MHz (background) and " + std::to_string(cfg_.memory_clock_mhz) + " MHz (memory)";
}

}  // namespace texsim
