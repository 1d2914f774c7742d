#include "blocks/texture/footprint/probe_setup_fx.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

#include "blocks/texture/sampler/texel_blend.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

std::string ProbeFx::name() {
  return Deriv::name() + " J, " + Sigma::name() + " Sigma, " + Angle::name() + " angle, " +
         Len::name() + " lengths, " + Coord::name() + " positions, " + Lod::name() + " LOD, " +
         Weight::name() + " weights";
}

// ---- fixed-point set-up units -------------------------------------------------------------

namespace probe_fx {

namespace {

// Rounds a non-negative wide value right by s bits, half up.
wide_int shr_half_up(wide_int v, int s) {
  return s <= 0 ? v << -s : (v + (wide_int{1} << (s - 1))) >> s;
}

// atan(2^-i) in Angle, i < kCordicSteps.
const std::array<int64_t, ProbeFx::kCordicSteps>& atan_table() {
  static const std::array<int64_t, ProbeFx::kCordicSteps> t = [] {
    std::array<int64_t, ProbeFx::kCordicSteps> a{};
    for (int i = 0; i < ProbeFx::kCordicSteps; ++i) {
      a[static_cast<size_t>(i)] = ProbeFx::Angle(std::atan(std::ldexp(1.0, -i))).raw();
    }
    return a;
  }();
  return t;
}

// log2(1 + j/1024) in Lod and 2^(-j/1024) in u0.24, j = 0 … 1023.
constexpr int kTable = 1 << ProbeFx::kTableBits;
const std::array<int64_t, kTable>& log2_table() {
  static const std::array<int64_t, kTable> t = [] {
    std::array<int64_t, kTable> a{};
    for (int j = 0; j < kTable; ++j)
      a[static_cast<size_t>(j)] =
          ProbeFx::Lod(std::log2(1.0 + j / static_cast<double>(kTable))).raw();
    return a;
  }();
  return t;
}
constexpr int kExpEntryBits = 24;
const std::array<int64_t, kTable>& exp2_table() {
  static const std::array<int64_t, kTable> t = [] {
    std::array<int64_t, kTable> a{};
    for (int j = 0; j < kTable; ++j) {
      a[static_cast<size_t>(j)] =
          std::llround(std::ldexp(std::exp2(-j / static_cast<double>(kTable)), kExpEntryBits));
    }
    return a;
  }();
  return t;
}

__extension__ typedef unsigned __int128 wide_uint;

// Integer square root (floor) of a 128-bit value: the digit recurrence, one result bit per step.
uint64_t isqrt(wide_uint n) {
  wide_uint rem = 0, root = 0;
  for (int i = 126; i >= 0; i -= 2) {
    rem = (rem << 2) | ((n >> i) & 3);
    root <<= 1;
    const wide_uint trial = (root << 1) | 1;
    if (rem >= trial) {
      rem -= trial;
      root |= 1;
    }
  }
  return static_cast<uint64_t>(root);
}

}  // namespace

ProbeFx::Len sqrt_len(ProbeFx::Sigma x) {
  using Len = ProbeFx::Len;
  if (x.raw() <= 0) return Len(0);
  // √(raw·2^-Fs) with Fl fraction bits = √(raw·2^(2Fl − Fs))·2^-Fl.
  constexpr int sh = 2 * Len::kFracBits - ProbeFx::Sigma::kFracBits;
  static_assert(sh >= 0, "Len needs at least half of Sigma's fraction bits");
  const wide_uint n = static_cast<wide_uint>(x.raw()) << sh;
  uint64_t r = isqrt(n);
  if (n - static_cast<wide_uint>(r) * r > r) ++r;  // n ≥ (r + ½)²: round up
  return Len::from_raw(static_cast<int64_t>(r));
}

ProbeFx::Lod log2_of(int64_t raw, int frac_bits) {
  using Lod = ProbeFx::Lod;
  if (raw <= 0) return Lod::min();
  int e = 63 - std::countl_zero(static_cast<uint64_t>(raw));  // leading-one position
  // f = raw/2^e − 1 to kTableBits bits, rounded; a carry out of the fraction bumps e.
  const wide_int mant = static_cast<wide_int>(raw) - (wide_int{1} << e);
  int64_t j = static_cast<int64_t>(shr_half_up(mant, e - ProbeFx::kTableBits));
  if (j >= kTable) {
    j = 0;
    ++e;
  }
  const wide_int v = (static_cast<wide_int>(e - frac_bits) << Lod::kFracBits) +
                     log2_table()[static_cast<size_t>(j)];
  return Lod::from_raw(static_cast<int64_t>(std::clamp<wide_int>(v, Lod::kRawMin, Lod::kRawMax)));
}

ProbeFx::Weight exp2_neg(ProbeFx::Arg y) {
  using Weight = ProbeFx::Weight;
  constexpr int fa = ProbeFx::Arg::kFracBits;
  int64_t e = y.raw() >> fa;
  int64_t j = static_cast<int64_t>(
      shr_half_up(y.raw() & ((int64_t{1} << fa) - 1), fa - ProbeFx::kTableBits));
  if (j >= kTable) {
    j = 0;
    ++e;
  }
  // entry·2^-24·2^-e into u1.15: a right shift by 24 − 15 + e with rounding.
  const int s = kExpEntryBits - Weight::kFracBits + static_cast<int>(std::min<int64_t>(e, 40));
  const int64_t w = static_cast<int64_t>(shr_half_up(exp2_table()[static_cast<size_t>(j)], s));
  return Weight::from_raw(w);
}

ProbeFx::Angle vector_angle(ProbeFx::Sigma x0, ProbeFx::Sigma y0, bool seed_literal,
                            ProbeFx::Sigma& mag) {
  using Angle = ProbeFx::Angle;
  // Pre-rotation into the right half-plane: (x, y) → (−x, −y), z0 = ±π (atan2) or 0 (the seed's
  // atan folds the quadrant away).
  int64_t x = x0.raw(), y = y0.raw(), z = 0;
  if (x < 0) {
    x = -x;
    y = -y;
    if (!seed_literal)
      z = y0.raw() >= 0 ? Angle(std::numbers::pi).raw() : -Angle(std::numbers::pi).raw();
  }
  // Normalisation (leading-zero count, barrel shift): the larger of |x|, |y| gets its leading one
  // at bit kTop, so the truncating shifts cost 2^-kTop relative whatever the footprint's size;
  // the gain (≤ 1.65·√2) still fits below bit 62.
  constexpr int kTop = 59;
  const uint64_t big = static_cast<uint64_t>(std::max(x, y < 0 ? -y : y));
  const int norm = big == 0 ? 0 : kTop - (63 - std::countl_zero(big));
  x = norm >= 0 ? x << norm : x >> -norm;
  y = norm >= 0 ? y << norm : y >> -norm;
  const auto& at = atan_table();
  for (int i = 0; i < ProbeFx::kCordicSteps; ++i) {
    const int64_t xs = x >> i, ys = y >> i;  // arithmetic shifts truncate (toward −∞)
    if (y >= 0) {
      x += ys;
      y -= xs;
      z += at[static_cast<size_t>(i)];
    } else {
      x -= ys;
      y += xs;
      z -= at[static_cast<size_t>(i)];
    }
  }
  mag = vd_detail::from_wide<ProbeFx::Sigma>(
      x, ProbeFx::Sigma::kFracBits + norm);  // shift back, rounded
  return Angle::from_raw(z);
}

void rotate(ProbeFx::Vec r, ProbeFx::Angle theta, ProbeFx::Vec& xo, ProbeFx::Vec& yo) {
  int64_t x = r.raw(), y = 0, z = theta.raw();
  const auto& at = atan_table();
  for (int i = 0; i < ProbeFx::kCordicSteps; ++i) {
    const int64_t xs = x >> i, ys = y >> i;
    if (z >= 0) {
      x -= ys;
      y += xs;
      z -= at[static_cast<size_t>(i)];
    } else {
      x += ys;
      y -= xs;
      z += at[static_cast<size_t>(i)];
    }
  }
  xo = ProbeFx::Vec::from_raw(x);
  yo = ProbeFx::Vec::from_raw(y);
}

double cordic_gain() {
  double k = 1;
  for (int i = 0; i < ProbeFx::kCordicSteps; ++i) k *= std::sqrt(1.0 + std::ldexp(1.0, -2 * i));
  return k;
}

ProbeFx::Const inv_gain() {
  static const ProbeFx::Const c(1.0 / cordic_gain());
  return c;
}

int64_t count_quotient(int64_t a, int64_t b, bool& rem_zero) {
  constexpr int64_t kSat = int64_t{1} << ProbeFx::kCountSteps;
  if (a >= kSat * b) {  // the first step's compare: the quotient has more bits than the divider
    rem_zero = false;
    return kSat;
  }
  rem_zero = a % b == 0;
  return a / b;
}

OpCounts cordic_ops() {
  OpCounts o;
  o.add = uint64_t{3} * ProbeFx::kCordicSteps;  // x, y shift-adds and the angle accumulator
  o.cmp = ProbeFx::kCordicSteps;                // direction: sign of y (vectoring) or z (rotation)
  return o;
}

OpCounts count_divider_ops() {
  OpCounts o;
  o.add = ProbeFx::kCountSteps;      // trial subtractions
  o.cmp = ProbeFx::kCountSteps + 1;  // restore/keep per step, remainder = 0
  return o;
}

}  // namespace probe_fx

