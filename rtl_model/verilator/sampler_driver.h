#pragma once
// SamplerDriver<Model>: the one driver of the Verilated sampler (rtl_model/rtl/texsim_sampler.v)
// for the virtual board's block (sampler_rtl_block.cc), the lockstep test
// (testbench/rtl/test_rtl_sampler.cc) and the C++/RTL benchmark (bench_rtl_vs_cpp.cc): loading
// a FixedSampler state and the texture's memory image, presenting a fragment's s15.32
// coordinates, and clocking with the texel reads answered from that image one cycle later, as
// block RAM would. Model is Vtexsim_sampler or the same design verilated with threads.
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/texture/sampler/fixed_sampler.h"
#include "rtl_model/verilator/rtl_harness.h"

namespace texsim::rtl {

template <class Model>
class SamplerDriver {
 public:
  using Addresses = std::array<uint32_t, FixedSampler::kQuadWords>;

  // `name` names the block's waveform (RtlHarness); the sampler comes out of reset.
  explicit SamplerDriver(const std::string& name) : h_(name) { h_.reset(); }

  RtlHarness<Model>& harness() { return h_; }
  Model& top() { return h_.top(); }
  uint64_t cycle() const { return h_.cycle(); }

  // Loads the sampler and texture state, clocking the 16 level bases in (the pipeline must be
  // empty: a fragment in flight would see the new state). `per_item` sets the op counters'
  // increments per fragment (the RTL counts add, mul, div, cmp; zero counts nothing).
  void configure(const FixedSampler::Config& c, const FixedSampler::TextureDesc& t,
                 const OpCounts& per_item = {}) {
    Model& top = h_.top();
    top.cfg_trilinear = c.trilinear;
    top.cfg_mode_u = static_cast<uint8_t>(c.address_u);
    top.cfg_mode_v = static_cast<uint8_t>(c.address_v);
    top.cfg_offset_u = static_cast<uint8_t>(c.offset_u & 31);
    top.cfg_offset_v = static_cast<uint8_t>(c.offset_v & 31);
    top.cfg_bias = static_cast<uint32_t>(c.bias);
    top.cfg_min_lod = static_cast<uint32_t>(c.min_lod);
    top.cfg_max_lod = static_cast<uint32_t>(c.max_lod);
    top.cfg_w0 = static_cast<uint16_t>(t.w0);
    top.cfg_h0 = static_cast<uint16_t>(t.h0);
    top.cfg_levels = static_cast<uint8_t>(t.levels);
    top.cfg_layout = static_cast<uint8_t>(t.layout);
    top.cfg_add_n = static_cast<uint16_t>(per_item.add);
    top.cfg_mul_n = static_cast<uint16_t>(per_item.mul);
    top.cfg_div_n = static_cast<uint16_t>(per_item.div);
    top.cfg_cmp_n = static_cast<uint16_t>(per_item.cmp);
    for (int l = 0; l < FixedSampler::kMaxLevels; ++l) {
      top.cfg_base_we = 1;
      top.cfg_base_idx = static_cast<uint8_t>(l);
      top.cfg_base_data = t.base[static_cast<size_t>(l)];
      clock();
    }
    top.cfg_base_we = 0;
  }
  // The memory the texel reads are answered from (word addresses; 0 past its end).
  void set_memory(std::vector<uint32_t> mem) { mem_ = std::move(mem); }
  std::vector<uint32_t>& memory() { return mem_; }

  // Presents a fragment for the next clock (in_valid high until no_input()).
  void input(const FixedSampler::Input& in) {
    Model& top = h_.top();
    top.in_valid = 1;
    top.u = coord_bits(in.u);
    top.v = coord_bits(in.v);
    top.dudx = coord_bits(in.dudx);
    top.dvdx = coord_bits(in.dvdx);
    top.dudy = coord_bits(in.dudy);
    top.dvdy = coord_bits(in.dvdy);
  }
  void no_input() { h_.top().in_valid = 0; }

  // One clock; then the memory's registered read: this cycle's addresses answered at the next
  // edge. The outputs read after it are those of cycle().
  void clock() {
    h_.step();
    Model& top = h_.top();
    for (size_t k = 0; k < FixedSampler::kQuadWords; ++k) {
      const uint32_t a = top.rd_addr[k];
      top.rd_data[k] = a < mem_.size() ? mem_[a] : 0;
    }
  }

  // A fragment retires this cycle: its colour, levels and δ (the addresses come from reads()).
  bool out_valid() { return h_.top().out_valid != 0; }
  FixedSampler::Result result() {
    Model& top = h_.top();
    FixedSampler::Result r;
    r.rgba = top.out_rgba;
    r.level_hi = static_cast<int32_t>(top.out_level_hi);
    r.level_lo = static_cast<int32_t>(top.out_level_lo);
    r.delta = top.out_delta;
    return r;
  }
  // A fragment's eight texel word addresses are read this cycle.
  bool read_valid() { return h_.top().rd_valid != 0; }
  Addresses reads() {
    Addresses a{};
    for (size_t k = 0; k < FixedSampler::kQuadWords; ++k) a[k] = h_.top().rd_addr[k];
    return a;
  }

  // An s15.32 raw as the 48-bit port takes it (Verilator expects the bits above it clear).
  static uint64_t coord_bits(int64_t x) {
    return static_cast<uint64_t>(x) & ((uint64_t{1} << 48) - 1);
  }

 private:
  RtlHarness<Model> h_;
  std::vector<uint32_t> mem_;
};

}  // namespace texsim::rtl
