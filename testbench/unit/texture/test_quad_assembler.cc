// Quads from a fragment stream (pipeline/texture/quad_assembler.*): the grouping rule (frame,
// primitive, square; a repeated pixel or any other fragment closes the quad), and derivatives
// from quad differences by Vulkan's coarse and fine rules, checked against hand-computed values
// on a plane (exact differences), on u = x·y (where coarse and fine differ), on partial quads
// (the fragment keeps its own derivatives where a needed lane is missing, counted).
#include <gtest/gtest.h>

#include <vector>

#include "pipeline/texture/quad_assembler.h"

namespace texsim {
namespace {

// The fragment's own derivatives: a marker no quad difference below gives.
constexpr double kOwn = 1000;

// u, v of a function of the pixel centre.
using Fn = double (*)(double, double);

Fragment frag(uint32_t x, uint32_t y, Fn u, Fn v, uint32_t prim = 0, uint32_t frame = 0) {
  Fragment f;
  f.frame = frame;
  f.prim = prim;
  f.x = x;
  f.y = y;
  f.u = u(x + 0.5, y + 0.5);
  f.v = v(x + 0.5, y + 0.5);
  f.dudx = f.dvdx = f.dudy = f.dvdy = kOwn;
  return f;
}

// A plane with dyadic coefficients: its differences are exact in double.
double plane_u(double x, double y) { return 0.25 * x - 0.125 * y + 3; }
double plane_v(double x, double y) { return -0.5 * x + 0.75 * y + 1; }
// u = x·y: x differences 0.5 on row 0 of square (0, 0), 1.5 on row 1; y differences likewise
// by column. v = x: x differences 1, y differences 0.
double xy(double x, double y) { return x * y; }
double just_x(double x, double) { return x; }

// Pushes the lanes (of square (sx, sy)) and returns the one quad they form.
Quad one_quad(QuadAssembler& qa, const std::vector<int>& lanes, Fn u, Fn v, uint32_t sx = 0,
              uint32_t sy = 0) {
  for (const int l : lanes) {
    EXPECT_EQ(qa.push(frag(2 * sx + (l & 1), 2 * sy + (l >> 1), u, v)), nullptr);
  }
  const Quad* q = qa.flush();
  EXPECT_NE(q, nullptr);
  return q ? *q : Quad{};
}

TEST(QuadAssembler, FullQuadOnAPlaneGivesItsExactDifferences) {
  for (const QuadDerivatives mode : {QuadDerivatives::Coarse, QuadDerivatives::Fine}) {
    QuadAssembler qa(mode);
    // Any lane order within the quad; a square away from the origin.
    const Quad q = one_quad(qa, {3, 0, 2, 1}, plane_u, plane_v, 3, 5);
    EXPECT_EQ(q.mask, 0xf);
    EXPECT_EQ(q.covered(), 4);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(q.lane[i].x, 6u + (i & 1));
      EXPECT_EQ(q.lane[i].y, 10u + (i >> 1));
      EXPECT_EQ(q.lane[i].dudx, 0.25);
      EXPECT_EQ(q.lane[i].dvdx, -0.5);
      EXPECT_EQ(q.lane[i].dudy, -0.125);
      EXPECT_EQ(q.lane[i].dvdy, 0.75);
    }
    EXPECT_EQ(qa.counts().quads, 1u);
    EXPECT_EQ(qa.counts().fragments, 4u);
    EXPECT_EQ(qa.counts().helper_lanes, 0u);
    EXPECT_EQ(qa.counts().own_x, 0u);
    EXPECT_EQ(qa.counts().own_y, 0u);
    EXPECT_EQ(qa.flush(), nullptr);  // nothing left open
  }
}

TEST(QuadAssembler, CoarseTakesTheTopRowAndLeftColumnFineEachRowAndColumn) {
  QuadAssembler coarse(QuadDerivatives::Coarse), fine(QuadDerivatives::Fine);
  const Quad c = one_quad(coarse, {0, 1, 2, 3}, xy, just_x);
  const Quad f = one_quad(fine, {0, 1, 2, 3}, xy, just_x);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(c.lane[i].dudx, 0.5) << i;  // row 0: 0.75 − 0.25
    EXPECT_EQ(c.lane[i].dudy, 0.5) << i;  // column 0: 0.75 − 0.25
    EXPECT_EQ(c.lane[i].dvdx, 1.0) << i;
    EXPECT_EQ(c.lane[i].dvdy, 0.0) << i;
    EXPECT_EQ(f.lane[i].dudx, i < 2 ? 0.5 : 1.5) << i;         // row 1: 2.25 − 0.75
    EXPECT_EQ(f.lane[i].dudy, (i & 1) == 0 ? 0.5 : 1.5) << i;  // column 1: 2.25 − 0.75
  }
}

