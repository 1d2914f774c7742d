// Stability suite of the relief, terrain and lighting blocks: view rays parallel to the
// surface, heights at 0 and at the maximum, flat maps, one-texel spikes, distance maps at the
// volume border, DEM no-data and NaN heights or view vectors — each with a bound or a defined
// fallback (docs/derivations/relief.md §5, terrain.md §6, lighting.md §3).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "blocks/lighting/blinn_phong_shader.h"
#include "blocks/lighting/normal_unit.h"
#include "blocks/texture/relief/distance_map_builder.h"
#include "blocks/texture/relief/parallax_mapper.h"
#include "blocks/texture/relief/sphere_tracer.h"
#include "blocks/texture/relief/terrain_ray_marcher.h"
#include "blocks/texture/relief/visibility_aware_filter.h"

namespace texsim {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

DistanceMapBuilder builder(int32_t depth) {
  DistanceMapBuilder::Config c;
  c.depth = depth;
  c.polar_steps = 2;
  c.azimuth_steps = 8;
  return DistanceMapBuilder(c);
}

ReliefHeightMap spike_map() {
  ReliefHeightMap hm(9, 9, 0.0F);
  hm.at(4, 4) = 1.0F;  // one texel at the maximum
  return hm;
}

TEST(StabilityRelief, TracerRayParallelToTheSurfaceEndsAtTheSideOrTheCap) {
  const auto b = builder(8);
  for (const bool refined : {false, true}) {
    const ReliefHeightMap hm(16, 16, 0.25F);
    const DistanceMap m = refined ? b.refined(hm) : b.classic(hm);
    const SphereTracer tracer;
    OpCounts ops;
    const auto r = tracer.trace(m, {1, 8, 5}, {1, 0, 0}, ops);
    EXPECT_EQ(r.status, SphereTracer::Status::Miss);  // level above the relief: out at x = 15.5
    EXPECT_LE(r.iterations, 64U);
    SphereTracer::Config c;
    c.max_iterations = 2;
    const auto capped = SphereTracer(c).trace(m, {1, 8, 5}, {1, 0, 0}, ops);
    EXPECT_EQ(capped.status, SphereTracer::Status::Capped);
    EXPECT_EQ(capped.iterations, 2U);
    EXPECT_EQ(capped.fetches, 3U);
  }
}

TEST(StabilityRelief, TracerNaNOrZeroInputsAreInvalidWithoutReads) {
  const auto b = builder(4);
  const DistanceMap m = b.classic(ReliefHeightMap(4, 4, 0.5F));
  const SphereTracer tracer;
  OpCounts ops;
  for (const auto& [p, d] : {std::pair{glm::dvec3(1, 1, 3), glm::dvec3(kNaN, 0, -1)},
                             std::pair{glm::dvec3(kNaN, 1, 3), glm::dvec3(0, 0, -1)},
                             std::pair{glm::dvec3(1, 1, 3), glm::dvec3(0, 0, 0)}}) {
    const auto r = tracer.trace(m, p, d, ops);
    EXPECT_EQ(r.status, SphereTracer::Status::Invalid);
    EXPECT_EQ(r.fetches, 0U);
  }
  EXPECT_EQ(ops.mem, 0U);
}

TEST(StabilityRelief, DistanceMapsOfFlatMapsAtZeroAndMaximum) {
  const auto b = builder(6);
  const DistanceMap zero = b.classic(ReliefHeightMap(5, 5, 0.0F));
  const DistanceMap full = b.classic(ReliefHeightMap(5, 5, 1.0F));
  const DistanceMap zero_r = b.refined(ReliefHeightMap(5, 5, 0.0F));
  for (int32_t z = 0; z < 6; ++z) {
    EXPECT_FLOAT_EQ(zero.at(2, 2, z), static_cast<float>(z + 1));    // the base, z + 1 below
    EXPECT_FLOAT_EQ(full.at(2, 2, z), 0.0F);                         // everything solid
    EXPECT_FLOAT_EQ(zero_r.at(2, 2, z), static_cast<float>(z + 1));  // straight down: z + 1/2 + 1/2
  }
  // A ray into a full volume stops at once; into an empty one, at the base.
  const SphereTracer tracer;
  OpCounts ops;
  auto r = tracer.trace(full, {2, 2, 10}, {0, 0, -1}, ops);
  EXPECT_EQ(r.status, SphereTracer::Status::Hit);
  EXPECT_EQ(r.iterations, 0U);
  r = tracer.trace(zero, {2, 2, 10}, {0, 0, -1}, ops);
  EXPECT_EQ(r.status, SphereTracer::Status::Hit);
  EXPECT_LT(r.pos.z, -0.5 + 1e-6);
  EXPECT_LE(r.iterations, 2U);
}

TEST(StabilityRelief, OneTexelSpikeIsFoundByBothMaps) {
  const auto b = builder(8);
  const ReliefHeightMap hm = spike_map();
  const DistanceMap classic = b.classic(hm), refined = b.refined(hm);
  EXPECT_FLOAT_EQ(classic.at(4, 4, 7), 0.0F);
  EXPECT_FLOAT_EQ(classic.at(4, 4, 7), refined.at(4, 4, 7));
  const SphereTracer tracer;
  for (const DistanceMap* m : {&classic, &refined}) {
    OpCounts ops;
    // Straight down onto the spike's top, and slanted into its side.
    auto r = tracer.trace(*m, {4, 4, 9}, {0, 0, -1}, ops);
    EXPECT_EQ(r.status, SphereTracer::Status::Hit);
    EXPECT_NEAR(r.pos.z, 7.5, 0.5 + 1e-9);
    r = tracer.trace(*m, {1.5, 4, 7.4}, {1, 0, -1}, ops);  // 45°: inside the cone
    EXPECT_EQ(r.status, SphereTracer::Status::Hit);
    EXPECT_NEAR(r.pos.x, 3.5, 1.0);  // within a voxel of the spike's face
  }
  // A ray outside the refined map's cone (73° from the normal) is not covered by it: the classic
  // map finds the spike, the refined one may step past it (defined: a miss at the side).
  OpCounts ops;
  const auto c = tracer.trace(classic, {1, 4, 7.4}, {1, 0, -0.3}, ops);
  EXPECT_EQ(c.status, SphereTracer::Status::Hit);
  EXPECT_NEAR(c.pos.x, 3.5, 1.0);
  const auto r = tracer.trace(refined, {1, 4, 7.4}, {1, 0, -0.3}, ops);
  EXPECT_TRUE(r.status == SphereTracer::Status::Hit || r.status == SphereTracer::Status::Miss);
  EXPECT_LE(r.iterations, 64U);
}

TEST(StabilityRelief, DistanceMapBorderRaysLeaveAsMisses) {
  const auto b = builder(8);
  const ReliefHeightMap hm(6, 6, 0.5F);
  for (const DistanceMap& m : {b.classic(hm), b.refined(hm)}) {
    const SphereTracer tracer;
    OpCounts ops;
    // From the border voxels outwards and down at a shallow angle: leaves through the side.
    auto r = tracer.trace(m, {5, 2, 7}, {1, 0, -0.1}, ops);
    EXPECT_EQ(r.status, SphereTracer::Status::Miss);
    r = tracer.trace(m, {0, 0, 7}, {-1, -1, -0.2}, ops);
    EXPECT_EQ(r.status, SphereTracer::Status::Miss);
    // Every refined value at the border is finite and at least the entry distance 1/2.
    for (int32_t z = 4; z < 8; ++z) {
      EXPECT_TRUE(std::isfinite(m.at(5, 5, z)));
      EXPECT_GE(m.at(0, 5, z), 0.5F);
    }
  }
}

TEST(StabilityRelief, NaNHeightsReadAsZero) {
  const auto b = builder(6);
  ReliefHeightMap with_nan = spike_map(), with_zero = spike_map();
  with_nan.at(2, 3) = std::numeric_limits<float>::quiet_NaN();
  with_zero.at(2, 3) = 0.0F;
  EXPECT_EQ(b.classic(with_nan).d, b.classic(with_zero).d);
  EXPECT_EQ(b.refined(with_nan).d, b.refined(with_zero).d);
  const ParallaxMapper pm;
  OpCounts ops;
  const auto a = pm.map(with_nan, 2.2, 3.1, 0.4, 0.1, 0.6, ops);
  const auto z = pm.map(with_zero, 2.2, 3.1, 0.4, 0.1, 0.6, ops);
  EXPECT_EQ(a.u, z.u);
  EXPECT_EQ(a.v, z.v);
}

TEST(StabilityRelief, ParallaxGrazingViewIsBoundedBySettings) {
  const ReliefHeightMap hm = spike_map();
  for (const auto& v : {glm::dvec3(1, 0, 0), glm::dvec3(0.7, 0.7, 0), glm::dvec3(1, 0, -0.5),
                        glm::dvec3(1, 0, 1e-12)}) {
    ParallaxMapper::Config c;
    const ParallaxMapper it(c);
    OpCounts ops;
    const auto r = it.map(hm, 4, 4, v.x, v.y, v.z, ops);
    EXPECT_FALSE(r.bad_input);
    EXPECT_LE(r.linear_steps, static_cast<uint32_t>(c.max_layers + 1));
    EXPECT_LE(r.binary_steps, static_cast<uint32_t>(c.binary_steps));
    // The shift is at most depth_texels / min_view_z along the unit view vector's xy.
    EXPECT_LE(std::hypot(r.u - 4, r.v - 4), c.depth_texels / c.min_view_z + 1e-9);
    EXPECT_GE(r.depth, 0.0);
    EXPECT_LE(r.depth, 1.0);
    c.method = ParallaxMapper::Method::Offset;
    const auto o = ParallaxMapper(c).map(hm, 4, 4, v.x, v.y, v.z, ops);
    EXPECT_LE(std::hypot(o.u - 4, o.v - 4), c.depth_texels + 1e-9);  // offset limiting
  }
}

TEST(StabilityRelief, ParallaxNaNViewOrCoordinatesAreUnshifted) {
  const ParallaxMapper pm;
  const ReliefHeightMap hm = spike_map();
  OpCounts ops;
  for (const auto& in :
       {std::array<double, 5>{kNaN, 1, 0, 0, 1}, std::array<double, 5>{1, 1, kNaN, 0, 1},
        std::array<double, 5>{1, 1, 0, 0, 0},
        std::array<double, 5>{1, 1, std::numeric_limits<double>::infinity(), 0, 1}}) {
    const auto r = pm.map(hm, in[0], in[1], in[2], in[3], in[4], ops);
    EXPECT_TRUE(r.bad_input);
    EXPECT_EQ(r.samples, 0U);
  }
}

TEST(StabilityRelief, ParallaxOneTexelSpikeAndExtremeHeights) {
  // The linear search may step over a one-texel spike; the result still lies on the ray
  // between the polygon and the base, and a full search (1024 layers) finds the spike.
  const ReliefHeightMap hm = spike_map();
  ParallaxMapper::Config c;
  c.min_layers = c.max_layers = 1024;
  OpCounts ops;
  const auto fine = ParallaxMapper(c).map(hm, 2, 4, -1, 0, 1, ops);  // towards the spike
  EXPECT_LT(fine.depth, 0.6);
  EXPECT_GT(fine.u, 3.0);
  EXPECT_LT(fine.u, 4.0);
  const auto top = ParallaxMapper().map(ReliefHeightMap(4, 4, 1.0F), 1, 1, -1, 0, 0.1, ops);
  EXPECT_EQ(top.depth, 0.0);
  EXPECT_EQ(top.u, 1.0);
}

TEST(StabilityRelief, VisibilityFilterGrazingViewsAndNaNHeights) {
  ReliefHeightMap hm = spike_map();
  hm.at(3, 3) = std::numeric_limits<float>::quiet_NaN();
  VisibilityAwareFilter::ColourMap tex{9, 9, std::vector<glm::vec4>(81, glm::vec4(0.25F))};
  VisibilityAwareFilter::Config c;
  c.max_trace_steps = 8;
  const VisibilityAwareFilter f(c);
  for (const auto& v : {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, -1), glm::dvec3(1, 1, 1e-9)}) {
    OpCounts ops;
    const auto r = f.filter(hm, tex, {4, 4, 2, 0, 0, 2}, v.x, v.y, v.z, ops);
    // Every trace is bounded; a constant texture stays constant whatever is hidden.
    EXPECT_LE(r.stats.trace_reads, r.stats.traced * 8U);
    EXPECT_NEAR(r.colour.x, 0.25F, 1e-6F);
    EXPECT_EQ(r.stats.visible + r.stats.hidden + r.stats.skipped, r.stats.texels);
  }
}

