// The incremental evaluation of eq. 2.39 (GroundPointAdder) against eq. 2.39 itself in long
// double with the seed's explicit c11…c33 (eq. 2.38), over the flight scene's view
// (scenes/flight.toml: 60 up, ψ 30°, ϑ -12°, γ 8°, 320 × 240, 50° vertical field) and with
// γ = 0, in double, float and two fixed-point formats; what each form leaves per pixel
// (docs/derivations/terrain.md §9).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/coords/ground_point_adder.h"
#include "rtl_model/number/fixed.h"

namespace texsim {
namespace {

using LD = long double;
constexpr LD kPi = 3.14159265358979323846264338327950288L;

AviationCamera flight_camera(double roll) {
  AviationCamera::Config c;
  c.y = 60;
  c.yaw_deg = 30;
  c.pitch_deg = -12;
  c.roll_deg = roll;
  c.width = 320;
  c.height = 240;
  c.screen_distance = 120 / std::tan(25 * M_PI / 180);
  return AviationCamera(c);
}

// Eq. 2.39 with eq. 2.38's c coefficients, in long double; false above the horizon.
bool seed_ground(const AviationCamera::Config& c, LD xs, LD ys, LD& x, LD& z) {
  const LD p = c.yaw_deg * kPi / 180, t = c.pitch_deg * kPi / 180, g = c.roll_deg * kPi / 180;
  const LD sp = std::sin(p), cp = std::cos(p), st = std::sin(t), ct = std::cos(t);
  const LD sg = std::sin(g), cg = std::cos(g);
  const LD c11 = cp * cg - sp * st * sg, c12 = cp * sg + sp * st * cg, azu = -sp * ct;
  const LD c21 = sp * cg + cp * st * sg, c22 = sp * sg - cp * st * cg, axu = cp * ct;
  const LD c31 = -ct * sg, c32 = ct * cg, ayu = st;
  const LD d = c.pixel_size, ye0 = c.height / 2.0L * d, ze0 = c.width / 2.0L * d;
  const LD u1 = c.screen_distance;
  const LD c13 = c12 * ye0 - c11 * ze0 + azu * u1, c23 = c22 * ye0 - c21 * ze0 + axu * u1;
  const LD c33 = c32 * ye0 - c31 * ze0 + ayu * u1;
  const LD ze = (xs + 0.5L) * d, ye = (ys + 0.5L) * d;
  const LD den = c31 * ze - c32 * ye + c33;
  if (!(den < 0)) return false;
  x = c.x - c.y * (c21 * ze - c22 * ye + c23) / den;
  z = c.z - c.y * (c11 * ze - c12 * ye + c13) / den;
  return true;
}

// Worst error over the pixels whose ground point lies within `range` of the nadir, in ground
// units and in pixels (the ground distance between a pixel and its right neighbour).
struct Err {
  double units = 0, pixels = 0;
  int n = 0, invalid = 0;
};

template <class T>
Err measure(const GroundPointAdder& adder, const AviationCamera& cam, double range) {
  const auto& c = cam.config();
  Err e;
  std::vector<GroundSample> row(static_cast<size_t>(c.width));
  for (int ys = 0; ys < c.height; ++ys) {
    adder.eval_row<T>(cam, ys, 0, c.width, row.data());
    for (int xs = 0; xs + 1 < c.width; ++xs) {
      LD x = 0, z = 0, x1 = 0, z1 = 0;
      if (!seed_ground(c, xs, ys, x, z) || !seed_ground(c, xs + 1, ys, x1, z1)) continue;
      if (std::hypot(static_cast<double>(x - c.x), static_cast<double>(z - c.z)) > range) continue;
      const GroundSample& s = row[static_cast<size_t>(xs)];
      ++e.n;
      if (!s.valid) {
        ++e.invalid;
        continue;
      }
      const double d = static_cast<double>(std::hypot(s.x - x, s.z - z));
      const double step = static_cast<double>(std::hypot(x1 - x, z1 - z));
      e.units = std::max(e.units, d);
      e.pixels = std::max(e.pixels, d / step);
    }
  }
  return e;
}

using Fx48 = Fixed<24, 24>;
using Fx36 = Fixed<24, 12>;

TEST(GroundPointAdder, PerPixelFormMatchesEquation239) {
  const GroundPointAdder adder;
  for (double roll : {8.0, 0.0}) {
    const AviationCamera cam = flight_camera(roll);
    for (double range : {600.0, 6000.0}) {  // 10 and 100 heights out
      const Err d = measure<double>(adder, cam, range), f = measure<float>(adder, cam, range);
      const Err q48 = measure<Fx48>(adder, cam, range), q36 = measure<Fx36>(adder, cam, range);
      std::printf(
          "per pixel, roll %.0f, range %.0f (%d px): double %.1e u / %.1e px, float "
          "%.1e / %.1e, s24.24 %.1e / %.1e, s24.12 %.1e / %.1e\n",
          roll, range, d.n, d.units, d.pixels, f.units, f.pixels, q48.units, q48.pixels, q36.units,
          q36.pixels);
      EXPECT_GT(d.n, 10000);
      EXPECT_EQ(d.invalid + f.invalid + q48.invalid + q36.invalid, 0);
      EXPECT_LT(d.pixels, 1e-9);
      EXPECT_LT(f.pixels, 0.05);
      EXPECT_LT(q48.pixels, 1e-3);
      EXPECT_LT(q36.pixels, 0.5);
    }
  }
}

// The constant-depth rows: exact at γ = 0 up to the accumulated steps' rounding; with roll the
// rows are not lines of constant depth and the form is wrong by many pixels.
TEST(GroundPointAdder, ConstantDepthRowsHoldOnlyWithoutRoll) {
  GroundPointAdder::Config rc;
  rc.form = GroundPointAdder::Form::ConstantDepthRows;
  const GroundPointAdder rows(rc);
  double at_roll[3] = {0, 0, 0};
  int k = 0;
  for (double roll : {0.0, 1.0, 8.0}) {
    const AviationCamera cam = flight_camera(roll);
    const Err d = measure<double>(rows, cam, 6000), f = measure<float>(rows, cam, 6000);
    const Err q48 = measure<Fx48>(rows, cam, 6000), q36 = measure<Fx36>(rows, cam, 6000);
    std::printf(
        "constant-depth rows, roll %.0f (%d px): double %.1e u / %.1e px, float %.1e / "
        "%.1e, s24.24 %.1e / %.1e, s24.12 %.1e / %.1e\n",
        roll, d.n, d.units, d.pixels, f.units, f.pixels, q48.units, q48.pixels, q36.units,
        q36.pixels);
    const Err near = measure<double>(rows, cam, 600);
    std::printf("  within 600: double %.1e u / %.1e px\n", near.units, near.pixels);
    at_roll[k++] = near.pixels;
    if (roll == 0) {
      EXPECT_LT(d.pixels, 1e-9);
      EXPECT_LT(f.pixels, 0.05);
      EXPECT_LT(q48.pixels, 1e-3);
    }
  }
  EXPECT_GT(at_roll[1], 1.0);   // 1° of roll: off by pixels within 10 heights already
  EXPECT_GT(at_roll[2], 10.0);  // the flight scene's 8°
}

TEST(GroundPointAdder, HardCasesAndContract) {
  const GroundPointAdder adder;
  // Level flight: the upper half of the screen is sky (invalid), the lower half ground.
  AviationCamera::Config c;
  c.pitch_deg = 0;
  c.width = 8;
  c.height = 8;
  c.screen_distance = 4;
  const AviationCamera level(c);
  GroundSample s[8];
  adder.eval_row<float>(level, 1, 0, 8, s);
  for (const auto& g : s) EXPECT_FALSE(g.valid);
  adder.eval_row<float>(level, 6, 0, 8, s);
  for (const auto& g : s) EXPECT_TRUE(g.valid);
  // A position beyond the fixed-point range, or NaN: the row is invalid, never garbage.
  c.x = 1e9;
  adder.eval_row<Fx36>(AviationCamera(c), 6, 0, 8, s);
  for (const auto& g : s) EXPECT_FALSE(g.valid);
  c.x = std::nan("");
  adder.eval_row<double>(AviationCamera(c), 6, 0, 8, s);
  for (const auto& g : s) EXPECT_FALSE(g.valid);
  // What each form leaves per pixel.
  EXPECT_EQ(adder.ops_per_item().div, 2u);
  EXPECT_EQ(adder.ops_per_item().mul, 0u);  // Y_h folded into the numerators at the row set-up
  EXPECT_EQ(adder.ops_per_item().add, 5u);
  GroundPointAdder::Config rc;
  rc.form = GroundPointAdder::Form::ConstantDepthRows;
  const GroundPointAdder rows(rc);
  EXPECT_EQ(rows.ops_per_item().add, 2u);
  EXPECT_EQ(rows.ops_per_item().mul + rows.ops_per_item().div + rows.ops_per_item().rcp, 0u);
  EXPECT_EQ(rows.row_setup_ops().rcp, 1u);
  const TechTable tech = TechTable::defaults();
  EXPECT_LT(rows.timing(tech).latency, adder.timing(tech).latency);
  for (const GroundPointAdder* b : {&adder, &rows}) {
    const TimingSpec t = b->timing(tech);
    std::printf("%s: latency %u cycles, II %u, area %.0f adder-equivalents\n",
                b == &adder ? "per pixel" : "constant-depth rows", t.latency, t.ii, t.area);
  }
  EXPECT_EQ(adder.name(), "coords.ground_point_adder");
  const toml::table t = toml::parse("form = \"constant_depth_rows\"\n");
  EXPECT_EQ(GroundPointAdder::Config::from_toml(ConfigReader(t, "s.toml", "g")).form,
            GroundPointAdder::Form::ConstantDepthRows);
  const toml::table bad = toml::parse("form = \"none\"\n");
  EXPECT_THROW(GroundPointAdder::Config::from_toml(ConfigReader(bad, "s.toml", "g")), InputError);
}

}  // namespace
}  // namespace texsim
