// Runs one block of an installed texsim: the sampler's sRGB decoder after the filter, on a
// grey whose linear value is known, and its operation count per fragment.
#include <cmath>
#include <cstdio>

#include "blocks/texture/sampler/srgb_decoder.h"

int main() {
  const texsim::SrgbDecoder decoder(texsim::SrgbDecode::AfterFilter, 4);
  const texsim::Rgba linear = texsim::SrgbDecoder::decode_filtered(texsim::Rgba(0.5f));
  const double expected = std::pow((0.5 + 0.055) / 1.055, 2.4);  // the sRGB EOTF at 0.5
  const uint64_t ops = decoder.ops_per_item().total();
  std::printf("srgb_decode(0.5) = %.6f (expected %.6f), alpha %.1f, %llu ops per fragment\n",
              static_cast<double>(linear.r), expected, static_cast<double>(linear.a),
              static_cast<unsigned long long>(ops));
  const bool ok = std::fabs(linear.r - expected) < 1e-6 && linear.a == 0.5f && ops > 0;
  return ok ? 0 : 1;
}
