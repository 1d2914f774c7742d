#include "rtl_model/verilator/vd_rtl_block.h"

#include <Vvd_p1.h>
#include <Vvd_p2.h>

#include <type_traits>

#include "rtl_model/link/framing.h"
#include "rtl_model/params/rtl_params.h"
#include "rtl_model/verilator/rtl_harness.h"

namespace texsim::link {

namespace {

// A V(d) block in RTL: ports d (u0.FIN) and v (u1.FC), one input per clock, fully pipelined.
template <class Model>
class VdRtlBlock : public BoardBlock {
 public:
  explicit VdRtlBlock(const std::string& name) : name_(name), h_(name) {
    h_.reset();
    latency_ = measure_latency();
    h_.reset();
  }

  BlockCaps caps() const override {
    return {name_, static_cast<uint8_t>(rtl_params::kVdFin),
            static_cast<uint8_t>(rtl_params::kVdFc + 1), static_cast<uint8_t>(latency_)};
  }

  std::string configure(std::span<const uint8_t> config) override {
    if (config.size() != 1 || config[0] != rtl_params::kVdFin) {
      return "the RTL of " + name_ + " is built for u0." + std::to_string(rtl_params::kVdFin) +
             " inputs only (rtl_model/params/rtl_params.h): configuration byte " +
             std::to_string(rtl_params::kVdFin);
    }
    return "";
  }

  // Drives `in` back to back, then idles until every result has left the pipeline. The cycles
  // run from the first input's clock to the last result's (n - 1 + latency when pipelined).
  uint64_t apply(std::span<const uint32_t> in, std::span<uint32_t> out) override {
    Model& top = h_.top();
    const uint64_t first = h_.cycle();
    uint64_t last = first;
    size_t got = 0;
    const auto clock = [&] {
      h_.step();
      if (top.out_valid && got < out.size()) {
        out[got++] = static_cast<uint32_t>(top.v);
        last = h_.cycle();
      }
    };
    for (const uint32_t x : in) {
      top.in_valid = 1;
      top.d = static_cast<std::remove_reference_t<decltype(top.d)>>(x);
      clock();
    }
    top.in_valid = 0;
    for (uint32_t i = 0; got < out.size() && i < kDrainLimit; ++i) clock();
    // Results the RTL never gave: all ones, wider than any result, so no comparison passes.
    for (; got < out.size(); ++got) out[got] = ~uint32_t{0};
    return in.empty() ? 0 : last - first;
  }

 private:
  static constexpr uint32_t kDrainLimit = 256;  // far above any V(d) latency

  // Cycles from one input to its result, as the RTL has them.
  uint32_t measure_latency() {
    Model& top = h_.top();
    top.in_valid = 1;
    top.d = 0;
    h_.step();
    top.in_valid = 0;
    for (uint32_t i = 1; i < kDrainLimit && !top.out_valid; ++i) h_.step();
    return static_cast<uint32_t>(h_.cycle());
  }

  std::string name_;
  rtl::RtlHarness<Model> h_;
  uint32_t latency_ = 0;
};

}  // namespace

bool rtl_board_available() { return true; }

int rtl_frac_bits() { return rtl_params::kVdFin; }

std::vector<std::string> rtl_block_names() { return {"vd_p2", "vd_p1"}; }

std::unique_ptr<BoardBlock> make_rtl_block(const std::string& name) {
  if (name == "vd_p2") return std::make_unique<VdRtlBlock<Vvd_p2>>(name);
  if (name == "vd_p1") return std::make_unique<VdRtlBlock<Vvd_p1>>(name);
  std::string known;
  for (const std::string& n : rtl_block_names()) known += (known.empty() ? "" : ", ") + n;
  throw LinkError("no RTL block '" + name + "' (RTL blocks: " + known + ")");
}

}  // namespace texsim::link
