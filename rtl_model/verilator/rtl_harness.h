#pragma once
// RtlHarness<Model>: a reusable clock/reset/trace harness around a Verilated block
// (docs/rtl/blocks.md). Every block has the ports clk, rst, in_valid, out_valid and the
// op counters ops_add, ops_mul, ops_div, ops_cmp, items (rtl_model/rtl/texsim_op_counters.v).
// Waveforms are switched at run time: a non-empty trace path (or the environment variable
// TEXSIM_RTL_TRACE naming a directory) writes a VCD of every clock edge. A waveform that cannot
// be written is an InputError, never a run without it.
#include <verilated.h>
#include <verilated_vcd_c.h>

#include <cstdint>
#include <memory>
#include <string>

#include "blocks/base/op_counts.h"

namespace texsim::rtl {

// Where the VCD of block `name` goes: `explicit_path` if set, else $TEXSIM_RTL_TRACE/<name>.vcd
// if that variable is set, else "" (no trace). Throws InputError naming the variable and the
// path when it is set to something that is not a directory this user can write into.
std::string trace_path_for(const std::string& name, const std::string& explicit_path = "");
// Throws InputError: the VCD at `path` could not be opened.
[[noreturn]] void throw_unopened_trace(const std::string& path);

template <class Model>
class RtlHarness {
 public:
  // `name` names the block in the default trace file name; `trace` as in trace_path_for.
  explicit RtlHarness(const std::string& name, const std::string& trace = "")
      : ctx_(std::make_unique<VerilatedContext>()), trace_path_(trace_path_for(name, trace)) {
    if (!trace_path_.empty()) ctx_->traceEverOn(true);
    top_ = std::make_unique<Model>(ctx_.get(), name.c_str());
    if (!trace_path_.empty()) {
      vcd_ = std::make_unique<VerilatedVcdC>();
      top_->trace(vcd_.get(), 99);
      vcd_->open(trace_path_.c_str());
      if (!vcd_->isOpen()) throw_unopened_trace(trace_path_);
    }
    top_->clk = 0;
    top_->rst = 1;
    top_->in_valid = 0;
    top_->eval();
  }
  RtlHarness(const RtlHarness&) = delete;
  RtlHarness& operator=(const RtlHarness&) = delete;
  ~RtlHarness() {
    if (vcd_) vcd_->close();
    top_->final();
  }

  Model& top() { return *top_; }
  const std::string& trace_path() const { return trace_path_; }

  // Holds reset for `cycles` clock edges with no input; counters and cycle() restart at 0.
  void reset(int cycles = 2) {
    top_->rst = 1;
    top_->in_valid = 0;
    for (int i = 0; i < cycles; ++i) step();
    top_->rst = 0;
    cycle_ = 0;
  }
  // One clock cycle: the inputs set before the call are sampled at the rising edge; the
  // outputs read after it are those of cycle() (one more than before the call).
  void step() {
    top_->clk = 1;
    top_->eval();
    dump();
    top_->clk = 0;
    top_->eval();
    dump();
    ++cycle_;
  }
  uint64_t cycle() const { return cycle_; }

  // The block's op counters as the C++ models count them.
  OpCounts ops() const {
    OpCounts o;
    o.add = top_->ops_add;
    o.mul = top_->ops_mul;
    o.div = top_->ops_div;
    o.cmp = top_->ops_cmp;
    return o;
  }
  uint64_t items() const { return top_->items; }

 private:
  void dump() {
    if (vcd_) vcd_->dump(time_);
    ++time_;
  }

  std::unique_ptr<VerilatedContext> ctx_;
  std::string trace_path_;
  std::unique_ptr<Model> top_;
  std::unique_ptr<VerilatedVcdC> vcd_;
  uint64_t cycle_ = 0;
  uint64_t time_ = 0;
};

}  // namespace texsim::rtl
