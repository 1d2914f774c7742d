// Lockstep of the bilinear lerp datapath (rtl_model/rtl/bilinear_lerp.v) against its C++ core
// (blocks/texture/sampler/bilinear_lerp.h) at the precision of rtl_model/params/rtl_params.h:
// directed corners (zero and full-scale texels, extreme weights, alternating channels) and
// seeded random quads and weights with random idle cycles. Also checks the core itself
// against the real-valued bilinear interpolation (within half an LSB).
#include <Vbilinear_lerp.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "rtl_model/params/rtl_params.h"
#include "testbench/rtl/lockstep.h"
#include "testbench/rtl/rtl_vectors.h"

namespace texsim::rtl {
namespace {

Scoreboard run_lerp(uint64_t n_random, uint32_t latency, int64_t perturb = 0,
                    size_t perturb_at = 0) {
  using Model = Vbilinear_lerp;
  const BilinearLerp core(rtl_params::kLerp);
  RtlHarness<Model> h("bilinear_lerp");
  h.reset();
  Scoreboard sb("bilinear_lerp", latency);
  const std::vector<LerpIn> vectors = lerp_vectors(rtl_params::kLerp, n_random, 21);
  // Words are packed into the model's ports: 32-bit ports for RGBA8 texels.
  auto set_in = [](Model& top, const LerpIn& in) {
    top.t00 = static_cast<uint32_t>(in.quad[0]);
    top.t10 = static_cast<uint32_t>(in.quad[1]);
    top.t01 = static_cast<uint32_t>(in.quad[2]);
    top.t11 = static_cast<uint32_t>(in.quad[3]);
    top.fx = static_cast<uint8_t>(in.fx);
    top.fy = static_cast<uint8_t>(in.fy);
  };
  stream_lockstep(
      h, sb, vectors, set_in, [](Model& top) { return OutWords{static_cast<int64_t>(top.out)}; },
      [&](const LerpIn& in, OpCounts& ops) {
        return OutWords{static_cast<int64_t>(core.lerp(in.quad, in.fx, in.fy, ops))};
      },
      35, 0.125, perturb, perturb_at);
  std::cout << sb.summary() << "\n" << sb.report();
  return sb;
}

uint32_t lerp_latency() {
  return BilinearLerp(rtl_params::kLerp).timing(rtl_params::tech()).latency;
}

// The ports above are sized for RGBA8 quads and 8-bit weights.
static_assert(rtl_params::kLerp.texel_bits == 8 && rtl_params::kLerp.sub_bits == 8);

TEST(RtlLockstep, BilinearLerpMatchesCppBitForBit) {
  const Scoreboard sb = run_lerp(lockstep_vectors(), lerp_latency());
  EXPECT_EQ(sb.mismatches(), 0u) << sb.report();
  EXPECT_GT(sb.compared(), lockstep_vectors());
}

TEST(RtlLockstep, BilinearLerpScoreboardCatchesOneLsb) {
  const Scoreboard sb = run_lerp(1000, lerp_latency(), 1, 500);
  EXPECT_EQ(sb.mismatches(), 1u);
  EXPECT_NE(sb.report().find("transaction 500"), std::string::npos) << sb.report();
}

// The core rounds the exact bilinear value of the quantised weights once: within 1/2 LSB.
TEST(BilinearLerpCore, WithinHalfLsbOfExactBilinear) {
  std::mt19937_64 rng(5);
  for (int sub : {1, 4, 8, 12}) {
    std::uniform_int_distribution<uint32_t> texel(0, 255), weight(0, (1u << sub) - 1);
    for (int i = 0; i < 20000; ++i) {
      const uint32_t t00 = texel(rng), t10 = texel(rng), t01 = texel(rng), t11 = texel(rng);
      const uint32_t fx = weight(rng), fy = weight(rng);
      const double ax = std::ldexp(fx, -sub), ay = std::ldexp(fy, -sub);
      const double exact =
          (1 - ay) * ((1 - ax) * t00 + ax * t10) + ay * ((1 - ax) * t01 + ax * t11);
      const uint32_t out = BilinearLerp::lerp_channel(t00, t10, t01, t11, fx, fy, sub);
      ASSERT_LE(std::fabs(out - exact), 0.5 + 1e-9)
          << sub << " " << t00 << " " << t10 << " " << t01 << " " << t11 << " " << fx << " " << fy;
    }
  }
}

}  // namespace
}  // namespace texsim::rtl
