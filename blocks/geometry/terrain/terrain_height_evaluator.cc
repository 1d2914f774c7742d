#include "blocks/geometry/terrain/terrain_height_evaluator.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<TerrainHeightEvaluator>);

namespace {

// Node (i, j) of g; logged (clamped, as TerrainGrid::node clamps) when `reads` is given.
double read_node(const TerrainGrid& g, int32_t i, int32_t j, std::vector<TerrainNode>* reads) {
  if (reads) reads->push_back({std::clamp(i, 0, g.nx - 1), std::clamp(j, 0, g.nz - 1)});
  return g.node(i, j);
}

}  // namespace

TerrainHeightEvaluator::Config TerrainHeightEvaluator::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"function", "deformation", "blend_shift", "datapath"});
  Config c;
  c.basis.kind =
      static_cast<FiniteKind>(r.get_choice("function", 0, {"cosine", "quadratic", "exp2", "tent"}));
  c.basis.deformation =
      static_cast<Deformation>(r.get_choice("deformation", 0, {"none", "widened", "blended"}));
  c.basis.blend_shift = static_cast<int32_t>(r.get_int("blend_shift", 1, 0, 30));
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

TerrainHeightEvaluator::Sample TerrainHeightEvaluator::sample_2x2(
    const TerrainGrid& g, double x, double z, bool grad, std::vector<TerrainNode>* reads) const {
  const double xu = std::floor(x), zu = std::floor(z);
  const double xd = x - xu, zd = z - zu;
  const auto i = static_cast<int32_t>(xu), j = static_cast<int32_t>(zu);
  const double h1 = read_node(g, i, j, reads), h2 = read_node(g, i, j + 1, reads),
               h3 = read_node(g, i + 1, j, reads), h4 = read_node(g, i + 1, j + 1, reads);
  const FiniteBasis& f = cfg_.basis;
  const double fx = f.value(xd), fz = f.value(zd);
  Sample s;
  const double a = h2 + (h1 - h2) * fz, b = h4 + (h3 - h4) * fz;  // eq. 2.52
  s.y = b + (a - b) * fx;                                         // eq. 2.51
  if (grad) {
    // f(t) + f(t - 1) = 1, so the weight of the far node is 1 - f and its derivative -f'.
    s.dydx = (a - b) * f.derivative(xd);
    s.dydz = ((h1 - h2) * fx + (h3 - h4) * (1 - fx)) * f.derivative(zd);
  }
  return s;
}

TerrainHeightEvaluator::Sample TerrainHeightEvaluator::sample_3x3(
    const TerrainGrid& g, double x, double z, bool grad, std::vector<TerrainNode>* reads) const {
  const double xc = std::floor(x + 0.5), zc = std::floor(z + 0.5);
  const double xp = x - xc, zp = z - zc;
  const auto i0 = static_cast<int32_t>(xc), j0 = static_cast<int32_t>(zc);
  const FiniteBasis& f = cfg_.basis;
  std::array<double, 3> fx{}, fz{}, dfx{}, dfz{};
  for (int k = 0; k < 3; ++k) {
    const double off = k - 1;  // node x̂ + off, weight f¹(xp - off)
    fx[k] = f.value(xp - off);
    fz[k] = f.value(zp - off);
    if (grad) {
      dfx[k] = f.derivative(xp - off);
      dfz[k] = f.derivative(zp - off);
    }
  }
  Sample s;
  for (int a = 0; a < 3; ++a) {
    double row = 0, drow = 0;  // Σ_b h(a, b) f(z - b), and with f'
    for (int b = 0; b < 3; ++b) {
      const double h = read_node(g, i0 + a - 1, j0 + b - 1, reads);
      row += h * fz[b];
      drow += h * dfz[b];
    }
    s.y += fx[a] * row;
    s.dydx += dfx[a] * row;
    s.dydz += fx[a] * drow;
  }
  return s;
}

TerrainHeightEvaluator::Sample TerrainHeightEvaluator::sample(const TerrainGrid& g, double x,
                                                              double z, OpCounts& ops) const {
  ops += ops_per_item();
  ops += gradient_ops();
  if (!std::isfinite(x) || !std::isfinite(z) || g.nx <= 0 || g.nz <= 0) {
    return {g.nx > 0 && g.nz > 0 ? g.node(0, 0) : 0.0, 0, 0};
  }
  return cfg_.basis.deformation == Deformation::Widened ? sample_3x3(g, x, z, true)
                                                        : sample_2x2(g, x, z, true);
}

