// Cube maps and arrays: face selection (Vulkan's table and the Z > Y > X tie rule), face-space
// derivatives, the seamless edge unit (neighbour texels across edges, three texels at corners),
// the layered address generator (seamless and per-face taps, cube arrays, array layers and their
// per-layer mip chains) and the layer rounding.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "blocks/texture/layered/cube_face_select.h"
#include "blocks/texture/layered/cube_seam.h"
#include "blocks/texture/layered/layered_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"

namespace texsim {
namespace {

using I3 = std::array<int64_t, 3>;

I3 centre(int face, int x, int y, int n) {
  // A texel centre on the cube surface, in units of half a texel ([−n, n] per face).
  const CubeFaceAxes& a = cube_face_axes(face);
  const int64_t s = 2 * int64_t{x} + 1 - n, t = 2 * int64_t{y} + 1 - n;
  I3 r{};
  for (size_t k = 0; k < 3; ++k) r[k] = a.m[k] * int64_t{n} + a.s[k] * s + a.t[k] * t;
  return r;
}

TEST(CubeFaceSelect, AxesAndTable) {
  const float d[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int f = 0; f < 6; ++f) {
    const CubeFaceCoord c = CubeFaceSelect::select(d[f][0], d[f][1], d[f][2]);
    EXPECT_EQ(c.face, f);
    EXPECT_EQ(c.s, 0.5f);
    EXPECT_EQ(c.t, 0.5f);
  }
  // Vulkan's table on (rx, ry, rz) = (0.5, −0.25, −1): −Z, sc = −rx, tc = −ry.
  const CubeFaceCoord c = CubeFaceSelect::select(0.5f, -0.25f, -1.0f);
  EXPECT_EQ(c.face, static_cast<int>(CubeFace::NegZ));
  EXPECT_FLOAT_EQ(c.s, 0.5f * -0.5f + 0.5f);
  EXPECT_FLOAT_EQ(c.t, 0.5f * 0.25f + 0.5f);
  // +Y: sc = +rx, tc = +rz.
  const CubeFaceCoord y = CubeFaceSelect::select(0.25f, 2.0f, -1.0f);
  EXPECT_EQ(y.face, static_cast<int>(CubeFace::PosY));
  EXPECT_FLOAT_EQ(y.s, 0.5f * 0.125f + 0.5f);
  EXPECT_FLOAT_EQ(y.t, 0.5f * -0.5f + 0.5f);
}

TEST(CubeFaceSelect, TiesTakeZThenYThenX) {
  auto face = [](float x, float y, float z) { return CubeFaceSelect::select(x, y, z).face; };
  EXPECT_EQ(face(1, 1, 0), static_cast<int>(CubeFace::PosY));
  EXPECT_EQ(face(-1, -1, 0), static_cast<int>(CubeFace::NegY));
  EXPECT_EQ(face(1, 0, -1), static_cast<int>(CubeFace::NegZ));
  EXPECT_EQ(face(0, -1, 1), static_cast<int>(CubeFace::PosZ));
  EXPECT_EQ(face(-1, 1, -1), static_cast<int>(CubeFace::NegZ));
  EXPECT_EQ(face(2, -2, 2), static_cast<int>(CubeFace::PosZ));
  // Zero and non-finite directions: +Z (ties on +0) at the centre, never NaN.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const auto& r : {std::array<float, 3>{0, 0, 0}, {nan, nan, nan}, {inf, -inf, nan}}) {
    const CubeFaceCoord c = CubeFaceSelect::select(r[0], r[1], r[2]);
    EXPECT_EQ(c.face, static_cast<int>(CubeFace::PosZ));
    EXPECT_EQ(c.s, 0.5f);
    EXPECT_EQ(c.t, 0.5f);
  }
  EXPECT_EQ(face(0, 0, -0.0f), static_cast<int>(CubeFace::NegZ));  // the sign bit of −0
  // A NaN component is 0: (NaN, 0.5, 0.25) is +Y.
  EXPECT_EQ(face(nan, 0.5f, 0.25f), static_cast<int>(CubeFace::PosY));
}

TEST(CubeFaceSelect, RandomDirectionsRebuildFromFaceCoordinates) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-3, 3);
  for (int i = 0; i < 2000; ++i) {
    const float r[3] = {u(rng), u(rng), u(rng)};
    const CubeFaceCoord c = CubeFaceSelect::select(r[0], r[1], r[2]);
    const CubeFaceAxes& a = cube_face_axes(c.face);
    const float mx = std::max({std::fabs(r[0]), std::fabs(r[1]), std::fabs(r[2])});
    EXPECT_EQ(c.rc, mx);
    for (size_t k = 0; k < 3; ++k) {
      const float rebuilt = static_cast<float>(a.m[k]) * c.rc +
                            static_cast<float>(a.s[k]) * (2 * c.s - 1) * c.rc +
                            static_cast<float>(a.t[k]) * (2 * c.t - 1) * c.rc;
      EXPECT_NEAR(rebuilt, r[k], 1e-5f * mx);
    }
  }
}

