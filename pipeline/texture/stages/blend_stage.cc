#include "pipeline/texture/stages/blend_stage.h"

namespace texsim {

BlendStage::BlendStage(const TexelBlend::Config& c, uint32_t taps_per_probe, bool bypassed)
    : blend_(c), bypassed_(bypassed) {
  for (int n = 1; n <= 16; ++n) {
    FilterTaps t;
    t.count = n * static_cast<int>(taps_per_probe);
    extra_ii_[n] = blend_.issue_cycles(t) - 1;
  }
}

}  // namespace texsim