OpCounts probe_footprint_fx_ops() {
  OpCounts o;
  // Non-finite test, Deriv converters (×w0·R, ×h0·R) and their saturation test: 1 cmp, 4 mul,
  // 1 cmp. Σ: 6 mul, 3 add. t, d = (Σuu ± Σvv)/2: 2 add. CORDIC vectoring: pre-rotation
  // (negate x, y; pick z0): 2 add, 2 cmp; normalisation (max |x|, |y|; leading-zero count):
  // 2 cmp; the steps; gain 1/K: 1 mul. λ± = t ± s: 2 add; λ₋ ≥ 0: 1 cmp. Clamp: λ₊·(1/maxA²)
  // 1 mul, compare with λ₋ 1 cmp, select 1 cmp.
  o.mul = 4 + 6 + 1 + 1;
  o.add = 3 + 2 + 2 + 2;
  o.cmp = 1 + 1 + 2 + 2 + 1 + 2;
  return o + probe_fx::cordic_ops();
}

ProbeFootprintFx probe_footprint_fx(const Fragment& f, int w0, int h0, double radius_px,
                                    double max_aniso, bool seed_theta) {
  using Deriv = ProbeFx::Deriv;
  using Sigma = ProbeFx::Sigma;
  using vd_detail::mul;
  ProbeFootprintFx fp;
  if (!std::isfinite(f.dudx) || !std::isfinite(f.dvdx) || !std::isfinite(f.dudy) ||
      !std::isfinite(f.dvdy)) {
    fp.bad_input = true;
    return fp;
  }
  // Converters: the derivative times w0·R rounded once into Deriv.
  const double sw = static_cast<double>(w0) * radius_px, sh = static_cast<double>(h0) * radius_px;
  const Deriv ux(f.dudx * sw), uy(f.dudy * sw), vx(f.dvdx * sh), vy(f.dvdy * sh);
  for (const Deriv d : {ux, uy, vx, vy}) {
    if (d.raw() == Deriv::kRawMax || d.raw() == Deriv::kRawMin) fp.overflow = true;
  }
  if (fp.overflow) return fp;
  const Sigma suu = mul<Sigma>(ux, ux) + mul<Sigma>(uy, uy);
  const Sigma suv = mul<Sigma>(ux, vx) + mul<Sigma>(uy, vy);
  const Sigma svv = mul<Sigma>(vx, vx) + mul<Sigma>(vy, vy);
  // (a ± b)/2 with the halving as one more fraction bit, rounded back.
  const auto half_sum = [](Sigma a, Sigma b, int sign) {
    const wide_int v = static_cast<wide_int>(a.raw()) + sign * static_cast<wide_int>(b.raw());
    return vd_detail::from_wide<Sigma>(v, Sigma::kFracBits + 1);
  };
  const Sigma t = half_sum(suu, svv, 1), d = half_sum(suu, svv, -1);
  Sigma mag;
  fp.two_theta = probe_fx::vector_angle(d, suv, seed_theta, mag);
  const Sigma s = mul<Sigma>(mag, probe_fx::inv_gain());
  const Sigma lp = t + s;
  Sigma lm = t - s;
  if (lm < Sigma(0)) lm = Sigma(0);
  const ProbeFx::Const inv_a2(1.0 / (max_aniso * max_aniso));
  const Sigma target = mul<Sigma>(lp, inv_a2);
  if (target > lm) {
    lm = target;
    fp.clamped = true;
  }
  fp.major2 = lp;
  fp.minor2 = lm;
  return fp;
}

}  // namespace texsim
