#include "pipeline/reference/ground_truth.h"

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

glm::dvec4 fetch(const Texture& t, int x, int y) {
  const Rgba c = t.texel(0, x, y);
  return {c.r, c.g, c.b, c.a};
}

}  // namespace

glm::dvec4 reference_bilinear(const Texture& tex, AddressMode au, AddressMode av, double u,
                              double v) {
  const int w = tex.width(0), h = tex.height(0);
  if (!std::isfinite(u) || !std::isfinite(v)) return {0, 0, 0, 0};
  const double x = u * w - 0.5, y = v * h - 0.5;
  if (!std::isfinite(x) || !std::isfinite(y)) return {0, 0, 0, 0};  // u·w overflowed
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const double a = x - fx0, b = y - fy0;
  const long long ix = texel_index(fx0, w), iy = texel_index(fy0, h);
  const int x0 = address(ix, w, au), x1 = address(ix + 1, w, au);
  const int y0 = address(iy, h, av), y1 = address(iy + 1, h, av);
  return (1 - a) * (1 - b) * fetch(tex, x0, y0) + a * (1 - b) * fetch(tex, x1, y0) +
         (1 - a) * b * fetch(tex, x0, y1) + a * b * fetch(tex, x1, y1);
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

glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, const PixelSamples& s) {
  glm::dvec4 sum(0);
  for (size_t k = 0; k < s.w.size(); ++k) {
    const UvSample t = map.at(px + s.x[k], py + s.y[k]);
    sum += s.w[k] * reference_bilinear(tex, au, av, t.u, t.v);
  }
  return sum / s.weight_sum;
}

glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, int n) {
  return ground_truth_exact(tex, au, av, map, px, py, PixelSamples::make(TruthPixel::Box, n));
}

glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, const PixelSamples& s) {
  glm::dvec4 sum(0);
  for (size_t k = 0; k < s.w.size(); ++k) {
    const double sx = s.x[k] - 0.5, sy = s.y[k] - 0.5;
    sum += s.w[k] * reference_bilinear(tex, au, av, f.u + sx * f.dudx + sy * f.dudy,
                                       f.v + sx * f.dvdx + sy * f.dvdy);
  }
  return sum / s.weight_sum;
}

glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, int n) {
  return ground_truth_footprint(tex, au, av, f, PixelSamples::make(TruthPixel::Box, n));
}

}  // namespace texsim
