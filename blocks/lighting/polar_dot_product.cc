#include "blocks/lighting/polar_dot_product.h"

#include <cmath>
#include <numbers>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<PolarDotProduct>);

namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kTwoPi = 2 * std::numbers::pi_v<float>;

bool finite(std::initializer_list<float> v) {
  for (const float x : v) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

}  // namespace

PolarDotProduct::Config PolarDotProduct::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"dims", "table_size", "datapath"});
  Config c;
  c.dims = static_cast<int>(r.get_int("dims", c.dims, 2, 3));
  c.table_size = static_cast<int32_t>(r.get_int("table_size", c.table_size, 16, 65536));
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

PolarDotProduct::PolarDotProduct(const Config& c) : cfg_(c) {
  const int32_t n = cfg_.table_size;
  value_.resize(static_cast<size_t>(n) + 1);
  slope_.resize(static_cast<size_t>(n) + 1);
  for (int32_t i = 0; i <= n; ++i) {
    const double x0 = std::numbers::pi * i / n, x1 = std::numbers::pi * (i + 1) / n;
    value_[static_cast<size_t>(i)] = static_cast<float>(std::cos(x0));
    slope_[static_cast<size_t>(i)] = static_cast<float>(std::cos(x1) - std::cos(x0));
  }
  scale_ = static_cast<float>(n / std::numbers::pi);
}

float PolarDotProduct::cosine(float angle, bool& out_of_range, OpCounts& ops) const {
  ops += cosine_ops();
  float a = angle;
  if (a > kPi) a -= kTwoPi;  // one wrap: inputs in [−π, π] give differences in (−2π, 2π)
  if (a < -kPi) a += kTwoPi;
  if (!(std::fabs(a) <= kPi)) {
    out_of_range = true;
    a = static_cast<float>(std::remainder(static_cast<double>(angle), 2 * std::numbers::pi));
  }
  const float x = std::fabs(a) * scale_;
  const float xf = std::floor(x);
  const auto i = std::min(static_cast<int32_t>(xf), cfg_.table_size);
  const float f = x - static_cast<float>(i);
  return value_[static_cast<size_t>(i)] + f * slope_[static_cast<size_t>(i)];
}

PolarDotProduct::Result PolarDotProduct::dot2(float ra, float ta, float rb, float tb,
                                              OpCounts& ops) const {
  Result r;
  if (!finite({ra, ta, rb, tb})) {
    r.invalid = true;
    return r;
  }
  ops.add += 1;  // Δ
  ops.mul += 2;  // ra·rb, × cos
  const float c = cosine(ta - tb, r.out_of_range, ops);
  r.value = (ra * rb) * c;
  return r;
}

PolarDotProduct::Result PolarDotProduct::dot3(float ra, float theta_a, float phi_a, float rb,
                                              float theta_b, float phi_b, OpCounts& ops) const {
  Result r;
  if (!finite({ra, theta_a, phi_a, rb, theta_b, phi_b})) {
    r.invalid = true;
    return r;
  }
  ops.add += 3 + 3;  // the three angles; c1 + c2, c1 − c2, the final sum
  ops.mul += 4;      // ½·ra·rb (2), (c1 − c2)·c3, the product
  const float c1 = cosine(theta_a - theta_b, r.out_of_range, ops);
  const float c2 = cosine(theta_a + theta_b, r.out_of_range, ops);
  const float c3 = cosine(phi_a - phi_b, r.out_of_range, ops);
  const float half = 0.5F * ra * rb;
  r.value = half * ((c1 + c2) + (c1 - c2) * c3);
  return r;
}

OpCounts PolarDotProduct::cosine_ops() {
  // Wrap (2 cmp, 1 add), |a| (1 cmp), the index (1 mul, floor as 1 cmp), the fraction (1 add),
  // one table read of the pair, the interpolation (1 mul, 1 add).
  OpCounts o;
  o.cmp = 4;
  o.add = 3;
  o.mul = 2;
  o.lut = 1;
  return o;
}

OpCounts PolarDotProduct::ops_per_item() const {
  OpCounts o;
  if (cfg_.dims == 2) {
    o = cosine_ops();
    o.add += 1;
    o.mul += 2;
  } else {
    o = cosine_ops() * 3;
    o.add += 6;
    o.mul += 4;
  }
  return o;
}

OpCounts PolarDotProduct::critical_path() const {
  // Δ → wrap (cmp, add) → |a| → index (mul, floor) → fraction → table → interpolation (mul,
  // add) → [3-D: c1 − c2 → × c3 → + (c1 + c2)] → × ra·rb (computed beside).
  OpCounts p;
  p.add = 1 + 1 + 1 + 1;
  p.cmp = 3;
  p.mul = 2 + 1;
  p.lut = 1;
  if (cfg_.dims == 3) {
    p.add += 2;
    p.mul += 1;
  }
  return p;
}

TimingSpec PolarDotProduct::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath);
}

OpCounts PolarDotProduct::cartesian_ops(int dims, bool from_polar) {
  OpCounts o;
  o.mul = static_cast<uint64_t>(dims);
  o.add = static_cast<uint64_t>(dims - 1);
  if (from_polar) {
    // Each sin and cos from the same table unit (a sine is cos(x − π/2): 1 add more). Per
    // vector: 2-D r cos θ, r sin θ (2 units, 2 mul); 3-D r sin θ cos φ, r sin θ sin φ, r cos θ
    // (4 units, 4 mul).
    const uint64_t units = dims == 2 ? 4 : 8;
    o += cosine_ops() * units;
    o.add += units / 2;
    o.mul += dims == 2 ? 4 : 8;
  }
  return o;
}

OpCounts PolarDotProduct::cartesian_critical_path(int dims, bool from_polar) {
  OpCounts p;
  p.mul = 1;
  p.add = dims == 2 ? 1 : 2;  // an adder tree of depth ⌈log2 dims⌉
  if (from_polar) {
    // The sine's shift, the cosine unit (as critical_path's), r·sin θ (and × cos φ in 3-D).
    p.add += 1 + 3;
    p.cmp += 3;
    p.mul += 2 + (dims == 2 ? 1 : 2);
    p.lut += 1;
  }
  return p;
}

}  // namespace texsim
