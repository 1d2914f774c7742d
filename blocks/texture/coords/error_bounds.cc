#include "blocks/texture/coords/error_bounds.h"

#include <cmath>
#include <limits>

namespace texsim {

double quotient_error_bound(double w, double z, double dw, double dz, bool reciprocal, bool fixed,
                            double unit) {
  if (!(z - dz > 0)) return std::numeric_limits<double>::infinity();
  const double u = std::fabs(w) / z;
  // |(w+δw)/(z+δz) − w/z| = |δw − u·δz| / |z + δz| <= (dw + u·dz)/(z − dz).
  const double du = (dw + u * dz) / (z - dz);
  if (!reciprocal) return du + (fixed ? unit / 2 : unit * (u + du));
  // r = 1/ẑ rounded (<= unit/2 or unit·r), then ŵ·r rounded.
  const double wmag = std::fabs(w) + dw;
  return du + (fixed ? unit / 2 * (1 + wmag) : 2.01 * unit * (u + du));
}

double linear_form_error_bound(long double a, long double b, long double c, long double x,
                               long double y, bool fixed, double unit) {
  if (fixed) return unit / 2 * static_cast<double>(std::fabs(x) + std::fabs(y) + 1);
  // Rounding a, b, c (1 each) and the products and sums (<= 3 more along any term).
  return 4.01 * unit * static_cast<double>(std::fabs(a * x) + std::fabs(b * y) + std::fabs(c));
}

}  // namespace texsim
