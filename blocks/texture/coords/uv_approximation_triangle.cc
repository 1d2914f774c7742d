#include "blocks/texture/coords/uv_approximation_triangle.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<UvApproximationTriangle>);

namespace {

using Matrix = std::array<std::array<long double, UvApproximationTriangle::kMaxTerms>,
                          UvApproximationTriangle::kMaxTerms>;

// Monomials 1, a, b, a², ab, b², a³, a²b, ab², b³ at (a, b).
std::array<long double, UvApproximationTriangle::kMaxTerms> monomials(long double a,
                                                                      long double b) {
  return {1, a, b, a * a, a * b, b * b, a * a * a, a * a * b, a * b * b, b * b * b};
}

// Inverse of the n×n Vandermonde matrix of the order's nodes (Gauss-Jordan, partial pivoting).
Matrix invert_nodes(UvApproximationTriangle::Order o, int n) {
  Matrix a{}, inv{};
  for (int i = 0; i < n; ++i) {
    const auto l = UvApproximationTriangle::node(o, i);
    const auto mono = monomials(l[0], l[1]);
    for (int j = 0; j < n; ++j) a[i][j] = mono[j];
    inv[i][i] = 1;
  }
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r) {
      if (std::fabs(a[r][c]) > std::fabs(a[p][c])) p = r;
    }
    if (std::fabs(a[p][c]) < 1e-12L) throw std::logic_error("triangle nodes are not unisolvent");
    std::swap(a[p], a[c]);
    std::swap(inv[p], inv[c]);
    const long double d = a[c][c];
    for (int j = 0; j < n; ++j) {
      a[c][j] /= d;
      inv[c][j] /= d;
    }
    for (int r = 0; r < n; ++r) {
      if (r == c || a[r][c] == 0) continue;
      const long double f = a[r][c];
      for (int j = 0; j < n; ++j) {
        a[r][j] -= f * a[c][j];
        inv[r][j] -= f * inv[c][j];
      }
    }
  }
  // Snap to the exact small rationals (multiples of 1/2) the construction yields.
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const long double r = std::round(inv[i][j] * 2) / 2;
      if (std::fabs(inv[i][j] - r) < 1e-9L) inv[i][j] = r;
    }
  }
  return inv;
}

// Operations to apply the node->coefficient matrix to one coordinate.
OpCounts matrix_ops(const Matrix& m, int n) {
  OpCounts o;
  for (int j = 0; j < n; ++j) {
    uint64_t nz = 0;
    for (int i = 0; i < n; ++i) {
      if (m[j][i] == 0) continue;
      ++nz;
      const long double a = std::fabs(m[j][i]);
      // Multiplying by ±1 or a power of two is wiring/negation, not a multiplier.
      int e = 0;
      if (std::frexp(a, &e) != 0.5L) ++o.mul;
    }
    if (nz > 1) o.add += nz - 1;
  }
  return o;
}

}  // namespace

std::array<long double, 2> UvApproximationTriangle::node(Order o, int i) {
  if (o == Order::Biquadratic) {
    static constexpr long double q[6][2] = {{0, 0},    {1, 0},    {0, 1},
                                            {0.5L, 0}, {0, 0.5L}, {0.5L, 0.5L}};
    return {q[i][0], q[i][1]};
  }
  const long double t = 1.0L / 3, s = 2.0L / 3;
  const long double c[10][2] = {{0, 0}, {1, 0}, {0, 1}, {t, 0}, {s, 0},
                                {0, t}, {0, s}, {s, t}, {t, s}, {t, t}};
  return {c[i][0], c[i][1]};
}

const Matrix& UvApproximationTriangle::node_to_coeffs(Order o) {
  static const Matrix q = invert_nodes(Order::Biquadratic, 6);
  static const Matrix c = invert_nodes(Order::Bicubic, 10);
  return o == Order::Biquadratic ? q : c;
}

UvApproximationTriangle::Config UvApproximationTriangle::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"order", "datapath", "min_denominator"});
  Config c;
  c.order = static_cast<Order>(2 + r.get_choice("order", 0, {"biquadratic", "bicubic"}));
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

OpCounts UvApproximationTriangle::ops_per_item() const {
  OpCounts o;
  o.add = 2 * static_cast<uint64_t>(cfg_.order);
  return o;
}

OpCounts UvApproximationTriangle::pixel_critical_path() const {
  OpCounts p;
  p.add = 1;
  return p;
}

OpCounts UvApproximationTriangle::row_setup_ops() const {
  // a0, b0 (barycentrics at the row start): 4 mul + 4 add. Row polynomials of the monomials:
  // a², ab, b² 10 mul + 1 add (and a³, a²b, ab², b³ from them: 24 mul + 8 add). Per
  // coordinate: the coefficients e_d = Σ c_j·m_j,d and the difference table (the ×2 and ×6
  // by a shift-add counted as one add / one mul).
  OpCounts o;
  if (cfg_.order == Order::Biquadratic) {
    o.mul = 4 + 10 + 2 * 13;
    o.add = 4 + 1 + 2 * (11 + 2);
  } else {
    o.mul = 4 + 10 + 24 + 2 * (29 + 1);
    o.add = 4 + 1 + 8 + 2 * (26 + 3);
  }
  return o;
}

OpCounts UvApproximationTriangle::row_setup_critical_path() const {
  OpCounts p;
  const bool cubic = cfg_.order == Order::Bicubic;
  p.mul = cubic ? 4 : 3;  // a0 -> monomials (-> cubic monomials) -> c·m
  p.add = cubic ? 6 : 5;  // a0 sums, coefficient sums, difference table
  return p;
}

OpCounts UvApproximationTriangle::triangle_setup_ops() const {
  const uint64_t n = static_cast<uint64_t>(nodes());
  OpCounts o;
  o.add = 4 + 1;  // edge vectors, determinant
  o.mul = 2;
  o.rcp = 1;
  o.mul += 4 + 4;  // barycentric a, b coefficients and the two products of each c
  o.add += 2;
  o.mul += n * (4 + 6);  // node position, then Heckbert's three linear forms
  o.add += n * (4 + 6);
  o.div += n * 2;
  o.cmp += n;
  o += matrix_ops(node_to_coeffs(cfg_.order), nodes()) * 2;
  return o;
}

OpCounts UvApproximationTriangle::triangle_setup_critical_path() const {
  OpCounts p;
  p.add = 2 + 2 + 4;  // position, linear form, coefficient sums
  p.mul = 3;
  p.div = 1;
  return p;
}

TimingSpec UvApproximationTriangle::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath, 1,
                       row_setup_ops() + triangle_setup_ops());
}

TimingSpec UvApproximationTriangle::row_setup_timing(const TechTable& t) const {
  TimingSpec s = derive_timing(t, row_setup_ops(), row_setup_critical_path(), cfg_.datapath);
  s.area = 0;
  return s;
}

TimingSpec UvApproximationTriangle::triangle_setup_timing(const TechTable& t) const {
  TimingSpec s =
      derive_timing(t, triangle_setup_ops(), triangle_setup_critical_path(), cfg_.datapath);
  s.area = 0;
  return s;
}

}  // namespace texsim
