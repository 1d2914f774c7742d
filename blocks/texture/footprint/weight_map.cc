#include "blocks/texture/footprint/weight_map.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<WeightMap>);

const char* to_string(WeightMap::Kind k) {
  switch (k) {
    case WeightMap::Kind::Full2D:
      return "full2d";
    case WeightMap::Kind::Quarter:
      return "quarter";
    case WeightMap::Kind::RadialR:
      return "radial_r";
    case WeightMap::Kind::RadialR2:
      return "radial_r2";
  }
  return "?";
}

const char* to_string(WeightMap::Element e) {
  switch (e) {
    case WeightMap::Element::U8:
      return "u8";
    case WeightMap::Element::U16:
      return "u16";
    case WeightMap::Element::Float:
      return "float";
  }
  return "?";
}

WeightMap::Config WeightMap::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"kind", "element", "size", "function", "alpha", "transform"});
  Config c;
  c.kind = static_cast<Kind>(r.get_choice("kind", static_cast<int>(c.kind),
                                          {"full2d", "quarter", "radial_r", "radial_r2"}));
  c.element = static_cast<Element>(
      r.get_choice("element", static_cast<int>(c.element), {"u8", "u16", "float"}));
  c.size = static_cast<int>(r.get_int("size", c.size, 2, 4096));
  c.function = static_cast<Function>(
      r.get_choice("function", static_cast<int>(c.function), {"exp", "pow8"}));
  c.alpha = r.get_double("alpha", c.alpha);
  if (!(c.alpha > 0) || !(c.alpha <= 64)) r.fail("alpha", "must be in (0, 64]");
  c.transform = static_cast<Transform>(
      r.get_choice("transform", static_cast<int>(c.transform), {"jacobian", "cholesky", "seed"}));
  return c;
}

WeightMap::WeightMap() : WeightMap(Config{}) {}

WeightMap::WeightMap(const Config& c) : cfg_(c) {
  cfg_.size = std::max(cfg_.size, 2);
  const bool two_d = cfg_.kind == Kind::Full2D || cfg_.kind == Kind::Quarter;
  w_ = cfg_.size;
  h_ = two_d ? cfg_.size : 1;
  data_.resize(static_cast<size_t>(w_) * static_cast<size_t>(h_));
  const double last = static_cast<double>(cfg_.size - 1);
  auto coord = [&](int k) {  // position of entry k along an axis
    const double t = static_cast<double>(k) / last;
    return cfg_.kind == Kind::Full2D ? 2.0 * t - 1.0 : t;
  };
  for (int j = 0; j < h_; ++j) {
    for (int i = 0; i < w_; ++i) {
      double r2 = 0;
      switch (cfg_.kind) {
        case Kind::Full2D:
        case Kind::Quarter:
          r2 = coord(i) * coord(i) + coord(j) * coord(j);
          break;
        case Kind::RadialR:
          r2 = coord(i) * coord(i);
          break;
        case Kind::RadialR2:
          r2 = coord(i);
          break;
      }
      const double w = function(r2);
      float q = 0;
      switch (cfg_.element) {
        case Element::U8:
          q = static_cast<float>(std::nearbyint(w * 255.0) / 255.0);
          break;
        case Element::U16:
          q = static_cast<float>(std::nearbyint(w * 65535.0) / 65535.0);
          break;
        case Element::Float:
          q = static_cast<float>(w);
          break;
      }
      data_[static_cast<size_t>(j) * static_cast<size_t>(w_) + static_cast<size_t>(i)] = q;
    }
  }
}

double WeightMap::function(double r2) const {
  // r = 1 itself belongs to the footprint (the edge entry of a radial map holds W(1)); the
  // filters' inside test Q < 1 decides which texels are read.
  if (!(r2 >= 0) || r2 > 1.0) return 0.0;
  if (cfg_.function == Function::Exp) return std::exp(-cfg_.alpha * r2);
  const double t = 1.0 - cfg_.alpha * r2 / 8.0;
  if (t <= 0) return 0.0;
  const double t2 = t * t, t4 = t2 * t2;
  return t4 * t4;
}

uint64_t WeightMap::bytes() const {
  const uint64_t per = cfg_.element == Element::U8 ? 1 : (cfg_.element == Element::U16 ? 2 : 4);
  return per * static_cast<uint64_t>(w_) * static_cast<uint64_t>(h_);
}

float WeightMap::read(float x, float y, uint32_t& reads) const {
  const float last = static_cast<float>(cfg_.size - 1);
  auto lerp = [](float a, float b, float t) { return a + t * (b - a); };
  // Continuous entry coordinate s ∈ [0, last]; outside the domain the weight is 0.
  auto split = [&](float s, int& i0, float& t) {
    s = std::clamp(s, 0.0f, last);
    const float fl = std::floor(s);
    i0 = std::min(static_cast<int>(fl), cfg_.size - 2);
    t = s - static_cast<float>(i0);
  };
  // The datapath issues its entry reads whatever the range test decides (the test selects 0
  // afterwards), so every call counts its reads.
  const bool radial = cfg_.kind == Kind::RadialR || cfg_.kind == Kind::RadialR2;
  reads += radial ? 2u : 4u;
  if (!std::isfinite(x) || !std::isfinite(y)) return 0.0f;
  if (radial) {
    const float r2 = x * x + y * y;
    if (r2 > 1.0f) return 0.0f;
    const float s = (cfg_.kind == Kind::RadialR ? std::sqrt(r2) : r2) * last;
    int i0 = 0;
    float t = 0;
    split(s, i0, t);
    return lerp(entry(i0, 0), entry(i0 + 1, 0), t);
  }
  float sx = 0, sy = 0;
  if (cfg_.kind == Kind::Quarter) {
    const float ax = std::fabs(x), ay = std::fabs(y);
    if (ax > 1.0f || ay > 1.0f) return 0.0f;
    sx = ax * last;
    sy = ay * last;
  } else {
    if (std::fabs(x) > 1.0f || std::fabs(y) > 1.0f) return 0.0f;
    const float half = 0.5f * last;
    sx = x * half + half;
    sy = y * half + half;
  }
  int i0 = 0, j0 = 0;
  float tx = 0, ty = 0;
  split(sx, i0, tx);
  split(sy, j0, ty);
  const float top = lerp(entry(i0, j0), entry(i0 + 1, j0), tx);
  const float bot = lerp(entry(i0, j0 + 1), entry(i0 + 1, j0 + 1), tx);
  return lerp(top, bot, ty);
}

