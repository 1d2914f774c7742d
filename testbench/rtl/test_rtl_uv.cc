// Lockstep of the incremental u/v adder with its dividers (rtl_model/rtl/uv_incremental.v)
// against UvIncrementalAdder::eval_row<Fixed<16,16>> in the k-lane form (the configuration of
// rtl_model/params/rtl_params.h). A transaction is one group of K pixels: its u, v, valid bits,
// the cycle it leaves the dividers (row load + row set-up latency + group index + divider
// latency, all from the C++ timing) and the op counters (row set-up ops on a row's first
// group, per-pixel ops on every pixel). Directed rows cover the denominator limit, saturating
// accumulators and quotients, HalfEven ties, one-pixel and long rows and extreme x0/y; the
// rest are seeded random maps and rows.
#include <Vuv_incremental.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "rtl_model/params/rtl_params.h"
#include "testbench/rtl/lockstep.h"

namespace texsim::rtl {
namespace {

using T = rtl_params::UvFixed;
using Model = Vuv_incremental;

struct UvRow {
  std::array<int64_t, 9> c;  // A..I raws
  RowSpan s;
  std::string text() const {
    std::ostringstream o;
    o << "A..I";
    for (int64_t v : c) o << " " << v;
    o << " x0 " << s.x0 << " y " << s.y << " n " << s.n;
    return o.str();
  }
};

std::vector<UvRow> directed_rows() {
  const int64_t one = int64_t{1} << T::kFracBits, mx = T::kRawMax, mn = T::kRawMin;
  std::vector<UvRow> r;
  // Denominator at the limit (z = 16 raw = 1/4096) and one LSB below it.
  r.push_back({{one, 0, 5, one, 0, -7, 0, 0, 16}, {0, 0, 9}});
  r.push_back({{one, 0, 5, one, 0, -7, 0, 0, 15}, {0, 0, 9}});
  r.push_back({{0, 0, 100, 0, 0, 100, 1, 0, 13}, {0, 0, 9}});  // z crosses the limit in the row
  // Saturating accumulators and quotients.
  r.push_back({{one * 1000, 0, mx - 5, -one * 1000, 0, mn + 5, 0, 0, one}, {3, 1, 13}});
  r.push_back({{one, one, mx, one, one, mn, 0, 0, 1 << 10}, {0, 0, 6}});
  r.push_back({{mx, mx, mx, mn, mn, mn, mx, mx, mx}, {-32768, 32767, 7}});
  // HalfEven ties: z = 2, numerators of odd raw.
  for (int64_t c : {1, 3, 5, -1, -3, -5})
    r.push_back({{0, 0, c, 0, 0, -c, 0, 0, 2 * one}, {0, 0, 5}});
  // Row lengths around the lane count, and a long row.
  for (int32_t n : {1, 2, 3, 4, 5, 8, 9, 1000})
    r.push_back(
        {{one / 3, -one / 7, 40 * one, one / 5, one / 9, -3 * one, 37, -11, one}, {17, 23, n}});
  r.push_back({{one, 0, 0, 0, one, 0, 0, 0, one}, {-32768, -32768, 20}});
  return r;
}

UvRow random_row(std::mt19937_64& rng) {
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  const int64_t k = 1 << 20, c = 1 << 28, g = 1 << 10;
  UvRow r;
  r.c = {uni(-k, k), uni(-k, k), uni(-c, c), uni(-k, k),           uni(-k, k),
         uni(-c, c), uni(-g, g), uni(-g, g), uni(1 << 12, 1 << 20)};
  r.s = {static_cast<int32_t>(uni(-100, 2000)), static_cast<int32_t>(uni(-100, 2000)),
         static_cast<int32_t>(uni(1, 80))};
  return r;
}

struct UvRun {
  Scoreboard sb;
  uint64_t rows = 0;
  uint64_t pixels = 0, valid_pixels = 0;  // how many pixels the C++ core accepted
};

// Drives rows until `groups` transactions have been issued (directed rows first).
UvRun run_uv(uint64_t groups, int64_t perturb = 0, uint64_t perturb_at = 0) {
  const UvIncrementalAdder core(rtl_params::uv_config());
  const int k = static_cast<int>(core.lane_count());
  const uint32_t setup_lat = core.row_setup_timing(rtl_params::tech()).latency;
  UvRun run{Scoreboard("uv_incremental", core.timing(rtl_params::tech()).latency)};
  Scoreboard& sb = run.sb;
  RtlHarness<Model> h("uv_incremental");
  h.reset();
  Model& top = h.top();
  auto read = [&](Model& m) {
    OutWords w{};
    for (size_t j = 0; j < static_cast<size_t>(k); ++j) {
      w[3 * j] = static_cast<int32_t>(m.out_u[j]);
      w[3 * j + 1] = static_cast<int32_t>(m.out_v[j]);
      w[3 * j + 2] = ((m.out_mask >> j) & 1) | (((m.out_ok >> j) & 1) << 1);
    }
    return w;
  };
  auto clock = [&] {
    h.step();
    if (top.out_valid) sb.observe(h.cycle(), read(top), h.ops());
  };
  std::mt19937_64 rng(77);
  std::bernoulli_distribution idle(0.2);
  const std::vector<UvRow> directed = directed_rows();
  OpCounts ops;
  uint64_t issued = 0;
  std::vector<CoordSample> out;
  for (uint64_t i = 0; issued < groups; ++i) {
    const UvRow row = i < directed.size() ? directed[i] : random_row(rng);
    while (idle(rng)) clock();
    while (!top.in_ready) clock();
    MapCoeffs<T> m;
    T* dst[9] = {&m.A, &m.B, &m.C, &m.D, &m.E, &m.F, &m.G, &m.H, &m.I};
    for (int j = 0; j < 9; ++j) *dst[j] = T::from_raw(row.c[static_cast<size_t>(j)]);
    m.ok = true;
    out.assign(static_cast<size_t>(row.s.n), CoordSample{});
    core.eval_row(m, row.s, out.data());
    const uint64_t load = h.cycle();
    for (int g = 0; g * k < row.s.n; ++g) {
      OutWords w{};
      const int cnt = std::min(k, row.s.n - g * k);
      for (size_t j = 0; j < static_cast<size_t>(cnt); ++j) {
        const CoordSample& p = out[static_cast<size_t>(g) * static_cast<size_t>(k) + j];
        w[3 * j] = static_cast<int64_t>(std::ldexp(p.u, T::kFracBits));
        w[3 * j + 1] = static_cast<int64_t>(std::ldexp(p.v, T::kFracBits));
        w[3 * j + 2] = 1 | (p.valid ? 2 : 0);
        run.valid_pixels += p.valid ? 1 : 0;
        ++run.pixels;
      }
      ops += core.ops_per_item() * static_cast<uint64_t>(cnt);
      if (g == 0) ops += core.row_setup_ops();
      if (perturb != 0 && issued == perturb_at) w[0] += perturb;
      sb.expect(row.text() + " group " + std::to_string(g),
                load + setup_lat + static_cast<uint64_t>(g), w, ops);
      ++issued;
    }
    top.ca = static_cast<uint32_t>(row.c[0]);
    top.cb = static_cast<uint32_t>(row.c[1]);
    top.cc = static_cast<uint32_t>(row.c[2]);
    top.cd = static_cast<uint32_t>(row.c[3]);
    top.ce = static_cast<uint32_t>(row.c[4]);
    top.cf = static_cast<uint32_t>(row.c[5]);
    top.cg = static_cast<uint32_t>(row.c[6]);
    top.ch = static_cast<uint32_t>(row.c[7]);
    top.ci = static_cast<uint32_t>(row.c[8]);
    top.x0 = static_cast<uint16_t>(row.s.x0);
    top.y = static_cast<uint16_t>(row.s.y);
    top.n = static_cast<uint16_t>(row.s.n);
    top.in_valid = 1;
    clock();
    top.in_valid = 0;
    ++run.rows;
  }
  for (int i = 0; i < (1 << 16) && sb.pending() > 0; ++i) clock();
  sb.finish();
  std::cout << sb.summary() << " (" << run.rows << " rows, " << run.pixels << " pixels, "
            << run.valid_pixels << " valid)\n"
            << sb.report();
  return run;
}

// The ports above: 32-bit raws, 16-bit x0, y, n; one 32-bit word per lane in out_u, out_v.
static_assert(T::kBits == 32 && rtl_params::kUvCoordBits == 16 && rtl_params::kUvCountBits == 16);

TEST(RtlLockstep, UvIncrementalMatchesCppBitForBit) {
  const UvRun r = run_uv(lockstep_vectors());
  EXPECT_EQ(r.sb.mismatches(), 0u) << r.sb.report();
  EXPECT_GE(r.sb.compared(), lockstep_vectors());
}

TEST(RtlLockstep, UvScoreboardCatchesOneLsb) {
  const UvRun r = run_uv(3000, 1, 2500);
  EXPECT_EQ(r.sb.mismatches(), 1u);
  EXPECT_NE(r.sb.report().find("transaction 2500"), std::string::npos) << r.sb.report();
}

}  // namespace
}  // namespace texsim::rtl
