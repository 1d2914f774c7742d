// The ground truth of sampler operations (pipeline/reference/operation_reference.h): each
// operation's truth is what it asks, not the plain filtered sample. Each test names the value
// the plain truth (the level-0 bilinear reconstruction over the footprint) would give, and
// checks that the operation's truth is not it.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "blocks/base/sample_op.h"
#include "pipeline/reference/operation_reference.h"

namespace texsim {
namespace {

// 8x8 RGBA32F; red = f(x, y), green = 1 - red, blue = x / 8, alpha 1.
template <class F>
Texture made(F&& f) {
  std::vector<float> rgba(size_t{8} * 8 * 4);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      float* p = &rgba[(static_cast<size_t>(y) * 8 + static_cast<size_t>(x)) * 4];
      p[0] = f(x, y);
      p[1] = 1.0f - p[0];
      p[2] = static_cast<float>(x) / 8.0f;
      p[3] = 1.0f;
    }
  return Texture::from_rgba("t", 8, 8, rgba, TexelFormat::Rgba32f, false);
}

// texel (x, y)'s red: x + 8y over 64.
Texture numbered() {
  return made([](int x, int y) { return static_cast<float>(x + 8 * y) / 64.0f; });
}

const PixelIntegrator kGrid(TruthPixel::Box, TruthSampling{16});

Fragment at(double u, double v, SampleOp op) {
  Fragment f;
  f.u = u;
  f.v = v;
  f.dudx = f.dvdy = 1.0 / 8;  // one texel per pixel
  f.op = static_cast<uint8_t>(op);
  return f;
}

TEST(OperationTruth, GatherIsTheFourTexelsInTheSpecsOrder) {
  const Texture t = numbered();
  OperationSampler s;
  s.au = s.av = AddressMode::Clamp;
  // (u, v) between texels (2, 3), (3, 3), (2, 4), (3, 4): i0 = 2, j0 = 3.
  Fragment f = at(3.2 / 8, 4.1 / 8, SampleOp::kGather);
  f.gather_component = 0;
  const glm::dvec4 g = ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid);
  const auto red = [&](int x, int y) { return static_cast<double>(t.texel(0, x, y).r); };
  EXPECT_EQ(g, glm::dvec4(red(2, 4), red(3, 4), red(3, 3), red(2, 3)));
  // The plain truth would be a blend of them: every channel differs from it.
  const glm::dvec4 plain = reference_bilinear(t, s.au, s.av, f.u, f.v);
  for (int k = 0; k < 4; ++k) EXPECT_NE(g[k], plain.r) << k;
  // An offset (1, -1) moves the quad; green, compared with 0.7 (LESS: 0.7 < texel).
  s.offset_u = 1;
  s.offset_v = -1;
  s.compare = CompareOp::Less;
  f.gather_component = 1;
  f.compare_ref = 0.7f;
  const glm::dvec4 c = ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid);
  const auto pass = [&](int x, int y) { return 0.7f < t.texel(0, x, y).g ? 1.0 : 0.0; };
  EXPECT_EQ(c, glm::dvec4(pass(3, 3), pass(4, 3), pass(4, 2), pass(3, 2)));
}

TEST(OperationTruth, DepthComparisonComparesEachTexelBeforeTheWeights) {
  // Depth 0.2 left of x = 4, 0.8 from it: a reference of 0.5 with LESS passes on the right.
  const Texture t = made([](int x, int) { return x < 4 ? 0.2f : 0.8f; });
  OperationSampler s;
  s.au = s.av = AddressMode::Clamp;
  s.compare = CompareOp::Less;
  Fragment f = at(4.0 / 8, 0.5, SampleOp::kSample);  // the footprint [3.5, 4.5] texels across
  f.compare_ref = 0.5f;
  const glm::dvec4 pcf = ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid);
  // Bilinear of the 0/1 results over the footprint: by symmetry one half.
  EXPECT_NEAR(pcf.r, 0.5, 1e-9);
  EXPECT_EQ(pcf.g, pcf.r);
  EXPECT_EQ(pcf.a, 1.0);
  // Comparing the filtered depth (0.5 here) instead: 0.5 < 0.5 fails, 0, not one half.
  const double filtered = reference_bilinear(t, s.au, s.av, f.u, f.v).r;
  EXPECT_NEAR(filtered, 0.5, 1e-6);
  EXPECT_GT(std::fabs(pcf.r - (0.5f < filtered ? 1.0 : 0.0)), 0.4);
  // A reference of 0.9: nothing passes; D16 clamps 1.5 to 1 (passes nothing either), 0.1 all.
  f.compare_ref = 0.9f;
  EXPECT_EQ(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, 0.0);
  f.compare_ref = 0.1f;
  EXPECT_NEAR(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, 1.0, 1e-12);
  // D16 clamps the reference to [0, 1]: −3 becomes 0, EQUAL to the texels of depth 0.
  const Texture d = made([](int x, int) { return x < 4 ? 0.0f : 1.0f; });
  s.compare = CompareOp::Equal;
  f = at(1.5 / 8, 0.5, SampleOp::kSample);
  f.compare_ref = -3.0f;
  EXPECT_EQ(ground_truth_operation(d, s, f, nullptr, 0, 0, kGrid).r, 0.0);
  s.unorm_depth = true;
  EXPECT_NEAR(ground_truth_operation(d, s, f, nullptr, 0, 0, kGrid).r, 1.0, 1e-12);
}

