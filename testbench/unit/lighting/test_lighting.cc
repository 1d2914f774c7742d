// Lighting subsystem (ПРО): Blinn-Phong (this project's choice of model) against a long double
// reference, its corner cases and fallbacks, and the three normal sources.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/lighting/blinn_phong_shader.h"
#include "blocks/lighting/normal_unit.h"

namespace texsim {
namespace {

struct V3 {
  long double x, y, z;
};
long double dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 unit(const V3& a) {
  const long double l = std::sqrt(dot(a, a));
  return {a.x / l, a.y / l, a.z / l};
}
V3 ld(const glm::vec3& a) { return {a.x, a.y, a.z}; }

// out = c·(ka + kd·max(0, n·l)) + ks·light·max(0, n·h)^s, clamped.
V3 reference(const BlinnPhongShader::Config& c, const V3& base, const V3& n, const V3& l,
             const V3& v) {
  const long double ndl = dot(n, l);
  long double spec = 0;
  if (ndl > 0) {
    const V3 h = unit({l.x + v.x, l.y + v.y, l.z + v.z});
    const long double ndh = dot(n, h);
    spec = ndh > 0 ? std::pow(ndh, static_cast<long double>(c.shininess)) : 0;
  }
  const long double k = c.ambient + c.diffuse * std::max<long double>(ndl, 0);
  auto ch = [&](long double b, long double light) {
    return std::clamp<long double>(b * k + c.specular * light * spec, 0, 1);
  };
  return {ch(base.x, c.light_r), ch(base.y, c.light_g), ch(base.z, c.light_b)};
}

glm::vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<float> g;
  glm::vec3 a(g(rng), g(rng), g(rng));
  return a / std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
}

TEST(BlinnPhong, MatchesLongDoubleReference) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<float> col(0, 1);
  const BlinnPhongShader s;
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 base(col(rng), col(rng), col(rng));
    const glm::vec3 n = random_unit(rng), l = random_unit(rng), v = random_unit(rng);
    OpCounts ops;
    const auto r = s.shade(base, n, l, v, ops);
    const V3 ref = reference(s.config(), ld(base), ld(n), ld(l), ld(v));
    worst = std::max({worst, std::fabs(r.rgb.x - static_cast<double>(ref.x)),
                      std::fabs(r.rgb.y - static_cast<double>(ref.y)),
                      std::fabs(r.rgb.z - static_cast<double>(ref.z))});
    EXPECT_FALSE(r.fallback);
    EXPECT_EQ(ops, s.ops_per_item());
  }
  EXPECT_LT(worst, 2e-5);  // float, with the power's 32·ulp growth
}

TEST(BlinnPhong, CornerCases) {
  const BlinnPhongShader s;
  OpCounts ops;
  const glm::vec3 base(0.5F, 0.25F, 1.0F), up(0, 0, 1);
  // Light, view and normal aligned: full diffuse and specular.
  auto r = s.shade(base, up, up, up, ops);
  EXPECT_NEAR(r.rgb.x, 0.5 * (0.15 + 0.85) + 0.25, 1e-6);
  EXPECT_NEAR(r.rgb.z, 1.0, 1e-6);  // clamped
  // Light behind the surface: ambient only, no specular.
  r = s.shade(base, up, {0, 0, -1}, up, ops);
  EXPECT_NEAR(r.rgb.x, 0.5 * 0.15, 1e-7);
  EXPECT_NEAR(r.rgb.y, 0.25 * 0.15, 1e-7);
}

TEST(BlinnPhong, NonFiniteInputsHaveDefinedFallbacks) {
  const BlinnPhongShader s;
  OpCounts ops;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const glm::vec3 base(0.5F), up(0, 0, 1), l = glm::vec3(0.6F, 0, 0.8F);
  // A NaN or zero normal is replaced by v.
  const auto a = s.shade(base, {nan, 0, 1}, l, up, ops);
  const auto b = s.shade(base, up, l, up, ops);
  EXPECT_TRUE(a.fallback);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_TRUE(s.shade(base, glm::vec3(0), l, up, ops).fallback);
  // A NaN light or view vector leaves the ambient term.
  const auto c = s.shade(base, up, {nan, nan, nan}, up, ops);
  EXPECT_TRUE(c.fallback);
  EXPECT_NEAR(c.rgb.x, 0.5 * 0.15, 1e-7);
  const auto d = s.shade({nan, 2, -1}, up, l, up, ops);  // colour sanitised and clamped
  EXPECT_TRUE(std::isfinite(d.rgb.x));
  EXPECT_LE(d.rgb.y, 1.0F);
}

