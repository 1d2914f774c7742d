#include "pipeline/reference/operation_reference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "blocks/base/sample_op.h"
#include "blocks/texture/volume/volume_address_gen.h"

namespace texsim {

namespace {

// Texel (x, y) of level 0 under the sampler's address modes, or the border colour.
glm::dvec4 texel_at(const Texture& tex, const OperationSampler& s, int64_t x, int64_t y) {
  // The spec's wrap functions on one integer coordinate (−1: the border).
  const int ax = VolumeAddressGen::address(x, tex.width(0), s.au);
  const int ay = VolumeAddressGen::address(y, tex.height(0), s.av);
  if (ax < 0 || ay < 0) return s.border;
  return glm::dvec4(tex.texel(0, ax, ay));
}

// The integer part of a texel coordinate, kept where every address mode still reads it.
int64_t floor_index(double x) {
  return static_cast<int64_t>(std::floor(std::clamp(x, -0x1p40, 0x1p40)));
}

// The comparison's reference as the stored format reads it (UNORM depth: clamped to [0, 1]).
float compare_reference(const OperationSampler& s, float r) {
  return s.unorm_depth && !std::isnan(r) ? std::clamp(r, 0.0f, 1.0f) : r;
}

double passes(const OperationSampler& s, float ref, double depth) {
  return compare_passes(s.compare, ref, static_cast<float>(depth)) ? 1.0 : 0.0;
}

// Normalised coordinates of an unnormalised sampler's texel coordinates.
glm::dvec2 normalised(const Fragment& f, const OperationSampler& s, int w, int h) {
  return s.unnormalized ? glm::dvec2(f.u / w, f.v / h) : glm::dvec2(f.u, f.v);
}

// Open-square test of the min/max footprint: does the convex quad q (texel coordinates) meet
// the open square (x0, x0 + 2) × (y0, y0 + 2)? Separating axes: x, y and the quad's edges.
bool quad_meets_square(const std::array<glm::dvec2, 4>& q, double x0, double y0) {
  double lo[2] = {q[0].x, q[0].y}, hi[2] = {q[0].x, q[0].y};
  for (const glm::dvec2& p : q) {
    lo[0] = std::min(lo[0], p.x);
    hi[0] = std::max(hi[0], p.x);
    lo[1] = std::min(lo[1], p.y);
    hi[1] = std::max(hi[1], p.y);
  }
  if (!(lo[0] < x0 + 2 && x0 < hi[0] && lo[1] < y0 + 2 && y0 < hi[1])) return false;
  const glm::dvec2 sq[4] = {{x0, y0}, {x0 + 2, y0}, {x0 + 2, y0 + 2}, {x0, y0 + 2}};
  for (size_t e = 0; e < 4; ++e) {
    const glm::dvec2 d = q[(e + 1) % 4] - q[e];
    const glm::dvec2 n(-d.y, d.x);
    if (n.x == 0 && n.y == 0) continue;  // a degenerate edge separates nothing
    double qlo = std::numeric_limits<double>::infinity(), qhi = -qlo;
    for (const glm::dvec2& p : q) {
      const double t = n.x * p.x + n.y * p.y;
      qlo = std::min(qlo, t);
      qhi = std::max(qhi, t);
    }
    double slo = std::numeric_limits<double>::infinity(), shi = -slo;
    for (const glm::dvec2& p : sq) {
      const double t = n.x * p.x + n.y * p.y;
      slo = std::min(slo, t);
      shi = std::max(shi, t);
    }
    if (!(qlo < shi && slo < qhi)) return false;
  }
  return true;
}

}  // namespace

bool operation_truth_applies(const Fragment& f, const OperationSampler& s) {
  return f.op != static_cast<uint8_t>(SampleOp::kSample) || s.compare != CompareOp::None ||
         s.reduction != Reduction::WeightedAverage || s.unnormalized;
}

glm::dvec2 OperationFootprint::at(double dx, double dy) const {
  if (map) {
    double u = 0, v = 0;
    map->uv(dx, dy, u, v);
    return glm::dvec2(u, v) + shift;
  }
  return centre + shift + (dx - 0.5) * a + (dy - 0.5) * b;
}

glm::dvec2 OperationFootprint::texels_across(int w, int h) const {
  if (map) return map->texels_across(w, h);
  return {std::hypot(a.x * w, a.y * h), std::hypot(b.x * w, b.y * h)};
}

double operation_lod(double lambda, const OperationSampler& s) {
  double l = (std::isnan(lambda) ? 0.0 : lambda) + s.lod_bias;
  if (std::isnan(l)) l = 0;
  const double clamped = std::clamp(l, s.min_lod, s.max_lod);
  // At or below 0 the unit reads level 0 whatever λ' is: a clamp up to min_lod ≤ 0 does not
  // widen the footprint (the end of the pyramid, not a blur).
  return clamped > 0 ? clamped : std::min(clamped, l);
}

OperationFootprint operation_footprint(const Fragment& f, const OperationSampler& s, int w, int h,
                                       const PixelMap* map) {
  OperationFootprint fp;
  fp.centre = normalised(f, s, w, h);
  // A square of 2^λ' level-0 texels (the footprint of an isotropic pixel of LOD λ').
  const auto square = [&](double lambda) {
    const double side = std::exp2(lambda);
    fp.a = {side / w, 0.0};
    fp.b = {0.0, side / h};
  };
  const auto op = static_cast<SampleOp>(f.op);
  double texel = 1;  // level-0 texels per texel of the level the operation asks for
  if (s.unnormalized) {
    fp.a = fp.b = glm::dvec2(0.0);  // a filtered texel fetch at the point, on level 0
  } else if (op == SampleOp::kSampleLod) {
    const double lambda = operation_lod(f.lod, s);
    square(lambda);
    texel = std::exp2(std::max(lambda, 0.0));
  } else if (op == SampleOp::kSampleGrad) {
    fp.a = {f.dudx, f.dvdx};
    fp.b = {f.dudy, f.dvdy};
    const double rho =
        std::max(std::hypot(f.dudx * w, f.dvdx * h), std::hypot(f.dudy * w, f.dvdy * h));
    if (std::isfinite(rho) && rho > 0) {
      const double lambda = std::log2(rho);
      const double k = std::exp2(operation_lod(lambda, s) - lambda);
      fp.a *= k;
      fp.b *= k;
      texel = std::max(1.0, k * rho);
    } else {  // no direction to scale: the square of the clamped λ
      square(operation_lod(std::isfinite(rho) ? -std::numeric_limits<double>::infinity()
                                              : std::numeric_limits<double>::infinity(),
                           s));
    }
  } else if (map) {
    fp.map = map;
  } else {
    fp.a = {f.dudx, f.dvdx};
    fp.b = {f.dudy, f.dvdy};
  }
  // The constant offset in texels of the level λ' stands for (level 0 for an implicit LOD, as
  // the plain truth).
  fp.shift = glm::dvec2(s.offset_u * texel / w, s.offset_v * texel / h);
  return fp;
}

glm::dvec4 reference_compare_bilinear(const Texture& tex, const OperationSampler& s, double u,
                                      double v, float reference) {
  if (!std::isfinite(u) || !std::isfinite(v)) return {0, 0, 0, 1};
  const float ref = compare_reference(s, reference);
  const double x = u * tex.width(0) - 0.5, y = v * tex.height(0) - 0.5;
  const int64_t i0 = floor_index(x), j0 = floor_index(y);
  const double a = std::clamp(x - static_cast<double>(i0), 0.0, 1.0);
  const double b = std::clamp(y - static_cast<double>(j0), 0.0, 1.0);
  const double w[4] = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
  double sum = 0;
  for (int k = 0; k < 4; ++k) {
    if (w[k] == 0) continue;
    sum += w[k] * passes(s, ref, texel_at(tex, s, i0 + (k & 1), j0 + (k >> 1)).r);
  }
  return {sum, sum, sum, 1.0};
}

glm::dvec4 reference_minmax(const Texture& tex, const OperationSampler& s, const glm::dvec2 q[4]) {
  const int w = tex.width(0), h = tex.height(0);
  std::array<glm::dvec2, 4> t{};
  for (size_t k = 0; k < 4; ++k) {
    if (!std::isfinite(q[k].x) || !std::isfinite(q[k].y)) return glm::dvec4(0.0);
    t[k] = {q[k].x * w, q[k].y * h};
  }
  double lo[2] = {t[0].x, t[0].y}, hi[2] = {t[0].x, t[0].y};
  for (const glm::dvec2& p : t) {
    lo[0] = std::min(lo[0], p.x);
    hi[0] = std::max(hi[0], p.x);
    lo[1] = std::min(lo[1], p.y);
    hi[1] = std::max(hi[1], p.y);
  }
  // Texel i is read with non-zero weight where |x − (i + ½)| < 1: i in (x − 1.5, x + 0.5).
  const int64_t i0 = floor_index(lo[0] - 1.5), i1 = floor_index(hi[0] + 0.5);
  const int64_t j0 = floor_index(lo[1] - 1.5), j1 = floor_index(hi[1] + 0.5);
  // Beyond a few periods every texel (and the border, if addressed) is read: one period of
  // each axis (two for mirror), its clamp edges and one texel beyond them stand for all.
  constexpr int64_t kMaxSpan = 1 << 12;
  const bool whole = i1 - i0 > kMaxSpan || j1 - j0 > kMaxSpan;
  const bool is_max = s.reduction == Reduction::Max;
  bool any = false;
  glm::dvec4 out(0.0);
  const auto take = [&](const glm::dvec4& c) {
    if (!any) {
      out = c;
      any = true;
      return;
    }
    out = is_max ? glm::max(out, c) : glm::min(out, c);
  };
  if (whole) {
    for (int64_t y = -1; y <= 2 * int64_t{h}; ++y)
      for (int64_t x = -1; x <= 2 * int64_t{w}; ++x) take(texel_at(tex, s, x, y));
    return out;
  }
  for (int64_t j = j0; j <= j1; ++j)
    for (int64_t i = i0; i <= i1; ++i)
      if (quad_meets_square(t, static_cast<double>(i) - 0.5, static_cast<double>(j) - 0.5))
        take(texel_at(tex, s, i, j));
  return out;
}

glm::dvec4 reference_gather(const Texture& tex, const OperationSampler& s, double u, double v,
                            int component, float reference) {
  if (!std::isfinite(u)) u = 0;
  if (!std::isfinite(v)) v = 0;
  const int64_t i0 = floor_index(u * tex.width(0) - 0.5) + s.offset_u;
  const int64_t j0 = floor_index(v * tex.height(0) - 0.5) + s.offset_v;
  const int64_t order[4][2] = {{i0, j0 + 1}, {i0 + 1, j0 + 1}, {i0 + 1, j0}, {i0, j0}};
  const int c = std::clamp(component, 0, 3);
  const float ref = compare_reference(s, reference);
  glm::dvec4 out(0.0);
  for (int k = 0; k < 4; ++k) {
    const glm::dvec4 t = texel_at(tex, s, order[k][0], order[k][1]);
    out[k] = s.compare != CompareOp::None ? passes(s, ref, t[c]) : t[c];
  }
  return out;
}

glm::dvec4 ground_truth_operation(const Texture& tex, const OperationSampler& s, const Fragment& f,
                                  const ProjectiveMap* map, int px, int py,
                                  const PixelIntegrator& integrate, int* samples, int* reach) {
  if (reach) *reach = TruthSampling::kTiers - 1;
  const int w = tex.width(0), h = tex.height(0);
  if (f.op == static_cast<uint8_t>(SampleOp::kGather)) {
    if (samples) *samples = 1;
    const glm::dvec2 c = normalised(f, s, w, h);
    return reference_gather(tex, s, c.x, c.y, f.gather_component, f.compare_ref);
  }
  std::optional<PixelMap> pm;
  if (map) pm.emplace(*map, px, py);
  const OperationFootprint fp = operation_footprint(f, s, w, h, pm ? &*pm : nullptr);
  if (s.reduction != Reduction::WeightedAverage && s.compare == CompareOp::None) {
    if (samples) *samples = 4;
    const glm::dvec2 q[4] = {fp.at(0, 0), fp.at(1, 0), fp.at(1, 1), fp.at(0, 1)};
    return reference_minmax(tex, s, q);
  }
  if (s.compare != CompareOp::None) {
    return integrate(
        [&](double dx, double dy) {
          const glm::dvec2 p = fp.at(dx, dy);
          return reference_compare_bilinear(tex, s, p.x, p.y, f.compare_ref);
        },
        fp.texels_across(w, h), samples, reach);
  }
  SamplerExtras extras;
  extras.border = s.border;
  return integrate(
      [&](double dx, double dy) {
        const glm::dvec2 p = fp.at(dx, dy);
        return reference_bilinear(tex, s.au, s.av, p.x, p.y, extras);
      },
      fp.texels_across(w, h), samples, reach);
}

}  // namespace texsim
