#include "pipeline/reference/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__x86_64__)
#include <immintrin.h>
#endif

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
    case AddressMode::Border:  // -1: the border colour
      return i < 0 || i >= size ? -1 : static_cast<int>(i);
    case AddressMode::MirrorClamp: {
      const long long r = i < 0 ? -(i + 1) : i;
      return static_cast<int>(r < size ? r : size - 1);
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
    case AddressMode::Border:
    case AddressMode::MirrorClamp:
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

// A texel, or the border colour where border addressing left the level (-1).
[[gnu::always_inline]] inline glm::dvec4 fetch(const Texture& t, int x, int y,
                                               const glm::dvec4& border) {
  return x < 0 || y < 0 ? border : fetch(t, x, y);
}

// reference_bilinear, inlined into the truths' sample loops (most of a run's reference time
// is this function; the same arithmetic either way).
[[gnu::always_inline]] inline glm::dvec4 bilinear_sample(const Texture& tex, AddressMode au,
                                                         AddressMode av, double u, double v,
                                                         const SamplerExtras& extras) {
  const int w = tex.width(0), h = tex.height(0);
  if (!std::isfinite(u) || !std::isfinite(v)) return {0, 0, 0, 0};
  const double x = u * w - 0.5, y = v * h - 0.5;
  if (!std::isfinite(x) || !std::isfinite(y)) return {0, 0, 0, 0};  // u·w overflowed
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const double a = x - fx0, b = y - fy0;
  // The offset joins the integer coordinates before addressing (beyond 2^53 texel_index's
  // value is far outside the level already, where ±8 changes no texel).
  const long long ix = texel_index(fx0, w) + extras.offset_u;
  const long long iy = texel_index(fy0, h) + extras.offset_v;
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  address_pair(ix, w, au, x0, x1);
  address_pair(iy, h, av, y0, y1);
  if (au == AddressMode::Border || av == AddressMode::Border) {
    const glm::dvec4& bc = extras.border;
    return (1 - a) * (1 - b) * fetch(tex, x0, y0, bc) + a * (1 - b) * fetch(tex, x1, y0, bc) +
           (1 - a) * b * fetch(tex, x0, y1, bc) + a * b * fetch(tex, x1, y1, bc);
  }
  return (1 - a) * (1 - b) * fetch(tex, x0, y0) + a * (1 - b) * fetch(tex, x1, y0) +
         (1 - a) * b * fetch(tex, x0, y1) + a * b * fetch(tex, x1, y1);
}

}  // namespace

glm::dvec4 reference_bilinear(const Texture& tex, AddressMode au, AddressMode av, double u,
                              double v, const SamplerExtras& extras) {
  return bilinear_sample(tex, au, av, u, v, extras);
}

namespace {

void exact_points_portable(const Texture& tex, AddressMode au, AddressMode av, const PixelMap& pm,
                           const double* dx, const double* dy, size_t n, glm::dvec4* out,
                           const SamplerExtras& extras) {
  for (size_t k = 0; k < n; ++k) {
    double u = 0, v = 0;
    pm.uv(dx[k], dy[k], u, v);
    out[k] = bilinear_sample(tex, au, av, u, v, extras);
  }
}

#if defined(__x86_64__)
// Four points at a time: the map and the bilinear weights in 4-wide double vectors, each
// texel's four bytes widened to a vector of its channels. Every operation is the portable
// path's own IEEE operation in the same order (no fused multiply-add: AVX2 without FMA), and
// the addressing is the portable path's own code, so the results are equal bit for bit.
[[gnu::target("avx2")]] __m256d texel_channels(const uint8_t* p) {
  int32_t bytes = 0;
  std::memcpy(&bytes, p, 4);
  const __m128 c = _mm_mul_ps(_mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(bytes))),
                              _mm_set1_ps(1.0f / 255.0f));  // float b · (1/255), as fetch()
  return _mm256_cvtps_pd(c);
}

