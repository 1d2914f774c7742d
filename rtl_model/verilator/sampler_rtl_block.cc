#include "rtl_model/verilator/sampler_rtl_block.h"

#include <Vtexsim_sampler.h>

#include <array>
#include <string>
#include <vector>

#include "rtl_model/link/framing.h"
#include "rtl_model/link/sampler_link.h"
#include "rtl_model/params/rtl_params.h"
#include "rtl_model/verilator/rtl_harness.h"

namespace texsim::link {

namespace {

// An s15.32 raw as the 48-bit port takes it (Verilator expects the bits above it clear).
uint64_t coord_bits(int64_t x) { return static_cast<uint64_t>(x) & ((uint64_t{1} << 48) - 1); }

class SamplerRtlBlock : public BoardBlock {
 public:
  SamplerRtlBlock() : h_("texsim_sampler") { h_.reset(); }

  BlockCaps caps() const override {
    return {"texsim_sampler", 32, 32,
            static_cast<uint8_t>(FixedSampler::latency(rtl_params::tech()))};
  }

  std::string configure(std::span<const uint8_t> config) override {
    if (config.empty()) return "empty sampler configuration";
    try {
      if (config[0] == kSamplerState) return load_state(read_sampler_state(config));
      if (config[0] == kSamplerChunk) return load_chunk(config);
    } catch (const LinkError& e) {
      return e.what();
    }
    return "unknown sampler configuration kind " + std::to_string(config[0]);
  }

  // Fragments of kSamplerWords inputs each, one per clock; the same number of words back per
  // fragment. A trailing partial fragment gives all-ones words (no result the host can take).
  uint64_t apply(std::span<const uint32_t> in, std::span<uint32_t> out) override {
    Vtexsim_sampler& top = h_.top();
    const size_t n = in.size() / kSamplerWords;
    const uint64_t first = h_.cycle();
    uint64_t last = first;
    size_t got = 0;
    const auto clock = [&] {
      h_.step();
      // The memory's registered read: this cycle's addresses answered at the next edge.
      for (size_t k = 0; k < FixedSampler::kQuadWords; ++k) {
        const uint32_t a = top.rd_addr[k];
        top.rd_data[k] = a < mem_.size() ? mem_[a] : 0;
      }
      if (top.out_valid && got < n) {
        uint32_t* o = out.data() + got * kSamplerWords;
        o[0] = top.out_rgba;
        o[1] = top.out_level_hi;
        o[2] = top.out_level_lo;
        o[3] = top.out_delta;
        for (size_t k = 0; k < FixedSampler::kQuadWords; ++k) o[4 + k] = reads_[got][k];
        ++got;
        last = h_.cycle();
      }
      if (top.rd_valid && reads_seen_ < n) {
        for (size_t k = 0; k < FixedSampler::kQuadWords; ++k)
          reads_[reads_seen_][k] = top.rd_addr[k];
        ++reads_seen_;
      }
    };
    reads_.assign(n, {});
    reads_seen_ = 0;
    for (size_t i = 0; i < n; ++i) {
      const FixedSampler::Input f = decode_fragment(
          std::span<const uint32_t, kSamplerWords>(in.data() + i * kSamplerWords, kSamplerWords));
      top.in_valid = 1;
      top.u = coord_bits(f.u);
      top.v = coord_bits(f.v);
      top.dudx = coord_bits(f.dudx);
      top.dvdx = coord_bits(f.dvdx);
      top.dudy = coord_bits(f.dudy);
      top.dvdy = coord_bits(f.dvdy);
      clock();
    }
    top.in_valid = 0;
    for (uint32_t i = 0; got < n && i < kDrainLimit; ++i) clock();
    clock();  // the counters take the last retirement's counts at this edge
    for (size_t w = got * kSamplerWords; w < out.size(); ++w) out[w] = ~uint32_t{0};
    return n == 0 ? 0 : last - first;
  }

 private:
  static constexpr uint32_t kDrainLimit = 256;

  std::string load_state(const SamplerState& s) {
    const TexelAddressGen::Config built;
    if (s.config.sub_bits != built.sub_texel_bits || s.config.mip_bits != built.mipmap_bits) {
      return "the RTL sampler is built for sub_texel_bits " + std::to_string(built.sub_texel_bits) +
             " and mipmap_bits " + std::to_string(built.mipmap_bits) +
             " only (rtl_model/params/rtl_params.h)";
    }
    Vtexsim_sampler& top = h_.top();
    const FixedSampler::Config& c = s.config;
    top.cfg_trilinear = c.trilinear;
    top.cfg_mode_u = static_cast<uint8_t>(c.address_u);
    top.cfg_mode_v = static_cast<uint8_t>(c.address_v);
    top.cfg_offset_u = static_cast<uint8_t>(c.offset_u & 31);
    top.cfg_offset_v = static_cast<uint8_t>(c.offset_v & 31);
    top.cfg_bias = static_cast<uint32_t>(c.bias);
    top.cfg_min_lod = static_cast<uint32_t>(c.min_lod);
    top.cfg_max_lod = static_cast<uint32_t>(c.max_lod);
    top.cfg_w0 = static_cast<uint16_t>(s.texture.w0);
    top.cfg_h0 = static_cast<uint16_t>(s.texture.h0);
    top.cfg_levels = static_cast<uint8_t>(s.texture.levels);
    top.cfg_layout = static_cast<uint8_t>(s.texture.layout);
    top.cfg_add_n = top.cfg_mul_n = top.cfg_div_n = top.cfg_cmp_n = 0;
    for (int l = 0; l < FixedSampler::kMaxLevels; ++l) {
      top.cfg_base_we = 1;
      top.cfg_base_idx = static_cast<uint8_t>(l);
      top.cfg_base_data = s.texture.base[static_cast<size_t>(l)];
      h_.step();
    }
    top.cfg_base_we = 0;
    mem_.assign(s.memory_words, 0);
    return "";
  }

  std::string load_chunk(std::span<const uint8_t> config) {
    ByteReader r(config, "sampler memory chunk");
    r.u8();
    const uint32_t at = r.u32();
    if (r.left() % 4 != 0) return "sampler memory chunk: not a whole number of words";
    const size_t n = r.left() / 4;
    if (at > mem_.size() || n > mem_.size() - at)
      return "sampler memory chunk: words " + std::to_string(at) + ".." + std::to_string(at + n) +
             " past the memory of " + std::to_string(mem_.size());
    for (size_t k = 0; k < n; ++k) mem_[at + k] = r.u32();
    return "";
  }

  rtl::RtlHarness<Vtexsim_sampler> h_;
  std::vector<uint32_t> mem_;
  std::vector<std::array<uint32_t, FixedSampler::kQuadWords>> reads_;
  size_t reads_seen_ = 0;
};

}  // namespace

std::unique_ptr<BoardBlock> make_rtl_sampler_block() { return std::make_unique<SamplerRtlBlock>(); }

}  // namespace texsim::link
