// Terrain normals for lighting (TerrainNormalUnit): the gradient and the seed's central
// differences against a long double direct sum of the finite-function surface, their fallbacks,
// the lighting stage's use of them at the marched position, and the scene keys that select them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/lighting/terrain_normal_unit.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/surface_effects.h"

namespace texsim {
namespace {

TerrainGrid random_grid(int32_t n, double amplitude, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> h(0, amplitude);
  TerrainGrid g(n, n);
  for (float& v : g.h) v = static_cast<float>(h(rng));
  return g;
}

// The unit normal (-∂y/∂x, 1, -∂y/∂z) of y = Σ h_ij f(x - i) f(z - j), summed in long double
// over every node (f is zero beyond its support, so the far nodes add nothing).
void reference_normal(const TerrainGrid& g, const FiniteBasis& f, double x, double z,
                      long double n[3]) {
  long double gx = 0, gz = 0;
  for (int32_t j = 0; j < g.nz; ++j) {
    for (int32_t i = 0; i < g.nx; ++i) {
      const long double h = g.node(i, j);
      gx += h * f.derivative(x - i) * f.value(z - j);
      gz += h * f.value(x - i) * f.derivative(z - j);
    }
  }
  const long double len = std::sqrt(gx * gx + 1 + gz * gz);
  n[0] = -gx / len;
  n[1] = 1 / len;
  n[2] = -gz / len;
}

double angle(const glm::vec3& a, const long double b[3]) {
  const long double c = a.x * b[0] + a.y * b[1] + a.z * b[2];
  const long double s =
      std::sqrt(std::pow(a.y * b[2] - a.z * b[1], 2) + std::pow(a.z * b[0] - a.x * b[2], 2) +
                std::pow(a.x * b[1] - a.y * b[0], 2));
  return static_cast<double>(std::atan2(s, c));
}

TEST(TerrainNormal, MatchesLongDoubleDirectSum) {
  // Heights up to 24 texels (the flyover's scale) on a 12 × 12 grid, points inside it.
  const TerrainGrid g = random_grid(12, 24, 5);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> pos(1.0, 10.0);
  for (const FiniteKind k : {FiniteKind::Cosine, FiniteKind::Quadratic, FiniteKind::Exp2}) {
    for (const Deformation d : {Deformation::None, Deformation::Widened}) {
      double worst_grad = 0, worst_cd = 0, worst_cd_smooth = 0;
      TerrainNormalUnit::Config c;
      c.evaluator.basis = {k, d, 1};
      const TerrainNormalUnit grad(c);
      c.method = TerrainNormalUnit::Method::CentralDifference;
      const TerrainNormalUnit cd(c);
      for (int s = 0; s < 2000; ++s) {
        const double x = pos(rng), z = pos(rng);
        long double ref[3];
        reference_normal(g, c.evaluator.basis, x, z, ref);
        OpCounts og, oc;
        const auto a = grad.normal(g, x, z, og), b = cd.normal(g, x, z, oc);
        EXPECT_FALSE(a.fallback || b.fallback);
        worst_grad = std::max(worst_grad, angle(a.n, ref));
        worst_cd = std::max(worst_cd, angle(b.n, ref));
        // y'' jumps at the nodes (and, for the piecewise functions, at the joins t = ±½):
        // there the differences straddle a kink of the slope. Away from them: O(ε²).
        const auto near_kink = [&](double t) {
          const double f = t - std::floor(t);
          return std::min({f, std::fabs(f - 0.5), 1 - f}) < 2 * c.epsilon;
        };
        if (d == Deformation::None && !near_kink(x) && !near_kink(z))
          worst_cd_smooth = std::max(worst_cd_smooth, angle(b.n, ref));
        EXPECT_EQ(og, grad.ops_per_item());
        EXPECT_EQ(oc, cd.ops_per_item());
      }
      // The gradient is exact up to the float normalisation (measured < 10⁻⁷ rad). Central
      // differences: the O(ε²) truncation ε²/6·y''' away from the kinks (measured < 10⁻⁴
      // rad), up to ε/4·|Δy''| across one (measured 0.004–0.030 rad, heights up to 24).
      std::printf(
          "function %d deformation %d: worst angle gradient %.3g, central %.3g rad "
          "(%.3g away from kinks)\n",
          static_cast<int>(k), static_cast<int>(d), worst_grad, worst_cd, worst_cd_smooth);
      EXPECT_LT(worst_grad, 2e-7);
      EXPECT_LT(worst_cd, 0.05);
      EXPECT_GT(worst_cd, 1e-3);  // the kinks are real: a test of an O(ε²) claim would fail
      if (d == Deformation::None) {
        EXPECT_LT(worst_cd_smooth, 1e-4);
      }
    }
  }
}

TEST(TerrainNormal, CostsAndTiming) {
  const TechTable t = TechTable::defaults();
  TerrainNormalUnit::Config c;
  const TerrainNormalUnit grad(c);
  c.method = TerrainNormalUnit::Method::CentralDifference;
  const TerrainNormalUnit cd(c);
  // One evaluation with the gradient (4 heights) against four (16 heights).
  EXPECT_EQ(grad.ops_per_item().mem, 4U);
  EXPECT_EQ(cd.ops_per_item().mem, 16U);
  EXPECT_EQ(grad.evaluations(), 1U);
  EXPECT_EQ(cd.evaluations(), 4U);
  EXPECT_LT(grad.ops_per_item().total(), cd.ops_per_item().total());
  EXPECT_EQ(grad.timing(t).ii, 1U);
  EXPECT_LT(grad.timing(t).area, cd.timing(t).area);
  EXPECT_LE(grad.timing(t).latency, cd.timing(t).latency);
}

TEST(TerrainNormal, FlatNonFiniteAndNoData) {
  TerrainGrid flat(4, 4, 3.0F);
  for (const auto m :
       {TerrainNormalUnit::Method::Gradient, TerrainNormalUnit::Method::CentralDifference}) {
    TerrainNormalUnit::Config c;
    c.method = m;
    const TerrainNormalUnit u(c);
    OpCounts ops;
    EXPECT_EQ(u.normal(flat, 1.3, 2.6, ops).n, glm::vec3(0, 1, 0));
    // A non-finite position reads node (0, 0): flat, up.
    const auto r = u.normal(flat, NAN, 1.0, ops);
    EXPECT_TRUE(std::isfinite(r.n.x) && std::isfinite(r.n.y) && std::isfinite(r.n.z));
    // A no-data (NaN) height reads as 0: a finite unit normal, not NaN.
    TerrainGrid holes = flat;
    holes.at(1, 2) = NAN;
    const auto h = u.normal(holes, 1.4, 2.3, ops);
    EXPECT_NEAR(glm::length(h.n), 1.0F, 1e-6F);
    EXPECT_GT(h.n.y, 0.0F);
  }
}

// A 16 × 16 height texture with a ridge that is not symmetric in u and v.
Texture ridge_texture() {
  const int w = 16, h = 16;
  std::vector<float> rgba(size_t{w} * h * 4, 1.0F);
  for (size_t y = 0; y < size_t{h}; ++y) {
    for (size_t x = 0; x < size_t{w}; ++x)
      rgba[(y * w + x) * 4] = static_cast<float>((x * 5 + y * 2) % 7) / 6.0F;
  }
  return Texture::from_rgba("h", w, h, rgba, TexelFormat::Rgba32f, false);
}

TEST(TerrainNormal, TheLightingStageLightsWithTheTerrainNormalAtTheMarchedPosition) {
  const Texture height = ridge_texture();
  LightingSetup ls;
  ls.normal = LightingSetup::Normal::Terrain;
  ls.normal_texture = "h";
  ls.terrain_scale = 6;
  const LightingEffect e(ls, &height);
  ASSERT_TRUE(e.has_terrain_normal());
  ASSERT_FALSE(e.has_normal_unit());
  // The relief's grid: heights h·scale, node (i, j) = texel (i, j), texel centres at integers.
  TerrainGrid g(16, 16);
  for (int32_t j = 0; j < 16; ++j) {
    for (int32_t i = 0; i < 16; ++i) g.at(i, j) = height.texel(0, i, j).r * 6.0F;
  }
  const TerrainNormalUnit unit(ls.terrain);
  const glm::dvec3 view = glm::normalize(glm::dvec3(0.2, -0.3, 0.9));
  const glm::dvec3 light = glm::normalize(glm::dvec3(0.6, 0.1, 0.5));
  int differ = 0;
  for (int k = 0; k < 40; ++k) {
    const double u = 0.05 + 0.022 * k, v = 0.93 - 0.021 * k;
    OpCounts nops, sops, ref_ops;
    const Rgba c{0.5F, 0.6F, 0.7F, 1.0F};
    const Rgba out = e.shade(c, u, v, view, light, nops, sops);
    const glm::vec3 gn = unit.normal(g, u * 16 - 0.5, v * 16 - 0.5, ref_ops).n;
    const glm::vec3 want =
        e.shader()
            .shade({c.r, c.g, c.b}, {gn.x, gn.z, gn.y}, glm::vec3(light), glm::vec3(view), ref_ops)
            .rgb;
    EXPECT_EQ(out.r, want.x);
    EXPECT_EQ(out.g, want.y);
    EXPECT_EQ(out.b, want.z);
    // Not the flat plane's lighting: the terrain's slope shows.
    const glm::vec3 flat =
        e.shader()
            .shade({c.r, c.g, c.b}, {0, 0, 1}, glm::vec3(light), glm::vec3(view), ref_ops)
            .rgb;
    differ += std::fabs(flat.x - out.r) > 1e-3F ? 1 : 0;
    EXPECT_EQ(nops, unit.ops_per_item());
  }
  EXPECT_GT(differ, 20);
}

MaterialSetup material(const std::string& effects) {
  const toml::table t = toml::parse(effects);
  const std::map<std::string, int> textures = {{"h", 0}, {"c", 1}};
  return material_from_toml("m", 1, t, "s.toml", &textures);
}

TEST(TerrainNormal, SceneKeysSelectAndCheckTheSource) {
  const std::string relief =
      "relief = { method = \"terrain\", height_texture = \"h\", scale = 12.0, "
      "terrain = { function = \"quadratic\" } }\n";
  const MaterialSetup m = material(relief +
                                   "lighting = { normal = \"terrain\", terrain_normal = "
                                   "\"central_difference\", terrain_epsilon = 0.01 }\n");
  ASSERT_TRUE(m.lighting);
  EXPECT_EQ(m.lighting->normal, LightingSetup::Normal::Terrain);
  EXPECT_EQ(m.lighting->normal_tex, 0);  // the relief's height texture
  EXPECT_DOUBLE_EQ(m.lighting->terrain_scale, 12.0);
  EXPECT_EQ(m.lighting->terrain.evaluator.basis.kind, FiniteKind::Quadratic);
  EXPECT_EQ(m.lighting->terrain.method, TerrainNormalUnit::Method::CentralDifference);
  EXPECT_DOUBLE_EQ(m.lighting->terrain.epsilon, 0.01);
  EXPECT_EQ(material(relief + "lighting = { normal = \"terrain\" }\n").lighting->terrain.method,
            TerrainNormalUnit::Method::Gradient);
  const std::vector<std::string> bad_inputs = {
      // no terrain relief
      "lighting = { normal = \"terrain\" }\n",
      std::string("relief = { method = \"steep\", height_texture = \"h\" }\n") +
          "lighting = { normal = \"terrain\" }\n",
      // keys that do not belong
      relief + "lighting = { normal = \"terrain\", normal_texture = \"h\" }\n",
      relief + "lighting = { normal = \"terrain\", bump_scale = 2.0 }\n",
      relief + "lighting = { normal = \"terrain\", terrain_normal = \"sobel\" }\n",
      relief + "lighting = { normal = \"terrain\", terrain_epsilon = 0.0 }\n",
      relief +
          "lighting = { normal = \"height_map\", normal_texture = \"h\", "
          "terrain_normal = \"gradient\" }\n",
  };
  for (const std::string& bad : bad_inputs) {
    EXPECT_THROW(material(bad), InputError) << bad;
  }
}

}  // namespace
}  // namespace texsim
