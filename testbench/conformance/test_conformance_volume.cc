// The Vulkan checker on 3-D textures (docs/texture-types.md §7): each query's result written
// from the specification's rules in double — ρ = max(|(∂u, ∂v, ∂r)/∂x ⊙ (w, h, d)|, … ∂y),
// λ = log2 ρ (or a quarter of the queries' explicit LOD) clamped to the chain, levels d = ⌊λ⌋
// and d + 1 weighted by the fraction (to within its 8 precision bits), each 3-D level (every
// size halved, at least 1) read with i0 = ⌊u·w − ½⌋, j0, k0 alike and the axis's wrap function
// — against the unit's, on a random RGBA32F volume. The checker accepts the unit and rejects
// four controls: a 2-D λ (∂r left out), k0 = ⌊r·d⌋ (half-up), coarser levels addressed in r as
// if they kept level 0's depth (a chain halving only width and height) and an explicit LOD
// ignored (λ from the derivatives).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

struct Query {
  double u, v, r, dx[3], dy[3];
  double lod = NAN;  // an explicit LOD (textureLod), else NaN: λ from the derivatives
};

struct Model {
  bool lambda_2d = false, k_half_up = false, depth_kept = false, lod_ignored = false;
};

int wrap(int64_t i, int n, AddressMode m) {
  if (m == AddressMode::Clamp) return static_cast<int>(std::clamp<int64_t>(i, 0, n - 1));
  const int64_t r = i % n;  // repeat
  return static_cast<int>(r < 0 ? r + n : r);
}

// Level l of the volume per the model: its size and texel reader.
glm::dvec4 level_sample(const Texture& t, int l, const Query& q, const AddressMode m[3],
                        const Model& md) {
  const int w = std::max(1, t.width(0) >> l), h = std::max(1, t.height(0) >> l);
  const int d = md.depth_kept ? t.shape().slices : std::max(1, t.shape().slices >> l);
  const int n[3] = {w, h, d};
  const double c[3] = {q.u, q.v, q.r};
  int64_t i0[3];
  double f[3];
  for (int k = 0; k < 3; ++k) {
    const double s = c[k] * n[k] - (md.k_half_up && k == 2 ? 0.0 : 0.5);
    i0[k] = static_cast<int64_t>(std::floor(s));
    f[k] = md.k_half_up && k == 2 ? 0.0 : s - std::floor(s);
  }
  glm::dvec4 sum(0);
  for (int corner = 0; corner < 8; ++corner) {
    double wt = 1;
    int a[3];
    for (int k = 0; k < 3; ++k) {
      const int hi = (corner >> k) & 1;
      wt *= hi ? f[k] : 1 - f[k];
      a[k] = wrap(i0[k] + hi, n[k], m[k]);
    }
    if (wt == 0) continue;
    // The control's k, addressed against level 0's depth, mapped onto the level's slices.
    const int z = md.depth_kept ? a[2] * t.volume_depth(l) / d : a[2];
    sum += wt * glm::dvec4(t.texel(t.volume_level(l, z), a[0], a[1]));
  }
  return sum;
}

// The two levels' samples and the fraction δ between them (linear mipmap mode).
struct SpecLevels {
  glm::dvec4 lo, hi;
  double delta;
};

SpecLevels spec_levels(const Texture& t, const Query& q, const AddressMode m[3], const Model& md) {
  const double size[3] = {static_cast<double>(t.width(0)), static_cast<double>(t.height(0)),
                          static_cast<double>(t.shape().slices)};
  double px = 0, py = 0;
  for (int k = 0; k < (md.lambda_2d ? 2 : 3); ++k) {
    px += q.dx[k] * size[k] * q.dx[k] * size[k];
    py += q.dy[k] * size[k] * q.dy[k] * size[k];
  }
  const int top = t.mips() - 1;
  const double lambda_base =
      std::isnan(q.lod) || md.lod_ignored ? 0.5 * std::log2(std::max({px, py, 1e-300})) : q.lod;
  const double lambda = std::clamp(lambda_base, 0.0, static_cast<double>(top));
  const int lo = static_cast<int>(std::floor(lambda)), hi = std::min(lo + 1, top);
  return {level_sample(t, lo, q, m, md), level_sample(t, hi, q, m, md), lambda - lo};
}

glm::dvec4 spec_sample(const Texture& t, const Query& q, const AddressMode m[3], const Model& md) {
  const SpecLevels s = spec_levels(t, q, m, md);
  return (1 - s.delta) * s.lo + s.delta * s.hi;
}