[[gnu::target("avx2")]] void exact_points_avx2(const Texture& tex, AddressMode au, AddressMode av,
                                               const PixelMap& pm, const double* dx,
                                               const double* dy, size_t n, glm::dvec4* out) {
  const int w = tex.width(0), h = tex.height(0);
  const uint8_t* base = tex.rgba8(0);
  const size_t row = static_cast<size_t>(tex.level(0).width) * 4;
  const __m256d one = _mm256_set1_pd(1.0), half = _mm256_set1_pd(0.5), zero = _mm256_setzero_pd();
  const __m256d wd = _mm256_set1_pd(w), hd = _mm256_set1_pd(h);
  const __m256d sign = _mm256_set1_pd(-0.0);
  size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d x_ = _mm256_loadu_pd(dx + k), y_ = _mm256_loadu_pd(dy + k);
    const __m256d den =
        _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(pm.q), _mm256_mul_pd(_mm256_set1_pd(pm.G), x_)),
                      _mm256_mul_pd(_mm256_set1_pd(pm.H), y_));
    const __m256d nu =
        _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(pm.nu), _mm256_mul_pd(_mm256_set1_pd(pm.A), x_)),
                      _mm256_mul_pd(_mm256_set1_pd(pm.B), y_));
    const __m256d nv =
        _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(pm.nv), _mm256_mul_pd(_mm256_set1_pd(pm.D), x_)),
                      _mm256_mul_pd(_mm256_set1_pd(pm.E), y_));
    const __m256d no_map = _mm256_cmp_pd(den, zero, _CMP_EQ_OQ);
    alignas(32) double u[4], v[4];
    _mm256_store_pd(u, _mm256_blendv_pd(_mm256_div_pd(nu, den), zero, no_map));
    _mm256_store_pd(v, _mm256_blendv_pd(_mm256_div_pd(nv, den), zero, no_map));
    const __m256d x = _mm256_sub_pd(_mm256_mul_pd(_mm256_load_pd(u), wd), half);
    const __m256d y = _mm256_sub_pd(_mm256_mul_pd(_mm256_load_pd(v), hd), half);
    const __m256d fx0 = _mm256_floor_pd(x), fy0 = _mm256_floor_pd(y);
    const __m256d a = _mm256_sub_pd(x, fx0), b = _mm256_sub_pd(y, fy0);
    // Lanes whose texel indices fit an int32 (NaN compares false; so does ±inf): the others
    // (no finite map there, or u·w overflowed) take the portable path.
    const __m256d lim = _mm256_set1_pd(0x1p30);
    const __m256d fits = _mm256_and_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, fx0), lim, _CMP_LT_OQ),
                                       _mm256_cmp_pd(_mm256_andnot_pd(sign, fy0), lim, _CMP_LT_OQ));
    const int fit_mask = _mm256_movemask_pd(fits);
    const __m256d ia = _mm256_sub_pd(one, a), ib = _mm256_sub_pd(one, b);
    alignas(32) double w00[4], w10[4], w01[4], w11[4];
    _mm256_store_pd(w00, _mm256_mul_pd(ia, ib));
    _mm256_store_pd(w10, _mm256_mul_pd(a, ib));
    _mm256_store_pd(w01, _mm256_mul_pd(ia, b));
    _mm256_store_pd(w11, _mm256_mul_pd(a, b));
    alignas(16) int32_t ix[4], iy[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(ix),
                    _mm256_cvttpd_epi32(_mm256_blendv_pd(zero, fx0, fits)));
    _mm_store_si128(reinterpret_cast<__m128i*>(iy),
                    _mm256_cvttpd_epi32(_mm256_blendv_pd(zero, fy0, fits)));
    for (int l = 0; l < 4; ++l) {
      if (!(fit_mask & (1 << l))) {
        out[k + l] = bilinear_sample(tex, au, av, u[l], v[l], SamplerExtras{});
        continue;
      }
      int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
      address_pair(ix[l], w, au, x0, x1);
      address_pair(iy[l], h, av, y0, y1);
      const uint8_t* r0 = base + static_cast<size_t>(y0) * row;
      const uint8_t* r1 = base + static_cast<size_t>(y1) * row;
      const size_t c0 = static_cast<size_t>(x0) * 4, c1 = static_cast<size_t>(x1) * 4;
      __m256d c = _mm256_mul_pd(_mm256_set1_pd(w00[l]), texel_channels(r0 + c0));
      c = _mm256_add_pd(c, _mm256_mul_pd(_mm256_set1_pd(w10[l]), texel_channels(r0 + c1)));
      c = _mm256_add_pd(c, _mm256_mul_pd(_mm256_set1_pd(w01[l]), texel_channels(r1 + c0)));
      c = _mm256_add_pd(c, _mm256_mul_pd(_mm256_set1_pd(w11[l]), texel_channels(r1 + c1)));
      _mm256_storeu_pd(&out[k + l].x, c);
    }
  }
  if (k == n) return;
  // The last one to three points: padded to four with copies of the last point.
  alignas(32) double px[4], py[4];
  glm::dvec4 c[4];
  for (size_t l = 0; l < 4; ++l) {
    px[l] = dx[std::min(k + l, n - 1)];
    py[l] = dy[std::min(k + l, n - 1)];
  }
  exact_points_avx2(tex, au, av, pm, px, py, 4, c);
  std::copy(c, c + (n - k), out + k);
}
#endif

}  // namespace

