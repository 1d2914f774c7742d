#include "rtl_model/verilator/lerp_rtl_block.h"

#include <Vbilinear_lerp.h>

#include <string>

#include "rtl_model/link/framing.h"
#include "rtl_model/link/lerp_link.h"
#include "rtl_model/params/rtl_params.h"
#include "rtl_model/verilator/rtl_harness.h"

namespace texsim::link {

namespace {

class LerpRtlBlock : public BoardBlock {
 public:
  LerpRtlBlock() : h_("bilinear_lerp") { h_.reset(); }

  BlockCaps caps() const override {
    return {
        "bilinear_lerp", 32, 32,
        static_cast<uint8_t>(BilinearLerp(rtl_params::kLerp).timing(rtl_params::tech()).latency)};
  }

  std::string configure(std::span<const uint8_t> config) override {
    try {
      const BilinearLerp::Config c = read_lerp_configuration(config);
      if (c.texel_bits != rtl_params::kLerp.texel_bits || c.sub_bits != rtl_params::kLerp.sub_bits)
        return "the RTL of bilinear_lerp is built for texel bits " +
               std::to_string(rtl_params::kLerp.texel_bits) + " and sub-texel bits " +
               std::to_string(rtl_params::kLerp.sub_bits) + " only (rtl_model/params/rtl_params.h)";
    } catch (const LinkError& e) {
      return e.what();
    }
    return "";
  }

  // Lerps of kLerpWords inputs each, one per clock; the blended RGBA then zeros per lerp. A
  // trailing partial lerp gives all-ones words (no result the host can take).
  uint64_t apply(std::span<const uint32_t> in, std::span<uint32_t> out) override {
    Vbilinear_lerp& top = h_.top();
    const size_t n = in.size() / kLerpWords;
    const uint64_t first = h_.cycle();
    uint64_t last = first;
    size_t got = 0;
    const uint32_t weight = (uint32_t{1} << rtl_params::kLerp.sub_bits) - 1;
    const auto clock = [&] {
      h_.step();
      if (top.out_valid && got < n) {
        out[got * kLerpWords] = top.out;
        for (size_t k = 1; k < kLerpWords; ++k) out[got * kLerpWords + k] = 0;
        ++got;
        last = h_.cycle();
      }
    };
    for (size_t i = 0; i < n; ++i) {
      const LerpOperands op = decode_lerp(
          std::span<const uint32_t, kLerpWords>(in.data() + i * kLerpWords, kLerpWords));
      top.in_valid = 1;
      top.t00 = op.quad[0];
      top.t10 = op.quad[1];
      top.t01 = op.quad[2];
      top.t11 = op.quad[3];
      top.fx = static_cast<uint8_t>(op.fx & weight);
      top.fy = static_cast<uint8_t>(op.fy & weight);
      clock();
    }
    top.in_valid = 0;
    for (uint32_t i = 0; got < n && i < kDrainLimit; ++i) clock();
    for (size_t w = got * kLerpWords; w < out.size(); ++w) out[w] = ~uint32_t{0};
    return n == 0 ? 0 : last - first;
  }

 private:
  static constexpr uint32_t kDrainLimit = 256;
  rtl::RtlHarness<Vbilinear_lerp> h_;
};

}  // namespace

std::unique_ptr<BoardBlock> make_rtl_lerp_block() { return std::make_unique<LerpRtlBlock>(); }

}  // namespace texsim::link
