#include "rtl_model/link/vd_core_block.h"

#include "blocks/base/tech_table.h"
#include "blocks/texture/subtexel/vd_evaluator_p1.h"
#include "blocks/texture/subtexel/vd_evaluator_p2.h"
#include "rtl_model/link/framing.h"

namespace texsim::link {

namespace {

template <class Ev>
class VdCoreBlock : public BoardBlock {
 public:
  explicit VdCoreBlock(std::string name)
      : name_(std::move(name)), latency_(Ev{}.timing(TechTable::defaults()).latency) {}

  BlockCaps caps() const override {
    // u0.F in, u1.(F-1) out: both F bits wide.
    return {name_, static_cast<uint8_t>(frac_), static_cast<uint8_t>(frac_),
            static_cast<uint8_t>(latency_)};
  }

  std::string configure(std::span<const uint8_t> config) override {
    if (config.size() != 1 || (config[0] != 16 && config[0] != 12 && config[0] != 8)) {
      return name_ + " takes one configuration byte, the input fraction bits: 16, 12 or 8";
    }
    frac_ = config[0];
    return "";
  }

  uint64_t apply(std::span<const uint32_t> in, std::span<uint32_t> out) override {
    for (size_t i = 0; i < in.size(); ++i) out[i] = eval(in[i]);
    // Fully pipelined: one input per cycle, the last result `latency` cycles after its input.
    return in.empty() ? 0 : in.size() - 1 + latency_;
  }

 private:
  template <class Fmt>
  static uint32_t eval_in(uint32_t code) {
    const auto v = Ev{}.template eval<Fmt>(Fmt::In::from_raw(code));
    return static_cast<uint32_t>(v.raw());
  }
  uint32_t eval(uint32_t code) const {
    switch (frac_) {
      case 12:
        return eval_in<VdFx12>(code);
      case 8:
        return eval_in<VdFx8>(code);
      default:
        return eval_in<VdFx16>(code);
    }
  }

  std::string name_;
  uint32_t latency_;
  int frac_ = 16;
};

}  // namespace

std::vector<std::string> core_block_names() { return {"vd_p2", "vd_p1"}; }

std::unique_ptr<BoardBlock> make_core_block(const std::string& name) {
  if (name == "vd_p2") return std::make_unique<VdCoreBlock<VdEvaluatorP2>>(name);
  if (name == "vd_p1") return std::make_unique<VdCoreBlock<VdEvaluatorP1>>(name);
  std::string known;
  for (const std::string& n : core_block_names()) known += (known.empty() ? "" : ", ") + n;
  throw LinkError("no block '" + name + "' (blocks: " + known + ")");
}

}  // namespace texsim::link
