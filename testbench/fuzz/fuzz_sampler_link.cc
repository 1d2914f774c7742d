// libFuzzer harness: the sampler's and the bilinear lerp's link messages
// (rtl_model/link/sampler_link.h, lerp_link.h) from bytes a peer sent. The board reads a
// CONFIGURE state payload (read_sampler_state) or a lerp configuration
// (read_lerp_configuration): only LinkError may leave them, and what they accept stays within
// the board's bounds. The host decodes STREAM results, and the board fragments and lerps, of a
// STREAM of several (any words decode; a trailing part of one is left). The first byte picks
// which, modulo 4.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <vector>

#include "rtl_model/link/framing.h"
#include "rtl_model/link/lerp_link.h"
#include "rtl_model/link/sampler_link.h"

using namespace texsim::link;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::span<const uint8_t> rest(data + 1, size - 1);
  std::vector<uint32_t> words((rest.size() + 3) / 4);
  if (!rest.empty()) std::memcpy(words.data(), rest.data(), rest.size());
  switch (data[0] % 4) {
    case 0:
      try {
        const SamplerState s = read_sampler_state(rest);
        (void)s.memory_words;
      } catch (const LinkError&) {
      }
      break;
    case 1:  // the fragments and results of a STREAM of several (less than one: zeros after)
      words.resize(std::max(kSamplerWords, words.size() / kSamplerWords * kSamplerWords));
      for (size_t at = 0; at < words.size(); at += kSamplerWords) {
        const std::span<const uint32_t, kSamplerWords> w(words.data() + at, kSamplerWords);
        (void)decode_result(w);
        (void)decode_fragment(w);
      }
      break;
    case 2:
      try {
        const texsim::BilinearLerp::Config c = read_lerp_configuration(rest);
        if (c.texel_bits < 1 || c.texel_bits > 16 || c.sub_bits < 1 || c.sub_bits > 16)
          std::abort();
      } catch (const LinkError&) {
      }
      break;
    default:  // lerps: decoded operands encode back to the same words, weights in 16 bits
      for (size_t at = 0; at + kLerpWords <= words.size(); at += kLerpWords) {
        const std::span<const uint32_t, kLerpWords> in(words.data() + at, kLerpWords);
        const LerpOperands op = decode_lerp(in);
        uint32_t back[kLerpWords] = {};
        encode_lerp(op, std::span<uint32_t, kLerpWords>(back));
        if (!std::equal(back, back + kLerpWords, in.begin()) || op.fx > 0xFFFF || op.fy > 0xFFFF)
          std::abort();
      }
      break;
  }
  return 0;
}