TEST(CubeFaceSelect, DerivativesMatchFiniteDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  int checked = 0;
  while (checked < 300) {
    const double r[3] = {u(rng), u(rng), u(rng)};
    const CubeFaceCoord c = CubeFaceSelect::select(
        static_cast<float>(r[0]), static_cast<float>(r[1]), static_cast<float>(r[2]));
    if (c.s < 0.05f || c.s > 0.95f || c.t < 0.05f || c.t > 0.95f || c.rc < 0.2f) continue;
    const float dx[3] = {u(rng), u(rng), u(rng)}, dy[3] = {u(rng), u(rng), u(rng)};
    const CubeFaceDerivs d = CubeFaceSelect::derivatives(c, dx, dy);
    const double h = 1e-3;
    auto st = [&](const float* dir, double k, double& s, double& t) {
      // The face's formula in double, on the same face.
      const CubeFaceAxes& a = cube_face_axes(c.face);
      double p[3];
      for (int j = 0; j < 3; ++j) p[j] = r[j] + k * dir[j];
      const double m = a.m[0] * p[0] + a.m[1] * p[1] + a.m[2] * p[2];
      s = 0.5 * (a.s[0] * p[0] + a.s[1] * p[1] + a.s[2] * p[2]) / m + 0.5;
      t = 0.5 * (a.t[0] * p[0] + a.t[1] * p[1] + a.t[2] * p[2]) / m + 0.5;
    };
    double s1, t1, s0, t0;
    st(dx, h, s1, t1);
    st(dx, -h, s0, t0);
    EXPECT_NEAR(d.dsdx, (s1 - s0) / (2 * h), 1e-3);
    EXPECT_NEAR(d.dtdx, (t1 - t0) / (2 * h), 1e-3);
    st(dy, h, s1, t1);
    st(dy, -h, s0, t0);
    EXPECT_NEAR(d.dsdy, (s1 - s0) / (2 * h), 1e-3);
    EXPECT_NEAR(d.dtdy, (t1 - t0) / (2 * h), 1e-3);
    ++checked;
  }
  // Zero direction: no derivatives, no NaN.
  const float one[3] = {1, 1, 1};
  const CubeFaceDerivs z = CubeFaceSelect::derivatives(CubeFaceSelect::select(0, 0, 0), one, one);
  EXPECT_EQ(z.dsdx, 0.0f);
  EXPECT_EQ(z.dtdy, 0.0f);
}

TEST(CubeFaceSelect, CostsAsDocumented) {
  // docs/texture-types.md §1: 5 cmp, 1 rcp, 10 mul, 6 add; 18 cycles, area 100.5 by default.
  const OpCounts o = CubeFaceSelect::ops_per_item();
  EXPECT_EQ(o.cmp, 5u);
  EXPECT_EQ(o.rcp, 1u);
  EXPECT_EQ(o.mul, 10u);
  EXPECT_EQ(o.add, 6u);
  const TimingSpec t = CubeFaceSelect::timing(TechTable::defaults());
  EXPECT_EQ(t.latency, 18u);
  EXPECT_DOUBLE_EQ(t.area, 100.5);
}