TEST(StabilityTerrain, NoDataNaNAndHorizontalRays) {
  TerrainGrid g(16, 16, 2.0F);
  g.at(5, 5) = std::numeric_limits<float>::quiet_NaN();  // DEM no-data
  g.no_data = 2.0;
  const TerrainHeightEvaluator e;
  OpCounts ops;
  EXPECT_DOUBLE_EQ(e.height(g, 5.3, 4.7, ops), 2.0);
  EXPECT_DOUBLE_EQ(e.height(g, kNaN, 4.7, ops), 2.0);  // non-finite position: node (0, 0)
  EXPECT_DOUBLE_EQ(g.max_height(), 2.0);
  // A level ray below the field's top and above the ground: the cap bounds it.
  AviationCamera::Config cc;
  cc.x = 8;
  cc.y = 3;
  cc.z = 8;
  cc.pitch_deg = 0;
  const AviationCamera level(cc);
  TerrainRayMarcher::Config mc;
  mc.max_steps = 100;
  const TerrainRayMarcher m(mc);
  const auto r = m.march(level, g, 5.0, cc.width / 2.0 - 0.5, cc.height / 2.0 - 0.5, ops);
  EXPECT_FALSE(r.hit);
  EXPECT_LE(r.steps, 100U);
  // A NaN camera position: no hit, no steps.
  cc.y = kNaN;
  const auto n = m.march(AviationCamera(cc), g, 5.0, 3, 3, ops);
  EXPECT_FALSE(n.hit);
  EXPECT_EQ(n.steps, 0U);
}

TEST(StabilityLighting, DegenerateNormalsAndLights) {
  const BlinnPhongShader s;
  const NormalUnit u;
  OpCounts ops;
  const auto n = u.from_map({0.5F, 0.5F, 0.5F}, ops);
  EXPECT_TRUE(n.fallback);
  const auto c = s.shade({0.4F, 0.4F, 0.4F}, n.n, {0, 0, 1}, {0, 0, 1}, ops);
  EXPECT_TRUE(std::isfinite(c.rgb.x));
  const auto inf = std::numeric_limits<float>::infinity();
  const auto d = s.shade({0.4F, 0.4F, 0.4F}, {inf, 0, 0}, {0, 0, 1}, {0, 0, 1}, ops);
  EXPECT_TRUE(d.fallback);
  EXPECT_GE(d.rgb.x, 0.0F);
  EXPECT_LE(d.rgb.x, 1.0F);
}

}  // namespace
}  // namespace texsim
