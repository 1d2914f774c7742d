#include "pipeline/reference/surface_reference.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace texsim {

namespace {

constexpr int kLayers = 1024, kHalvings = 24;
// Terrain: march steps per texel along the ray, and the longest ray in texels.
constexpr double kTerrainStepsPerTexel = 16, kTerrainMaxTexels = 4096;

// The finite-function surface at grid (x, z) as the direct sum Σ h_ij f(x - i) f(z - j) over
// the nodes within the basis's support (heights h·scale; reads clamp to the edge).
double terrain_height(const ReliefHeightMap& hm, const FiniteBasis& f, double scale, double x,
                      double z) {
  const int r = static_cast<int>(std::ceil(f.radius()));
  const double fx = std::floor(x), fz = std::floor(z);
  if (!std::isfinite(fx) || !std::isfinite(fz) || std::fabs(fx) > 1e9 || std::fabs(fz) > 1e9)
    return 0;
  const auto i0 = static_cast<int32_t>(fx), j0 = static_cast<int32_t>(fz);
  double y = 0;
  for (int32_t j = j0 - r + 1; j <= j0 + r; ++j) {
    const double wz = f.value(z - j);
    if (wz == 0) continue;
    for (int32_t i = i0 - r + 1; i <= i0 + r; ++i)
      y += hm.texel(i, j) * scale * f.value(x - i) * wz;
  }
  return y;
}

// The gradient (∂y/∂x, ∂y/∂z) of that direct sum: Σ h_ij f'(x - i) f(z - j) and its mirror.
glm::dvec2 terrain_gradient(const ReliefHeightMap& hm, const FiniteBasis& f, double scale, double x,
                            double z) {
  const int r = static_cast<int>(std::ceil(f.radius()));
  const double fx = std::floor(x), fz = std::floor(z);
  if (!std::isfinite(fx) || !std::isfinite(fz) || std::fabs(fx) > 1e9 || std::fabs(fz) > 1e9)
    return {0, 0};
  const auto i0 = static_cast<int32_t>(fx), j0 = static_cast<int32_t>(fz);
  glm::dvec2 g(0);
  for (int32_t j = j0 - r + 1; j <= j0 + r; ++j) {
    const double wz = f.value(z - j), dz = f.derivative(z - j);
    for (int32_t i = i0 - r + 1; i <= i0 + r; ++i) {
      const double h = hm.texel(i, j) * scale;
      g.x += h * f.derivative(x - i) * wz;
      g.y += h * f.value(x - i) * dz;
    }
  }
  return g;
}

// Blinn-Phong in double (docs/derivations/lighting.md §1), each channel clamped to [0, 1].
glm::dvec3 blinn_phong(const glm::dvec3& base, const glm::dvec3& n, const glm::dvec3& l,
                       const glm::dvec3& v, const BlinnPhongShader::Config& c) {
  const double ndl = glm::dot(n, l);
  double spec = 0;
  if (ndl > 0) {
    const glm::dvec3 h = glm::normalize(l + v);
    spec = std::pow(std::max(glm::dot(n, h), 0.0), c.shininess);
  }
  const glm::dvec3 light(c.light_r, c.light_g, c.light_b);
  return glm::clamp(
      base * (c.ambient + c.diffuse * std::max(ndl, 0.0)) + light * (c.specular * spec), 0.0, 1.0);
}

}  // namespace

SurfaceReference::SurfaceReference(const MaterialSetup& m, const TextureSet& textures,
                                   bool per_sample_relief)
    : au_(m.address_u()),
      av_(m.address_v()),
      per_sample_(per_sample_relief),
      relief_(m.relief),
      lighting_(m.lighting) {
  if (relief_ && relief_->height_tex >= 0)
    relief_hm_ = height_map_of(textures[relief_->height_tex].reference());
  if (lighting_ && lighting_->normal_tex >= 0) {
    normal_tex_ = &textures[lighting_->normal_tex].reference();
    if (lighting_->normal == LightingSetup::Normal::HeightMap ||
        lighting_->normal == LightingSetup::Normal::Terrain)
      normal_hm_ = height_map_of(*normal_tex_);
  }
}

glm::dvec2 SurfaceReference::terrain_xy(double x, double y, const glm::dvec3& d) const {
  // A march in steps of 1/16 texel from the polygon (height `scale`) down the ray, then 40
  // halvings of the last step; no hit within kTerrainMaxTexels: (x, y) unshifted.
  const ReliefHeightMap& hm = relief_hm_;
  const FiniteBasis& f = relief_->terrain.evaluator.basis;
  const double scale = relief_->scale, dt = 1 / kTerrainStepsPerTexel;
  auto below = [&](double t) {
    return scale + t * d.y < terrain_height(hm, f, scale, x + t * d.x, y + t * d.z);
  };
  double t_prev = 0;
  for (double t = dt; t <= kTerrainMaxTexels; t += dt) {
    if (scale + t * d.y < -scale) break;  // far below every height (widened weights > 1)
    if (below(t)) {
      double lo = t_prev, hi = t;
      for (int k = 0; k < 40; ++k) {
        const double mid = 0.5 * (lo + hi);
        (below(mid) ? hi : lo) = mid;
      }
      return {x + hi * d.x, y + hi * d.z};
    }
    t_prev = t;
  }
  return {x, y};
}

