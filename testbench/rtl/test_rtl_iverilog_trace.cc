// A second simulator for the sequential blocks and the sampler: the Verilated block is driven
// with seeded stimulus (the protocols of the lockstep tests: rows and triangles loaded when
// in_ready, texel reads answered one cycle later), every cycle's inputs and outputs are written
// as a cycle trace (docs/rtl/blocks.md, "Cycle traces"), and Icarus Verilog replays the inputs
// through its testbench in testbench/rtl/iverilog/ and compares every output bit the mask
// counts: ready, valid and the op counters on every cycle, data while valid. The Verilated
// blocks are locked to the C++ models by the lockstep tests; this checks that a second
// simulator gives the same outputs (widths, signedness, X). Negative control per block: one
// expected data bit flipped is exactly one mismatch, at that cycle. Skipped, with the reason,
// when iverilog or vvp is not on PATH. TEXSIM_IVERILOG_CYCLES scales the traces.
#include <Vrect_scan_control.h>
#include <Vrect_scan_raster.h>
#include <Vrect_scan_stepper.h>
#include <Vtexsim_sampler.h>
#include <Vuv_incremental.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/shell_quote.h"
#include "blocks/texture/memory/texture_memory.h"
#include "rtl_model/params/rtl_params.h"
#include "rtl_model/verilator/rtl_harness.h"
#include "testbench/rtl/rtl_vectors.h"

namespace texsim::rtl {
namespace {

namespace fs = std::filesystem;

const std::string kRtl = std::string(TEXSIM_SOURCE_DIR) + "/rtl_model/rtl/";
const std::string kTb = std::string(TEXSIM_SOURCE_DIR) + "/testbench/rtl/iverilog/";

bool tools_found() {
  return std::system("command -v iverilog >/dev/null 2>&1 && command -v vvp >/dev/null 2>&1") == 0;
}
constexpr const char* kSkip = "iverilog or vvp not found on PATH (Debian: iverilog)";

size_t cycles(size_t def) {
  const char* s = std::getenv("TEXSIM_IVERILOG_CYCLES");  // NOLINT(concurrency-mt-unsafe)
  return s != nullptr && *s != '\0' ? std::strtoull(s, nullptr, 10) : def;
}

// One output port in a trace: its value and width, whether it is compared on this cycle, and
// whether it is data (the field a negative control corrupts) rather than a flag or counter.
struct OutField {
  uint64_t value;
  int width;
  bool counted;
  bool data;
};

// The inputs and outputs of a port wider than 64 bits (Verilator's 32-bit words, least
// significant first), as 32-bit fields, most significant first.
template <class Wide>
void wide_in(std::vector<VectorField>& f, const Wide& w, int bits) {
  for (int k = bits / 32 - 1; k >= 0; --k) f.emplace_back(w[static_cast<size_t>(k)], 32);
}
template <class Wide>
void wide_out(std::vector<OutField>& f, const Wide& w, int bits, bool counted) {
  for (int k = bits / 32 - 1; k >= 0; --k)
    f.push_back({w[static_cast<size_t>(k)], 32, counted, true});
}

template <class Model>
void counters(std::vector<OutField>& f, const Model& m) {
  for (const uint64_t c : {m.ops_add, m.ops_mul, m.ops_div, m.ops_cmp, m.items})
    f.push_back({c, 64, true, false});
}

// A Verilated block and the trace of its cycles.
template <class Model>
class Recorder {
 public:
  using Ins = std::function<std::vector<VectorField>(const Model&)>;
  using Outs = std::function<std::vector<OutField>(const Model&)>;
  Recorder(const std::string& name, Ins ins, Outs outs)
      : h_(name), ins_(std::move(ins)), outs_(std::move(outs)) {
    h_.reset();
  }
  Model& top() { return h_.top(); }
  // One clock: the inputs set now, the outputs after the rising edge.
  void step() {
    std::vector<VectorField> line = ins_(h_.top());
    h_.step();
    const std::vector<OutField> out = outs_(h_.top());
    int bit = 0, data_lsb = -1;
    for (auto it = out.rbegin(); it != out.rend(); ++it) {  // least significant field first
      if (it->data && it->counted && data_lsb < 0) data_lsb = bit;
      bit += it->width;
    }
    for (const OutField& o : out) {
      const uint64_t ones = o.width == 64 ? ~uint64_t{0} : (uint64_t{1} << o.width) - 1;
      line.emplace_back(o.counted ? ones : 0, o.width);
    }
    for (const OutField& o : out) line.emplace_back(o.value, o.width);
    lines_.push_back(vector_line(line));
    data_lsb_.push_back(data_lsb);
  }
  std::vector<std::string>& lines() { return lines_; }
  // The first cycle at or after `from` whose outputs hold counted data, and that data's lowest
  // bit; {-1, -1} if none.
  std::pair<int, int> data_cycle(size_t from) const {
    for (size_t i = from; i < data_lsb_.size(); ++i)
      if (data_lsb_[i] >= 0) return {static_cast<int>(i), data_lsb_[i]};
    return {-1, -1};
  }

