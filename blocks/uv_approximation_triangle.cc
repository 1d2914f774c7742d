#include "blocks/uv_approximation_triangle.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "blocks/config_reader.h"

namespace texsim {

namespace {

using Matrix = std::array<std::array<long double, UvApproximationTriangle::kMaxTerms>,
                          UvApproximationTriangle::kMaxTerms>;

// Monomials 1, a, b, a², ab, b², a³, a²b, ab², b³ at (a, b).
std::array<long double, UvApproximationTriangle::kMaxTerms> monomials(long double a, long double b) {
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
    static constexpr long double q[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5L, 0}, {0, 0.5L}, {0.5L, 0.5L}};
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

OpCounts UvApproximationTriangle::pixel_ops() const {
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
  const bool cubic = cfg_.order == Order::Bicubic;
  const uint64_t pts = cubic ? 4 : 3;
  OpCounts per_point;
  per_point.mul = 4;  // l1, l2 = a·x + b·y + c
  per_point.add = 4;
  per_point.mul += cubic ? 7 : 3;  // monomials a², ab, b² (and a³, a²b, ab², b³)
  const uint64_t terms = cubic ? 10 : 6;
  per_point.mul += 2 * (terms - 1);  // coefficient products, u and v
  per_point.add += 2 * (terms - 1);
  OpCounts o = per_point * pts;
  o.add += 2 * (cubic ? 6 : 3);  // difference table, u and v
  return o;
}

OpCounts UvApproximationTriangle::row_setup_critical_path() const {
  OpCounts p;
  p.mul = cfg_.order == Order::Bicubic ? 4 : 3;  // l, monomial, coefficient product
  p.add = 2 + (cfg_.order == Order::Bicubic ? 4 : 3) + static_cast<uint64_t>(cfg_.order);
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
  return derive_timing(t, pixel_ops(), pixel_critical_path(), cfg_.datapath, 1,
                       row_setup_ops() + triangle_setup_ops());
}

TimingSpec UvApproximationTriangle::row_setup_timing(const TechTable& t) const {
  TimingSpec s = derive_timing(t, row_setup_ops(), row_setup_critical_path(), cfg_.datapath);
  s.area = 0;
  return s;
}

TimingSpec UvApproximationTriangle::triangle_setup_timing(const TechTable& t) const {
  TimingSpec s = derive_timing(t, triangle_setup_ops(), triangle_setup_critical_path(), cfg_.datapath);
  s.area = 0;
  return s;
}

}  // namespace texsim
