// AstcDecoder against the ARM reference codec on random 16-byte blocks at every 2-D footprint:
// plain random bytes (mostly reserved or illegal blocks), random void-extent blocks, and random
// blocks under a legal block mode (partitions, dual planes, every endpoint mode, colour ranges
// too small to fit). Every texel of every block is compared with astcenc's decoding of a .astc
// file made of those blocks; docs/derivations/astc.md §9 lists the two places where astcenc
// 4.2 departs from the spec and the spec is required instead.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "blocks/texture/decode/astc_block_mode.h"
#include "testbench/lib/astc_reference.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

using astc_reference::AstcFile;
using astc_reference::Image;
using astc_reference::Tally;

void set_bits(std::vector<uint8_t>& b, size_t block, int pos, int count, uint64_t v) {
  for (int i = 0; i < count; ++i) {
    const size_t byte = block * 16 + static_cast<size_t>((pos + i) / 8);
    const auto mask = static_cast<uint8_t>(1U << ((pos + i) % 8));
    b[byte] = static_cast<uint8_t>(((v >> i) & 1U) != 0 ? (b[byte] | mask) : (b[byte] & ~mask));
  }
}

// `count` blocks for a footprint: a quarter plain random, a sixth void extents, the rest random
// under one of the footprint's legal block modes.
std::vector<uint8_t> random_blocks(int bw, int bh, size_t count, std::mt19937_64& rng) {
  std::vector<uint32_t> legal;
  for (uint32_t m = 0; m < 2048; ++m) {
    if (astc_decode_block_mode(m, bw, bh).kind == AstcBlockMode::Kind::Normal) legal.push_back(m);
  }
  std::vector<uint8_t> b(count * 16);
  for (auto& x : b) x = static_cast<uint8_t>(rng());
  for (size_t i = 0; i < count; ++i) {
    const uint64_t r = rng();
    switch (r % 12) {
      case 0:
      case 1:
      case 2:
        break;  // plain random
      case 3:
      case 4: {
        set_bits(b, i, 0, 9, 0x1FC);
        set_bits(b, i, 9, 1, (r >> 8) % 8 == 0 ? 1 : 0);        // HDR now and then
        if ((r >> 12) % 8 != 0) set_bits(b, i, 10, 2, 3);       // reserved bits mostly right
        if ((r >> 16) % 2 == 0) set_bits(b, i, 12, 52, ~0ULL);  // "no extent" (all 1s)
        break;
      }
      default:
        set_bits(b, i, 0, 11, legal[static_cast<size_t>((r >> 8) % legal.size())]);
        break;
    }
  }
  return b;
}

struct Footprint {
  int w, h;
};

class AstcRandomBlocks : public ::testing::TestWithParam<Footprint> {};

TEST_P(AstcRandomBlocks, EveryTexelMatchesAstcenc) {
  if (!std::filesystem::exists(astc_reference::kAstcenc)) GTEST_SKIP() << "astcenc missing";
  const Footprint fp = GetParam();
  std::mt19937_64 rng(0xA57CU + static_cast<uint64_t>(fp.w * 16 + fp.h));
  AstcFile f;
  f.block_width = fp.w;
  f.block_height = fp.h;
  f.width = 32 * fp.w;
  f.height = 32 * fp.h;
  f.blocks = random_blocks(fp.w, fp.h, size_t{32} * 32, rng);
  const TempDir dir("texsim_astc_random");
  const std::string astc = dir.file("r.astc"), exr = dir.file("r.exr");
  ASSERT_TRUE(astc_reference::write_astc(astc, f));
  ASSERT_TRUE(astc_reference::run_astcenc({"-dl", astc, exr}));
  Image ref;
  ASSERT_TRUE(astc_reference::read_exr(exr, &ref));
  Tally t;
  astc_reference::compare_blocks(f, ref, &t);
  EXPECT_EQ(t.mismatches, 0U);
  // The mix reaches every kind of block.
  EXPECT_GT(t.void_extent, 0U);
  EXPECT_GT(t.error_blocks, 0U);
  EXPECT_GT(t.hdr_partition_texels, 0U);
  EXPECT_GT(t.multi_partition, 0U);
  EXPECT_GT(t.dual_plane, 0U);
  char what[32];
  std::snprintf(what, sizeof what, "random %dx%d", fp.w, fp.h);
  std::printf("%s\n", astc_reference::tally_row(what, t).c_str());
}

INSTANTIATE_TEST_SUITE_P(AllFootprints, AstcRandomBlocks,
                         ::testing::Values(Footprint{4, 4}, Footprint{5, 4}, Footprint{5, 5},
                                           Footprint{6, 5}, Footprint{6, 6}, Footprint{8, 5},
                                           Footprint{8, 6}, Footprint{8, 8}, Footprint{10, 5},
                                           Footprint{10, 6}, Footprint{10, 8}, Footprint{10, 10},
                                           Footprint{12, 10}, Footprint{12, 12}));

}  // namespace
}  // namespace texsim