double TerrainHeightEvaluator::height(const TerrainGrid& g, double x, double z, OpCounts& ops,
                                      std::vector<TerrainNode>* reads) const {
  ops += ops_per_item();
  if (!std::isfinite(x) || !std::isfinite(z) || g.nx <= 0 || g.nz <= 0) {
    return g.nx > 0 && g.nz > 0 ? read_node(g, 0, 0, reads) : 0.0;
  }
  return cfg_.basis.deformation == Deformation::Widened ? sample_3x3(g, x, z, false, reads).y
                                                        : sample_2x2(g, x, z, false, reads).y;
}

double TerrainHeightEvaluator::height_8mul(const TerrainGrid& g, double x, double z,
                                           OpCounts& ops) const {
  if (cfg_.basis.deformation == Deformation::Widened || !std::isfinite(x) || !std::isfinite(z)) {
    return height(g, x, z, ops);
  }
  const double xu = std::floor(x), zu = std::floor(z);
  const auto i = static_cast<int32_t>(xu), j = static_cast<int32_t>(zu);
  const double fx = cfg_.basis.value(x - xu), fz = cfg_.basis.value(z - zu);
  const double gx = 1 - fx, gz = 1 - fz;
  // Eq. 2.50: four products of two weights, four products with the heights.
  const double y = g.node(i, j) * (fx * fz) + g.node(i, j + 1) * (fx * gz) +
                   g.node(i + 1, j) * (gx * fz) + g.node(i + 1, j + 1) * (gx * gz);
  OpCounts o = basis_ops() * 2;
  o.add += 2 + 2 + 3;  // the fractions, 1 - f twice, the sum
  o.mul += 8;
  o.cmp += 2;  // floor
  o.mem += 4;
  ops += o;
  return y;
}

OpCounts TerrainHeightEvaluator::basis_ops() const {
  // One base function: a table read (cos, exp2 or the polynomial's segment) and its argument.
  OpCounts o;
  switch (cfg_.basis.deformation) {
    case Deformation::None:
      o.lut = cfg_.basis.kind == FiniteKind::Tent ? 0 : 1;
      o.add = 1;  // |t|
      break;
    case Deformation::Widened:
      o.lut = 1;
      o.mul = 2;  // (2/3)·t and (2/3)·f
      o.add = 1;
      break;
    case Deformation::Blended:
      o.lut = 1;
      o.add = 1 + 1 + 2;  // |t|, tent 1 - |t|, f1 - f2 and + f2 (a·: a shift, no multiplier)
      break;
  }
  return o;
}

OpCounts TerrainHeightEvaluator::ops_per_item() const {
  OpCounts o;
  if (cfg_.basis.deformation == Deformation::Widened) {
    o = basis_ops() * 6;
    o.mul += 9 + 3;          // three rows of F(zp)·Ŷ, then F(xp)·rows
    o.add += 6 + 2 + 2 + 4;  // the row sums, the final sum, x̂ and ẑ, the offsets xp ± 1
    o.cmp += 2;              // floor
    o.mem += 9;
  } else {
    o = basis_ops() * 2;
    o.mul += 3;          // eq. 2.51–2.52
    o.add += 2 + 3 + 3;  // the fractions, the three differences, the three sums
    o.cmp += 2;          // floor
    o.mem += 4;
  }
  return o;
}

OpCounts TerrainHeightEvaluator::critical_path() const {
  // floor -> fraction -> f -> (h1 - h2)·f(zd) + h2 -> (A - B)·f(xd) + B
  OpCounts p;
  p.cmp = 1;
  p.add = 1 + 1 + 1 + 1 + 1;
  p.lut = 1;
  p.mul = cfg_.basis.deformation == Deformation::Widened ? 3 : 2;
  return p;
}

OpCounts TerrainHeightEvaluator::gradient_ops() const {
  // f' at both fractions (two more table reads), the two brackets and products.
  OpCounts o;
  if (cfg_.basis.deformation == Deformation::Widened) {
    o.lut = 6;
    o.mul = 9 + 3 + 3;
    o.add = 6 + 4;
  } else {
    o.lut = 2;
    o.mul = 4;
    o.add = 3;
  }
  return o;
}

TimingSpec TerrainHeightEvaluator::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath);
}

}  // namespace texsim