TEST(NormalUnit, FromNormalMap) {
  const NormalUnit u;
  OpCounts ops;
  auto r = u.from_map({0.5F, 0.5F, 1.0F}, ops);
  EXPECT_FALSE(r.fallback);
  EXPECT_NEAR(r.n.z, 1.0F, 1e-7);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<float> col(0, 1);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec3 c(col(rng), col(rng), col(rng));
    r = u.from_map(c, ops);
    const V3 ref = unit({2.0L * c.x - 1, 2.0L * c.y - 1, 2.0L * c.z - 1});
    EXPECT_NEAR(r.n.x, static_cast<double>(ref.x), 1e-6);
    EXPECT_NEAR(r.n.z, static_cast<double>(ref.z), 1e-6);
  }
  r = u.from_map({0.5F, 0.5F, 0.5F}, ops);  // the zero vector
  EXPECT_TRUE(r.fallback);
  EXPECT_EQ(r.n, glm::vec3(0, 0, 1));
}

TEST(NormalUnit, FromHeightMapAndTerrain) {
  NormalUnit::Config c;
  c.source = NormalUnit::Source::HeightMap;
  c.bump_scale = 8;
  const NormalUnit u(c);
  ReliefHeightMap ramp(8, 8);
  for (int32_t y = 0; y < 8; ++y) {
    for (int32_t x = 0; x < 8; ++x) ramp.at(x, y) = 0.05F * static_cast<float>(x);
  }
  OpCounts ops;
  const auto r = u.from_height(ramp, 3, 3, ops);
  const V3 ref = unit({-0.05L * 8, 0, 1});  // central differences are exact on a ramp
  EXPECT_NEAR(r.n.x, static_cast<double>(ref.x), 1e-6);
  EXPECT_NEAR(r.n.z, static_cast<double>(ref.z), 1e-6);
  EXPECT_EQ(ops.mem, 4U);
  EXPECT_EQ(u.from_height(ReliefHeightMap(4, 4, 1.0F), 0, 0, ops).n, glm::vec3(0, 0, 1));
  const auto t = NormalUnit().from_terrain(0.5, -0.25, ops);
  const V3 tr = unit({-0.5L, 1, 0.25L});
  EXPECT_NEAR(t.n.x, static_cast<double>(tr.x), 1e-6);
  EXPECT_NEAR(t.n.y, static_cast<double>(tr.y), 1e-6);
  EXPECT_TRUE(NormalUnit().from_terrain(std::nan(""), 0, ops).fallback);
}

TEST(Lighting, TimingFromOps) {
  const TechTable t = TechTable::defaults();
  EXPECT_GE(BlinnPhongShader().timing(t).latency, 1U);
  EXPECT_EQ(BlinnPhongShader().timing(t).ii, 1U);
  EXPECT_GE(NormalUnit().timing(t).latency, 1U);
}

TEST(Lighting, ConfigsReadAndReject) {
  const toml::table t = toml::parse("shininess = 8\nambient = 0.2\n");
  const auto c = BlinnPhongShader::Config::from_toml(ConfigReader(t, "s.toml", "lighting"));
  EXPECT_DOUBLE_EQ(c.shininess, 8);
  EXPECT_DOUBLE_EQ(c.ambient, 0.2);
  for (const char* bad : {"shininess = 0\n", "diffuse = -1\n", "spec = 1\n"}) {
    const toml::table b = toml::parse(bad);
    EXPECT_THROW(BlinnPhongShader::Config::from_toml(ConfigReader(b, "s.toml", "lighting")),
                 InputError);
  }
  const toml::table n = toml::parse("source = \"height_map\"\nbump_scale = 2\n");
  const auto nc = NormalUnit::Config::from_toml(ConfigReader(n, "s.toml", "normals"));
  EXPECT_EQ(nc.source, NormalUnit::Source::HeightMap);
  const toml::table b = toml::parse("source = \"bump\"\n");
  EXPECT_THROW(NormalUnit::Config::from_toml(ConfigReader(b, "s.toml", "normals")), InputError);
}

}  // namespace
}  // namespace texsim
