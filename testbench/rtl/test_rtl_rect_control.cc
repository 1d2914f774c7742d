// Lockstep of the rectangle-scan texturing control (rtl_model/rtl/rect_scan_control.v) against
// OutlineComparator and TexturingControl (blocks/raster/rect_scan/): random triangles give the
// edge set-up (EdgeRasterizer) and closing edges, random rows along random lines give the
// row-start sides, and random memory words (with random foreground planes) drive the parity
// flags. A transaction is one decision: texture, end of row and the comparator's hits, its
// latency (TexturingControl::timing) and the compares (3 per decision, 1 per comparator use;
// the comparator's memory read is outside the block and not counted).
#include <Vrect_scan_control.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/rect_scan/outline_comparator.h"
#include "rtl_model/params/rtl_params.h"
#include "testbench/rtl/lockstep.h"

namespace texsim::rtl {
namespace {

using Model = Vrect_scan_control;

Scoreboard run_control(uint64_t decisions, int64_t perturb = 0, uint64_t perturb_at = 0) {
  Scoreboard sb("rect_scan_control", TexturingControl().timing(rtl_params::tech()).latency);
  RtlHarness<Model> h("rect_scan_control");
  h.reset();
  Model& top = h.top();
  auto clock = [&] {
    h.step();
    if (top.out_valid) {
      sb.observe(h.cycle(), {top.out_texture, top.out_end_of_row, top.out_hits}, h.ops());
    }
  };
  std::mt19937_64 rng(5150);
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  std::bernoulli_distribution idle(0.1), marked(0.25);
  const EdgeRasterizer raster;
  const LineStepper stepper(rtl_params::kRectScanLine);
  OpCounts ops, decision, compare;
  decision.cmp = TexturingControl().ops_per_item().cmp;
  compare.cmp = OutlineComparator().ops_per_item().cmp;
  uint64_t issued = 0, textured = 0, row_ends = 0;
  auto issue = [&](bool row, uint8_t inside0, uint8_t word, int32_t minor,
                   const TexturingControl::Decision& d, uint8_t hits) {
    ops += decision;
    if (!row) ops += compare;
    OutWords w{d.texture ? 1 : 0, d.end_of_row ? 1 : 0, hits};
    textured += d.texture ? 1 : 0;
    row_ends += d.end_of_row ? 1 : 0;
    if (perturb != 0 && issued == perturb_at) w[0] += perturb;
    sb.expect("row " + std::to_string(row) + " minor " + std::to_string(minor), h.cycle(), w, ops);
    ++issued;
    top.in_valid = 1;
    top.row_start = row;
    top.inside0 = inside0;
    top.word = word;
    top.minor = static_cast<uint16_t>(minor);
    clock();
    top.in_valid = 0;
  };
  while (issued < decisions) {
    const ScreenVertex v[3] = {
        {static_cast<double>(uni(0, 200)) + 0.25, static_cast<double>(uni(0, 200)), 1},
        {static_cast<double>(uni(0, 200)), static_cast<double>(uni(0, 200)) + 0.5, 1},
        {static_cast<double>(uni(0, 200)), static_cast<double>(uni(0, 200)), 1}};
    const EdgeRasterizer::Setup st = raster.setup(v, Scissor{0, 0, 256, 256});
    if (!st.ok()) continue;
    const RowLine line =
        stepper.line_for_slope(uni(0, 1) == 1, static_cast<double>(uni(-100, 100)) / 100);
    const auto lo = static_cast<int32_t>(uni(0, 100)), hi = static_cast<int32_t>(uni(100, 255));
    const auto coverage = uni(0, 1) == 1 ? RectScanCoverage::Outline : RectScanCoverage::TopLeft;
    const auto fg = static_cast<uint8_t>(uni(0, 7));
    TexturingControl bkt;
    bkt.load(st, line, lo, hi, coverage);
    OutlineComparator bp;
    bp.set_foreground(fg);
    top.load = 1;
    top.foreground = fg;
    top.closing = static_cast<uint8_t>(bkt.closing(0) | bkt.closing(1) << 1 | bkt.closing(2) << 2);
    top.outline = coverage == RectScanCoverage::Outline;
    top.minor_lo = static_cast<uint16_t>(lo);
    top.minor_hi = static_cast<uint16_t>(hi);
    clock();
    top.load = 0;
    for (int row = 0; row < 8; ++row) {
      int32_t major = static_cast<int32_t>(uni(0, 200)), minor = static_cast<int32_t>(uni(0, 255));
      uint8_t inside0 = 0;
      for (int e = 0; e < 3; ++e) {
        const int32_t x = line.x_major ? major : minor, y = line.x_major ? minor : major;
        inside0 |= static_cast<uint8_t>(
            EdgeRasterizer::inside(st, e, EdgeRasterizer::edge_value(st, e, x, y)) << e);
      }
      while (idle(rng)) clock();
      TexturingControl::Decision d = bkt.start_row(major, minor);
      issue(true, inside0, 0, minor, d, 0);
      for (int n = 0; n < 40 && !d.end_of_row; ++n) {
        ++major;
        minor = std::clamp(minor + static_cast<int32_t>(uni(-1, 1)), 0, 255);
        const auto word = static_cast<uint8_t>(marked(rng) ? uni(1, 7) : 0);
        const uint8_t hits = bp.compare(word);
        d = bkt.on_pixel(hits, major, minor);
        if (idle(rng)) clock();
        issue(false, 0, word, minor, d, hits);
      }
    }
  }
  for (int i = 0; i < (1 << 12) && sb.pending() > 0; ++i) clock();
  sb.finish();
  std::cout << sb.summary() << " (" << textured << " textured, " << row_ends << " row ends)\n"
            << sb.report();
  return sb;
}

TEST(RtlLockstep, RectScanControlMatchesCppBitForBit) {
  const Scoreboard sb = run_control(lockstep_vectors());
  EXPECT_EQ(sb.mismatches(), 0u) << sb.report();
  EXPECT_GE(sb.compared(), lockstep_vectors());
}

TEST(RtlLockstep, RectScanControlScoreboardCatchesOneLsb) {
  const Scoreboard sb = run_control(3000, 1, 2222);
  EXPECT_EQ(sb.mismatches(), 1u);
  EXPECT_NE(sb.report().find("transaction 2222 "), std::string::npos) << sb.report();
}

}  // namespace
}  // namespace texsim::rtl
