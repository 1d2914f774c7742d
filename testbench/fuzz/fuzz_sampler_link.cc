// libFuzzer harness: the sampler's link messages (rtl_model/link/sampler_link.h) from bytes a
// peer sent. The board reads a CONFIGURE state payload (read_sampler_state: only LinkError may
// leave it, and the sizes it accepts stay within the board's bounds); the host decodes a
// STREAM result and the board a fragment (any words decode). The first byte picks which.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <span>

#include "rtl_model/link/framing.h"
#include "rtl_model/link/sampler_link.h"

using namespace texsim::link;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::span<const uint8_t> rest(data + 1, size - 1);
  if (data[0] % 2 == 0) {
    try {
      const SamplerState s = read_sampler_state(rest);
      (void)s.memory_words;
    } catch (const LinkError&) {
    }
    return 0;
  }
  uint32_t words[kSamplerWords] = {};
  std::memcpy(words, rest.data(), std::min(rest.size(), sizeof words));
  const auto r = decode_result(std::span<const uint32_t, kSamplerWords>(words));
  const auto f = decode_fragment(std::span<const uint32_t, kSamplerWords>(words));
  (void)r;
  (void)f;
  return 0;
}
