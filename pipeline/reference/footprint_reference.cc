#include "pipeline/reference/footprint_reference.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pipeline/reference/ground_truth.h"

namespace texsim {

double PixelModel::weight(double r2) const {
  if (!(r2 <= radius_px * radius_px)) return 0.0;
  return std::exp(-r2 / (2.0 * sigma_px * sigma_px));
}

namespace {

// Samples per axis for a footprint whose screen axes span (ex, ey) level-0 texels per pixel.
void sample_counts(const FootprintReferenceConfig& cfg, double ex, double ey, int& nx, int& ny) {
  const double span = 2.0 * cfg.pixel.radius_px * cfg.samples_per_texel;
  auto count = [&](double e) {
    const double n = std::isfinite(e) ? std::ceil(span * e) : static_cast<double>(cfg.max_samples);
    return static_cast<int>(
        std::clamp(n, static_cast<double>(cfg.min_samples), static_cast<double>(cfg.max_samples)));
  };
  nx = count(ex);
  ny = count(ey);
  const double total = static_cast<double>(nx) * ny;
  if (total > static_cast<double>(cfg.max_total)) {
    const double k = std::sqrt(static_cast<double>(cfg.max_total) / total);
    nx = std::max(1, static_cast<int>(nx * k));
    ny = std::max(1, static_cast<int>(ny * k));
  }
}

// Stratified offsets in [−R, R] and their 1-D Gaussian factors (the 2-D weight is separable;
// the truncation r ≤ R is applied per sample).
void offsets(int n, const PixelModel& pm, std::vector<double>& o, std::vector<double>& g) {
  o.resize(static_cast<size_t>(n));
  g.resize(static_cast<size_t>(n));
  const double r = pm.radius_px;
  for (int i = 0; i < n; ++i) {
    o[static_cast<size_t>(i)] = ((i + 0.5) / n) * 2.0 * r - r;
    const double x = o[static_cast<size_t>(i)];
    g[static_cast<size_t>(i)] = std::exp(-x * x / (2.0 * pm.sigma_px * pm.sigma_px));
  }
}

template <class MapFn>
ReferenceSample integrate(const Texture& tex, const FootprintReferenceConfig& cfg, double ex,
                          double ey, MapFn&& map) {
  ReferenceSample r;
  sample_counts(cfg, ex, ey, r.nx, r.ny);
  std::vector<double> ox, gx, oy, gy;
  offsets(r.nx, cfg.pixel, ox, gx);
  offsets(r.ny, cfg.pixel, oy, gy);
  const double r2max = cfg.pixel.radius_px * cfg.pixel.radius_px;
  glm::dvec4 sum(0);
  double wsum = 0;
  for (int j = 0; j < r.ny; ++j) {
    const double sy = oy[static_cast<size_t>(j)];
    for (int i = 0; i < r.nx; ++i) {
      const double sx = ox[static_cast<size_t>(i)];
      if (sx * sx + sy * sy > r2max) continue;
      const double w = gx[static_cast<size_t>(i)] * gy[static_cast<size_t>(j)];
      double u = 0, v = 0;
      if (!map(sx, sy, u, v)) continue;
      sum += w * reference_bilinear(tex, cfg.address_u, cfg.address_v, u, v);
      wsum += w;
    }
  }
  if (wsum > 0) r.colour = sum / wsum;
  return r;
}

}  // namespace

ReferenceSample footprint_reference(const Texture& tex, const PlaneProjection& map, int px, int py,
                                    const FootprintReferenceConfig& cfg) {
  const double cx = px + 0.5, cy = py + 0.5;
  const UvSample c = map.at(cx, cy);
  const double w = tex.width(0), h = tex.height(0);
  const double ex = std::hypot(c.dudx * w, c.dvdx * h), ey = std::hypot(c.dudy * w, c.dvdy * h);
  // Far samples of a strongly receding footprint stretch more than the centre's derivatives
  // say; the reference evaluates the exact map per sample, so only the density is affected.
  const double A = static_cast<double>(map.A), B = static_cast<double>(map.B),
               C = static_cast<double>(map.C);
  const double D = static_cast<double>(map.D), E = static_cast<double>(map.E),
               F = static_cast<double>(map.F);
  const double G = static_cast<double>(map.G), H = static_cast<double>(map.H),
               I = static_cast<double>(map.I);
  return integrate(tex, cfg, ex, ey, [&](double sx, double sy, double& u, double& v) {
    const double x = cx + sx, y = cy + sy;
    const double den = G * x + H * y + I;
    if (den == 0) return false;
    const double r = 1.0 / den;
    u = (A * x + B * y + C) * r;
    v = (D * x + E * y + F) * r;
    return std::isfinite(u) && std::isfinite(v);
  });
}

ReferenceSample footprint_reference_affine(const Texture& tex, const Fragment& f,
                                           const FootprintReferenceConfig& cfg) {
  const double w = tex.width(0), h = tex.height(0);
  const double ex = std::hypot(f.dudx * w, f.dvdx * h), ey = std::hypot(f.dudy * w, f.dvdy * h);
  return integrate(tex, cfg, ex, ey, [&](double sx, double sy, double& u, double& v) {
    u = f.u + sx * f.dudx + sy * f.dudy;
    v = f.v + sx * f.dvdx + sy * f.dvdy;
    return std::isfinite(u) && std::isfinite(v);
  });
}

}  // namespace texsim