TEST(QuadAssembler, PartialQuadsUseTheLanesThereAndCountTheRest) {
  {
    // Lanes 0, 1, 2: coarse has its preferred row and column.
    QuadAssembler c(QuadDerivatives::Coarse);
    const Quad q = one_quad(c, {0, 1, 2}, xy, just_x);
    EXPECT_EQ(q.mask, 0x7);
    for (const int i : {0, 1, 2}) {
      EXPECT_EQ(q.lane[i].dudx, 0.5);
      EXPECT_EQ(q.lane[i].dudy, 0.5);
    }
    EXPECT_EQ(c.counts().helper_lanes, 1u);
    EXPECT_EQ(c.counts().own_x + c.counts().own_y, 0u);
    // Fine: lane 2's row and lane 1's column lack lane 3.
    QuadAssembler f(QuadDerivatives::Fine);
    const Quad g = one_quad(f, {0, 1, 2}, xy, just_x);
    EXPECT_EQ(g.lane[0].dudx, 0.5);
    EXPECT_EQ(g.lane[0].dudy, 0.5);
    EXPECT_EQ(g.lane[1].dudx, 0.5);
    EXPECT_EQ(g.lane[1].dudy, kOwn);
    EXPECT_EQ(g.lane[1].dvdy, kOwn);
    EXPECT_EQ(g.lane[2].dudx, kOwn);
    EXPECT_EQ(g.lane[2].dvdx, kOwn);
    EXPECT_EQ(g.lane[2].dudy, 0.5);
    EXPECT_EQ(f.counts().own_x, 1u);
    EXPECT_EQ(f.counts().own_y, 1u);
  }
  {
    // Lanes 1, 2, 3: coarse falls back to the bottom row and the right column (1.5 both).
    QuadAssembler c(QuadDerivatives::Coarse);
    const Quad q = one_quad(c, {1, 2, 3}, xy, just_x);
    for (const int i : {1, 2, 3}) {
      EXPECT_EQ(q.lane[i].dudx, 1.5) << i;
      EXPECT_EQ(q.lane[i].dudy, 1.5) << i;
    }
    EXPECT_EQ(c.counts().own_x + c.counts().own_y, 0u);
    QuadAssembler f(QuadDerivatives::Fine);
    const Quad g = one_quad(f, {1, 2, 3}, xy, just_x);
    EXPECT_EQ(g.lane[1].dudx, kOwn);
    EXPECT_EQ(g.lane[1].dudy, 1.5);
    EXPECT_EQ(g.lane[2].dudx, 1.5);
    EXPECT_EQ(g.lane[2].dudy, kOwn);
    EXPECT_EQ(g.lane[3].dudx, 1.5);
    EXPECT_EQ(g.lane[3].dudy, 1.5);
    EXPECT_EQ(f.counts().own_x, 1u);
    EXPECT_EQ(f.counts().own_y, 1u);
  }
  {
    // A diagonal pair has no row and no column: both keep their own, in x and in y.
    QuadAssembler c(QuadDerivatives::Coarse);
    const Quad q = one_quad(c, {0, 3}, plane_u, plane_v);
    for (const int i : {0, 3}) {
      EXPECT_EQ(q.lane[i].dudx, kOwn);
      EXPECT_EQ(q.lane[i].dvdy, kOwn);
    }
    EXPECT_EQ(c.counts().own_x, 2u);
    EXPECT_EQ(c.counts().own_y, 2u);
    EXPECT_EQ(c.counts().helper_lanes, 2u);
  }
  {
    // Own: the quad is formed, the derivatives are not touched, nothing counted as missing.
    QuadAssembler o(QuadDerivatives::Own);
    const Quad q = one_quad(o, {0, 1, 2, 3}, plane_u, plane_v);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(q.lane[i].dudx, kOwn);
    EXPECT_EQ(o.counts().quads, 1u);
    EXPECT_EQ(o.counts().own_x + o.counts().own_y, 0u);
  }
}

TEST(QuadAssembler, AQuadInterruptedByAnotherPrimitiveIsSplit) {
  QuadAssembler qa(QuadDerivatives::Coarse);
  // Primitive 0's top row, primitive 1's lane 2, then primitive 0's bottom row.
  EXPECT_EQ(qa.push(frag(0, 0, plane_u, plane_v, 0)), nullptr);
  EXPECT_EQ(qa.push(frag(1, 0, plane_u, plane_v, 0)), nullptr);
  const Quad* a = qa.push(frag(0, 1, plane_u, plane_v, 1));
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->mask, 0x3);
  EXPECT_EQ(a->lane[0].prim, 0u);
  EXPECT_EQ(a->lane[0].dudx, 0.25);  // its top row
  EXPECT_EQ(a->lane[0].dudy, kOwn);  // no column
  const Quad* b = qa.push(frag(0, 1, plane_u, plane_v, 0));
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->mask, 0x4);
  EXPECT_EQ(b->lane[2].prim, 1u);
  EXPECT_EQ(qa.push(frag(1, 1, plane_u, plane_v, 0)), nullptr);
  const Quad* c = qa.flush();
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->mask, 0xc);
  EXPECT_EQ(c->lane[3].dudx, 0.25);  // the bottom row: coarse's other choice
  EXPECT_EQ(qa.counts().quads, 3u);
  EXPECT_EQ(qa.counts().fragments, 5u);
  EXPECT_EQ(qa.counts().helper_lanes, 7u);
  EXPECT_EQ(qa.counts().own_x, 1u);  // primitive 1's lone lane
  EXPECT_EQ(qa.counts().own_y, 5u);  // no quad had a whole column
}

TEST(QuadAssembler, FrameSquareAndRepeatedPixelCloseAQuad) {
  QuadAssembler qa(QuadDerivatives::Fine);
  int closed = 0;
  const auto push = [&](uint32_t x, uint32_t y, uint32_t frame) {
    if (qa.push(frag(x, y, plane_u, plane_v, 0, frame))) ++closed;
  };
  push(0, 0, 0);
  push(1, 0, 1);  // next frame: a new quad
  EXPECT_EQ(closed, 1);
  push(2, 0, 1);  // next square
  EXPECT_EQ(closed, 2);
  push(3, 1, 1);  // same square: joins
  EXPECT_EQ(closed, 2);
  push(3, 1, 1);  // the same pixel again: a new quad
  EXPECT_EQ(closed, 3);
  ASSERT_NE(qa.flush(), nullptr);
  EXPECT_EQ(qa.counts().quads, 4u);
  EXPECT_EQ(qa.counts().fragments, 5u);
  EXPECT_EQ(qa.counts().helper_lanes, 11u);
}

}  // namespace
}  // namespace texsim