 private:
  RtlHarness<Model> h_;
  Ins ins_;
  Outs outs_;
  std::vector<std::string> lines_;
  std::vector<int> data_lsb_;
};

// Flips bit `bit` (0: least significant) of a trace line's hex digits.
void flip_bit(std::string& line, int bit) {
  const size_t at = line.size() - 1 - static_cast<size_t>(bit / 4);
  const char* hex = "0123456789abcdef";
  const int nib = static_cast<int>(std::string(hex).find(line[at])) ^ (1 << (bit % 4));
  line[at] = hex[nib];
}

struct SimResult {
  int code = -1;
  std::string out;
  size_t cycles = 0, mismatches = 0;
  bool summary = false;
};

// Writes the trace, compiles tb_<block>.v with the block's generated parameters and replays it.
SimResult replay(const std::string& block, const std::vector<std::string>& rtl,
                 const std::vector<rtl_params::Param>& params,
                 const std::vector<std::string>& lines, const std::string& tag) {
  const fs::path dir =
      fs::temp_directory_path() / ("texsim_ivtrace_" + std::to_string(::getpid()) + "_" + tag);
  fs::remove_all(dir);
  fs::create_directories(dir);
  {
    std::ofstream f(dir / "trace.hex");
    f << "// texsim RTL cycle trace: " << block << "; " << lines.size() << " cycles\n";
    for (const std::string& l : lines) f << l << "\n";
  }
  const std::string top = "tb_" + block;
  std::string cmd = "iverilog -g2012 -o ";
  cmd += shell_quote((dir / "sim.vvp").string());
  cmd += " -s " + top + " -I " + shell_quote(kTb);
  for (const auto& [name, value] : params) {
    cmd += " -P" + top + ".";
    cmd += name + "=" + std::to_string(value);
  }
  cmd += " " + shell_quote(kTb + top + ".v");
  for (const std::string& f : rtl) {
    cmd += " ";
    cmd += shell_quote(f.front() == '/' ? f : kRtl + f);
  }
  cmd += " >" + shell_quote((dir / "sim.log").string()) + " 2>&1 && vvp -n ";
  cmd += shell_quote((dir / "sim.vvp").string()) + " +trace=";
  cmd += shell_quote((dir / "trace.hex").string()) + " +n=" + std::to_string(lines.size());
  cmd += " >>" + shell_quote((dir / "sim.log").string()) + " 2>&1";
  const int rc = std::system(cmd.c_str());
  SimResult r;
  r.code = rc != -1 && WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  std::ifstream f(dir / "sim.log");
  std::stringstream ss;
  ss << f.rdbuf();
  r.out = ss.str();
  // TEXSIM_IVERILOG_KEEP set: the trace, simulation and log stay for a look.
  if (std::getenv("TEXSIM_IVERILOG_KEEP") == nullptr) {  // NOLINT(concurrency-mt-unsafe)
    fs::remove_all(dir);
  } else {
    r.out += "kept in " + dir.string() + "\n";
  }
  for (size_t p = r.out.find("iverilog: "); p != std::string::npos;
       p = r.out.find("iverilog: ", p + 1)) {
    size_t a = 0, b = 0;
    if (std::sscanf(r.out.c_str() + p, "iverilog: %zu cycles, %zu mismatches", &a, &b) == 2) {
      r.cycles = a;
      r.mismatches = b;
      r.summary = true;
    }
  }
  return r;
}

constexpr int kSlope = LineStepper::Config{}.slope_bits;
constexpr int kCw = rtl_params::kRectScanCoordBits;
constexpr int kMaj = rtl_params::kRectScanMemMajorBits;
constexpr int kMin = rtl_params::kRectScanMemMinorBits;

const std::vector<std::string> kHelpers = {"texsim_pipe.v",        "texsim_round_sat.v",
                                           "texsim_op_counters.v", "texsim_mul_rs.v",
                                           "texsim_add_sat.v",     "texsim_mul_tree.v"};

std::vector<std::string> with_helpers(std::vector<std::string> files) {
  files.insert(files.end(), kHelpers.begin(), kHelpers.end());
  return files;
}

// Replays the trace as recorded (every output equal), then with one data bit flipped in the
// middle of the trace (exactly one mismatch, at that cycle).
template <class Model>
void check_both_ways(Recorder<Model>& rec, const std::string& block,
                     const std::vector<std::string>& rtl,
                     const std::vector<rtl_params::Param>& params) {
  std::vector<std::string>& lines = rec.lines();
  const SimResult r = replay(block, rtl, params, lines, block);
  ASSERT_TRUE(r.summary) << r.out;
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.cycles, lines.size()) << r.out;
  EXPECT_EQ(r.mismatches, 0u) << r.out;
  const auto [at, bit] = rec.data_cycle(lines.size() / 2);
  ASSERT_GE(at, 0) << block << ": no output data in the second half of the trace";
  flip_bit(lines[static_cast<size_t>(at)], bit);
  const SimResult neg = replay(block, rtl, params, lines, block + "_neg");
  EXPECT_EQ(neg.mismatches, 1u) << neg.out;
  EXPECT_NE(neg.out.find("cycle " + std::to_string(at) + ":"), std::string::npos) << neg.out;
}

// ---- uv_incremental: random maps and rows (n 1..12), loaded when in_ready ----
TEST(RtlIverilogTrace, UvIncrementalEqualsVerilator) {
  if (!tools_found()) GTEST_SKIP() << kSkip;
  using M = Vuv_incremental;
  static_assert(rtl_params::UvFixed::kBits == 32 && rtl_params::kUvCoordBits == 16);
  const int k = static_cast<int>(UvIncrementalAdder(rtl_params::uv_config()).lane_count());
  const int kw = k * rtl_params::UvFixed::kBits;
  Recorder<M> rec(
      "uv_incremental",
      [](const M& m) {
        std::vector<VectorField> f = {{m.in_valid, 1}};
        for (const uint32_t c : {m.ca, m.cb, m.cc, m.cd, m.ce, m.cf, m.cg, m.ch, m.ci})
          f.emplace_back(c, 32);
        f.insert(f.end(), {{m.x0, 16}, {m.y, 16}, {m.n, 16}});
        return f;
      },
      [k, kw](const M& m) {
        const bool v = m.out_valid;
        std::vector<OutField> f = {{m.in_ready, 1, true, false},
                                   {m.out_valid, 1, true, false},
                                   {m.out_mask, k, v, true},
                                   {m.out_ok, k, v, true}};
        wide_out(f, m.out_u, kw, v);
        wide_out(f, m.out_v, kw, v);
        counters(f, m);
        return f;
      });
  M& top = rec.top();
  std::mt19937_64 rng(2929);
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  const size_t n = cycles(80);
  const int64_t a = 1 << 20, c = 1 << 28, g = 1 << 10;
  while (rec.lines().size() < n) {
    if (top.in_ready && uni(0, 3) != 0) {
      uint32_t* dst[9] = {&top.ca, &top.cb, &top.cc, &top.cd, &top.ce,
                          &top.cf, &top.cg, &top.ch, &top.ci};
      const int64_t lim[9] = {a, a, c, a, a, c, g, g, 1 << 20};
      for (int j = 0; j < 9; ++j)
        *dst[j] = static_cast<uint32_t>(j == 8 ? uni(-(1 << 12), lim[j]) : uni(-lim[j], lim[j]));
      top.x0 = static_cast<uint16_t>(uni(-100, 2000));
      top.y = static_cast<uint16_t>(uni(-100, 2000));
      top.n = static_cast<uint16_t>(uni(1, 12));
      top.in_valid = 1;
    }
    rec.step();
    top.in_valid = 0;
  }
  check_both_ways(rec, "uv_incremental",
                  with_helpers({"uv_incremental.v", "texsim_fixed_div.v", "texsim_udiv_pipe.v"}),
                  rtl_params::uv_incremental_params());
}

// ---- rect_scan_stepper: random lines and rectangles, loaded when in_ready ----
TEST(RtlIverilogTrace, RectScanStepperEqualsVerilator) {
  if (!tools_found()) GTEST_SKIP() << kSkip;
  using M = Vrect_scan_stepper;
  Recorder<M> rec(
      "rect_scan_stepper",
      [](const M& m) {
        return std::vector<VectorField>{
            {m.in_valid, 1}, {m.x_major, 1},  {m.neg, 1},    {m.delta_minor, kSlope + 1},
            {m.major0, kCw}, {m.major1, kCw}, {m.t_lo, kCw}, {m.t_hi, kCw},
            {m.row_end, 1}};
      },
      [](const M& m) {
        const bool v = m.out_valid;
        std::vector<OutField> f = {{m.in_ready, 1, true, false},
                                   {m.out_valid, 1, true, false},
                                   {m.out_row_start, 1, v, true},
                                   {m.out_x, kCw, v, true},
                                   {m.out_y, kCw, v, true}};
        counters(f, m);
        return f;
      });
  M& top = rec.top();
  std::mt19937_64 rng(2930);
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  const size_t n = cycles(1500);
  while (rec.lines().size() < n) {
    top.row_end = uni(0, 19) == 0 ? 1 : 0;
    if (top.in_ready && uni(0, 2) != 0) {
      top.x_major = static_cast<uint8_t>(uni(0, 1));
      top.neg = static_cast<uint8_t>(uni(0, 1));
      top.delta_minor = static_cast<uint16_t>(uni(0, 1 << kSlope));
      const int64_t m0 = uni(-40, 40), t0 = uni(-40, 40);
      top.major0 = static_cast<uint16_t>(m0);
      top.major1 = static_cast<uint16_t>(m0 + uni(0, 9));
      top.t_lo = static_cast<uint16_t>(t0);
      top.t_hi = static_cast<uint16_t>(t0 + uni(0, 4));
      top.in_valid = 1;
    }
    rec.step();
    top.in_valid = 0;
  }
  check_both_ways(rec, "rect_scan_stepper", with_helpers({"rect_scan_stepper.v"}),
                  rtl_params::rect_scan_stepper_params());
}

// ---- rect_scan_control: a load (edges, closing edge, outline, minor range) every few dozen
// cycles, decisions with random row starts, memory words and minor coordinates between ----
TEST(RtlIverilogTrace, RectScanControlEqualsVerilator) {
  if (!tools_found()) GTEST_SKIP() << kSkip;
  using M = Vrect_scan_control;
  Recorder<M> rec(
      "rect_scan_control",
      [](const M& m) {
        return std::vector<VectorField>{{m.load, 1},     {m.foreground, 3}, {m.closing, 3},
                                        {m.outline, 1},  {m.minor_lo, kCw}, {m.minor_hi, kCw},
                                        {m.in_valid, 1}, {m.row_start, 1},  {m.inside0, 3},
                                        {m.word, 3},     {m.minor, kCw}};
      },
      [](const M& m) {
        const bool v = m.out_valid;
        std::vector<OutField> f = {{m.out_valid, 1, true, false},
                                   {m.out_texture, 1, v, true},
                                   {m.out_end_of_row, 1, v, true},
                                   {m.out_hits, 3, v, true}};
        counters(f, m);
        return f;
      });
  M& top = rec.top();
  std::mt19937_64 rng(2931);
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  const size_t n = cycles(1500);
  while (rec.lines().size() < n) {
    top.load = uni(0, 39) == 0 || rec.lines().empty() ? 1 : 0;
    if (top.load) {
      top.foreground = static_cast<uint8_t>(uni(0, 7));
      top.closing = static_cast<uint8_t>(1 << uni(0, 2));
      top.outline = static_cast<uint8_t>(uni(0, 1));
      const int64_t lo = uni(-30, 30);
      top.minor_lo = static_cast<uint16_t>(lo);
      top.minor_hi = static_cast<uint16_t>(lo + uni(0, 20));
    }
    top.in_valid = top.load == 0 && uni(0, 9) != 0 ? 1 : 0;
    top.row_start = uni(0, 7) == 0 ? 1 : 0;
    top.inside0 = static_cast<uint8_t>(uni(0, 7));
    top.word = static_cast<uint8_t>(uni(0, 7));
    top.minor = static_cast<uint16_t>(uni(-40, 60));
    rec.step();
    top.load = 0;
    top.in_valid = 0;
  }
  check_both_ways(rec, "rect_scan_control", with_helpers({"rect_scan_control.v"}),
                  rtl_params::rect_scan_control_params());
}

// ---- rect_scan_raster: memory words written, then small triangles loaded when in_ready ----
TEST(RtlIverilogTrace, RectScanRasterEqualsVerilator) {
  if (!tools_found()) GTEST_SKIP() << kSkip;
  using M = Vrect_scan_raster;
  Recorder<M> rec(
      "rect_scan_raster",
      [](const M& m) {
        std::vector<VectorField> f = {
            {m.mem_we, 1},   {m.mem_major, kMaj}, {m.mem_minor, kMin}, {m.mem_wdata, 3},
            {m.in_valid, 1}, {m.x_major, 1},      {m.neg, 1},          {m.delta_minor, kSlope + 1}};
        for (const uint16_t c :
             {m.major0, m.major1, m.t_lo, m.t_hi, m.mem_lo, m.mem_hi, m.minor_lo, m.minor_hi})
          f.emplace_back(c, kCw);
        f.insert(f.end(), {{m.closing, 3}, {m.outline, 1}});
        for (const uint64_t e : {m.ev0, m.ev1, m.ev2, m.ev_row0, m.ev_row1, m.ev_row2})
          f.emplace_back(e, 64);
        return f;
      },
      [](const M& m) {
        const bool v = m.out_valid;
        std::vector<OutField> f = {{m.in_ready, 1, true, false},   {m.out_valid, 1, true, false},
                                   {m.out_row_start, 1, v, true},  {m.out_x, kCw, v, true},
                                   {m.out_y, kCw, v, true},        {m.out_texture, 1, v, true},
                                   {m.out_end_of_row, 1, v, true}, {m.out_hits, 3, v, true}};
        counters(f, m);
        return f;
      });
  M& top = rec.top();
  std::mt19937_64 rng(2932);
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  // Every word the triangles below can read: majors 0..15, minors −16..15 (a minor below 0
  // wraps to the top of the window). Icarus reads an unwritten word as x, Verilator as 0.
  for (int maj = 0; maj < 16; ++maj) {
    for (int mi = -16; mi < 16; ++mi) {
      top.mem_we = 1;
      top.mem_major = static_cast<uint8_t>(maj);
      top.mem_minor = static_cast<uint16_t>(mi & ((1 << kMin) - 1));
      top.mem_wdata = static_cast<uint8_t>(uni(0, 7));
      rec.step();
    }
  }
  top.mem_we = 0;
  const size_t n = cycles(1500);
  while (rec.lines().size() < n) {
    if (top.in_ready && uni(0, 2) != 0) {
      top.x_major = static_cast<uint8_t>(uni(0, 1));
      top.neg = static_cast<uint8_t>(uni(0, 1));
      top.delta_minor = static_cast<uint16_t>(uni(0, 1 << kSlope));
      const int64_t m0 = uni(0, 8), t0 = uni(0, 4);
      top.major0 = static_cast<uint16_t>(m0);
      top.major1 = static_cast<uint16_t>(m0 + uni(0, 6));
      top.t_lo = static_cast<uint16_t>(t0);
      top.t_hi = static_cast<uint16_t>(t0 + uni(0, 3));
      top.mem_lo = 0;
      top.mem_hi = 15;
      top.minor_lo = static_cast<uint16_t>(uni(0, 4));
      top.minor_hi = static_cast<uint16_t>(uni(5, 15));
      top.closing = static_cast<uint8_t>(1 << uni(0, 2));
      top.outline = static_cast<uint8_t>(uni(0, 1));
      for (uint64_t* e : {&top.ev0, &top.ev1, &top.ev2, &top.ev_row0, &top.ev_row1, &top.ev_row2})
        *e = static_cast<uint64_t>(uni(-(int64_t{1} << 20), int64_t{1} << 20));
      top.in_valid = 1;
    }
    rec.step();
    top.in_valid = 0;
  }
  check_both_ways(
      rec, "rect_scan_raster",
      with_helpers({"rect_scan_raster.v", "rect_scan_stepper.v", "rect_scan_control.v"}),
      rtl_params::rect_scan_raster_params());
}

// ---- texsim_sampler: a 37x23 mipmapped noise texture (tiled layout), trilinear with mirror
// and clamp addressing, random fragments over about eight levels of detail; the texel reads
// answered from its memory image one cycle later, as the lockstep's block RAM ----
TEST(RtlIverilogTrace, SamplerEqualsVerilator) {
  if (!tools_found()) GTEST_SKIP() << kSkip;
  using M = Vtexsim_sampler;
  const int mb = TexelAddressGen::Config{}.mipmap_bits;
  Recorder<M> rec(
      "texsim_sampler",
      [](const M& m) {
        std::vector<VectorField> f = {{m.in_valid, 1}};
        for (const uint64_t c : {m.u, m.v, m.dudx, m.dvdx, m.dudy, m.dvdy}) f.emplace_back(c, 48);
        f.insert(f.end(), {{m.cfg_trilinear, 1},
                           {m.cfg_mode_u, 3},
                           {m.cfg_mode_v, 3},
                           {m.cfg_offset_u, 5},
                           {m.cfg_offset_v, 5},
                           {m.cfg_bias, 32},
                           {m.cfg_min_lod, 32},
                           {m.cfg_max_lod, 32},
                           {m.cfg_w0, 16},
                           {m.cfg_h0, 16},
                           {m.cfg_levels, 5},
                           {m.cfg_layout, 2},
                           {m.cfg_base_we, 1},
                           {m.cfg_base_idx, 4},
                           {m.cfg_base_data, 32},
                           {m.cfg_add_n, 16},
                           {m.cfg_mul_n, 16},
                           {m.cfg_div_n, 16},
                           {m.cfg_cmp_n, 16}});
        wide_in(f, m.rd_data, 256);
        return f;
      },
      [](const M& m) {
        const bool v = m.out_valid;
        std::vector<OutField> f = {{m.rd_valid, 1, true, false}};
        wide_out(f, m.rd_addr, 256, m.rd_valid);
        f.insert(f.end(), {{m.out_valid, 1, true, false},
                           {m.out_rgba, 32, v, true},
                           {m.out_level_hi, 4, v, true},
                           {m.out_level_lo, 4, v, true},
                           {m.out_delta, mb, v, true}});
        counters(f, m);
        return f;
      });
  std::mt19937_64 rng(2933);
  std::vector<float> rgba(size_t{37} * 23 * 4);
  for (float& c : rgba) c = static_cast<float>(rng() % 256) / 255.0f;
  const Texture tex = Texture::from_rgba("noise", 37, 23, rgba, TexelFormat::Rgba8, true);
  const FixedSampler::TextureDesc t = FixedSampler::describe(tex);
  const std::vector<uint32_t> mem = FixedSampler::memory_image(tex);
  M& top = rec.top();
  top.cfg_trilinear = 1;
  top.cfg_mode_u = static_cast<uint8_t>(AddressMode::Mirror);
  top.cfg_mode_v = static_cast<uint8_t>(AddressMode::Clamp);
  top.cfg_offset_u = 3;
  top.cfg_offset_v = 31;  // −1
  top.cfg_bias = static_cast<uint32_t>(1 << (FixedSampler::kLodFrac - 2));
  top.cfg_min_lod = 0;
  top.cfg_max_lod = static_cast<uint32_t>(INT32_MAX);
  top.cfg_w0 = static_cast<uint16_t>(t.w0);
  top.cfg_h0 = static_cast<uint16_t>(t.h0);
  top.cfg_levels = static_cast<uint8_t>(t.levels);
  top.cfg_layout = static_cast<uint8_t>(t.layout);
  top.cfg_add_n = 5;
  top.cfg_mul_n = 3;
  auto answer = [&] {  // the memory's registered read
    for (size_t k = 0; k < FixedSampler::kQuadWords; ++k) {
      const uint32_t a = top.rd_addr[k];
      top.rd_data[k] = a < mem.size() ? mem[a] : 0;
    }
  };
  for (int l = 0; l < FixedSampler::kMaxLevels; ++l) {
    top.cfg_base_we = 1;
    top.cfg_base_idx = static_cast<uint8_t>(l);
    top.cfg_base_data = t.base[static_cast<size_t>(l)];
    rec.step();
    answer();
  }
  top.cfg_base_we = 0;
  std::uniform_real_distribution<double> coord(-1.5, 2.5), octave(-12, 0);
  const size_t n = cycles(200), drain = FixedSampler::latency(rtl_params::tech()) + 2;
  while (rec.lines().size() + drain < n) {
    const double d = std::exp2(octave(rng));
    const auto c48 = [](double x) {
      return static_cast<uint64_t>(FixedSampler::to_coord(x)) & ((uint64_t{1} << 48) - 1);
    };
    top.u = c48(coord(rng));
    top.v = c48(coord(rng));
    top.dudx = c48(d);
    top.dvdx = c48(-d * 0.3);
    top.dudy = c48(d * 0.2);
    top.dvdy = c48(d * 1.1);
    top.in_valid = rng() % 5 != 0 ? 1 : 0;
    rec.step();
    answer();
  }
  top.in_valid = 0;
  while (rec.lines().size() < n) {
    rec.step();
    answer();
  }
  std::vector<std::string> rtl = with_helpers(
      {"texsim_sampler.v", "texsim_sampler_lod.v", "texsim_sampler_addr.v", "bilinear_lerp.v"});
  rtl.push_back(std::string(TEXSIM_RTL_PARAMS_DIR) + "/texsim_sampler_log2.v");
  check_both_ways(rec, "texsim_sampler", rtl, rtl_params::sampler_params());
}

}  // namespace
}  // namespace texsim::rtl