// Queries whose result differs from the spec's by more than `tol` in any channel.
int check(const Texture& t, const std::vector<Query>& qs, const AddressMode m[3],
          const std::function<glm::dvec4(const Query&)>& model, double tol = 2e-4) {
  int bad = 0;
  for (const Query& q : qs) {
    // δ is allowed its precision, ±2^-mipmapPrecisionBits (8, the unit's mipmap_bits): the
    // result may lie anywhere between the blends at δ ∓ 2^-8 (clamped to [0, 1]).
    const SpecLevels s = spec_levels(t, q, m, Model{});
    const double d0 = std::max(s.delta - 0x1p-8, 0.0), d1 = std::min(s.delta + 0x1p-8, 1.0);
    const glm::dvec4 a = (1 - d0) * s.lo + d0 * s.hi, b = (1 - d1) * s.lo + d1 * s.hi;
    const glm::dvec4 got = model(q);
    for (int k = 0; k < 4; ++k) {
      if (got[k] < std::min(a[k], b[k]) - tol || got[k] > std::max(a[k], b[k]) + tol) {
        ++bad;
        break;
      }
    }
  }
  return bad;
}

TEST(ConformanceVolume, AcceptsTheUnitAndRejectsTheControls) {
  std::mt19937 rng(27);
  std::uniform_real_distribution<float> texel(0, 1);
  const int w = 16, h = 8, d = 8;
  std::vector<std::vector<float>> slices(d, std::vector<float>(size_t{w} * h * 4));
  for (auto& s : slices)
    for (float& x : s) x = texel(rng);
  TextureSet set;
  set.add(Texture::from_volume("v", w, h, slices, TexelFormat::Rgba32f, true));
  MaterialSetup mat;
  mat.name = "m";
  mat.filter.filter = FilterMode::Trilinear;
  mat.filter.address_u = AddressMode::Wrap;
  mat.filter.address_v = AddressMode::Clamp;
  mat.filter.address_w = AddressMode::Clamp;
  const AddressMode modes[3] = {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Clamp};
  TextureUnit unit(set, {mat}, PipelineSetup{}, TechTable::defaults(), false);
  const Texture& t = set[0];
  // Coordinates over and beyond the volume; footprints from magnified to the whole chain, with
  // ∂r as large as ∂u, ∂v or alone.
  std::uniform_real_distribution<double> coord(-0.3, 1.3), scale(-7, 1), lod(-1, 5);
  std::vector<Query> qs;
  qs.reserve(2000);
  for (int i = 0; i < 2000; ++i) {
    Query q{coord(rng), coord(rng), coord(rng), {}, {}};
    const double s = std::exp2(scale(rng));
    q.dx[0] = s * (i % 3 == 0 ? 0.0 : 0.7);
    q.dy[1] = s * (i % 3 == 0 ? 0.0 : 0.5);
    q.dx[2] = s * (i % 3 == 1 ? 0.1 : 1.0);
    if (i % 4 == 3) q.lod = lod(rng);  // textureLod: the derivatives stay but do not count
    qs.push_back(q);
  }
  const auto unit_model = [&](const Query& q) {
    Fragment f;
    f.u = q.u;
    f.v = q.v;
    f.w = q.r;
    f.dudx = q.dx[0];
    f.dvdx = q.dx[1];
    f.dwdx = q.dx[2];
    f.dudy = q.dy[0];
    f.dvdy = q.dy[1];
    f.dwdy = q.dy[2];
    if (!std::isnan(q.lod)) {
      f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
      f.lod = static_cast<float>(q.lod);
    }
    return glm::dvec4(unit.process(f, 0));
  };
  EXPECT_EQ(check(t, qs, modes, unit_model), 0);
  for (const Model& control : {Model{true, false, false, false}, Model{false, true, false, false},
                               Model{false, false, true, false}}) {
    const int bad =
        check(t, qs, modes, [&](const Query& q) { return spec_sample(t, q, modes, control); });
    EXPECT_GT(bad, 200) << control.lambda_2d << control.k_half_up << control.depth_kept;
  }
  // An explicit LOD taken from the derivatives instead: rejected on most of the 500 queries.
  const Model ignored{false, false, false, true};
  const int bad =
      check(t, qs, modes, [&](const Query& q) { return spec_sample(t, q, modes, ignored); });
  EXPECT_GT(bad, 300) << "lod ignored";
}

}  // namespace
}  // namespace texsim
