#include "testbench/conformance/aniso_envelope.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

namespace texsim {
namespace {

struct Vec {
  double x = 0, y = 0;
};
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y; }

// The pixel's footprint on one level, in that level's texels: centre ± e1 ± e2.
struct Parallelogram {
  Vec c, e1, e2;
  double half_x() const { return std::fabs(e1.x) + std::fabs(e2.x); }
  double half_y() const { return std::fabs(e1.y) + std::fabs(e2.y); }
};

Parallelogram footprint_on_level(const Texture& tex, int level, const AnisoQuery& q) {
  const double w = tex.width(level), h = tex.height(level);
  return {{q.u * w, q.v * h},
          {0.5 * q.dudx * w, 0.5 * q.dvdx * h},
          {0.5 * q.dudy * w, 0.5 * q.dvdy * h}};
}

// Whether the axis-aligned box [lo, hi] meets the parallelogram (separating-axis test: the
// box's two axes and the parallelogram's two edge normals; degenerate edges give no axis).
bool box_meets(const Parallelogram& p, Vec lo, Vec hi) {
  const Vec bc{0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y)};
  const Vec bh{0.5 * (hi.x - lo.x), 0.5 * (hi.y - lo.y)};
  const std::array<Vec, 4> axes = {Vec{1, 0}, Vec{0, 1}, Vec{-p.e1.y, p.e1.x},
                                   Vec{-p.e2.y, p.e2.x}};
  for (const Vec& n : axes) {
    if (n.x == 0 && n.y == 0) continue;
    const double reach = std::fabs(dot(n, p.e1)) + std::fabs(dot(n, p.e2)) + std::fabs(n.x) * bh.x +
                         std::fabs(n.y) * bh.y;
    const double gap = std::fabs(dot(n, Vec{p.c.x - bc.x, p.c.y - bc.y}));
    if (gap > reach * (1 + 1e-12) + 1e-9) return false;
  }
  return true;
}

constexpr double kFar = 1e9;  // clamp-to-edge: the edge texel stands for everything beyond

// The interval of sample positions (one axis, level texels) from which a bilinear probe may
// read texel `i` of a level `size` wide, before wrapping: [i + ½ − s, i + ½ + s].
void support(int i, int size, double s, AddressMode m, double& lo, double& hi) {
  lo = i + 0.5 - s;
  hi = i + 0.5 + s;
  if (m == AddressMode::Clamp) {
    if (i == 0) lo = -kFar;
    if (i == size - 1) hi = kFar;
  }
}

// Whether texel (x, y) of `level`, read through the addressing, is within a bilinear support
// of the footprint. Wrap: any repeat of the texel counts.
bool texel_inside(const Parallelogram& p, int x, int y, int w, int h, double s, AddressMode au,
                  AddressMode av) {
  double lx = 0, hx = 0, ly = 0, hy = 0;
  support(x, w, s, au, lx, hx);
  support(y, h, s, av, ly, hy);
  auto repeats = [](AddressMode m, double lo, double hi, double centre, double half, int size,
                    int& k0, int& k1) {
    k0 = k1 = 0;
    if (m != AddressMode::Wrap) return true;
    k0 = static_cast<int>(std::ceil((centre - half - hi) / size));
    k1 = static_cast<int>(std::floor((centre + half - lo) / size));
    return k1 - k0 <= 256;  // more repeats than that: the footprint covers the whole level
  };
  int kx0 = 0, kx1 = 0, ky0 = 0, ky1 = 0;
  if (!repeats(au, lx, hx, p.c.x, p.half_x(), w, kx0, kx1)) return true;
  if (!repeats(av, ly, hy, p.c.y, p.half_y(), h, ky0, ky1)) return true;
  for (int kx = kx0; kx <= kx1; ++kx) {
    for (int ky = ky0; ky <= ky1; ++ky) {
      const Vec lo{lx + static_cast<double>(kx) * w, ly + static_cast<double>(ky) * h};
      const Vec hi{hx + static_cast<double>(kx) * w, hy + static_cast<double>(ky) * h};
      if (box_meets(p, lo, hi)) return true;
    }
  }
  return false;
}

