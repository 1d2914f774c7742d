#include "rtl_model/verilator/sampler_rtl_block.h"

#include <Vtexsim_sampler.h>

#include <array>
#include <string>
#include <vector>

#include "rtl_model/link/framing.h"
#include "rtl_model/link/sampler_link.h"
#include "rtl_model/params/rtl_params.h"
#include "rtl_model/verilator/sampler_driver.h"

namespace texsim::link {

namespace {

class SamplerRtlBlock : public BoardBlock {
 public:
  SamplerRtlBlock() : d_("texsim_sampler") {}

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
    const size_t n = in.size() / kSamplerWords;
    const uint64_t first = d_.cycle();
    uint64_t last = first;
    size_t got = 0;
    const auto clock = [&] {
      d_.clock();
      if (d_.out_valid() && got < n) {
        FixedSampler::Result r = d_.result();
        r.addr = reads_[got];
        encode_result(
            r, std::span<uint32_t, kSamplerWords>(out.data() + got * kSamplerWords, kSamplerWords));
        ++got;
        last = d_.cycle();
      }
      if (d_.read_valid() && reads_seen_ < n) reads_[reads_seen_++] = d_.reads();
    };
    reads_.assign(n, {});
    reads_seen_ = 0;
    for (size_t i = 0; i < n; ++i) {
      d_.input(decode_fragment(
          std::span<const uint32_t, kSamplerWords>(in.data() + i * kSamplerWords, kSamplerWords)));
      clock();
    }
    d_.no_input();
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
    d_.configure(s.config, s.texture);
    d_.set_memory(std::vector<uint32_t>(s.memory_words, 0));
    return "";
  }

  std::string load_chunk(std::span<const uint8_t> config) {
    ByteReader r(config, "sampler memory chunk");
    r.u8();
    const uint32_t at = r.u32();
    if (r.left() % 4 != 0) return "sampler memory chunk: not a whole number of words";
    const size_t n = r.left() / 4;
    std::vector<uint32_t>& mem = d_.memory();
    if (at > mem.size() || n > mem.size() - at)
      return "sampler memory chunk: words " + std::to_string(at) + ".." + std::to_string(at + n) +
             " past the memory of " + std::to_string(mem.size());
    for (size_t k = 0; k < n; ++k) mem[at + k] = r.u32();
    return "";
  }

  rtl::SamplerDriver<Vtexsim_sampler> d_;
  std::vector<rtl::SamplerDriver<Vtexsim_sampler>::Addresses> reads_;
  size_t reads_seen_ = 0;
};

}  // namespace

std::unique_ptr<BoardBlock> make_rtl_sampler_block() { return std::make_unique<SamplerRtlBlock>(); }

}  // namespace texsim::link
