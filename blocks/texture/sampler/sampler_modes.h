#pragma once
// Sampler state beyond filter and addressing: the reduction (VK_EXT_sampler_filter_minmax) and
// the depth comparison (compareEnable + compareOp). TexelAddressGen::Config carries them; the
// texel reducer (texel_reduce.h) applies them in place of the weighted blend.
#include <cstdint>
#include <string_view>

namespace texsim {

enum class Reduction : uint8_t { WeightedAverage, Min, Max };
inline constexpr std::string_view kReductionNames[] = {"weighted_average", "min", "max"};

// None: no comparison (compareEnable = false); the others are VkCompareOp in its order.
enum class CompareOp : uint8_t {
  None,
  Never,
  Less,
  Equal,
  LessOrEqual,
  Greater,
  NotEqual,
  GreaterOrEqual,
  Always
};
inline constexpr std::string_view kCompareOpNames[] = {
    "none",  "never", "less", "equal", "less_or_equal", "greater", "not_equal", "greater_or_equal",
    "always"};

// Vulkan's depth comparison: `reference OP texel` (VK_COMPARE_OP_LESS passes when
// reference < texel); IEEE comparisons, so a NaN fails all but NOT_EQUAL and ALWAYS.
inline bool compare_passes(CompareOp op, float reference, float texel) {
  switch (op) {
    case CompareOp::None:
    case CompareOp::Never:
      return false;
    case CompareOp::Less:
      return reference < texel;
    case CompareOp::Equal:
      return reference == texel;
    case CompareOp::LessOrEqual:
      return reference <= texel;
    case CompareOp::Greater:
      return reference > texel;
    case CompareOp::NotEqual:
      return reference != texel;
    case CompareOp::GreaterOrEqual:
      return reference >= texel;
    case CompareOp::Always:
      return true;
  }
  return false;
}

}  // namespace texsim