glm::dvec2 SurfaceReference::relief_uv(double u, double v, const glm::dvec3& view_ts, double u_len,
                                       double v_len) const {
  const ReliefHeightMap& hm = relief_hm_;
  if (hm.width <= 0 || !std::isfinite(u) || !std::isfinite(v)) return {u, v};
  const double tu = std::floor(u), tv = std::floor(v);
  const double x = (u - tu) * hm.width - 0.5, y = (v - tv) * hm.height - 0.5;
  const glm::dvec3 vt = view_in_texels(view_ts, u_len, v_len, hm.width, hm.height);
  const double len = glm::length(vt);
  if (!(len > 0) || !std::isfinite(len)) return {u, v};
  if (relief_->method == ReliefSetup::Method::Terrain) {
    const glm::dvec2 p = terrain_xy(x, y, glm::dvec3(-vt.x, -vt.z, -vt.y) / len);
    return {tu + (p.x + 0.5) / hm.width, tv + (p.y + 0.5) / hm.height};
  }
  // Texel shift per unit of depth (0 at the polygon, 1 at height 0); V.z clamped as the
  // blocks' grazing limit is not a property of the surface: 1e-3 only avoids a division by 0.
  const double vz = std::max(vt.z / len, 1e-3);
  const double sx = -vt.x / len / vz * relief_->scale, sy = -vt.y / len / vz * relief_->scale;
  // First layer whose depth reaches below the surface (depth d is under height 1 − d).
  double lo = 0, hi = 1;
  bool hit = false;
  for (int i = 1; i <= kLayers; ++i) {
    const double d = static_cast<double>(i) / kLayers;
    if (d >= 1 - hm.bilinear(x + sx * d, y + sy * d)) {
      lo = d - 1.0 / kLayers;
      hi = d;
      hit = true;
      break;
    }
  }
  if (hit) {
    for (int k = 0; k < kHalvings; ++k) {
      const double d = 0.5 * (lo + hi);
      (d >= 1 - hm.bilinear(x + sx * d, y + sy * d) ? hi : lo) = d;
    }
  }
  return {tu + (x + sx * hi + 0.5) / hm.width, tv + (y + sy * hi + 0.5) / hm.height};
}

glm::dvec3 SurfaceReference::normal_at(double u, double v) const {
  if (!lighting_ || lighting_->normal == LightingSetup::Normal::Flat) return {0, 0, 1};
  glm::dvec3 n;
  if (lighting_->normal == LightingSetup::Normal::NormalMap) {
    n = normal_map_rgb(*normal_tex_, u, v) * 2.0 - 1.0;
    n.y = -n.y;  // green up: towards −v
  } else if (lighting_->normal == LightingSetup::Normal::Terrain) {
    // The same source in double: the direct sum's analytic gradient, or its central
    // differences at ±ε; grid x along u, z along v, y up (the tangent frame's z).
    const ReliefHeightMap& hm = normal_hm_;
    const double x = (u - std::floor(u)) * hm.width - 0.5,
                 z = (v - std::floor(v)) * hm.height - 0.5;
    const FiniteBasis& f = lighting_->terrain.evaluator.basis;
    const double s = lighting_->terrain_scale;
    glm::dvec2 g;
    if (lighting_->terrain.method == TerrainNormalUnit::Method::Gradient) {
      g = terrain_gradient(hm, f, s, x, z);
    } else {
      const double e = lighting_->terrain.epsilon;
      g = {(terrain_height(hm, f, s, x + e, z) - terrain_height(hm, f, s, x - e, z)) / (2 * e),
           (terrain_height(hm, f, s, x, z + e) - terrain_height(hm, f, s, x, z - e)) / (2 * e)};
    }
    n = {-g.x, -g.y, 1.0};
  } else {
    const ReliefHeightMap& hm = normal_hm_;
    const double x = (u - std::floor(u)) * hm.width - 0.5,
                 y = (v - std::floor(v)) * hm.height - 0.5;
    const double s = lighting_->normals.bump_scale * 0.5;
    n = {-(hm.bilinear(x + 1, y) - hm.bilinear(x - 1, y)) * s,
         -(hm.bilinear(x, y + 1) - hm.bilinear(x, y - 1)) * s, 1.0};
  }
  const double l = glm::length(n);
  return l > 0 && std::isfinite(l) ? n / l : glm::dvec3(0, 0, 1);
}

glm::dvec4 SurfaceReference::operator()(const Texture& tex, const PlaneProjection& map,
                                        const SurfaceFrame& sf, int px, int py,
                                        const PixelIntegrator& integrate, int* samples,
                                        int* reach) const {
  const glm::dvec3 view_ts = sf.to_tangent(sf.view(px + 0.5, py + 0.5));
  glm::dvec2 shift(0);
  if (relief_) {
    const UvSample c = map.at(px + 0.5, py + 0.5);
    shift = relief_uv(c.u, c.v, view_ts, sf.u_length(), sf.v_length()) - glm::dvec2(c.u, c.v);
  }
  const glm::dvec3 light_ts = lighting_ ? sf.to_tangent(lighting_->light_dir) : glm::dvec3(0, 0, 1);
  const PixelMap pm(map, px, py);
  return integrate(
      [&](double dx, double dy) {
        double u = 0, v = 0;
        pm.uv(dx, dy, u, v);
        if (relief_ && per_sample_) {
          // The sample's own ray: from the eye through the sample's point of the pixel.
          const glm::dvec3 vs = sf.to_tangent(sf.view(px + dx, py + dy));
          const glm::dvec2 p = relief_uv(u, v, vs, sf.u_length(), sf.v_length());
          u = p.x;
          v = p.y;
        } else {
          u += shift.x;
          v += shift.y;
        }
        glm::dvec4 c = reference_bilinear(tex, au_, av_, u, v);
        if (lighting_) {
          const glm::dvec3 lit = blinn_phong(glm::clamp(glm::dvec3(c), 0.0, 1.0), normal_at(u, v),
                                             light_ts, view_ts, lighting_->shader);
          c = glm::dvec4(lit, c.a);
        }
        return c;
      },
      pm.texels_across(tex.width(0), tex.height(0)), samples, reach);
}

}  // namespace texsim