TEST(CubeSeam, KnownEdge) {
  // +X's s = 1 edge (towards −Z) meets −Z's s = 0 edge, rows aligned (both tc = −ry).
  std::array<CubeTexel, 3> r;
  for (int y = 0; y < 8; ++y) {
    ASSERT_EQ(CubeSeam::resolve(0, 8, y, 8, r), 1);
    EXPECT_EQ(r[0].face, static_cast<int>(CubeFace::NegZ));
    EXPECT_EQ(r[0].x, 0);
    EXPECT_EQ(r[0].y, y);
  }
  // +Z's top row (t = 0, +ry) meets +Y's last row (t = 1 is +rz on +Y).
  ASSERT_EQ(CubeSeam::resolve(4, 3, -1, 8, r), 1);
  EXPECT_EQ(r[0].face, static_cast<int>(CubeFace::PosY));
  EXPECT_EQ(r[0].x, 3);
  EXPECT_EQ(r[0].y, 7);
}

TEST(CubeSeam, EveryEdgeTexelIsTheNeighbourAcrossTheEdge) {
  for (int n : {1, 2, 5, 8}) {
    for (int f = 0; f < 6; ++f) {
      for (int k = 0; k < n; ++k) {
        const int xs[4] = {-1, n, k, k}, ys[4] = {k, k, -1, n};
        for (int e = 0; e < 4; ++e) {
          std::array<CubeTexel, 3> r;
          ASSERT_EQ(CubeSeam::resolve(f, xs[e], ys[e], n, r), 1);
          const CubeTexel& q = r[0];
          ASSERT_NE(q.face, f);
          ASSERT_NE(q.face ^ 1, f);  // not the opposite face
          ASSERT_GE(q.x, 0);
          ASSERT_LT(q.x, n);
          ASSERT_GE(q.y, 0);
          ASSERT_LT(q.y, n);
          // The in-face texel at the edge and q differ by one half-texel step along each
          // face's normal: E − Q = m_f − m_g.
          const int ex = std::clamp(xs[e], 0, n - 1), ey = std::clamp(ys[e], 0, n - 1);
          const I3 pe = centre(f, ex, ey, n), pq = centre(q.face, q.x, q.y, n);
          const CubeFaceAxes &af = cube_face_axes(f), &ag = cube_face_axes(q.face);
          for (size_t j = 0; j < 3; ++j) EXPECT_EQ(pe[j] - pq[j], af.m[j] - ag.m[j]);
          EXPECT_EQ(CubeSeam::neighbour(f, xs[e] < 0 ? -1 : (xs[e] >= n ? 1 : 0),
                                        ys[e] < 0 ? -1 : (ys[e] >= n ? 1 : 0)),
                    q.face);
        }
      }
    }
  }
}

TEST(CubeSeam, CornersGiveTheThreeTexelsAtTheCubeCorner) {
  for (int n : {1, 4}) {
    for (int f = 0; f < 6; ++f) {
      for (int cx : {-1, n}) {
        for (int cy : {-1, n}) {
          std::array<CubeTexel, 3> r;
          ASSERT_EQ(CubeSeam::resolve(f, cx, cy, n, r), 3);
          std::set<int> faces;
          for (const CubeTexel& q : r) {
            faces.insert(q.face);
            // Each is its face's corner texel, at the same cube corner: every component of
            // its centre is ±n or ±(n − 1) with the corner's signs.
            const I3 p = centre(q.face, q.x, q.y, n);
            const I3 p0 = centre(r[0].face, r[0].x, r[0].y, n);
            for (size_t j = 0; j < 3; ++j) {
              EXPECT_GE(std::abs(p[j]), n - 1);
              if (n > 1) {  // n = 1: the centre is on the axes
                EXPECT_EQ(p[j] > 0, p0[j] > 0);
              }
            }
          }
          EXPECT_EQ(faces.size(), 3u);
        }
      }
    }
  }
}

