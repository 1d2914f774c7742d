// The Vulkan checker for cube maps, cube arrays and array layers: texsim's layered address
// generator passes on random, edge, corner and tie directions and on half-integer layers; the
// checker rejects the controls (a face of the wrong sign at a tie, a non-seamless fetch where
// seamless is asked, layers rounded half up); hard cases (zero and non-finite directions, layers
// far out of range) stay finite. Prints the query counts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "blocks/texture/layered/cube_face_select.h"
#include "blocks/texture/layered/layered_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "testbench/conformance/vulkan_cube_conformance.h"

namespace texsim {
namespace {

Texture random_layered(TextureType type, int n, int slices, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> c(0.0f, 1.0f);
  std::vector<std::vector<float>> s(static_cast<size_t>(slices));
  for (auto& px : s) {
    px.resize(static_cast<size_t>(n) * n * 4);
    for (float& p : px) p = c(rng);
  }
  return Texture::from_slices("t", type, n, n, s, TexelFormat::Rgba32f, true);
}

struct Sampler {
  TexelAddressGen base;
  LayeredAddressGen gen;
  explicit Sampler(bool seamless)
      : base([] {
          TexelAddressGen::Config c;
          c.filter = FilterMode::Bilinear;
          c.address_u = c.address_v = AddressMode::Clamp;
          return c;
        }()),
        gen(base, seamless) {}
  Rgba cube(const Texture& tex, const CubeFaceCoord& c, double lambda, float layer) const {
    FilterTaps taps;
    LodResult lod;
    lod.lambda = static_cast<float>(lambda);
    gen.cube_taps(tex, c, LayeredAddressGen::select_layer(layer, tex.shape().slices / 6), lod,
                  taps);
    return TexelBlend(TexelBlend::Config{}).blend(taps, tex);
  }
  Rgba cube(const Texture& tex, const VkCubeQuery& q) const {
    return cube(tex,
                CubeFaceSelect::select(static_cast<float>(q.dir[0]), static_cast<float>(q.dir[1]),
                                       static_cast<float>(q.dir[2])),
                q.lambda, static_cast<float>(q.layer));
  }
  Rgba array(const Texture& tex, const VkCubeQuery& q, int layer) const {
    FilterTaps taps;
    LodResult lod;
    lod.lambda = static_cast<float>(q.lambda);
    gen.array_taps(tex, q.dir[0], q.dir[1], layer, lod, taps);
    return TexelBlend(TexelBlend::Config{}).blend(taps, tex);
  }
};

// Directions: random, on edges (two equal magnitudes), at corners, near edges.
std::vector<VkCubeQuery> queries(uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), l(0, 3.2), layer(-0.6, 2.6);
  std::uniform_int_distribution<int> sg(0, 1);
  std::vector<VkCubeQuery> out;
  for (int i = 0; i < n; ++i) {
    VkCubeQuery q;
    q.lambda = l(rng);
    q.layer = layer(rng);
    const double a = u(rng), b = u(rng), s1 = sg(rng) ? 1 : -1, s2 = sg(rng) ? 1 : -1;
    const double s3 = sg(rng) ? 1 : -1;
    switch (i % 4) {
      case 0:
        q.dir[0] = a, q.dir[1] = b, q.dir[2] = u(rng);
        break;
      case 1: {  // an edge: two components of equal magnitude, the third smaller
        const int k = i % 3;
        q.dir[k] = s1;
        q.dir[(k + 1) % 3] = s2;
        q.dir[(k + 2) % 3] = a;
        break;
      }
      case 2:  // a corner
        q.dir[0] = s1 * 0.75, q.dir[1] = s2 * 0.75, q.dir[2] = s3 * 0.75;
        break;
      default:  // near an edge, within a texel
        q.dir[0] = s1, q.dir[1] = s2 * (1 - 0.05 * std::fabs(a)), q.dir[2] = b;
        break;
    }
    out.push_back(q);
  }
  return out;
}

TEST(ConformanceCube, TexsimPassesSeamlessAndPerFace) {
  const Texture tex = random_layered(TextureType::Cube, 8, 12, 1);
  int judged = 0;
  for (bool seamless : {true, false}) {
    const VulkanCubeConformance checker(seamless);
    const Sampler s(seamless);
    int fails = 0;
    for (const VkCubeQuery& q : queries(seamless ? 2 : 3, 2000)) {
      const VkCubeVerdict v = checker.check_cube(tex, q, s.cube(tex, q));
      judged += v.judged;
      if (!v.pass) {
        ++fails;
        if (fails < 4)
          ADD_FAILURE() << (seamless ? "seamless " : "per-face ") << q.dir[0] << " " << q.dir[1]
                        << " " << q.dir[2] << " λ " << q.lambda << ": " << v.reason;
      }
    }
    EXPECT_EQ(fails, 0);
  }
  std::printf("cube conformance: %d queries judged, all accepted\n", judged);
}

TEST(ConformanceCube, RejectsTheWrongFaceAtATie) {
  const Texture tex = random_layered(TextureType::Cube, 8, 6, 4);
  const VulkanCubeConformance checker(true);
  const Sampler s(true);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  int rejected = 0, total = 0;
  for (int i = 0; i < 300; ++i) {
    // (1, −1, z): +X and −Y tie; the control takes +Y, the face of the wrong sign.
    VkCubeQuery q;
    q.dir[0] = 1, q.dir[1] = -1, q.dir[2] = u(rng);
    ASSERT_TRUE(checker.check_cube(tex, q, s.cube(tex, q)).pass);
    const CubeFaceCoord wrong = CubeFaceSelect::select(1, 1, static_cast<float>(q.dir[2]));
    ASSERT_EQ(wrong.face, static_cast<int>(CubeFace::PosY));
    rejected += !checker.check_cube(tex, q, s.cube(tex, wrong, q.lambda, 0)).pass;
    ++total;
  }
  std::printf("wrong face at a tie: %d of %d rejected\n", rejected, total);
  EXPECT_GE(rejected, total * 95 / 100);
}

TEST(ConformanceCube, RejectsANonSeamlessFetchWhereSeamlessIsAsked) {
  const Texture tex = random_layered(TextureType::Cube, 8, 6, 6);
  const VulkanCubeConformance seamless(true), per_face(false);
  const Sampler wrong(false);
  int rejected = 0, total = 0;
  for (const VkCubeQuery& q : queries(7, 800)) {
    const Rgba r = wrong.cube(tex, q);
    EXPECT_TRUE(per_face.check_cube(tex, q, r).pass);  // right for its own mode
    // Directions whose filter reaches across an edge (s or t within half a texel of it).
    const CubeFaceCoord c = CubeFaceSelect::select(
        static_cast<float>(q.dir[0]), static_cast<float>(q.dir[1]), static_cast<float>(q.dir[2]));
    const int n = tex.level(tex.slice_level(0, std::clamp(static_cast<int>(std::lround(q.lambda)),
                                                          0, tex.mips() - 1)))
                      .width;
    const float edge = 0.5f / static_cast<float>(n);
    if (!(c.s < edge * 0.8f || c.s > 1 - edge * 0.8f || c.t < edge * 0.8f ||
          c.t > 1 - edge * 0.8f) ||
        n == 1)
      continue;
    ++total;
    rejected += !seamless.check_cube(tex, q, r).pass;
  }
  std::printf("non-seamless where seamless is asked: %d of %d rejected\n", rejected, total);
  ASSERT_GT(total, 100);
  EXPECT_GE(rejected, total * 9 / 10);
}

TEST(ConformanceCube, ArrayLayersAndTheHalfUpControl) {
  std::vector<std::vector<float>> layers;
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<float> c(0, 1);
  for (int l = 0; l < 4; ++l) {
    layers.emplace_back(size_t{16} * 16 * 4);
    for (float& p : layers.back()) p = c(rng);
  }
  const Texture tex =
      Texture::from_slices("a", TextureType::Array, 16, 16, layers, TexelFormat::Rgba32f, true);
  const VulkanCubeConformance checker(true);
  const Sampler s(true);
  std::uniform_real_distribution<double> u(0, 1);
  int pass = 0, rejected = 0, halves = 0;
  const double layer_values[] = {0.5, 1.5, 2.5, -0.5, 3.4999, 1e9, -1e9, 2.0, 0.49999};
  for (int i = 0; i < 200; ++i) {
    VkCubeQuery q;
    q.dir[0] = u(rng), q.dir[1] = u(rng);
    q.lambda = 3 * u(rng);
    q.layer = layer_values[static_cast<size_t>(i) % std::size(layer_values)];
    const int layer = LayeredAddressGen::select_layer(static_cast<float>(q.layer), 4);
    pass += checker.check_array(tex, q, s.array(tex, q, layer)).pass;
    if (q.layer == 0.5 || q.layer == 2.5) {
      // Control: round half up, layer ⌊a + ½⌋.
      const int up = static_cast<int>(std::floor(q.layer + 0.5));
      ++halves;
      rejected += !checker.check_array(tex, q, s.array(tex, q, up)).pass;
    }
  }
  std::printf("array layers: %d of 200 accepted; half-up rounding: %d of %d rejected\n", pass,
              rejected, halves);
  EXPECT_EQ(pass, 200);
  EXPECT_GE(rejected, halves * 95 / 100);
}

TEST(ConformanceCube, HardCasesStayFinite) {
  const Texture tex = random_layered(TextureType::Cube, 4, 6, 9);
  const VulkanCubeConformance checker(true);
  const Sampler s(true);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  const double dirs[][3] = {{0, 0, 0},          {nan, 0, 1},           {inf, 1, 0},
                            {-0.0, -0.0, -0.0}, {1e-40, 1e-40, 1e-40}, {1, 1, 1},
                            {-1, 1, -1},        {1e30, -1e30, 0}};
  for (const auto& d : dirs) {
    VkCubeQuery q;
    q.dir[0] = d[0], q.dir[1] = d[1], q.dir[2] = d[2];
    for (double layer : {0.0, 1e30, -1e30, nan}) {
      q.layer = layer;
      const Rgba r = s.cube(tex, q);
      for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isfinite(r[k]));
      const VkCubeVerdict v = checker.check_cube(tex, q, r);
      EXPECT_TRUE(v.pass) << d[0] << " " << d[1] << " " << d[2] << ": " << v.reason;
    }
  }
  // Depth-1 arrays (one layer): every layer index reads it.
  std::vector<std::vector<float>> one(1, std::vector<float>(size_t{4} * 4 * 4, 0.25f));
  const Texture a =
      Texture::from_slices("one", TextureType::Array, 4, 4, one, TexelFormat::Rgba32f, true);
  VkCubeQuery q;
  q.layer = 7;
  EXPECT_FLOAT_EQ(s.array(a, q, LayeredAddressGen::select_layer(7.0f, 1)).x, 0.25f);
}

}  // namespace
}  // namespace texsim
