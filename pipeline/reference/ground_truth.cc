#include "pipeline/reference/ground_truth.h"

#include <algorithm>
#include <cmath>

namespace texsim {

namespace {

// Integer texel coordinate under an addressing mode (written independently of the blocks).
int address(long long i, int size, AddressMode m) {
  switch (m) {
    case AddressMode::Wrap: {
      long long r = i % size;
      return static_cast<int>(r < 0 ? r + size : r);
    }
    case AddressMode::Clamp:
      return static_cast<int>(i < 0 ? 0 : (i >= size ? size - 1 : i));
    case AddressMode::Mirror: {
      const long long period = 2LL * size;
      long long r = i % period;
      if (r < 0) r += period;
      return static_cast<int>(r < size ? r : period - 1 - r);
    }
  }
  return 0;
}

// The integer texel coordinate floor(x) = f as a long long that addresses the same texel.
// Beyond 2^53 every double is an integer and may not fit a long long: it becomes a value of
// the same sign and residue modulo 2·size (so wrap, mirror and clamp address the same texel).
long long texel_index(double f, int size) {
  if (std::fabs(f) < 0x1p53) return static_cast<long long>(f);
  const long long far = (2LL * size) << 20;
  return static_cast<long long>(std::fmod(f, 2.0 * size)) + (f > 0 ? far : -far);
}

// address(i, size, m) and address(i + 1, size, m) with at most one division (none for a
// power-of-two size), as the bilinear footprint's two columns (or rows) need.
[[gnu::always_inline]] inline void address_pair(long long i, int size, AddressMode m, int& a0,
                                                int& a1) {
  if (i >= 0 && i + 1 < size) {  // both inside: every mode leaves them as they are
    a0 = static_cast<int>(i);
    a1 = a0 + 1;
    return;
  }
  const bool pow2 = (size & (size - 1)) == 0;
  switch (m) {
    case AddressMode::Wrap: {
      long long r = pow2 ? (i & (size - 1)) : i % size;
      if (r < 0) r += size;
      a0 = static_cast<int>(r);
      a1 = a0 + 1 == size ? 0 : a0 + 1;
      return;
    }
    case AddressMode::Clamp:
      a0 = address(i, size, m);
      a1 = address(i + 1, size, m);
      return;
    case AddressMode::Mirror: {
      const long long period = 2LL * size;
      long long r = pow2 ? (i & (period - 1)) : i % period;
      if (r < 0) r += period;
      const long long r1 = r + 1 == period ? 0 : r + 1;
      a0 = static_cast<int>(r < size ? r : period - 1 - r);
      a1 = static_cast<int>(r1 < size ? r1 : period - 1 - r1);
      return;
    }
  }
  a0 = a1 = 0;
}

// The values Texture::texel gives an 8-bit channel (float b/255), as doubles.
struct ByteToDouble {
  double v[256];
  ByteToDouble() {
    constexpr float k = 1.0f / 255.0f;
    for (int b = 0; b < 256; ++b) v[b] = static_cast<float>(b) * k;
  }
};
const ByteToDouble kByte;

[[gnu::always_inline]] inline glm::dvec4 fetch(const Texture& t, int x, int y) {
  if (t.format() == TexelFormat::Rgba8) {
    const Texture::Level& lv = t.level(0);
    const uint8_t* p = t.rgba8(0) + (static_cast<size_t>(y) * lv.width + x) * 4;
    return {kByte.v[p[0]], kByte.v[p[1]], kByte.v[p[2]], kByte.v[p[3]]};
  }
  const Rgba c = t.texel(0, x, y);
  return {c.r, c.g, c.b, c.a};
}

// reference_bilinear, inlined into the truths' sample loops (most of a run's reference time
// is this function; the same arithmetic either way).
[[gnu::always_inline]] inline glm::dvec4 bilinear_sample(const Texture& tex, AddressMode au,
                                                         AddressMode av, double u, double v) {
  const int w = tex.width(0), h = tex.height(0);
  if (!std::isfinite(u) || !std::isfinite(v)) return {0, 0, 0, 0};
  const double x = u * w - 0.5, y = v * h - 0.5;
  if (!std::isfinite(x) || !std::isfinite(y)) return {0, 0, 0, 0};  // u·w overflowed
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const double a = x - fx0, b = y - fy0;
  const long long ix = texel_index(fx0, w), iy = texel_index(fy0, h);
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  address_pair(ix, w, au, x0, x1);
  address_pair(iy, h, av, y0, y1);
  return (1 - a) * (1 - b) * fetch(tex, x0, y0) + a * (1 - b) * fetch(tex, x1, y0) +
         (1 - a) * b * fetch(tex, x0, y1) + a * b * fetch(tex, x1, y1);
}

}  // namespace

glm::dvec4 reference_bilinear(const Texture& tex, AddressMode au, AddressMode av, double u,
                              double v) {
  return bilinear_sample(tex, au, av, u, v);
}

PixelSamples PixelSamples::make(TruthPixel p, int n) {
  PixelSamples s;
  if (p == TruthPixel::Box) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        s.x.push_back((i + 0.5) / n);
        s.y.push_back((j + 0.5) / n);
        s.w.push_back(1.0);
      }
    }
    s.weight_sum = static_cast<double>(n * n);
    return s;
  }
  const PixelModel g;
  const int m = static_cast<int>(std::ceil(2 * g.radius_px * n));
  const double step = 2 * g.radius_px / m;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const double dx = -g.radius_px + (i + 0.5) * step, dy = -g.radius_px + (j + 0.5) * step;
      const double w = g.weight(dx * dx + dy * dy);
      if (w == 0) continue;
      s.x.push_back(0.5 + dx);
      s.y.push_back(0.5 + dy);
      s.w.push_back(w);
      s.weight_sum += w;
    }
  }
  return s;
}

