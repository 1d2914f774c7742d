#include "blocks/geometry/terrain/terrain_measures.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace texsim {

double flat_ripple(const TerrainHeightEvaluator& e) {
  const TerrainGrid g(8, 8, 1.0F);
  double r = 0;
  OpCounts ops;
  for (int a = 0; a <= 256; ++a) {
    for (int b = 0; b <= 256; ++b) {
      r = std::max(r, std::fabs(e.height(g, 3 + a / 256.0, 3 + b / 256.0, ops) - 1));
    }
  }
  return r;
}

double ripple_1d(const FiniteBasis& f) {
  double r = 0;
  for (int a = 0; a <= 4096; ++a) {
    const double x = -0.5 + a / 4096.0;
    r = std::max(r, std::fabs(f.value(x - 1) + f.value(x) + f.value(x + 1) - 1));
  }
  return r;
}

double slope_jump_ratio(const TerrainHeightEvaluator& e, double& lo, double* max_jump) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<float> u(0.0F, 10.0F);
  TerrainGrid g(16, 4);
  for (int32_t i = 0; i < g.nx; ++i) {
    const float v = u(rng);
    for (int32_t j = 0; j < g.nz; ++j) g.at(i, j) = v;
  }
  double hi = 0, jump_hi = 0;
  lo = 1e9;
  OpCounts ops;
  for (int32_t i = 3; i < 13; ++i) {
    const double d2 = g.node(i + 1, 0) - 2 * g.node(i, 0) + g.node(i - 1, 0);
    const double right = e.sample(g, i, 1.5, ops).dydx;
    const double left = e.sample(g, std::nextafter(i, 0.0), 1.5, ops).dydx;
    const double jump = std::fabs(right - left);
    const double ratio = jump / std::fabs(d2);
    hi = std::max(hi, ratio);
    lo = std::min(lo, ratio);
    jump_hi = std::max(jump_hi, jump);
  }
  if (max_jump) *max_jump = jump_hi;
  return hi;
}

double terrace_measure(const TerrainHeightEvaluator& e, double& dev) {
  TerrainGrid g(16, 4);
  for (int32_t i = 0; i < g.nx; ++i) {
    for (int32_t j = 0; j < g.nz; ++j) g.at(i, j) = static_cast<float>(i);
  }
  double smin = 1e9, smax = -1e9;
  dev = 0;
  OpCounts ops;
  for (int a = 0; a <= 512; ++a) {
    const double x = 7 + a / 512.0;
    const auto s = e.sample(g, x, 1.5, ops);
    smin = std::min(smin, s.dydx);
    smax = std::max(smax, s.dydx);
    dev = std::max(dev, std::fabs(s.y - x));
  }
  return 1 - smin / smax;
}

}  // namespace texsim
