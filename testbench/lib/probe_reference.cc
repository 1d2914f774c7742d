#include "testbench/lib/probe_reference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace texsim {

RefEllipse reference_ellipse(const Fragment& f, int w0, int h0, double radius_px,
                             double max_aniso) {
  using L = long double;
  RefEllipse e;
  const L sw = static_cast<L>(w0) * radius_px, sh = static_cast<L>(h0) * radius_px;
  e.ux = f.dudx * sw;
  e.uy = f.dudy * sw;
  e.vx = f.dvdx * sh;
  e.vy = f.dvdy * sh;
  e.suu = e.ux * e.ux + e.uy * e.uy;
  e.suv = e.ux * e.vx + e.uy * e.vy;
  e.svv = e.vx * e.vx + e.vy * e.vy;
  e.d = (e.suu - e.svv) / 2;
  const L t = (e.suu + e.svv) / 2, s = std::hypot(e.d, e.suv);
  e.major2 = t + s;
  e.minor2 = std::max(t - s, L(0));
  const L a2 = static_cast<L>(max_aniso) * max_aniso;
  if (e.major2 > a2 * e.minor2) e.minor2 = e.major2 / a2;
  return e;
}

void compare_probes(const ProbeSet& p, const RefProbes& r, const ProbeBound& b, Deviation& d) {
  const long double frac = std::fabs(r.q - std::nearbyint(r.q));
  if (!r.special && r.q < b.q_clamp && frac < 1e-4L * r.q) {
    ++d.near_boundary;
    return;
  }
  if (p.n != r.n) {
    ++d.n_mismatch;
    return;
  }
  ++d.compared;
  double best = 1e300, best_w = 0;
  for (bool reversed : {false, true}) {
    double e = 0, ew = 0;
    for (int k = 0; k < p.n; ++k) {
      const auto i = static_cast<size_t>(k), j = static_cast<size_t>(reversed ? p.n - 1 - k : k);
      e = std::max(e, static_cast<double>(std::max(std::fabs((p.u[i] - r.u[j]) * b.w0),
                                                   std::fabs((p.v[i] - r.v[j]) * b.h0))));
      ew = std::max(ew, static_cast<double>(std::fabs(p.w[i] - r.w[j])));
    }
    if (e < best) {
      best = e;
      best_w = ew;
    }
  }
  d.pos_abs = std::max(d.pos_abs, best);
  const double bound =
      b.rel * static_cast<double>(1 + r.len) +
      (b.fixed ? (p.n + 1) * std::max(b.w0, b.h0) * std::exp2(-33) + std::exp2(-24) : 0.0);
  d.pos = std::max(d.pos, best / bound);
  d.w = std::max(d.w, best_w);
  if (!r.special && r.lambda > -1)
    d.lambda = std::max(d.lambda, static_cast<double>(std::fabs(p.lambda - r.lambda)));
}

std::string describe(const Deviation& d) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%d compared, %d near an N boundary, %d N mismatches; positions %.3g texel (%.3g "
                "of the bound), "
                "weights %.3g, lambda %.3g",
                d.compared, d.near_boundary, d.n_mismatch, d.pos_abs, d.pos, d.w, d.lambda);
  return buf;
}

void ColourDeviation::add(const Rgba& a, const Rgba& b) {
  for (int ch = 0; ch < 3; ++ch) {
    const double e = std::fabs(a[ch] - b[ch]);
    worst = std::max(worst, e);
    sum += e;
    ++n;
  }
}

Fragment ellipse_fragment(double u, double v, double major, double minor, double theta, int w0,
                          int h0) {
  Fragment f;
  f.u = u;
  f.v = v;
  const double c = std::cos(theta), s = std::sin(theta);
  f.dudx = major * c / w0;
  f.dvdx = major * s / h0;
  f.dudy = -minor * s / w0;
  f.dvdy = minor * c / h0;
  return f;
}

Fragment random_footprint(std::mt19937& rng, int w0, int h0, bool general) {
  std::uniform_real_distribution<double> uni(0, 1);
  const double u = uni(rng) * 4 - 2;
  const double v = uni(rng) * 4 - 2;
  Fragment f;
  if (general) {
    auto comp = [&] { return (uni(rng) < 0.5 ? -1 : 1) * std::exp2(uni(rng) * 14 - 4); };
    const double ux = comp();
    const double vx = comp();
    const double uy = comp();
    const double vy = comp();
    f.u = u;
    f.v = v;
    f.dudx = ux / w0;
    f.dvdx = vx / h0;
    f.dudy = uy / w0;
    f.dvdy = vy / h0;
  } else {
    const double major = std::exp2(uni(rng) * 15 - 3),
                 minor = major / (1 + 199 * uni(rng) * uni(rng));
    const double th = uni(rng) * std::numbers::pi;
    f = ellipse_fragment(u, v, major, minor, th, w0, h0);
  }
  f.lod_bias = static_cast<float>(uni(rng) - 0.5);
  return f;
}

Fragment random_ellipse_footprint(std::mt19937& rng, int w0, int h0) {
  std::uniform_real_distribution<double> uni(0, 1);
  const double major = std::exp2(uni(rng) * 9 - 1), minor = major / (1 + 63 * uni(rng));
  const double th = uni(rng) * std::numbers::pi;
  const double u = uni(rng);
  const double v = uni(rng);
  return ellipse_fragment(u, v, major, minor, th, w0, h0);
}

}  // namespace texsim