bool exact_points_avx2_available() {
#if defined(__x86_64__)
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
#else
  return false;
#endif
}

void sample_exact_points(const Texture& tex, AddressMode au, AddressMode av, const PixelMap& pm,
                         const double* dx, const double* dy, size_t n, glm::dvec4* out,
                         ExactKernel kernel, const SamplerExtras& extras) {
  // Border addressing and texel offsets are the portable kernel's (the AVX2 kernel reads four
  // texels always, at the coordinates' own integer parts).
  const bool plain = au != AddressMode::Border && av != AddressMode::Border &&
                     extras.offset_u == 0 && extras.offset_v == 0;
#if defined(__x86_64__)
  if (tex.format() == TexelFormat::Rgba8 && kernel != ExactKernel::Portable && plain &&
      exact_points_avx2_available()) {
    exact_points_avx2(tex, au, av, pm, dx, dy, n, out);
    return;
  }
#endif
  exact_points_portable(tex, au, av, pm, dx, dy, n, out, extras);
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
         "until two levels agree within 1/1020 per channel, or 1/4, 1/16 or 1/64 of that where the "
         "filter's error is small beside it, with a point at least every 2 level-0 texels or 81 "
         "points, then one Richardson step; at most 64x64 intervals)";
}

int TruthSampling::refine_tier(double err) {
  if (std::isnan(err)) return 0;
  int k = 0;
  while (k + 1 < kTiers && !(tolerance_of(k) * kTierRatio <= err)) ++k;
  return k;
}

int AdaptiveGrid::shape_index(int ax, int ay) {
  const int a = ay == 1 ? ax : ay;
  int l = 0;
  while ((1 << l) < a) ++l;
  return ay == 1 ? l : 6 + l;
}

