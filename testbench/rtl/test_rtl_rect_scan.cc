// Lockstep of the rectangle-scan address generator (rtl_model/rtl/rect_scan_stepper.v) against
// the C++ elements it is made of, driven in RectScanRasterizer's order with no texturing-control
// early row end: RowStartCounter, LineStepper and CoordinateCounters
// (blocks/raster/rect_scan/). A transaction is one visited pixel: its x, y and row-start flag,
// the cycle it is on the outputs (load + the C++ model's fast-clock cycles: rows started plus
// pixels visited) and the op counters (the row-start counter's increment on a row's first pixel,
// one stepper and counter step on every other). Directed rectangles cover empty and one-pixel
// rectangles, ΔY = 0 and ΔY = ΔX, both signs and axes, and coordinates near the limits.
#include <Vrect_scan_stepper.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/raster/rect_scan/coordinate_counters.h"
#include "blocks/raster/rect_scan/row_start_counter.h"
#include "rtl_model/params/rtl_params.h"
#include "testbench/rtl/lockstep.h"

namespace texsim::rtl {
namespace {

using Model = Vrect_scan_stepper;

struct Rect {
  RowLine line;
  int32_t major0, major1, t_lo, t_hi;
  std::string text() const {
    std::ostringstream o;
    o << (line.x_major ? "x" : "y") << "-major sign " << line.sign << " dY " << line.delta_minor
      << " major " << major0 << ".." << major1 << " rows " << t_lo << ".." << t_hi;
    return o.str();
  }
};

RowLine make_line(bool x_major, int sign, int64_t dy) {
  RowLine l;
  l.x_major = x_major;
  l.sign = sign;
  l.delta_major = int64_t{1} << rtl_params::kRectScanLine.slope_bits;
  l.delta_minor = dy;
  return l;
}

std::vector<Rect> directed_rects() {
  const int64_t dx = int64_t{1} << rtl_params::kRectScanLine.slope_bits;
  std::vector<Rect> r;
  r.push_back({make_line(true, 1, 0), 0, 9, 0, 2});
  r.push_back({make_line(true, 1, dx), 0, 9, 0, 2});
  r.push_back({make_line(true, -1, dx), -5, 5, -3, 3});
  r.push_back({make_line(false, -1, dx / 3), 10, 30, 5, 7});
  r.push_back({make_line(false, 1, dx / 2), 10, 30, 5, 7});  // ties: ΔX/2 + n·ΔY hits ΔX exactly
  r.push_back({make_line(true, 1, 1), 4, 4, 8, 8});          // one pixel
  r.push_back({make_line(true, 1, 7), 4, 2, 8, 9});          // major1 < major0: one per row
  r.push_back({make_line(true, 1, 7), 0, 5, 3, 2});          // no rows
  // Coordinates at the limits of the 16-bit counters (the scan stays inside them).
  r.push_back({make_line(true, 1, dx - 1), 32700, 32767, 32690, 32700});
  r.push_back({make_line(false, -1, dx - 1), -32768, -32700, -32700, -32690});
  r.push_back({make_line(true, 1, 0), 0, 5, 32760, 32767});  // the last row counter value
  return r;
}

Rect random_rect(std::mt19937_64& rng) {
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  const int64_t dx = int64_t{1} << rtl_params::kRectScanLine.slope_bits;
  const auto m0 = static_cast<int32_t>(uni(-2000, 2000)),
             t0 = static_cast<int32_t>(uni(-2000, 2000));
  return {make_line(uni(0, 1) == 1, uni(0, 1) == 1 ? 1 : -1, uni(0, dx)), m0,
          m0 + static_cast<int32_t>(uni(0, 40)), t0, t0 + static_cast<int32_t>(uni(0, 12))};
}

// The C++ elements in RectScanRasterizer's order; calls visit(x, y, row_start, fast, ops).
template <class Visit>
void cpp_scan(const Rect& r, OpCounts& ops, Visit visit) {
  LineStepper li(rtl_params::kRectScanLine);
  RowStartCounter start;
  CoordinateCounters counters(r.line.x_major);
  uint64_t fast = 0;
  start.load(r.major0, r.t_lo);
  for (; start.minor() <= r.t_hi; start.next_row()) {
    counters.load(start.major0(), start.minor());
    li.start_row(r.line);
    ++fast;
    ops += start.ops_per_item();
    bool first = true;
    for (;;) {
      ++fast;
      visit(counters.x(), counters.y(), first, fast, ops);
      if (counters.major() >= r.major1) break;
      counters.step(li.step(r.line));
      ops += li.ops_per_item() + counters.ops_per_item();
      first = false;
    }
    if (start.minor() == INT16_MAX) break;  // the RTL's row counter is 16 bits
  }
}

Scoreboard run_rect(uint64_t pixels, int64_t perturb = 0, uint64_t perturb_at = 0) {
  Scoreboard sb("rect_scan_stepper", 0);
  RtlHarness<Model> h("rect_scan_stepper");
  h.reset();
  Model& top = h.top();
  auto clock = [&] {
    h.step();
    if (top.out_valid) {
      sb.observe(
          h.cycle(),
          {static_cast<int16_t>(top.out_x), static_cast<int16_t>(top.out_y), top.out_row_start},
          h.ops());
    }
  };
  std::mt19937_64 rng(99);
  std::bernoulli_distribution idle(0.2);
  const std::vector<Rect> directed = directed_rects();
  OpCounts ops;
  uint64_t issued = 0;
  for (uint64_t i = 0; issued < pixels; ++i) {
    const Rect r = i < directed.size() ? directed[i] : random_rect(rng);
    while (idle(rng)) clock();
    while (!top.in_ready) clock();
    const uint64_t load = h.cycle();
    cpp_scan(r, ops, [&](int32_t x, int32_t y, bool first, uint64_t fast, const OpCounts& o) {
      OutWords w{x, y, first ? 1 : 0};
      if (perturb != 0 && issued == perturb_at) w[0] += perturb;
      sb.expect(r.text(), load + fast, w, o);
      ++issued;
    });
    top.x_major = r.line.x_major;
    top.neg = r.line.sign < 0;
    top.delta_minor = static_cast<uint16_t>(r.line.delta_minor);
    top.major0 = static_cast<uint16_t>(r.major0);
    top.major1 = static_cast<uint16_t>(r.major1);
    top.t_lo = static_cast<uint16_t>(r.t_lo);
    top.t_hi = static_cast<uint16_t>(r.t_hi);
    top.in_valid = 1;
    clock();
    top.in_valid = 0;
  }
  for (int i = 0; i < (1 << 16) && sb.pending() > 0; ++i) clock();
  sb.finish();
  std::cout << sb.summary() << "\n" << sb.report();
  return sb;
}

static_assert(rtl_params::kRectScanCoordBits == 16 && rtl_params::kRectScanLine.slope_bits < 16);

TEST(RtlLockstep, RectScanStepperMatchesCppBitForBit) {
  const Scoreboard sb = run_rect(lockstep_vectors());
  EXPECT_EQ(sb.mismatches(), 0u) << sb.report();
  EXPECT_GE(sb.compared(), lockstep_vectors());
}

TEST(RtlLockstep, RectScanScoreboardCatchesOneLsb) {
  const Scoreboard sb = run_rect(5000, 1, 4000);
  EXPECT_EQ(sb.mismatches(), 1u);
  EXPECT_NE(sb.report().find("transaction 4000"), std::string::npos) << sb.report();
}

}  // namespace
}  // namespace texsim::rtl