TEST(OperationTruth, MinMaxIsOverTheFootprintsTexels) {
  const Texture t = numbered();
  OperationSampler s;
  s.au = s.av = AddressMode::Clamp;
  s.reduction = Reduction::Max;
  // A footprint of 2 x 2 texels centred on the corner of texels (3, 3) … (4, 4): centre
  // (4, 4) texels; bilinear reads texels 2..5 in each axis (|x − (i + ½)| < 1 somewhere).
  Fragment f = at(0.5, 0.5, SampleOp::kSample);
  f.dudx = f.dvdy = 2.0 / 8;
  const glm::dvec4 mx = ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid);
  EXPECT_EQ(mx.r, t.texel(0, 5, 5).r);
  EXPECT_EQ(mx.g, t.texel(0, 2, 2).g);  // green = 1 − red: its max at the smallest red
  EXPECT_EQ(mx.b, 5.0 / 8);
  s.reduction = Reduction::Min;
  const glm::dvec4 mn = ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid);
  EXPECT_EQ(mn.r, t.texel(0, 2, 2).r);
  // The plain truth (the footprint's mean) lies strictly between them.
  const double mean = reference_bilinear(t, s.au, s.av, 0.5, 0.5).r;
  EXPECT_GT(mx.r - mean, 0.1);
  EXPECT_GT(mean - mn.r, 0.1);
  // A footprint on texel (1, 1)'s centre with no extent reads that texel alone.
  f = at(1.5 / 8, 1.5 / 8, SampleOp::kSample);
  f.dudx = f.dvdy = 0;
  EXPECT_EQ(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, t.texel(0, 1, 1).r);
}

TEST(OperationTruth, ExplicitLodIsTheSquareOfItsLevelAndGradientsTheirParallelogram) {
  // Stripes one texel wide: the plain truth of a magnified pixel keeps them, LOD 1 (a square
  // of 2 × 2 texels) averages them to ½.
  const Texture t = made([](int x, int) { return x % 2 == 0 ? 1.0f : 0.0f; });
  OperationSampler s;
  s.au = s.av = AddressMode::Wrap;
  Fragment f = at(2.5 / 8, 0.5, SampleOp::kSampleLod);  // on texel 2's centre
  f.dudx = f.dvdy = 0.01 / 8;                           // magnified 100 x
  f.lod = 1;
  EXPECT_NEAR(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, 0.5, 1e-3);
  EXPECT_NEAR(reference_bilinear(t, s.au, s.av, f.u, f.v).r, 1.0, 1e-9);  // the plain truth
  // The sampler's bias and clamp take part: LOD −1 biased by +2 is LOD 1; max_lod 0 keeps the
  // square at one texel (the tent of texels 1..3 around texel 2: ¾).
  f.lod = -1;
  s.lod_bias = 2;
  EXPECT_NEAR(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, 0.5, 1e-3);
  s.max_lod = 0;
  EXPECT_NEAR(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, 0.75, 1e-3);
  // LOD −1 unbiased is clamped to min_lod 0 (level 0), but its footprint stays half a texel
  // (the tent over texel 2's middle half: ⅞).
  s = {};
  EXPECT_NEAR(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, 0.875, 1e-3);
  // Gradients of 2 texels along u and v: their footprint averages the stripes.
  s = {};
  f.op = static_cast<uint8_t>(SampleOp::kSampleGrad);
  f.dudx = 2.0 / 8;
  f.dvdy = 2.0 / 8;
  EXPECT_NEAR(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, 0.5, 1e-3);
  // 0.01 texels: the tent's mean over ±0.005 texels, 1 − 0.0025 (not widened to a texel by
  // the clamp to min_lod 0, which would give ¾).
  f.dudx = f.dvdy = 0.01 / 8;
  EXPECT_NEAR(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r, 0.9975, 1e-6);
  // Its footprint: the parallelogram scaled by the bias (2^1: 4 texels from 2).
  f.dudx = f.dvdy = 2.0 / 8;
  s.lod_bias = 1;
  const OperationFootprint fp = operation_footprint(f, s, 8, 8, nullptr);
  EXPECT_NEAR(fp.a.x * 8, 4.0, 1e-12);
  EXPECT_NEAR(fp.b.y * 8, 4.0, 1e-12);
}

TEST(OperationTruth, UnnormalisedCoordinatesReadLevelZeroInTexels) {
  const Texture t = numbered();
  OperationSampler s;
  s.au = s.av = AddressMode::Clamp;
  s.unnormalized = true;
  s.max_lod = 0;
  Fragment f = at(3.5, 2.5, SampleOp::kSampleLod);  // texel (3, 2)'s centre, in texels
  const glm::dvec4 v = ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid);
  // The point's bilinear value: the texel's own at its centre, a blend off it.
  EXPECT_NEAR(v.r, t.texel(0, 3, 2).r, 1e-6);
  f.u = 3.75;
  EXPECT_NEAR(ground_truth_operation(t, s, f, nullptr, 0, 0, kGrid).r,
              0.75 * t.texel(0, 3, 2).r + 0.25 * t.texel(0, 4, 2).r, 1e-6);
  // Read as normalised coordinates (the plain truth), (3.5, 2.5) clamps to the last texel.
  EXPECT_NEAR(reference_bilinear(t, s.au, s.av, f.u, f.v).r, t.texel(0, 7, 7).r, 1e-9);
}

TEST(OperationTruth, APlainSampleHasNoOperationTruth) {
  OperationSampler s;
  EXPECT_FALSE(operation_truth_applies(at(0.5, 0.5, SampleOp::kSample), s));
  EXPECT_TRUE(operation_truth_applies(at(0.5, 0.5, SampleOp::kGather), s));
  s.reduction = Reduction::Min;
  EXPECT_TRUE(operation_truth_applies(at(0.5, 0.5, SampleOp::kSample), s));
}

}  // namespace
}  // namespace texsim