// A cube whose texels hold a smooth function of their centre's direction, so that seamless
// filtering is continuous across edges.
Texture smooth_cube(int n, int cubes = 1) {
  std::vector<std::vector<float>> faces;
  for (int c = 0; c < cubes; ++c) {
    for (int f = 0; f < 6; ++f) {
      std::vector<float> px(static_cast<size_t>(n) * n * 4);
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          const I3 p = centre(f, x, y, n);
          const double px0 = static_cast<double>(p[0]), py0 = static_cast<double>(p[1]),
                       pz0 = static_cast<double>(p[2]);
          const double len = std::sqrt(px0 * px0 + py0 * py0 + pz0 * pz0);
          float* d = &px[(static_cast<size_t>(y) * n + x) * 4];
          d[0] = static_cast<float>(0.5 + 0.5 * px0 / len);
          d[1] = static_cast<float>(0.5 + 0.5 * py0 / len);
          d[2] = static_cast<float>(0.5 + 0.5 * pz0 / len);
          d[3] = static_cast<float>(c);
        }
      }
      faces.push_back(std::move(px));
    }
  }
  return Texture::from_slices("cube", TextureType::Cube, n, n, faces, TexelFormat::Rgba32f, true);
}

Rgba sample(const LayeredAddressGen& g, const Texture& tex, const CubeFaceCoord& c, int cube = 0,
            float lambda = 0) {
  FilterTaps taps;
  LodResult lod;
  lod.lambda = lambda;
  g.cube_taps(tex, c, cube, lod, taps);
  float wsum = 0;
  for (int k = 0; k < taps.count; ++k) wsum += taps.tap[static_cast<size_t>(k)].w;
  EXPECT_NEAR(wsum, 1.0f, 1e-5f);
  TexelBlend::Config bc;
  return TexelBlend(bc).blend(taps, tex);
}

TEST(LayeredAddressGen, SeamlessIsContinuousAcrossEdgesAndTiesAgree) {
  const Texture tex = smooth_cube(8);
  TexelAddressGen::Config ac;
  ac.filter = FilterMode::Bilinear;
  ac.address_u = ac.address_v = AddressMode::Clamp;
  const TexelAddressGen base(ac);
  const LayeredAddressGen seamless(base, true), per_face(base, false);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.9f, 0.9f);
  float worst_seamless = 0, worst_per_face = 0;
  for (int i = 0; i < 200; ++i) {
    // A direction on the +X / +Y edge (|x| = |y|), taken on either face.
    const float z = u(rng);
    const CubeFaceCoord ty = CubeFaceSelect::select(1, 1, z);  // the tie rule: +Y
    ASSERT_EQ(ty.face, static_cast<int>(CubeFace::PosY));
    CubeFaceCoord tx;  // the same direction on +X
    tx.face = 0;
    tx.rc = 1;
    tx.s = 0.5f * -z + 0.5f;
    tx.t = 0.0f;
    for (const LayeredAddressGen* g : {&seamless, &per_face}) {
      const Rgba a = sample(*g, tex, ty), b = sample(*g, tex, tx);
      const float d = std::max({std::fabs(a.x - b.x), std::fabs(a.y - b.y), std::fabs(a.z - b.z)});
      (g == &seamless ? worst_seamless : worst_per_face) =
          std::max(g == &seamless ? worst_seamless : worst_per_face, d);
    }
  }
  EXPECT_LT(worst_seamless, 1e-5f);
  EXPECT_GT(worst_per_face, 0.02f);  // per-face clamping shows the seam
}