int address(long long i, int size, AddressMode m) {
  switch (m) {
    case AddressMode::Wrap:
      return static_cast<int>(((i % size) + size) % size);
    case AddressMode::Clamp:
      return static_cast<int>(std::clamp<long long>(i, 0, size - 1));
    case AddressMode::Mirror: {
      const long long period = 2LL * size;
      const long long t = ((i % period) + period) % period;
      return static_cast<int>(t < size ? t : period - 1 - t);
    }
    case AddressMode::MirrorClamp:
      return static_cast<int>(std::min<long long>(i < 0 ? -(1 + i) : i, size - 1));
    case AddressMode::Border:
      // Not modelled: the envelope has no border colour, and its tests never ask for border.
      return static_cast<int>(std::clamp<long long>(i, 0, size - 1));
  }
  return 0;
}

struct Hull {
  Rgba lo{std::numeric_limits<float>::max()}, hi{-std::numeric_limits<float>::max()};
  long long texels = 0;
};

// Per-channel extremes of every texel of levels [l0, l1] within a bilinear support of the
// footprint; false when there are more than `cap` candidates.
bool footprint_hull(const Texture& tex, const AnisoQuery& q, int l0, int l1, double s,
                    AddressMode au, AddressMode av, long long cap, Hull& hull) {
  for (int l = l0; l <= l1; ++l) {
    const Parallelogram p = footprint_on_level(tex, l, q);
    const auto x0 = static_cast<long long>(std::floor(p.c.x - p.half_x() - s - 0.5));
    const auto x1 = static_cast<long long>(std::ceil(p.c.x + p.half_x() + s - 0.5));
    const auto y0 = static_cast<long long>(std::floor(p.c.y - p.half_y() - s - 0.5));
    const auto y1 = static_cast<long long>(std::ceil(p.c.y + p.half_y() + s - 0.5));
    if ((x1 - x0 + 1) * (y1 - y0 + 1) > cap) return false;
    for (long long y = y0; y <= y1; ++y) {
      for (long long x = x0; x <= x1; ++x) {
        const Vec lo{static_cast<double>(x) + 0.5 - s, static_cast<double>(y) + 0.5 - s};
        const Vec hi{static_cast<double>(x) + 0.5 + s, static_cast<double>(y) + 0.5 + s};
        if (!box_meets(p, lo, hi)) continue;
        const Rgba t = tex.texel(l, address(x, tex.width(l), au), address(y, tex.height(l), av));
        for (int c = 0; c < 4; ++c) {
          hull.lo[c] = std::min(hull.lo[c], t[c]);
          hull.hi[c] = std::max(hull.hi[c], t[c]);
        }
        ++hull.texels;
      }
    }
  }
  return true;
}

int round_up_rate(int n, int max_aniso, bool power_of_two) {
  if (!power_of_two) return n;
  int r = 1;
  while (r < n) r *= 2;
  return std::min(r, max_aniso);
}

std::string fmt(const char* f, double a, double b, double c) {
  std::array<char, 160> buf{};
  std::snprintf(buf.data(), buf.size(), f, a, b, c);
  return buf.data();
}

}  // namespace

