// Every block's timing() is the shared derivation (blocks/base/derive_timing.h) of its own op
// counts and critical path, also for a technology table other than the defaults. (That every
// block satisfies the Block concept is checked by the static_asserts beside the blocks.)
#include <gtest/gtest.h>

#include "blocks/base/block.h"
#include "blocks/base/derive_timing.h"
#include "blocks/texture/coords/uv_approximation.h"
#include "blocks/texture/coords/uv_heckbert_direct.h"
#include "blocks/texture/coords/uv_incremental_adder.h"
#include "blocks/texture/derivs/derivatives_quad.h"
#include "blocks/texture/derivs/ellipse_setup.h"
#include "blocks/texture/footprint/gaussian_weight.h"
#include "blocks/texture/footprint/weight_map.h"
#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/texture_cache.h"
#include "blocks/texture/subtexel/subtexel_cutoff.h"

namespace texsim {
namespace {

// Latencies and areas unlike the defaults (and not all integers).
TechTable odd_tech() {
  TechTable t;
  t.latency = {2.0, 5.0, 20.0, 9.0, 11.0, 3.5, 0.5, 4.0};
  t.area = {1.5, 10.0, 30.0, 14.0, 20.0, 6.0, 0.25, 0.0};
  return t;
}

void expect_same(const TimingSpec& a, const TimingSpec& b) {
  EXPECT_EQ(a.latency, b.latency);
  EXPECT_EQ(a.ii, b.ii);
  EXPECT_EQ(a.lanes, b.lanes);
  EXPECT_DOUBLE_EQ(a.area, b.area);
}

TEST(BlockTiming, DerivationDefinesSpatialAndShared) {
  const TechTable t = odd_tech();
  OpCounts ops;
  ops.add = 3;
  ops.mul = 2;
  OpCounts path;
  path.add = 2;
  path.mul = 1;
  const TimingSpec s = derive_timing(t, ops, path, Datapath::Spatial, 2);
  EXPECT_EQ(s.latency, 9u);  // 2·2 + 5
  EXPECT_EQ(s.ii, 1u);
  EXPECT_EQ(s.lanes, 2u);
  EXPECT_DOUBLE_EQ(s.area, 2 * (3 * 1.5 + 2 * 10.0));
  const TimingSpec h = derive_timing(t, ops, path, Datapath::Shared);
  EXPECT_EQ(h.ii, 3u);  // three adds on one adder
  EXPECT_EQ(h.latency, 9u + 3u - 1u);
  EXPECT_DOUBLE_EQ(h.area, 1.5 + 10.0);
}

TEST(BlockTiming, CoordinateBlocksUseTheDerivation) {
  const TechTable t = odd_tech();
  for (Datapath dp : {Datapath::Spatial, Datapath::Shared}) {
    UvHeckbertDirect::Config hc;
    hc.datapath = dp;
    const UvHeckbertDirect h(hc);
    expect_same(h.timing(t), derive_timing(t, h.ops_per_item(), h.pixel_critical_path(), dp));
    UvApproximation::Config ac;
    ac.datapath = dp;
    const UvApproximation a(ac);
    expect_same(a.timing(t), derive_timing(t, a.ops_per_item(), a.pixel_critical_path(), dp, 1,
                                           a.row_setup_ops()));
    UvIncrementalAdder::Config ic;
    ic.datapath = dp;
    const UvIncrementalAdder i(ic);
    expect_same(i.timing(t), derive_timing(t, i.ops_per_item(), i.pixel_critical_path(), dp,
                                           i.lane_count(), i.row_setup_ops()));
    DerivativesQuad::Config qc;
    qc.datapath = dp;
    const DerivativesQuad q(qc);
    expect_same(q.timing(t), derive_timing(t, q.ops_per_item(), q.pixel_critical_path(), dp));
    EllipseSetup::Config ec;
    ec.datapath = dp;
    const EllipseSetup e(ec);
    expect_same(e.timing(t), derive_timing(t, e.ops_per_item(), e.pixel_critical_path(), dp));
  }
}

TEST(BlockTiming, SubtexelAndWeightBlocksUseTheDerivation) {
  const TechTable t = odd_tech();
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    SubtexelCutoff::Config c;
    c.evaluator = k;
    c.lanes = 3;
    const SubtexelCutoff cut(c);
    expect_same(cut.timing(t),
                derive_timing(t, cut.ops_per_item(), cut.critical_path(), Datapath::Spatial, 3));
    visit_vd_evaluator(k, [&](auto ev) {
      expect_same(ev.timing(t), derive_timing(t, ev.ops_per_item(), ev.critical_path(),
                                              Datapath::Spatial, ev.config().lanes));
    });
  }
  GaussianWeight::Config gc;
  gc.lanes = 2;
  const GaussianWeight g(gc);
  expect_same(g.timing(t),
              derive_timing(t, g.ops_per_item(), g.texel_critical_path(), Datapath::Spatial, 2));
  const WeightMap m;
  expect_same(m.timing(t),
              derive_timing(t, m.ops_per_item(), m.read_critical_path(), Datapath::Spatial));
}

TEST(BlockTiming, MemoryBlocksUseTheDerivation) {
  const TechTable t = odd_tech();
  const TextureCache cache;
  expect_same(cache.timing(t),
              derive_timing(t, OpCounts{}, double(cache.config().hit_latency), Datapath::Spatial));
  EXPECT_EQ(cache.timing(t).latency, cache.config().hit_latency);
  const DramModel dram;
  EXPECT_EQ(dram.timing(t).latency, dram.config().latency);
  EXPECT_EQ(TextureCache::name(), "cache");
  EXPECT_EQ(TextureCache::arithmetic(), "tag compare");
}

}  // namespace
}  // namespace texsim
