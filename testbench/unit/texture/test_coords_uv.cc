// Heckbert direct and incremental u/v blocks against the long double projective map.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "blocks/base/tech_table.h"
#include "blocks/geometry/projective_map.h"
#include "blocks/texture/coords/uv_heckbert_direct.h"
#include "blocks/texture/coords/uv_incremental_adder.h"

namespace texsim {
namespace {

using Q16 = Fixed<16, 16>;
using Q20 = Fixed<20, 28>;

ProjectiveMap tilted(double tilt, double az = 20.0) {
  PlaneView pv;
  pv.tilt_deg = tilt;
  pv.azimuth_deg = az;
  pv.u_offset = 512;
  pv.v_offset = 512;
  ProjectiveMap m = ProjectiveMap::from_plane_view(pv);
  // Normalised at the screen centre (q in (0.5, 1] there); rows used below lie between the
  // top of the screen (near) and the horizon, which these tilts put below the centre.
  const long double xs[1] = {255.5L}, ys[1] = {255.5L};
  return m.normalised(xs, ys, 1);
}

TEST(ProjectiveMap, ScreenParallelIsOneTexelPerPixel) {
  const ProjectiveMap m = tilted(0.0, 0.0);
  // Pixel (i, j) centre at (i + 0.5) - cx = texels from the hit point.
  EXPECT_NEAR(static_cast<double>(m.u(255.5L, 255.5L)), 512.0, 1e-12);
  EXPECT_NEAR(static_cast<double>(m.u(300, 200) - m.u(299, 200)), 1.0, 1e-12);
  EXPECT_NEAR(static_cast<double>(m.v(300, 201) - m.v(300, 200)), 1.0, 1e-12);
}

TEST(ProjectiveMap, RoundTripThroughThePlane) {
  // The map must invert the projection: project texel (u, v) to the screen and back.
  PlaneView pv;
  pv.tilt_deg = 70;
  pv.azimuth_deg = 33;
  const ProjectiveMap m = ProjectiveMap::from_plane_view(pv);
  ASSERT_TRUE(m.finite());
  // Denominator is 1/Z in front of the camera (unnormalised map): the hit point is at Z = 1.
  EXPECT_NEAR(static_cast<double>(m.den(255.5L, 255.5L)), 1.0, 1e-15);
  const DerivsL a = analytic_derivs(m, 250, 260);
  const long double h = 1e-6L;
  EXPECT_NEAR(static_cast<double>(a.ux),
              static_cast<double>((m.u(250 + h, 260) - m.u(250 - h, 260)) / (2 * h)), 1e-6);
  EXPECT_NEAR(static_cast<double>(a.vy),
              static_cast<double>((m.v(250, 260 + h) - m.v(250, 260 - h)) / (2 * h)), 1e-6);
}

TEST(ProjectiveMap, PlaneThroughTheEyeIsDegenerate) {
  PlaneView pv;
  pv.tilt_deg = 90;  // plane contains the view axis and the eye
  const ProjectiveMap m = ProjectiveMap::from_plane_view(pv);
  EXPECT_TRUE(m.degenerate);
  EXPECT_FALSE(m.finite());
  EXPECT_FALSE(to_coeffs<float>(m).ok);
}

TEST(ProjectiveMap, TranslatedShiftsCoordinates) {
  const ProjectiveMap m = tilted(60);
  const ProjectiveMap t = m.translated(1024, -2048);
  EXPECT_NEAR(static_cast<double>(t.u(100, 300) - (m.u(100, 300) - 1024)), 0.0, 1e-12);
  EXPECT_NEAR(static_cast<double>(t.v(100, 300) - (m.v(100, 300) + 2048)), 0.0, 1e-12);
}

template <class T>
double max_row_error(const ProjectiveMap& m, const RowSpan& s,
                     const std::vector<CoordSample>& out) {
  double e = 0;
  for (int32_t n = 0; n < s.n; ++n) {
    EXPECT_TRUE(out[n].valid) << format_name<T>() << " n=" << n;
    const long double x = s.x0 + n, y = s.y;
    e = std::max(e, std::fabs(out[n].u - static_cast<double>(m.u(x, y))));
    e = std::max(e, std::fabs(out[n].v - static_cast<double>(m.v(x, y))));
  }
  return e;
}

TEST(UvHeckbertDirect, ErrorPerFormat) {
  const ProjectiveMap m = tilted(60);
  const RowSpan s{0, 200, 512};
  for (auto form : {UvHeckbertDirect::Form::Divide, UvHeckbertDirect::Form::Reciprocal}) {
    UvHeckbertDirect::Config c;
    c.form = form;
    const UvHeckbertDirect b(c);
    std::vector<CoordSample> out(512);
    b.eval_row(to_coeffs<double>(m), s, out.data());
    EXPECT_LT(max_row_error<double>(m, s, out), 1e-9);
    b.eval_row(to_coeffs<float>(m), s, out.data());
    EXPECT_LT(max_row_error<float>(m, s, out), 0.05);
    b.eval_row(to_coeffs<Q20>(m), s, out.data());
    EXPECT_LT(max_row_error<Q20>(m, s, out), 1e-3);
  }
}

TEST(UvHeckbertDirect, OpsAndTiming) {
  const TechTable t = TechTable::defaults();
  UvHeckbertDirect::Config c;
  const UvHeckbertDirect d(c);
  EXPECT_EQ(d.ops_per_item().mul, 6u);
  EXPECT_EQ(d.ops_per_item().add, 6u);
  EXPECT_EQ(d.ops_per_item().div, 2u);
  EXPECT_EQ(d.timing(t).ii, 1u);
  EXPECT_EQ(d.timing(t).latency, 3u + 2u + 12u);
  c.form = UvHeckbertDirect::Form::Reciprocal;
  c.datapath = Datapath::Shared;
  const UvHeckbertDirect r(c);
  EXPECT_EQ(r.ops_per_item().mul, 8u);
  EXPECT_EQ(r.timing(t).ii, 8u);  // one shared multiplier does 8 products
}

TEST(UvIncrementalAdder, FormsAgreeWithReferenceAndBound) {
  const ProjectiveMap m = tilted(75);
  const RowSpan s{3, 150, 500};
  for (auto form : {UvIncrementalAdder::Form::Sequential, UvIncrementalAdder::Form::KLane,
                    UvIncrementalAdder::Form::Bidirectional, UvIncrementalAdder::Form::DirectN}) {
    UvIncrementalAdder::Config c;
    c.form = form;
    c.lanes = 4;
    const UvIncrementalAdder b(c);
    std::vector<CoordSample> out(static_cast<size_t>(s.n));
    b.eval_row(to_coeffs<float>(m), s, out.data());
    for (int32_t n = 0; n < s.n; ++n) {
      const double e = std::max(std::fabs(out[n].u - static_cast<double>(m.u(s.x0 + n, s.y))),
                                std::fabs(out[n].v - static_cast<double>(m.v(s.x0 + n, s.y))));
      ASSERT_LE(e, b.error_bound<float>(m, s, n)) << "n=" << n;
    }
    b.eval_row(to_coeffs<Q20>(m), s, out.data());
    for (int32_t n = 0; n < s.n; ++n) {
      const double e = std::max(std::fabs(out[n].u - static_cast<double>(m.u(s.x0 + n, s.y))),
                                std::fabs(out[n].v - static_cast<double>(m.v(s.x0 + n, s.y))));
      ASSERT_LE(e, b.error_bound<Q20>(m, s, n)) << "n=" << n;
    }
    EXPECT_LT(max_row_error<double>(m, s, (b.eval_row(to_coeffs<double>(m), s, out.data()), out)),
              1e-8);
  }
}

TEST(UvIncrementalAdder, FixedPointLanesAreBitIdentical) {
  // Fixed-point adds are exact, so the k-lane form equals the sequential form bit for bit.
  const ProjectiveMap m = tilted(80);
  const RowSpan s{0, 150, 400};
  UvIncrementalAdder::Config c;
  std::vector<CoordSample> a(400), b(400);
  UvIncrementalAdder(c).eval_row(to_coeffs<Q16>(m), s, a.data());
  c.form = UvIncrementalAdder::Form::KLane;
  c.lanes = 8;
  UvIncrementalAdder(c).eval_row(to_coeffs<Q16>(m), s, b.data());
  for (int i = 0; i < 400; ++i) {
    ASSERT_EQ(a[i].u, b[i].u);
    ASSERT_EQ(a[i].v, b[i].v);
  }
}

TEST(UvIncrementalAdder, OpsAndTiming) {
  const TechTable t = TechTable::defaults();
  UvIncrementalAdder::Config c;
  const UvIncrementalAdder seq(c);
  EXPECT_EQ(seq.ops_per_item().add + seq.ops_per_item().mul, 3u);
  EXPECT_EQ(seq.ops_per_item().div, 2u);
  EXPECT_EQ(seq.row_setup_ops().mul, 6u);
  EXPECT_EQ(seq.timing(t).latency, 12u);
  EXPECT_EQ(seq.row_setup_timing(t).latency, 3u + 2u);
  c.form = UvIncrementalAdder::Form::KLane;
  c.lanes = 4;
  const UvIncrementalAdder kl(c);
  EXPECT_EQ(kl.timing(t).lanes, 4u);
  EXPECT_EQ(kl.row_setup_ops().add, 6u + 9u);
}

// Thesis fig. 7's direct-n form: in fixed point w0 + n·A_q is exact, so it equals the running
// sums bit for bit; in float it rounds one product and one sum per pixel instead of n sums, so
// at the end of a long row its error is well below the sequential form's; its cost is 3
// multiplications per pixel more, and no pixel waits for another.
TEST(UvIncrementalAdder, DirectNFormEqualsTheSumsInFixedPoint) {
  const ProjectiveMap m = tilted(80);
  const RowSpan s{0, 200, 4096};
  UvIncrementalAdder::Config c;
  const UvIncrementalAdder seq(c);
  c.form = UvIncrementalAdder::Form::DirectN;
  const UvIncrementalAdder direct(c);
  std::vector<CoordSample> a(static_cast<size_t>(s.n)), b(a.size());
  seq.eval_row(to_coeffs<Q20>(m), s, a.data());
  direct.eval_row(to_coeffs<Q20>(m), s, b.data());
  for (int32_t n = 0; n < s.n; ++n) {
    ASSERT_EQ(a[n].valid, b[n].valid) << n;
    ASSERT_EQ(a[n].u, b[n].u) << n;
    ASSERT_EQ(a[n].v, b[n].v) << n;
  }
  seq.eval_row(to_coeffs<float>(m), s, a.data());
  direct.eval_row(to_coeffs<float>(m), s, b.data());
  const double e_seq = max_row_error<float>(m, s, a), e_direct = max_row_error<float>(m, s, b);
  EXPECT_LT(e_direct, e_seq / 4) << "sequential " << e_seq << ", direct-n " << e_direct;
  for (int32_t n = 0; n < s.n; ++n) {
    const double e = std::max(std::fabs(b[n].u - static_cast<double>(m.u(s.x0 + n, s.y))),
                              std::fabs(b[n].v - static_cast<double>(m.v(s.x0 + n, s.y))));
    ASSERT_LE(e, direct.error_bound<float>(m, s, n)) << "n=" << n;
  }
  EXPECT_EQ(direct.ops_per_item().mul, seq.ops_per_item().mul + 3);
  EXPECT_EQ(direct.ops_per_item().add, seq.ops_per_item().add);
  EXPECT_EQ(direct.lane_count(), 4u);
  EXPECT_EQ(direct.pixel_critical_path().mul, 1u);
}

}  // namespace
}  // namespace texsim
