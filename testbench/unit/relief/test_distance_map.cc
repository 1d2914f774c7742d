// Distance maps: the classic map against a brute-force long double reference, the refined map
// against an independent fine-step ray march, the thesis's toy example (fig. 14–16), and the
// iterations of classic and refined maps on a sharp relief.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <limits>
#include <numbers>
#include <random>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/relief/distance_map_builder.h"
#include "blocks/texture/relief/sphere_tracer.h"
#include "blocks/texture/relief/voxel_walk.h"

namespace texsim {
namespace {

// The thesis's toy example (fig. 14–16; the figures survive only as captions, so the scene is
// rebuilt from the text): a 2-D cross-section, extruded along y so that rays may tilt sideways.
// Assumed: a flat floor whose top solid voxel under C is A, 4 px below C; a wall whose top voxel
// is level with C and 3 px to its side, so the nearest surface to C is the wall (3 px) while
// the vertical view ray through C first meets A (4 px). The rays come from above C unblocked
// (the case of fig. 15): the volume is 8 layers, C at layer 6, floor 3 layers, wall 7 layers.
constexpr int32_t kToyDepth = 8;
ReliefHeightMap toy_map() {
  ReliefHeightMap hm(12, 9, 3.0F / kToyDepth);
  for (int32_t y = 0; y < hm.height; ++y) hm.at(7, y) = 7.0F / kToyDepth;
  return hm;
}
const glm::dvec3 kC(4, 4, 6);

DistanceMapBuilder::Config toy_config() {
  DistanceMapBuilder::Config c;
  c.depth = kToyDepth;
  c.cone_deg = 45;
  return c;
}

TEST(DistanceMap, ToyExampleClassicStoresThreeAndNeedsStepsThreeThenOne) {
  const DistanceMapBuilder b(toy_config());
  const DistanceMap m = b.classic(toy_map());
  EXPECT_FLOAT_EQ(m.at(4, 4, 6), 3.0F);  // C: the wall is 3 px away
  EXPECT_FLOAT_EQ(m.at(4, 4, 3), 1.0F);  // 3 px below C: A is 1 px away
  EXPECT_FLOAT_EQ(m.at(4, 4, 2), 0.0F);  // A is solid
  const SphereTracer tracer;
  OpCounts ops;
  const auto r = tracer.trace(m, kC, {0, 0, -1}, ops);
  EXPECT_EQ(r.status, SphereTracer::Status::Hit);
  EXPECT_EQ(r.iterations, 2U);  // steps 3 then 1: C -> A is 4 px
  EXPECT_EQ(r.fetches, 3U);
  EXPECT_DOUBLE_EQ(r.pos.z, 2.0);
  EXPECT_EQ(ops.mem, 3U);
}

TEST(DistanceMap, ToyExampleRefinedStoresFourAndNeedsOneStep) {
  const DistanceMapBuilder b(toy_config());
  const DistanceMap m = b.refined(toy_map());
  EXPECT_FLOAT_EQ(m.at(4, 4, 6), 4.0F);
  const SphereTracer tracer;
  OpCounts ops;
  const auto r = tracer.trace(m, kC, {0, 0, -1}, ops);
  EXPECT_EQ(r.status, SphereTracer::Status::Hit);
  EXPECT_EQ(r.iterations, 1U);
  EXPECT_EQ(r.fetches, 2U);
  EXPECT_DOUBLE_EQ(r.pos.z, 2.0);
  // A cone wide enough to reach the wall's face at under 3.5 px brings the value down.
  auto wide = toy_config();
  wide.cone_deg = 80;
  wide.polar_steps = 8;
  EXPECT_LT(DistanceMapBuilder(wide).refined_voxel(toy_map(), 4, 4, 6, 3.0), 4.0);
}

ReliefHeightMap random_map(std::mt19937_64& rng, int32_t w, int32_t h, bool sharp) {
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  ReliefHeightMap hm(w, h);
  for (auto& v : hm.h) v = sharp ? (u(rng) < 0.15F ? u(rng) : 0.1F * u(rng)) : u(rng);
  return hm;
}

TEST(DistanceMap, ClassicMatchesBruteForceLongDouble) {
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 4; ++trial) {
    const ReliefHeightMap hm = random_map(rng, 9, 7, trial % 2 == 0);
    DistanceMapBuilder::Config c;
    c.depth = 6;
    const DistanceMapBuilder b(c);
    const DistanceMap m = b.classic(hm);
    for (int32_t z = 0; z < c.depth; ++z) {
      for (int32_t y = 0; y < hm.height; ++y) {
        for (int32_t x = 0; x < hm.width; ++x) {
          long double best = std::numeric_limits<long double>::infinity();
          for (int32_t zz = -1; zz < c.depth; ++zz) {
            for (int32_t yy = 0; yy < hm.height; ++yy) {
              for (int32_t xx = 0; xx < hm.width; ++xx) {
                if (!(zz < 0 || zz < b.solid_layers(hm, xx, yy))) continue;
                const long double dx = xx - x, dy = yy - y, dz = zz - z;
                best = std::min(best, std::sqrt(dx * dx + dy * dy + dz * dz));
              }
            }
          }
          ASSERT_NEAR(m.at(x, y, z), static_cast<double>(best), 1e-6) << x << ' ' << y << ' ' << z;
        }
      }
    }
  }
}

// Independent reference of one refined voxel: every sampled ray marched in steps of 1/4096
// voxel in long double (blocked before p? first solid point? end of that solid run?).
long double refined_reference(const DistanceMapBuilder& b, const ReliefHeightMap& hm, int x, int y,
                              int z) {
  const auto& c = b.config();
  auto solid_at = [&](long double px, long double py, long double pz) {
    const auto ix = static_cast<int>(std::floor(px + 0.5L));
    const auto iy = static_cast<int>(std::floor(py + 0.5L));
    const auto iz = static_cast<int>(std::floor(pz + 0.5L));
    return iz < 0 || iz < b.solid_layers(hm, ix, iy);
  };
  auto inside = [&](long double px, long double py, long double pz) {
    return px >= -0.5L && px < hm.width - 0.5L && py >= -0.5L && py < hm.height - 0.5L &&
           pz < c.depth - 0.5L && pz >= -1.5L;
  };
  const long double dt = 1.0L / 4096;
  long double best = std::numeric_limits<long double>::infinity();
  for (int k = 0; k <= c.polar_steps; ++k) {
    const long double th = c.cone_deg * std::numbers::pi_v<long double> / 180 * k / c.polar_steps;
    for (int j = 0; j < (k == 0 ? 1 : c.azimuth_steps); ++j) {
      const long double ph = 2 * std::numbers::pi_v<long double> * j / c.azimuth_steps;
      const long double dx = std::sin(th) * std::cos(ph), dy = std::sin(th) * std::sin(ph),
                        dz = -std::cos(th);
      bool blocked = false;
      for (long double t = dt; inside(x - t * dx, y - t * dy, z - t * dz); t += dt) {
        if (solid_at(x - t * dx, y - t * dy, z - t * dz)) {
          blocked = true;
          break;
        }
      }
      if (blocked) continue;
      long double t_in = -1, t = 0;
      for (; inside(x + t * dx, y + t * dy, z + t * dz); t += dt) {
        const bool s = solid_at(x + t * dx, y + t * dy, z + t * dz);
        if (s && t_in < 0) t_in = t;
        if (!s && t_in >= 0) break;
        if (z + t * dz < -0.5L) {
          t = std::numeric_limits<long double>::infinity();
          break;
        }
      }
      if (t_in < 0) continue;
      best = std::min(best, t_in + std::min<long double>(c.penetration, 0.5L * (t - t_in)));
    }
  }
  return best;
}

TEST(DistanceMap, RefinedMatchesFineStepRayMarch) {
  std::mt19937_64 rng(7);
  const ReliefHeightMap hm = random_map(rng, 8, 8, true);
  DistanceMapBuilder::Config c;
  c.depth = 6;
  c.polar_steps = 2;
  c.azimuth_steps = 6;
  const DistanceMapBuilder b(c);
  const DistanceMap classic = b.classic(hm);
  int checked = 0;
  for (int z = 0; z < c.depth; z += 2) {
    for (int y = 1; y < 7; y += 2) {
      for (int x = 1; x < 7; x += 2) {
        const double got = b.refined_voxel(hm, x, y, z, classic.at(x, y, z));
        const long double ref = refined_reference(b, hm, x, y, z);
        if (std::isinf(ref)) {
          EXPECT_EQ(got, classic.at(x, y, z));
        } else {
          EXPECT_NEAR(got, static_cast<double>(ref), 2.0 / 4096) << x << ' ' << y << ' ' << z;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 10);
}

// Exact entry of a ray into its first solid voxel (the DDA), for the hit error.
double exact_entry(const DistanceMapBuilder& b, const ReliefHeightMap& hm, const glm::dvec3& p,
                   const glm::dvec3& d) {
  double t_hit = std::numeric_limits<double>::infinity();
  walk_voxels(p, d, hm.width, hm.height, b.config().depth,
              [&](int32_t x, int32_t y, int32_t z, double t_in, double) {
                if (z < 0 || z < b.solid_layers(hm, x, y)) {
                  t_hit = t_in;
                  return false;
                }
                return true;
              });
  return t_hit;
}

struct TraceStats {
  double iterations = 0, fetches = 0, hits = 0, max_err = 0, capped = 0, far = 0;
};

TraceStats trace_many(const DistanceMap& m, const DistanceMapBuilder& b, const ReliefHeightMap& hm,
                      uint64_t seed, int n, const SphereTracer& tracer = SphereTracer()) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(1.0, hm.width - 2.0), uy(1.0, hm.height - 2.0),
      uc(0, 1);
  TraceStats s;
  for (int i = 0; i < n; ++i) {
    // Directions uniform in the admissible cone's solid angle.
    const double cmin = std::cos(b.config().cone_deg * std::numbers::pi / 180);
    const double cz = 1 - uc(rng) * (1 - cmin), ph = 2 * std::numbers::pi * uc(rng);
    const double sz = std::sqrt(1 - cz * cz);
    const glm::dvec3 d(sz * std::cos(ph), sz * std::sin(ph), -cz);
    const glm::dvec3 p(ux(rng), uy(rng), m.depth - 0.5 - 1e-9);
    OpCounts ops;
    const auto r = tracer.trace(m, p, d, ops);
    s.iterations += r.iterations;
    s.fetches += r.fetches;
    s.capped += r.status == SphereTracer::Status::Capped;
    const double t_exact = exact_entry(b, hm, p, d);
    if (r.status == SphereTracer::Status::Hit && std::isfinite(t_exact)) {
      s.hits += 1;
      const double err = glm::length(r.pos - p) - t_exact;
      s.max_err = std::max(s.max_err, err);
      s.far += err > std::sqrt(3.0);  // passed a solid voxel it only clipped
    }
  }
  s.iterations /= n;
  s.fetches /= n;
  s.far /= s.hits;
  return s;
}

// Cycles of one ray on the tracer's datapath: a ray's iterations are dependent, so each read
// waits for the previous step (latency per read) after the ray set-up.
double cycles_per_ray(const TraceStats& s) {
  const SphereTracer t;
  const TechTable tech = TechTable::defaults();
  const double setup = tech.path_latency(t.ray_setup_ops());
  return setup + s.fetches * t.timing(tech).latency;
}

TEST(DistanceMap, RefinedNeedsFewerIterationsOnSharpRelief) {
  DistanceMapBuilder::Config c;
  c.depth = 16;
  const DistanceMapBuilder b(c);
  for (const bool sharp : {true, false}) {
    std::mt19937_64 rng(2024);
    const ReliefHeightMap hm = random_map(rng, 48, 48, sharp);
    const DistanceMap classic = b.classic(hm), refined = b.refined(hm);
    const TraceStats sc = trace_many(classic, b, hm, 5, 4000);
    const TraceStats sr = trace_many(refined, b, hm, 5, 4000);
    const double cc = cycles_per_ray(sc), cr = cycles_per_ray(sr);
    std::printf(
        "%s relief 48x48x16, cone 45 deg: iterations classic %.3f refined %.3f (%.1f %%)"
        ", fetches %.3f / %.3f, cycles %.1f / %.1f (%.1f %%), rays that pass a clipped "
        "voxel %.2f %% / %.2f %%\n",
        sharp ? "sharp" : "noise", sc.iterations, sr.iterations,
        100 * (1 - sr.iterations / sc.iterations), sc.fetches, sr.fetches, cc, cr,
        100 * (1 - cr / cc), 100 * sc.far, 100 * sr.far);
    EXPECT_LT(sr.iterations, sc.iterations);
    EXPECT_EQ(sc.capped, 0);
    EXPECT_EQ(sr.capped, 0);
    // Nearest-voxel reads of centre distances can step past a voxel that the ray only clips
    // (both maps): bounded as measured, and the refined map adds little to it.
    EXPECT_LT(sc.far, 0.12);  // measured 8.2 % (sharp)
    EXPECT_LE(sr.far, sc.far + 0.01);
  }
}

TEST(DistanceMap, SafetyMarginTradesIterationsForClippedVoxels) {
  std::mt19937_64 rng(2024);
  const ReliefHeightMap hm = random_map(rng, 48, 48, true);
  DistanceMapBuilder::Config c;
  c.depth = 16;
  const DistanceMapBuilder b(c);
  const DistanceMap classic = b.classic(hm), refined = b.refined(hm);
  double prev_far = 1, prev_it = 0;
  for (const double safety : {0.0, 0.5, 0.87}) {
    SphereTracer::Config tc;
    tc.safety = safety;
    tc.min_step = safety > 0 ? 0.25 : 0.0;
    const SphereTracer tracer(tc);
    const TraceStats sc = trace_many(classic, b, hm, 5, 2000, tracer);
    const TraceStats sr = trace_many(refined, b, hm, 5, 2000, tracer);
    std::printf(
        "safety %.2f: iterations classic %.3f refined %.3f, clipped voxels stepped "
        "through %.2f %% / %.2f %%\n",
        safety, sc.iterations, sr.iterations, 100 * sc.far, 100 * sr.far);
    EXPECT_LE(sc.far, prev_far);
    EXPECT_GT(sc.iterations, prev_it);
    EXPECT_LT(sr.iterations, sc.iterations);
    prev_far = sc.far;
    prev_it = sc.iterations;
  }
}

TEST(DistanceMap, GainDependsOnTheCone) {
  // The refined map serves only rays inside its cone: a narrower cone allows longer steps.
  std::mt19937_64 rng(2024);
  const ReliefHeightMap hm = random_map(rng, 48, 48, true);
  double prev_gain = 1;
  for (const double cone : {20.0, 45.0, 70.0}) {
    DistanceMapBuilder::Config c;
    c.depth = 16;
    c.cone_deg = cone;
    const DistanceMapBuilder b(c);
    const TraceStats sc = trace_many(b.classic(hm), b, hm, 9, 2000);
    const TraceStats sr = trace_many(b.refined(hm), b, hm, 9, 2000);
    const double gain = 1 - sr.iterations / sc.iterations;
    std::printf("cone %2.0f deg: iterations classic %.3f refined %.3f (%.1f %%)\n", cone,
                sc.iterations, sr.iterations, 100 * gain);
    EXPECT_GT(gain, 0.0);
    EXPECT_LT(gain, prev_gain);
    prev_gain = gain;
  }
}

TEST(DistanceMap, TracerTimingAndConfig) {
  const SphereTracer t;
  const TimingSpec s = t.timing(TechTable::defaults());
  EXPECT_GE(s.latency, 1U);
  EXPECT_EQ(s.ii, 1U);
  EXPECT_EQ(t.ops_per_item().mem, 1U);
}

TEST(DistanceMap, ConfigsReadAndReject) {
  const toml::table t = toml::parse("depth = 12\ncone_deg = 30\n");
  const auto c = DistanceMapBuilder::Config::from_toml(ConfigReader(t, "s.toml", "relief"));
  EXPECT_EQ(c.depth, 12);
  EXPECT_DOUBLE_EQ(c.cone_deg, 30);
  for (const char* bad : {"cone_deg = 90\n", "penetration = 0\n", "depht = 3\n"}) {
    const toml::table b = toml::parse(bad);
    EXPECT_THROW(DistanceMapBuilder::Config::from_toml(ConfigReader(b, "s.toml", "relief")),
                 InputError);
  }
  const toml::table s = toml::parse("max_iterations = 8\nmin_step = 0.25\n");
  const auto sc = SphereTracer::Config::from_toml(ConfigReader(s, "s.toml", "tracer"));
  EXPECT_EQ(sc.max_iterations, 8);
  const toml::table b = toml::parse("max_iterations = 0\n");
  EXPECT_THROW(SphereTracer::Config::from_toml(ConfigReader(b, "s.toml", "tracer")), InputError);
}

}  // namespace
}  // namespace texsim