OpCounts WeightMap::ops_per_item() const {
  OpCounts o;
  switch (cfg_.kind) {
    case Kind::Full2D:
      // s = x·(last/2) + last/2 per axis: 2 mul, 2 add; range test 2 cmp; floor/clamp 2 cmp,
      // fraction 2 add; three lerps (1 mul, 2 add each); four entry reads.
      o.mul = 2 + 3;
      o.add = 2 + 2 + 6;
      o.cmp = 2 + 2;
      o.mem = 4;
      break;
    case Kind::Quarter:
      // As Full2D with |x|, |y| (2 cmp: sign strip) and no offset add.
      o.mul = 2 + 3;
      o.add = 2 + 6;
      o.cmp = 2 + 2 + 2;
      o.mem = 4;
      break;
    case Kind::RadialR:
    case Kind::RadialR2:
      // r² = x² + y²: 2 mul, 1 add; range test 1 cmp; (√r²); s = ·last: 1 mul; floor/clamp
      // 1 cmp, fraction 1 add; one lerp (1 mul, 2 add); two entry reads.
      o.mul = 2 + 1 + 1;
      o.add = 1 + 1 + 2;
      o.cmp = 1 + 1;
      o.sqrt = cfg_.kind == Kind::RadialR ? 1 : 0;
      o.mem = 2;
      break;
  }
  return o;
}

OpCounts WeightMap::read_critical_path() const {
  OpCounts o;
  switch (cfg_.kind) {
    case Kind::Full2D:
    case Kind::Quarter:  // index mul, add, floor, fraction, read, two lerp levels
      o.mul = 1 + 2;
      o.add = 1 + 1 + 4;
      o.cmp = cfg_.kind == Kind::Quarter ? 2 : 1;
      o.mem = 1;
      break;
    case Kind::RadialR:
    case Kind::RadialR2:  // square, add, (sqrt), index mul, floor, fraction, read, lerp
      o.mul = 1 + 1 + 1;
      o.add = 1 + 1 + 2;
      o.cmp = 1;
      o.sqrt = cfg_.kind == Kind::RadialR ? 1 : 0;
      o.mem = 1;
      break;
  }
  return o;
}

OpCounts WeightMap::setup_ops() const {
  OpCounts o;
  if (cfg_.transform == Transform::Jacobian) {
    // det = UxVy − UyVx: 2 mul, 1 add; 1/det: rcp; four increments Vy/det, −Uy/det, −Vx/det,
    // Ux/det: 4 mul; the row start (x, y) = J⁻¹(U0, V) per row is counted per row below.
    o.mul = 2 + 4;
    o.add = 1;
    o.rcp = 1;
  } else if (cfg_.transform == Transform::Seed) {
    o = SeedTransform::setup_ops();
  } else {
    // √a, 1/√a, b/2·(1/√a), c − (b/(2√a))², √(…): 2 sqrt, 1 rcp, 2 mul, 1 add.
    o.sqrt = 2;
    o.rcp = 1;
    o.mul = 2;
    o.add = 1;
  }
  return o;
}

OpCounts WeightMap::ops_per_step() const {
  OpCounts o;
  o.add = cfg_.transform == Transform::Cholesky ? 1 : 2;
  return o;
}

SeedTransform SeedTransform::from(double ux, double vx, double uy, double vy, double u0,
                                  double v0) {
  SeedTransform t;
  const double A = vx * vx + vy * vy;
  const double C = ux * ux + uy * uy;
  const double ac = A * C;
  if (!(ac > 0) || !std::isfinite(ac)) return t;
  t.s = 1.0 / std::sqrt(ac);
  t.kx = u0 * vy - v0 * vx;
  t.ky = u0 * uy - v0 * ux;
  t.kxs = t.kx * t.s;
  t.kys = t.ky * t.s;
  t.xu = -vy * t.s;
  t.xv = vx * t.s;
  t.yu = -uy * t.s;
  t.yv = ux * t.s;
  return t;
}

OpCounts SeedTransform::setup_ops() {
  OpCounts o;
  o.mul = 4 + 1 + 4 + 6;
  o.add = 2 + 2;
  o.sqrt = 1;
  o.rcp = 1;
  return o;
}

TimingSpec WeightMap::timing(const TechTable& tech) const {
  return derive_timing(tech, ops_per_item(), read_critical_path(), Datapath::Spatial);
}

std::string WeightMap::arithmetic() const { return to_string(cfg_.element); }

std::string WeightMap::name() const {
  std::string s = to_string(cfg_.kind);
  s.append(1, ' ').append(std::to_string(w_));
  if (h_ > 1) s.append(1, 'x').append(std::to_string(h_));
  s.append(1, ' ').append(to_string(cfg_.element));
  return s;
}

}  // namespace texsim