TEST(LayeredAddressGen, CornerAveragesThreeTexelsAndCubeArraysReadTheirOwnCube) {
  const Texture tex = smooth_cube(4, 3);
  EXPECT_EQ(tex.shape().slices, 18);
  EXPECT_EQ(tex.mips(), 3);
  TexelAddressGen::Config ac;
  ac.filter = FilterMode::Trilinear;
  const TexelAddressGen base(ac);
  const LayeredAddressGen g(base, true);
  const CubeFaceCoord corner = CubeFaceSelect::select(1, 1, 1);  // +Z, s = 1, t = 0
  FilterTaps taps;
  LodResult lod;
  lod.lambda = 0.5f;
  EXPECT_EQ(g.cube_taps(tex, corner, 2, lod, taps), 8);  // per level: 2 edge taps, 2 corner taps
  EXPECT_EQ(taps.count, 12);  // two levels, each quad with one corner (4 − 1 + 3 taps)
  for (int k = 0; k < taps.count; ++k) {
    const int level = taps.tap[static_cast<size_t>(k)].level;
    EXPECT_GE(level, tex.slice_level(12, 0));
    EXPECT_LT(level, tex.slice_level(18, 0));
    EXPECT_LE(level % 3, 1);  // mips 0 and 1
  }
  const Rgba c = sample(g, tex, corner, 2, 0.5f);
  EXPECT_FLOAT_EQ(c.w, 2.0f);
  // The corner direction (1, 1, 1) reads (nearly) the colour of its own direction.
  const float e = 0.5f + 0.5f / std::sqrt(3.0f);
  EXPECT_NEAR(c.x, e, 0.06f);
  EXPECT_NEAR(c.y, e, 0.06f);
  EXPECT_NEAR(c.z, e, 0.06f);
}

TEST(LayeredAddressGen, LayerRoundsHalfToEvenAndClamps) {
  EXPECT_EQ(LayeredAddressGen::select_layer(0.5f, 4), 0);
  EXPECT_EQ(LayeredAddressGen::select_layer(1.5f, 4), 2);
  EXPECT_EQ(LayeredAddressGen::select_layer(2.5f, 4), 2);
  EXPECT_EQ(LayeredAddressGen::select_layer(2.5000002f, 4), 3);
  EXPECT_EQ(LayeredAddressGen::select_layer(-0.5f, 4), 0);
  EXPECT_EQ(LayeredAddressGen::select_layer(-7.0f, 4), 0);
  EXPECT_EQ(LayeredAddressGen::select_layer(1e30f, 4), 3);
  EXPECT_EQ(LayeredAddressGen::select_layer(-1e30f, 4), 0);
  EXPECT_EQ(LayeredAddressGen::select_layer(std::numeric_limits<float>::quiet_NaN(), 4), 0);
  EXPECT_EQ(LayeredAddressGen::select_layer(std::numeric_limits<float>::infinity(), 4), 0);
  EXPECT_EQ(LayeredAddressGen::select_layer(3.0f, 1), 0);
}

TEST(LayeredAddressGen, ArrayTapsStayOnTheLayersMipChain) {
  std::vector<std::vector<float>> layers;
  layers.reserve(5);
  for (int l = 0; l < 5; ++l) layers.emplace_back(16 * 8 * 4, static_cast<float>(l));
  const Texture tex =
      Texture::from_slices("arr", TextureType::Array, 16, 8, layers, TexelFormat::Rgba32f, true);
  EXPECT_EQ(tex.mips(), 5);
  TexelAddressGen::Config ac;
  ac.filter = FilterMode::Trilinear;
  const TexelAddressGen base(ac);
  const LayeredAddressGen g(base, true);
  FilterTaps taps;
  LodResult lod;
  lod.lambda = 2.25f;
  g.array_taps(tex, 0.3, 0.7, 3, lod, taps);
  EXPECT_EQ(taps.count, 8);
  for (int k = 0; k < taps.count; ++k) {
    const TexelTap& t = taps.tap[static_cast<size_t>(k)];
    EXPECT_EQ(t.level / 5, 3);
    EXPECT_EQ(t.level % 5, k < 4 ? 2 : 3);
    EXPECT_LT(t.x, tex.level(t.level).width);
  }
  TexelBlend::Config bc;
  EXPECT_FLOAT_EQ(TexelBlend(bc).blend(taps, tex).x, 3.0f);
}

}  // namespace
}  // namespace texsim