namespace {

// The points of the grid kx : ky = ax : ay over [origin, origin + size]², level by level,
// refined until kx·ky ≥ kMaxGrid² (the integral may stop at any level before).
AdaptiveGrid make_grid(int ax, int ay, double origin, double size, bool box,
                       const PixelModel& gauss) {
  AdaptiveGrid grid;
  double wsum = 0;
  // The point (i, j) of the level with kx × ky intervals (trapezoid weights: ½ on each edge of
  // the square, so a point keeps its weight at every level).
  auto add = [&](int i, int j, int kx, int ky) {
    const double dx = origin + size * (static_cast<double>(i) / kx),
                 dy = origin + size * (static_cast<double>(j) / ky);
    double w = (i == 0 || i == kx ? 0.5 : 1.0) * (j == 0 || j == ky ? 0.5 : 1.0);
    if (!box) {
      const double cx = dx - 0.5, cy = dy - 0.5;
      w *= gauss.weight(cx * cx + cy * cy);
      if (w == 0) return;  // outside the truncated Gaussian
    }
    grid.dx.push_back(dx);
    grid.dy.push_back(dy);
    grid.w.push_back(w);
    wsum += w;
  };
  auto close_level = [&](int kx, int ky) {
    grid.levels.push_back({kx, ky, static_cast<uint32_t>(grid.w.size()), wsum});
  };
  int kx = ax, ky = ay;
  for (int j = 0; j <= ky; ++j)
    for (int i = 0; i <= kx; ++i) add(i, j, kx, ky);
  close_level(kx, ky);
  while (kx * ky < TruthSampling::kMaxGrid * TruthSampling::kMaxGrid) {
    kx *= 2;
    ky *= 2;
    for (int j = 0; j <= ky; ++j) {
      // Rows of the previous level gain their odd columns; new rows gain every column.
      const bool old_row = j % 2 == 0;
      for (int i = old_row ? 1 : 0; i <= kx; i += old_row ? 2 : 1) add(i, j, kx, ky);
    }
    close_level(kx, ky);
  }
  return grid;
}

}  // namespace

const PixelIntegrator::Grids& PixelIntegrator::grids(TruthPixel pixel) {
  auto make = [](bool box) {
    const PixelModel gauss;
    const double origin = box ? 0.0 : 0.5 - gauss.radius_px;
    const double size = box ? 1.0 : 2 * gauss.radius_px;
    Grids g;
    for (int a = 1; a <= TruthSampling::kMaxAspect; a *= 2) {
      g[AdaptiveGrid::shape_index(a, 1)] = make_grid(a, 1, origin, size, box, gauss);
      if (a > 1) g[AdaptiveGrid::shape_index(1, a)] = make_grid(1, a, origin, size, box, gauss);
    }
    return g;
  };
  static const Grids box = make(true);
  static const Grids gaussian = make(false);
  return pixel == TruthPixel::Box ? box : gaussian;
}

PixelIntegrator::PixelIntegrator(TruthPixel pixel, TruthSampling sampling)
    : pixel_(pixel), sampling_(sampling) {
  if (!sampling_.adaptive()) fixed_ = PixelSamples::make(pixel, sampling_.fixed);
  if (pixel == TruthPixel::Gaussian) {
    origin_ = 0.5 - gauss_.radius_px;
    size_ = 2 * gauss_.radius_px;
  }
  if (sampling_.adaptive()) grids_ = &grids(pixel);
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
                              const PixelIntegrator& integrate, int* samples, int* reach,
                              const SamplerExtras& extras) {
  const PixelMap pm(map, px, py);
  struct Points {
    const Texture& tex;
    AddressMode au, av;
    const PixelMap& pm;
    const SamplerExtras& extras;
    glm::dvec4 operator()(double dx, double dy) const {
      double u = 0, v = 0;
      pm.uv(dx, dy, u, v);
      return bilinear_sample(tex, au, av, u, v, extras);
    }
    void operator()(const double* dx, const double* dy, size_t n, glm::dvec4* out) const {
      sample_exact_points(tex, au, av, pm, dx, dy, n, out, ExactKernel::Auto, extras);
    }
  };
  return integrate(Points{tex, au, av, pm, extras}, pm.texels_across(tex.width(0), tex.height(0)),
                   samples, reach);
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
                                  const Fragment& f, const PixelIntegrator& integrate, int* samples,
                                  int* reach, const SamplerExtras& extras) {
  return integrate(
      [&](double dx, double dy) {
        const double sx = dx - 0.5, sy = dy - 0.5;
        return bilinear_sample(tex, au, av, f.u + sx * f.dudx + sy * f.dudy,
                               f.v + sx * f.dvdx + sy * f.dvdy, extras);
      },
      texels_across(f, tex.width(0), tex.height(0)), samples, reach);
}

glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, int n) {
  return ground_truth_footprint(tex, au, av, f, PixelIntegrator(TruthPixel::Box, {n}));
}

}  // namespace texsim