std::string PixelSamples::describe(TruthPixel p, int n) const {
  if (p == TruthPixel::Box) {
    return "box-filtered over each pixel with " + std::to_string(n) + "x" + std::to_string(n) +
           " samples";
  }
  return "weighted over each pixel by the Gaussian pixel model (sigma 0.5 px, truncated at 1 px, "
         "EWA's pixel model) with " +
         std::to_string(w.size()) + " samples";
}

std::string TruthSampling::describe(TruthPixel p) const {
  if (!adaptive()) return PixelSamples::make(p, fixed).describe(p, fixed);
  return std::string(p == TruthPixel::Box
                         ? "box-filtered over each pixel"
                         : "weighted over each pixel by the Gaussian pixel model (sigma 0.5 px, "
                           "truncated at 1 px, EWA's pixel model)") +
         " with adaptive samples (nested trapezoid grids shaped by the pixel's footprint, refined "
         "until two levels agree within 1/1020 per channel, with a point at least every 2 "
         "level-0 texels or 81 points, then one Richardson step; at most 64x64 intervals)";
}

PixelIntegrator::PixelIntegrator(TruthPixel pixel, TruthSampling sampling)
    : pixel_(pixel), sampling_(sampling) {
  if (!sampling_.adaptive()) fixed_ = PixelSamples::make(pixel, sampling_.fixed);
  if (pixel == TruthPixel::Gaussian) {
    origin_ = 0.5 - gauss_.radius_px;
    size_ = 2 * gauss_.radius_px;
  }
}

PixelMap::PixelMap(const ProjectiveMap& m, int px, int py)
    : A(static_cast<double>(m.A)),
      B(static_cast<double>(m.B)),
      D(static_cast<double>(m.D)),
      E(static_cast<double>(m.E)),
      G(static_cast<double>(m.G)),
      H(static_cast<double>(m.H)),
      nu(static_cast<double>(m.num_u(px, py))),
      nv(static_cast<double>(m.num_v(px, py))),
      q(static_cast<double>(m.den(px, py))) {}

glm::dvec2 PixelMap::texels_across(int w, int h) const {
  const double den = q + 0.5 * (G + H);
  const double u = (nu + 0.5 * (A + B)) / den, v = (nv + 0.5 * (D + E)) / den;
  const double ux = (A - G * u) / den, uy = (B - H * u) / den;
  const double vx = (D - G * v) / den, vy = (E - H * v) / den;
  return {std::hypot(ux * w, vx * h), std::hypot(uy * w, vy * h)};
}

glm::dvec2 texels_across(const Fragment& f, int w, int h) {
  return {std::hypot(f.dudx * w, f.dvdx * h), std::hypot(f.dudy * w, f.dvdy * h)};
}

PixelIntegrator::GridShape PixelIntegrator::grid_shape(glm::dvec2 texels) const {
  GridShape g;
  const double ex = size_ * texels.x, ey = size_ * texels.y;  // across the grid's square
  if (!std::isfinite(ex) || !std::isfinite(ey) || !(ex > 0) || !(ey > 0)) return g;
  const double r = ey / ex;
  while (g.ay < TruthSampling::kMaxAspect && g.ay * 1.5 < r) g.ay *= 2;
  while (g.ax < TruthSampling::kMaxAspect && g.ax * 1.5 * r < 1) g.ax *= 2;
  g.min_kx = ex / TruthSampling::kTexelsPerPoint;
  g.min_ky = ey / TruthSampling::kTexelsPerPoint;
  return g;
}

glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const ProjectiveMap& map, int px, int py,
                              const PixelIntegrator& integrate, int* samples) {
  const PixelMap pm(map, px, py);
  return integrate(
      [&](double dx, double dy) {
        double u = 0, v = 0;
        pm.uv(dx, dy, u, v);
        return bilinear_sample(tex, au, av, u, v);
      },
      pm.texels_across(tex.width(0), tex.height(0)), samples);
}

glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, int n) {
  return ground_truth_exact(tex, au, av, map, px, py, PixelSamples::make(TruthPixel::Box, n));
}

glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, const PixelSamples& s) {
  glm::dvec4 sum(0);
  for (size_t k = 0; k < s.w.size(); ++k) {
    const UvSample t = map.at(px + s.x[k], py + s.y[k]);
    sum += s.w[k] * reference_bilinear(tex, au, av, t.u, t.v);
  }
  return sum / s.weight_sum;
}

glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, const PixelIntegrator& integrate,
                                  int* samples) {
  return integrate(
      [&](double dx, double dy) {
        const double sx = dx - 0.5, sy = dy - 0.5;
        return bilinear_sample(tex, au, av, f.u + sx * f.dudx + sy * f.dudy,
                               f.v + sx * f.dvdx + sy * f.dvdy);
      },
      texels_across(f, tex.width(0), tex.height(0)), samples);
}

glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, int n) {
  return ground_truth_footprint(tex, au, av, f, PixelIntegrator(TruthPixel::Box, {n}));
}

}  // namespace texsim
