// Stability suite of the coordinate-generation blocks: the hard cases of issue 3, each
// asserting a numeric bound against the long double map in every number format
// (docs/derivations/coords-derivations.md §3.3 states the bounds; §8 the rejection rules).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "blocks/geometry/projective_map.h"
#include "blocks/texture/coords/uv_approximation.h"
#include "blocks/texture/coords/uv_approximation_triangle.h"
#include "blocks/texture/coords/uv_constant_depth.h"
#include "blocks/texture/coords/uv_heckbert_direct.h"
#include "blocks/texture/coords/uv_incremental_adder.h"
#include "blocks/texture/derivs/derivatives_analytic.h"
#include "blocks/texture/derivs/derivatives_forward_diff.h"
#include "blocks/texture/derivs/derivatives_iterative.h"
#include "blocks/texture/derivs/derivatives_quad.h"
#include "blocks/texture/derivs/ellipse_setup.h"
#include "pipeline/studies/study_coords.h"
#include "pipeline/texture/coord_method.h"

namespace texsim {
namespace {

using S16 = Fixed<16, 16>;
using S20 = Fixed<20, 28>;
using S24 = Fixed<24, 36>;

// Calls f.template operator()<T>() for every format the blocks support.
template <class F>
void for_each_format(F&& f) {
  f(std::type_identity<float>{});
  f(std::type_identity<double>{});
  f(std::type_identity<S16>{});
  f(std::type_identity<S20>{});
  f(std::type_identity<S24>{});
}

double uv_err(const CoordSample& s, const ProjectiveMap& m, long double x, long double y) {
  return std::max(std::fabs(s.u - static_cast<double>(m.u(x, y))),
                  std::fabs(s.v - static_cast<double>(m.v(x, y))));
}

bool has_nan(const CoordSample& s) { return std::isnan(s.u) || std::isnan(s.v); }
bool has_nan(const CoordDerivs& d) {
  return std::isnan(d.ux) || std::isnan(d.vx) || std::isnan(d.uy) || std::isnan(d.vy);
}

ProjectiveMap plane_map(double tilt, double az, double focal, double u_off = 2048) {
  PlaneView pv;
  pv.tilt_deg = tilt;
  pv.azimuth_deg = az;
  pv.u_offset = pv.v_offset = u_off;
  pv.camera = square_camera(static_cast<int>(2 * focal));  // f = focal
  const long double c[1] = {static_cast<long double>(focal) - 0.5L};
  return ProjectiveMap::from_plane_view(pv).normalised(c, c, 1);
}

// ---------------------------------------------------------------------------------------
// Grazing planes up to 89.9°: Heckbert and incremental stay within their a-priori bound at
// every pixel of the clipped plane, in every format that can hold the map.
TEST(StabilityCoords, GrazingPlanesWithinBound) {
  StudyCoordsOptions o;
  o.width = o.height = 256;
  o.tiles = 4;
  for (double tilt : {80.0, 85.0, 89.0, 89.5, 89.9}) {
    const StudyPlane sp = make_study_plane(o, tilt);
    ASSERT_GT(sp.pixels, 100u) << tilt;
    for_each_format([&]<class T>(std::type_identity<T>) {
      const MapCoeffs<T> mc = to_coeffs<T>(sp.map);
      const UvHeckbertDirect hd;
      const UvIncrementalAdder inc;
      uint64_t rejected = 0, checked = 0;
      double worst_ratio = 0, worst_ratio_hd = 0;
      for (const auto& tri : sp.tris) {
        for (const auto& r : tri.rows) {
          std::vector<CoordSample> a(static_cast<size_t>(r.n)), b(static_cast<size_t>(r.n));
          hd.eval_row(mc, r, a.data());
          inc.eval_row(mc, r, b.data());
          for (int32_t n = 0; n < r.n; ++n) {
            ASSERT_FALSE(has_nan(a[n]) || has_nan(b[n]));
            if (!a[n].valid || !b[n].valid) {
              ++rejected;
              continue;
            }
            const double ba = hd.error_bound<T>(sp.map, r.x0 + n, r.y);
            const double bb = inc.error_bound<T>(sp.map, r, n);
            const double ea = uv_err(a[n], sp.map, r.x0 + n, r.y);
            const double eb = uv_err(b[n], sp.map, r.x0 + n, r.y);
            ASSERT_LE(ea, ba) << format_name<T>() << " tilt " << tilt << " (" << r.x0 + n << ","
                              << r.y << ")";
            ASSERT_LE(eb, bb) << format_name<T>() << " tilt " << tilt << " (" << r.x0 + n << ","
                              << r.y << ")";
            ASSERT_TRUE(std::isfinite(ba) && std::isfinite(bb));
            worst_ratio = std::max(worst_ratio, eb / bb);
            worst_ratio_hd = std::max(worst_ratio_hd, ea / ba);
            ++checked;
          }
        }
      }
      if (checked > 0) {
        // The bounds are tight, not vacuous: the worst pixel reaches at least 1/20 of its
        // bound (measured: 0.16 … 0.93 over these tilts and formats).
        EXPECT_GE(worst_ratio, 0.05) << format_name<T>() << " tilt " << tilt;
        EXPECT_GE(worst_ratio_hd, 0.05) << format_name<T>() << " tilt " << tilt;
      }
      if (!mc.ok) {
        // The map does not fit the format (s16.16 at grazing tilts): every pixel rejected.
        EXPECT_EQ(checked, 0u) << format_name<T>();
      } else if (!std::is_same_v<T, S16>) {
        // The clipped plane keeps q >= z_near/z_far·q_max > the limit: nothing is rejected.
        EXPECT_EQ(rejected, 0u) << format_name<T>() << " tilt " << tilt;
      }
    });
  }
}

// ---------------------------------------------------------------------------------------
// A row crossing the horizon (denominator through zero, changing sign): pixels with
// q < min_denominator are rejected (u = v = 0, valid = false), the rest stay within bound;
// approximations whose sample points fall past the limit reject the whole span; derivative
// blocks reject likewise. Never a NaN.
TEST(StabilityCoords, DenominatorChangingSignInsideARow) {
  const ProjectiveMap m = plane_map(75, 20, 256);
  // Find a row whose denominator changes sign between its ends.
  int32_t y = -1;
  for (int32_t j = 0; j < 512 && y < 0; ++j) {
    if (m.den(0, j) > 0 && m.den(511, j) < 0) y = j;
    if (m.den(0, j) < 0 && m.den(511, j) > 0) y = j;
  }
  ASSERT_GE(y, 0);
  const RowSpan row{0, y, 512};
  const double limit = UvHeckbertDirect::Config{}.min_denominator;
  for_each_format([&]<class T>(std::type_identity<T>) {
    const MapCoeffs<T> mc = to_coeffs<T>(m);
    if (!mc.ok) return;
    std::vector<CoordSample> out(512);
    for (int form = 0; form < 4; ++form) {
      UvIncrementalAdder::Config ic;
      ic.form = static_cast<UvIncrementalAdder::Form>(form % 3);
      const UvIncrementalAdder inc(ic);
      const UvHeckbertDirect hd;
      if (form == 3)
        hd.eval_row(mc, row, out.data());
      else
        inc.eval_row(mc, row, out.data());
      int valid = 0;
      for (int32_t n = 0; n < 512; ++n) {
        ASSERT_FALSE(has_nan(out[n]));
        const double q = static_cast<double>(m.den(n, y));
        const double margin = 1e-3 * limit + (is_fixed_v<T> ? 1024 * format_unit<T>() : 0.0);
        if (q < limit - margin) {
          EXPECT_FALSE(out[n].valid) << format_name<T>() << " n=" << n << " q=" << q;
        }
        if (!out[n].valid) {
          EXPECT_EQ(out[n].u, 0.0);
          continue;
        }
        ++valid;
        const double b = form == 3 ? hd.error_bound<T>(m, n, y) : inc.error_bound<T>(m, row, n);
        if (std::isfinite(b)) {
          EXPECT_LE(uv_err(out[n], m, n, y), b) << format_name<T>() << " n=" << n;
        }
      }
      EXPECT_GT(valid, 0) << format_name<T>();
      EXPECT_LT(valid, 512) << format_name<T>();
    }
    // Approximations: a sample point past the limit rejects the span.
    for (auto ord : {UvApproximation::Order::Affine, UvApproximation::Order::Quadratic,
                     UvApproximation::Order::Cubic}) {
      UvApproximation::Config ac;
      ac.order = ord;
      UvApproximation(ac).eval_row(mc, row, out.data());
      for (const auto& s : out) EXPECT_FALSE(s.valid || has_nan(s)) << format_name<T>();
    }
    // Derivative blocks.
    std::vector<CoordDerivs> d(512);
    const DerivativesIterative it;
    it.eval_row(mc, it.setup_triangle(mc), row, d.data());
    for (int32_t n = 0; n < 512; ++n) {
      ASSERT_FALSE(has_nan(d[n]));
      if (static_cast<double>(m.den(n, y)) < limit * 0.999) {
        EXPECT_FALSE(d[n].valid);
      }
    }
    DerivativesAnalytic().eval_row(mc, row, d.data());
    for (const auto& x : d) ASSERT_FALSE(has_nan(x));
    DerivativesForwardDiff().eval_row(mc, row, d.data());
    for (const auto& x : d) ASSERT_FALSE(has_nan(x));
  });
}

// ---------------------------------------------------------------------------------------
// Constant-depth lines with B -> 0 (here H -> 0) and |k| >> 1: the scan axis is chosen by
// |k|, so the slope used is <= 1 and the error at pixel centres stays the rounded-line
// offset: <= 0.5 pixel of footprint (+ arithmetic) in every format that holds the map.
TEST(StabilityCoords, ConstantDepthBToZeroAndLargeK) {
  for (double hscale : {0.0, 1e-12, 1e-6, 1e-3, 1e3}) {
    ProjectiveMap m = plane_map(60, 90, 256);  // depth varies along x: G != 0, H ~ 0
    m.H = m.G * hscale;                        // |k| = |G/H| = 1/hscale: huge, or H exactly 0
    const UvConstantDepth cd;
    const long double k = cd.slope(m);
    ASSERT_LE(std::fabs(k), 1.0L) << hscale;
    const bool xm = cd.x_major(m);
    EXPECT_EQ(xm, hscale > 1) << hscale;
    for_each_format([&]<class T>(std::type_identity<T>) {
      const MapCoeffs<T> mc = to_coeffs<T>(m);
      if (!mc.ok) return;
      const auto st = cd.setup_triangle(mc);
      ASSERT_TRUE(st.ok) << format_name<T>() << " " << hscale;
      // The line start is Heckbert's evaluation in the reciprocal form (R = 1/q, then w·R).
      UvHeckbertDirect::Config hc;
      hc.form = UvHeckbertDirect::Form::Reciprocal;
      const UvHeckbertDirect hd(hc);
      for (int32_t j = 200; j < 450; j += 60) {  // lines in front of the eye
        const UvConstantDepth::SlopedSpan l{60, static_cast<double>(j), 300};
        std::vector<CoordSample> out(300);
        cd.eval_row(mc, st, l, out.data());
        for (int32_t n = 0; n < l.n; ++n) {
          ASSERT_FALSE(has_nan(out[n]));
          ASSERT_TRUE(out[n].valid) << format_name<T>();
          const long double s = l.s0 + n, pix = j + std::floor(k * s + 0.5L);
          const long double x = xm ? s : pix, y = xm ? pix : s;
          const DerivsL d = analytic_derivs(m, x, y);
          // Half a pixel along the minor axis (first order, 5 % for curvature), the
          // arithmetic of the evaluation at the line start (twice Heckbert's reciprocal-form
          // bound: the start is at a non-integer minor coordinate, so the products round too)
          // and n rounded increments.
          const double minor = static_cast<double>(xm ? std::max(std::fabs(d.uy), std::fabs(d.vy))
                                                      : std::max(std::fabs(d.ux), std::fabs(d.vx)));
          const double u_mag =
              static_cast<double>(std::max(std::fabs(m.u(x, y)), std::fabs(m.v(x, y))));
          const double tol =
              0.5 * 1.05 * minor +
              2 * hd.error_bound<T>(m, static_cast<int32_t>(x), static_cast<int32_t>(y)) +
              2.0 * (n + 2) * format_unit<T>() * (is_fixed_v<T> ? 1.0 : u_mag + 1);
          ASSERT_LE(uv_err(out[n], m, x, y), tol)
              << format_name<T>() << " H/G=" << hscale << " n=" << n;
        }
      }
    });
  }
  // Forcing the x axis when H = 0 would need an infinite slope: the triangle is rejected.
  ProjectiveMap m = plane_map(60, 90, 256);
  m.H = 0;
  UvConstantDepth::Config c;
  c.axis = UvConstantDepth::Axis::X;
  EXPECT_FALSE(UvConstantDepth(c).setup_triangle(to_coeffs<float>(m)).ok);
}

// ---------------------------------------------------------------------------------------
// Spans of 1, 2 and 8192 pixels. The incremental form's error bound grows linearly in n:
// fixed point by n·LSB/2 in the numerators (exact adds), float by n·u·max|w| (each add
// rounds); measured errors must stay below the bound at every pixel.
TEST(StabilityCoords, Spans1And2AllRowMethods) {
  const ProjectiveMap m = plane_map(60, 20, 256);
  for_each_format([&]<class T>(std::type_identity<T>) {
    const MapCoeffs<T> mc = to_coeffs<T>(m);
    ASSERT_TRUE(mc.ok);
    for (int32_t n : {1, 2}) {
      const RowSpan s{200, 100, n};
      const UvHeckbertDirect hd;
      double tol = 0;
      for (int32_t i = 0; i < n; ++i) tol = std::max(tol, hd.error_bound<T>(m, s.x0 + i, s.y));
      // Polynomials through exact points evaluated at those points: Heckbert's bound plus the
      // rounding of the coefficient sums (up to 64 roundings of |u| or LSBs).
      const double u_mag = static_cast<double>(std::fabs(m.u(s.x0, s.y))) + 1;
      const double poly_tol = 2 * tol + 64 * format_unit<T>() * (is_fixed_v<T> ? 1.0 : u_mag);
      std::vector<CoordSample> out(static_cast<size_t>(n));
      auto check = [&](double bound, const char* what) {
        for (int32_t i = 0; i < n; ++i) {
          ASSERT_TRUE(out[i].valid) << what << " " << format_name<T>();
          EXPECT_LE(uv_err(out[i], m, s.x0 + i, s.y), bound)
              << what << " " << format_name<T>() << " n=" << n;
        }
      };
      hd.eval_row(mc, s, out.data());
      check(tol, "heckbert");
      for (int f = 0; f < 3; ++f) {
        UvIncrementalAdder::Config ic;
        ic.form = static_cast<UvIncrementalAdder::Form>(f);
        const UvIncrementalAdder inc(ic);
        inc.eval_row(mc, s, out.data());
        double b = 0;
        for (int32_t i = 0; i < n; ++i) b = std::max(b, inc.error_bound<T>(m, s, i));
        check(b, "incremental");
      }
      for (auto ord : {UvApproximation::Order::Affine, UvApproximation::Order::Quadratic,
                       UvApproximation::Order::Cubic}) {
        UvApproximation::Config ac;
        ac.order = ord;
        UvApproximation(ac).eval_row(mc, s, out.data());
        check(poly_tol, "approximation");
      }
    }
  });
}

TEST(StabilityCoords, Span8192IncrementalErrorGrowth) {
  // 8192-pixel rows: focal 4096 px, the row near the top of the screen (close to the eye).
  const ProjectiveMap m = plane_map(60, 20, 4096);
  const RowSpan s{0, 1200, 8192};
  ASSERT_GT(m.den(0, s.y), 1e-2L);
  ASSERT_GT(m.den(8191, s.y), 1e-2L);
  double worst[5] = {}, bound_end[5] = {}, bound_start[5] = {};
  int fi = 0;
  for_each_format([&]<class T>(std::type_identity<T>) {
    const MapCoeffs<T> mc = to_coeffs<T>(m);
    ASSERT_TRUE(mc.ok) << format_name<T>();
    const UvIncrementalAdder inc;
    std::vector<CoordSample> out(8192);
    inc.eval_row(mc, s, out.data());
    for (int32_t n = 0; n < s.n; ++n) {
      ASSERT_TRUE(out[n].valid);
      const double e = uv_err(out[n], m, n, s.y), b = inc.error_bound<T>(m, s, n);
      ASSERT_LE(e, b) << format_name<T>() << " n=" << n;
      worst[fi] = std::max(worst[fi], e);
    }
    bound_start[fi] = inc.error_bound<T>(m, s, 0);
    bound_end[fi] = inc.error_bound<T>(m, s, 8191);
    ++fi;
  });
  // The bound grows with n (linear accumulation): the end of the row has a much larger
  // bound than the start in float and in fixed point; double stays far below a texel.
  EXPECT_GT(bound_end[0], 20 * bound_start[0]);  // float
  EXPECT_GT(bound_end[3], 2 * bound_start[3]);   // s20.28
  EXPECT_LT(bound_end[1], 1e-7);                 // double
  EXPECT_LT(worst[4], worst[0]);                 // s24.36 beats float over 8192 steps
  EXPECT_LT(bound_end[0], 4.0);                  // float: a few texels at most, stated
}

// ---------------------------------------------------------------------------------------
// k-lane and bidirectional lanes meeting in the middle: the jump of the error between
// neighbouring pixels served by different lanes (a visible seam) is within the sum of the
// two pixels' bounds; in fixed point the k-lane form is bit-identical to the sequential one.
TEST(StabilityCoords, LaneSeams) {
  const ProjectiveMap m = plane_map(70, 20, 1024);
  const RowSpan s{0, 300, 2000};
  ASSERT_GT(m.den(0, s.y), 1e-2L);
  ASSERT_GT(m.den(1999, s.y), 1e-2L);
  for_each_format([&]<class T>(std::type_identity<T>) {
    const MapCoeffs<T> mc = to_coeffs<T>(m);
    if (!mc.ok) return;
    std::vector<CoordSample> seq(2000), out(2000);
    const UvIncrementalAdder sequential;
    sequential.eval_row(mc, s, seq.data());
    for (auto form : {UvIncrementalAdder::Form::KLane, UvIncrementalAdder::Form::Bidirectional}) {
      for (int k : {2, 4, 8}) {
        UvIncrementalAdder::Config c;
        c.form = form;
        c.lanes = k;
        const UvIncrementalAdder b(c);
        b.eval_row(mc, s, out.data());
        double worst_seam = 0;
        for (int32_t n = 1; n < s.n; ++n) {
          ASSERT_TRUE(out[n].valid && out[n - 1].valid);
          const double du =
              (out[n].u - out[n - 1].u) - static_cast<double>(m.u(n, s.y) - m.u(n - 1, s.y));
          const double dv =
              (out[n].v - out[n - 1].v) - static_cast<double>(m.v(n, s.y) - m.v(n - 1, s.y));
          const double seam = std::max(std::fabs(du), std::fabs(dv));
          const double bound = b.error_bound<T>(m, s, n) + b.error_bound<T>(m, s, n - 1);
          ASSERT_LE(seam, bound) << format_name<T>() << " n=" << n;
          worst_seam = std::max(worst_seam, seam);
        }
        if (form == UvIncrementalAdder::Form::KLane && is_fixed_v<T>) {
          for (int32_t n = 0; n < s.n; ++n) ASSERT_EQ(out[n].u, seq[n].u) << format_name<T>();
        }
        if (form == UvIncrementalAdder::Form::Bidirectional) break;  // lanes fixed at 2
      }
    }
  });
}

// ---------------------------------------------------------------------------------------
// Coordinates of 10^6 texels: float cannot hold a sub-texel position there (ulp 1/16 texel);
// rebasing the map by whole texture tiles at set-up (ProjectiveMap::translated, long double)
// restores it. Formats whose range is below 10^6 reject the map cleanly.
TEST(StabilityCoords, MillionTexelCoordinatesAndWrapRebase) {
  const double big = 1.0e6;
  const ProjectiveMap far = plane_map(30, 20, 256, big);
  const double tile = 1024;  // texture width: wrapping keeps u mod 1024
  const long double base = std::floor(big / tile) * tile;
  const ProjectiveMap rebased = far.translated(base, base);
  const RowSpan s{0, 200, 512};
  auto wrapped_err = [&](const CoordSample& o, const ProjectiveMap& mm, long double shift,
                         int32_t x) {
    const long double ur = mm.u(x, s.y) + shift, vr = mm.v(x, s.y) + shift;
    auto wrap = [&](long double a) { return a - std::floor(a / tile) * tile; };
    auto dist = [&](long double a, long double b) {
      const long double d = std::fabs(wrap(a) - wrap(b));
      return static_cast<double>(std::min(d, tile - d));
    };
    return std::max(dist(o.u + shift, ur), dist(o.v + shift, vr));
  };
  double float_far = 0, float_rebased = 0;
  for_each_format([&]<class T>(std::type_identity<T>) {
    const UvHeckbertDirect hd;
    std::vector<CoordSample> out(512);
    for (int pass = 0; pass < 2; ++pass) {
      const ProjectiveMap& mm = pass == 0 ? far : rebased;
      const long double shift = pass == 0 ? 0 : base;
      const MapCoeffs<T> mc = to_coeffs<T>(mm);
      hd.eval_row(mc, s, out.data());
      if (!mc.ok) {
        // s16.16 and s20.28 cannot hold coefficients of 10^6 texels: rejected, no garbage.
        EXPECT_EQ(pass, 0) << format_name<T>();
        for (const auto& o : out) EXPECT_FALSE(o.valid || has_nan(o));
        continue;
      }
      double worst = 0;
      for (int32_t n = 0; n < 512; ++n) {
        ASSERT_TRUE(out[n].valid) << format_name<T>() << " pass " << pass;
        const double e = wrapped_err(out[n], mm, shift, n);
        ASSERT_LE(e, hd.error_bound<T>(mm, n, s.y)) << format_name<T>() << " pass " << pass;
        worst = std::max(worst, e);
      }
      if (std::is_same_v<T, float>) (pass == 0 ? float_far : float_rebased) = worst;
    }
  });
  EXPECT_GT(float_far, 1.0 / 256);      // float at 10^6 texels: sub-texel bits lost
  EXPECT_LT(float_rebased, 1.0 / 256);  // rebased by whole tiles: within 8 sub-texel bits
  EXPECT_LT(float_rebased * 16, float_far);
}

// ---------------------------------------------------------------------------------------
// NaN / Inf inputs: rejected cleanly by every block in every format, never a NaN output.
TEST(StabilityCoords, NanAndInfInputsAreRejected) {
  const ProjectiveMap good = plane_map(45, 20, 256);
  const long double bad_values[] = {std::numeric_limits<long double>::quiet_NaN(),
                                    std::numeric_limits<long double>::infinity(),
                                    -std::numeric_limits<long double>::infinity()};
  for (int coef = 0; coef < 9; ++coef) {
    for (long double bad : bad_values) {
      ProjectiveMap m = good;
      long double* c[9] = {&m.A, &m.B, &m.C, &m.D, &m.E, &m.F, &m.G, &m.H, &m.I};
      *c[coef] = bad;
      for_each_format([&]<class T>(std::type_identity<T>) {
        const MapCoeffs<T> mc = to_coeffs<T>(m);
        EXPECT_FALSE(mc.ok);
        const RowSpan s{10, 100, 64};
        std::vector<CoordSample> out(64, CoordSample{1, 1, true});
        auto none = [&](const char* what) {
          for (const auto& o : out)
            ASSERT_FALSE(o.valid || has_nan(o)) << what << " " << format_name<T>();
        };
        UvHeckbertDirect().eval_row(mc, s, out.data());
        none("heckbert");
        UvIncrementalAdder().eval_row(mc, s, out.data());
        none("incremental");
        UvApproximation().eval_row(mc, s, out.data());
        none("quadratic");
        const UvApproximationTriangle at;
        UvApproximationTriangle::Triangle tri;
        tri.x[1] = 100;
        tri.y[2] = 100;
        at.eval_row(at.setup_triangle(mc, tri), s, out.data());
        none("biquadratic");
        const UvConstantDepth cd;
        cd.eval_row(mc, cd.setup_triangle(mc), {10, 100.0, 64}, out.data());
        none("constant-depth");
        std::vector<CoordDerivs> d(64, CoordDerivs{1, 1, 1, 1, true});
        auto no_d = [&](const char* what) {
          for (const auto& x : d)
            ASSERT_FALSE(x.valid || has_nan(x)) << what << " " << format_name<T>();
        };
        DerivativesAnalytic().eval_row(mc, s, d.data());
        no_d("analytic");
        DerivativesQuad().eval_row(mc, s, d.data());
        no_d("quad");
        DerivativesForwardDiff().eval_row(mc, s, d.data());
        no_d("forward-diff");
        const DerivativesIterative it;
        it.eval_row(mc, it.setup_triangle(mc), s, d.data());
        no_d("iterative");
      });
    }
  }
  // A NaN vertex or line offset, a NaN derivative into the ellipse set-up, a degenerate map.
  for_each_format([&]<class T>(std::type_identity<T>) {
    const MapCoeffs<T> mc = to_coeffs<T>(good);
    const UvApproximationTriangle at;
    UvApproximationTriangle::Triangle tri;
    tri.x[1] = std::numeric_limits<double>::quiet_NaN();
    tri.y[2] = 100;
    EXPECT_FALSE(at.setup_triangle(mc, tri).ok);
    const UvConstantDepth cd;
    std::vector<CoordSample> out(8, CoordSample{1, 1, true});
    cd.eval_row(mc, cd.setup_triangle(mc), {0, std::numeric_limits<double>::infinity(), 8},
                out.data());
    for (const auto& o : out) EXPECT_FALSE(o.valid || has_nan(o));
    for (auto form : {EllipseSetup::FForm::Determinant, EllipseSetup::FForm::AcMinusB2}) {
      EllipseSetup::Config ec;
      ec.f_form = form;
      const double nan = std::numeric_limits<double>::quiet_NaN();
      const EllipseCoeffs e = EllipseSetup(ec).eval<T>(CoordDerivs{nan, 1, 1, 1, true});
      if constexpr (!is_fixed_v<T>) {
        EXPECT_FALSE(e.valid);
      }
      EXPECT_FALSE(std::isnan(e.an) || std::isnan(e.bn) || std::isnan(e.cn) || std::isnan(e.f));
      const EllipseCoeffs z = EllipseSetup(ec).eval<T>(CoordDerivs{0, 0, 0, 0, true});
      EXPECT_FALSE(z.valid);  // a zero footprint has F = 0: no ellipse, no division by zero
    }
  });
  PlaneView pv;
  pv.tilt_deg = 90;  // the plane through the eye
  const ProjectiveMap eye = ProjectiveMap::from_plane_view(pv);
  ASSERT_TRUE(eye.degenerate);
  for (const auto& method : CoordGenerator::method_names()) {
    const auto g = CoordGenerator::create(method, "float");
    CoordTriangle tri;
    tri.map = eye;
    tri.x[1] = 50;
    tri.y[2] = 50;
    tri.rows = triangle_rows(tri.x, tri.y, 64, 64);
    std::vector<CoordFragment> frags;
    std::vector<ItemCost> costs;
    OpCounts ops;
    CoordGeneratorStats st;
    g->generate(tri, TechTable::defaults(), frags, costs, ops, st);
    ASSERT_FALSE(frags.empty());
    for (const auto& f : frags) ASSERT_FALSE(f.uv.valid || has_nan(f.uv)) << method;
  }
}

}  // namespace
}  // namespace texsim