AnisoBounds AnisoEnvelope::bounds(const Texture& tex, const AnisoQuery& q) const {
  AnisoBounds b;
  const double w = tex.width(0), h = tex.height(0);
  const double ax = std::fabs(q.dudx * w), bx = std::fabs(q.dvdx * h);
  const double ay = std::fabs(q.dudy * w), by = std::fabs(q.dvdy * h);
  b.px_lo = std::max(ax, bx);
  b.px_hi = ax + bx;
  b.py_lo = std::max(ay, by);
  b.py_hi = ay + by;
  const double pmax_lo = std::max(b.px_lo, b.py_lo), pmax_hi = std::max(b.px_hi, b.py_hi);
  // The anisotropy max(Fx, Fy)/min(Fx, Fy) over the box of allowed (Fx, Fy): 1 where the
  // intervals overlap, else the nearest corners; its largest value is at a far corner.
  const double inf = std::numeric_limits<double>::infinity();
  const double pmin_hi = std::min(b.px_hi, b.py_hi);
  const double ratio_lo = pmin_hi > 0 ? std::max(1.0, pmax_lo / pmin_hi) : inf;
  const double ratio_hi =
      std::max({1.0, b.py_lo > 0 ? b.px_hi / b.py_lo : inf, b.px_lo > 0 ? b.py_hi / b.px_lo : inf});
  const int cap = spec_.max_aniso;
  auto n_of = [cap](double r) {
    if (!(r < cap)) return cap;  // also NaN (0/0: a point footprint has ratio 1 by fiat)
    return std::clamp(static_cast<int>(std::ceil(r - 1e-9 * r)), 1, cap);
  };
  b.n_lo = pmax_hi == 0 ? 1 : n_of(ratio_lo);
  b.n_hi =
      pmax_hi == 0 ? 1 : round_up_rate(n_of(ratio_hi * (1 + 1e-9)), cap, spec_.power_of_two_rates);
  const double top = tex.levels() - 1;
  const double acc = std::ldexp(1.0, -spec_.lod_fraction_bits);
  b.lambda_lo = std::clamp(std::log2(pmax_lo / b.n_hi) - acc, 0.0, top);
  b.lambda_hi = std::clamp(std::log2(pmax_hi / b.n_lo) + acc, 0.0, top);
  if (std::isnan(b.lambda_lo)) b.lambda_lo = 0;
  if (std::isnan(b.lambda_hi)) b.lambda_hi = 0;
  b.level_lo = static_cast<int>(std::floor(b.lambda_lo));
  b.level_hi = static_cast<int>(std::ceil(b.lambda_hi));
  return b;
}

AnisoVerdict AnisoEnvelope::check(const Texture& tex, const AnisoQuery& q,
                                  const AnisoObservation& obs, AddressMode au,
                                  AddressMode av) const {
  AnisoVerdict v;
  const AnisoBounds b = bounds(tex, q);
  auto fail = [&v](bool& flag, const std::string& why) {
    if (flag && v.reason.empty()) v.reason = why;
    flag = false;
  };
  if (obs.probes != 0 && (obs.probes < b.n_lo || obs.probes > b.n_hi)) {
    fail(v.probes_ok, fmt("%.0f probes outside N in [%.0f, %.0f]", obs.probes, b.n_lo, b.n_hi));
  }
  const double s = 1.0 + std::ldexp(1.0, -spec_.sub_texel_bits);
  for (const TexelRef& t : obs.texels) {
    if (t.level < b.level_lo || t.level > b.level_hi) {
      (t.level < b.level_lo ? v.too_fine : v.too_coarse) = true;
      fail(v.levels_ok,
           fmt("level %.0f read outside levels [%.0f, %.0f]", t.level, b.level_lo, b.level_hi));
      continue;
    }
    if (au == AddressMode::Mirror || av == AddressMode::Mirror) continue;
    const Parallelogram p = footprint_on_level(tex, t.level, q);
    if (!texel_inside(p, t.x, t.y, tex.width(t.level), tex.height(t.level), s, au, av)) {
      fail(v.region_ok, fmt("texel (%.0f, %.0f) of level %.0f outside the pixel's footprint", t.x,
                            t.y, t.level));
    }
  }
  Hull hull;
  const int l0 = std::max(b.level_lo, 0), l1 = std::min(b.level_hi, tex.levels() - 1);
  if (!footprint_hull(tex, q, l0, l1, s, au, av, spec_.max_hull_texels, hull)) {
    v.colour_judged = false;
  } else if (hull.texels > 0) {
    for (int c = 0; c < 4; ++c) {
      const double lo = hull.lo[c] - spec_.colour_eps, hi = hull.hi[c] + spec_.colour_eps;
      if (!(obs.colour[c] >= lo && obs.colour[c] <= hi)) {
        fail(v.colour_ok, fmt("channel value %.6f outside the footprint's [%.6f, %.6f]",
                              obs.colour[c], hull.lo[c], hull.hi[c]));
        break;
      }
    }
  }
  if (v.reason.empty()) v.reason = "ok";
  return v;
}

}  // namespace texsim
