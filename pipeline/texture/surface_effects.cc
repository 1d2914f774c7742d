#include "pipeline/texture/surface_effects.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {

// The effect's own keys beside those of the blocks it builds.
const std::vector<std::string_view> kLightingKeys = {
    "model",      "normal",         "normal_texture", "light_dir",
    "bump_scale", "terrain_normal", "terrain_epsilon"};

glm::dvec3 read_vec3(const ConfigReader& r, std::string_view key, glm::dvec3 def) {
  const toml::node* n = r.table().get(key);
  if (!n) return def;
  const toml::array* a = n->as_array();
  if (!a || a->size() != 3) r.fail(key, "expected an array of three numbers");
  glm::dvec3 v;
  for (int i = 0; i < 3; ++i) {
    const auto x = (*a)[static_cast<size_t>(i)].value<double>();
    if (!x || !std::isfinite(*x)) r.fail(key, "expected an array of three finite numbers");
    v[i] = *x;
  }
  if (!(glm::length(v) > 0)) r.fail(key, "must not be the zero vector");
  return glm::normalize(v);
}

double frac_floor(double x) { return std::isfinite(x) ? std::floor(x) : 0.0; }

}  // namespace

LightingSetup LightingSetup::from_toml(const ConfigReader& r) {
  LightingSetup s;
  (void)r.get_choice("model", 0, {"blinn_phong"});
  s.normal = static_cast<Normal>(
      r.get_choice("normal", 0, {"flat", "normal_map", "height_map", "terrain"}));
  s.normal_texture = r.get_string("normal_texture", "");
  const bool map = s.normal == Normal::NormalMap || s.normal == Normal::HeightMap;
  if (map && s.normal_texture.empty())
    r.fail("normal", "needs `normal_texture`, the name of the map's texture");
  if (s.normal == Normal::Flat && !s.normal_texture.empty())
    r.fail("normal_texture", "flat normals read no texture");
  if (s.normal == Normal::Terrain) {
    if (!s.normal_texture.empty())
      r.fail("normal_texture", "terrain normals read the relief's height texture");
    if (r.table().contains("bump_scale"))
      r.fail("bump_scale", "terrain normals take the relief's `scale`");
    s.terrain.method = static_cast<TerrainNormalUnit::Method>(
        r.get_choice("terrain_normal", 0, {"gradient", "central_difference"}));
    s.terrain.epsilon = r.get_double("terrain_epsilon", s.terrain.epsilon);
    if (!(s.terrain.epsilon > 0 && s.terrain.epsilon <= 1))
      r.fail("terrain_epsilon", "must be in (0, 1] texels");
  } else {
    for (const char* k : {"terrain_normal", "terrain_epsilon"}) {
      if (r.table().contains(k)) r.fail(k, "is for `normal = \"terrain\"` only");
    }
  }
  s.light_dir = read_vec3(r, "light_dir", glm::normalize(s.light_dir));
  s.normals.source =
      s.normal == Normal::HeightMap ? NormalUnit::Source::HeightMap : NormalUnit::Source::NormalMap;
  s.normals.bump_scale = r.get_double("bump_scale", s.normals.bump_scale);
  if (!(std::fabs(s.normals.bump_scale) <= 1e6)) r.fail("bump_scale", "must be finite, |s| <= 1e6");
  s.shader =
      BlinnPhongShader::Config::from_toml(r.for_block("lighting.blinn_phong", kLightingKeys));
  s.terrain.datapath = s.shader.datapath;
  return s;
}

void LightingSetup::bind_terrain(const ConfigReader& lighting, const ReliefSetup* relief) {
  if (normal != Normal::Terrain) return;
  if (!relief || relief->method != ReliefSetup::Method::Terrain)
    lighting.fail("normal",
                  "\"terrain\" takes the normal from the surface of the material's "
                  "`relief = { method = \"terrain\", ... }`, which it does not have");
  normal_texture = relief->height_texture;
  terrain_scale = relief->scale;
  terrain.evaluator = relief->terrain.evaluator;
  terrain.evaluator.datapath = terrain.datapath;
}

ReliefSetup ReliefSetup::from_toml(const ConfigReader& r) {
  r.reject_unknown({"method", "height_texture", "scale", "parallax", "tracer", "distance_map",
                    "refined", "terrain", "visibility_filter", "footprint",
                    "footprint_max_stretch"});
  ReliefSetup s;
  s.method = static_cast<Method>(
      r.get_choice("method", 1, {"parallax", "steep", "distance_map", "terrain"}));
  s.height_texture = r.get_string("height_texture", "");
  if (s.height_texture.empty()) r.fail("height_texture", "is required: the height map's texture");
  s.scale = r.get_double("scale", s.scale);
  if (!(s.scale > 0 && s.scale <= 1024)) r.fail("scale", "must be in (0, 1024] texels");
  s.refined = r.get_bool("refined", s.refined);
  const ConfigReader p = r.sub("parallax");
  if (p.table().contains("method") || p.table().contains("depth_texels"))
    p.fail("method", "is set by relief.method and relief.scale, not here");
  s.parallax = ParallaxMapper::Config::from_toml(p);
  s.parallax.method = s.method == Method::Parallax ? ParallaxMapper::Method::Offset
                                                   : ParallaxMapper::Method::Iterative;
  s.parallax.depth_texels = s.scale;
  s.tracer = SphereTracer::Config::from_toml(r.sub("tracer"));
  s.distance_map = DistanceMapBuilder::Config::from_toml(r.sub("distance_map"));
  s.terrain = TerrainRayMarcher::Config::from_toml(r.sub("terrain"));
  s.footprint = ReliefFootprint::Config::from_toml(r);
  s.footprint.datapath = s.parallax.datapath;
  if (r.table().contains("visibility_filter")) {
    const ConfigReader vf = r.sub("visibility_filter");
    if (vf.table().contains("depth_texels"))
      vf.fail("depth_texels", "is set by relief.scale, not here");
    s.visibility_filter = true;
    s.visibility = VisibilityAwareFilter::Config::from_toml(vf);
    s.visibility.depth_texels = s.scale;
  }
  return s;
}

std::string ReliefSetup::block_name() const {
  switch (method) {
    case Method::Parallax:
      return "relief.parallax_offset";
    case Method::Steep:
      return "relief.parallax_iterative";
    case Method::DistanceMap:
      return refined ? "relief.sphere_tracer[refined]" : "relief.sphere_tracer";
    case Method::Terrain:
      return "relief.terrain_ray_marcher";
  }
  return "relief";
}

ReliefHeightMap height_map_of(const Texture& t) {
  ReliefHeightMap hm(t.width(0), t.height(0));
  for (int y = 0; y < hm.height; ++y) {
    for (int x = 0; x < hm.width; ++x) hm.at(x, y) = std::clamp(t.texel(0, x, y).r, 0.0F, 1.0F);
  }
  return hm;
}

glm::dvec3 view_in_texels(const glm::dvec3& view_ts, double u_len, double v_len, int hm_w,
                          int hm_h) {
  // World length of one texel along u and v, and their geometric mean for the depth axis.
  const double su = u_len / hm_w, sv = v_len / hm_h, sz = std::sqrt(su * sv);
  return {view_ts.x / su, view_ts.y / sv, view_ts.z / sz};
}

ReliefEffect::ReliefEffect(const ReliefSetup& s, const Texture& height, const Texture* colour)
    : setup_(s),
      hm_(height_map_of(height)),
      mapper_(s.parallax),
      footprint_(s.footprint),
      tracer_(s.tracer),
      marcher_(s.terrain),
      vaf_(s.visibility) {
  if (s.visibility_filter) {
    if (!colour)
      throw std::logic_error("relief: the visibility-aware filter has no colour texture");
    // The filter works on the height map's texel grid: the colour texture's level 0 read there
    // (nearest texel; texel (x, y) of the grid covers colour texels x·cw/hw ...).
    colours_ = {hm_.width, hm_.height, {}};
    colours_.c.reserve(hm_.h.size());
    for (int32_t y = 0; y < hm_.height; ++y) {
      for (int32_t x = 0; x < hm_.width; ++x) {
        const Rgba c = colour->texel(0, static_cast<int>(int64_t{x} * colour->width(0) / hm_.width),
                                     static_cast<int>(int64_t{y} * colour->height(0) / hm_.height));
        colours_.c.emplace_back(c.r, c.g, c.b, c.a);
      }
    }
  }
  if (s.method == ReliefSetup::Method::DistanceMap) {
    const DistanceMapBuilder b(s.distance_map);
    dmap_ = s.refined ? b.refined(hm_) : b.classic(hm_);
  }
  if (s.method == ReliefSetup::Method::Terrain) {
    grid_ = TerrainGrid(hm_.width, hm_.height);
    for (size_t i = 0; i < grid_.h.size(); ++i) grid_.h[i] = static_cast<float>(hm_.h[i] * s.scale);
    top_ = std::min(marcher_.top_bound(grid_), s.scale);
  }
}

std::string ReliefEffect::arithmetic() const {
  switch (setup_.method) {
    case ReliefSetup::Method::DistanceMap:
      return tracer_.arithmetic();
    case ReliefSetup::Method::Terrain:
      return marcher_.arithmetic();
    default:
      return mapper_.arithmetic();
  }
}

TimingSpec ReliefEffect::timing(const TechTable& t) const {
  switch (setup_.method) {
    case ReliefSetup::Method::DistanceMap:
      return tracer_.timing(t);
    case ReliefSetup::Method::Terrain:
      return marcher_.timing(t);
    default:
      return mapper_.timing(t);
  }
}

ReliefEffect::Shift ReliefEffect::march_terrain(double x, double y, const glm::dvec3& vt,
                                                OpCounts& ops,
                                                std::vector<ReliefRead>* reads) const {
  // Grid coordinates: x along u, z along v, y up; the ray enters at the polygon (height
  // `scale`) and runs against the view vector. Node (i, j) of the grid is texel (i, j) of the
  // height map's level 0, so the nodes the marcher logs are the height texels it reads.
  const TerrainRayMarcher::Result r =
      marcher_.march_ray(grid_, top_, {x, setup_.scale, y}, {-vt.x, -vt.z, -vt.y}, ops, reads);
  Shift s{x, y, r.steps + r.refinements, r.fetches};
  if (r.hit) {  // no hit (capped, or invalid input): the fragment keeps its (u, v)
    s.u = r.point.x;
    s.v = r.point.z;
    s.moved = true;
  }
  return s;
}

ReliefEffect::Shift ReliefEffect::shift(double u, double v, const glm::dvec3& view_ts, double u_len,
                                        double v_len, OpCounts& ops,
                                        std::vector<ReliefRead>* reads) const {
  Shift s{u, v, 0, 0};
  // The height map repeats with the texture: work in the tile holding (u, v).
  const double tu = frac_floor(u), tv = frac_floor(v);
  const double x = (u - tu) * hm_.width - 0.5, y = (v - tv) * hm_.height - 0.5;
  const glm::dvec3 vt = view_in_texels(view_ts, u_len, v_len, hm_.width, hm_.height);
  // The texel shift per unit depth along the ray (the analytic footprint's s), V.z clamped as
  // the parallax mapper clamps it (the ray marchers: only away from 0).
  const bool mapper =
      setup_.method == ReliefSetup::Method::Parallax || setup_.method == ReliefSetup::Method::Steep;
  const double len = glm::length(vt);
  const double nz = std::max(vt.z / len, mapper ? setup_.parallax.min_view_z : 1e-3);
  s.sx = -vt.x / len / nz * setup_.scale;
  s.sy = -vt.y / len / nz * setup_.scale;
  double sx = x, sy = y;
  if (setup_.method == ReliefSetup::Method::Terrain) {
    const Shift m = march_terrain(x, y, vt, ops, reads);
    s.steps = m.steps;
    s.fetches = m.fetches;
    s.moved = m.moved;
    sx = m.u;
    sy = m.v;
  } else if (setup_.method == ReliefSetup::Method::DistanceMap) {
    const double layers_per_texel = dmap_.depth / setup_.scale;
    const glm::dvec3 dir(-vt.x, -vt.y, -vt.z * layers_per_texel);
    const SphereTracer::Result r =
        tracer_.trace(dmap_, {x, y, static_cast<double>(dmap_.depth)}, dir, ops, reads);
    s.steps = r.iterations;
    s.fetches = r.fetches;
    if (r.status == SphereTracer::Status::Invalid) return s;
    s.moved = r.status == SphereTracer::Status::Hit;
    sx = r.pos.x;
    sy = r.pos.y;
  } else {
    const ParallaxMapper::Result r = mapper_.map(hm_, x, y, vt.x, vt.y, vt.z, ops, reads);
    s.steps = setup_.method == ReliefSetup::Method::Parallax ? 1 : r.linear_steps + r.binary_steps;
    s.fetches = 4 * r.samples;
    if (r.bad_input) return s;
    s.moved = true;
    sx = r.u;
    sy = r.v;
    if (setup_.method == ReliefSetup::Method::Parallax) {
      // x' = x + l·(1 − h(x)): the gradient at the entry point; l is V.xy·depth with offset
      // limiting, else the shift per unit depth.
      s.kind = ReliefFootprint::Kind::Offset;
      if (setup_.parallax.offset_limiting) {
        s.sx = -vt.x / len * setup_.scale;
        s.sy = -vt.y / len * setup_.scale;
      }
      s.gx = x;
      s.gy = y;
    }
  }
  if (s.kind == ReliefFootprint::Kind::RayHit) {
    s.gx = sx;
    s.gy = sy;
  }
  s.u = tu + (sx + 0.5) / hm_.width;
  s.v = tv + (sy + 0.5) / hm_.height;
  return s;
}

void ReliefEffect::analytic_derivatives(Fragment& g, const Shift& sh, OpCounts& ops) const {
  if (!sh.moved) return;
  // To height-map texels and back: the map spans one unit of u and v.
  const double w = hm_.width, h = hm_.height;
  const ReliefFootprint::Derivs in{g.dudx * w, g.dvdx * h, g.dudy * w, g.dvdy * h};
  const ReliefFootprint::Derivs o =
      footprint_.analytic(hm_, sh.kind, sh.gx, sh.gy, sh.sx, sh.sy, in, ops);
  g.dudx = o.xx / w;
  g.dvdx = o.yx / h;
  g.dudy = o.xy / w;
  g.dvdy = o.yy / h;
}

VisibilityAwareFilter::Result ReliefEffect::filter_visible(const Fragment& g,
                                                           const glm::dvec3& view_ts, double u_len,
                                                           double v_len, OpCounts& ops,
                                                           std::vector<ReliefRead>* reads) const {
  // The footprint in height-map texels (centres at integers), in the tile holding (u, v).
  const double w = hm_.width, h = hm_.height;
  VisibilityAwareFilter::Footprint fp;
  fp.u = (g.u - frac_floor(g.u)) * w - 0.5;
  fp.v = (g.v - frac_floor(g.v)) * h - 0.5;
  fp.ux = g.dudx * w;
  fp.vx = g.dvdx * h;
  fp.uy = g.dudy * w;
  fp.vy = g.dvdy * h;
  const glm::dvec3 vt = view_in_texels(view_ts, u_len, v_len, hm_.width, hm_.height);
  return vaf_.filter(hm_, colours_, fp, vt.x, vt.y, vt.z, ops, reads);
}

glm::dvec3 normal_map_rgb(const Texture& t, double u, double v) {
  const int w = t.width(0), h = t.height(0);
  if (!std::isfinite(u) || !std::isfinite(v)) return {0.5, 0.5, 1.0};
  const double x = (u - std::floor(u)) * w - 0.5, y = (v - std::floor(v)) * h - 0.5;
  const double fx = std::floor(x), fy = std::floor(y), a = x - fx, b = y - fy;
  const auto wrap = [](int i, int n) { return ((i % n) + n) % n; };
  const int x0 = wrap(static_cast<int>(fx), w), x1 = wrap(static_cast<int>(fx) + 1, w);
  const int y0 = wrap(static_cast<int>(fy), h), y1 = wrap(static_cast<int>(fy) + 1, h);
  const auto at = [&](int xi, int yi) {
    const Rgba c = t.texel(0, xi, yi);
    return glm::dvec3(c.r, c.g, c.b);
  };
  return (1 - a) * (1 - b) * at(x0, y0) + a * (1 - b) * at(x1, y0) + (1 - a) * b * at(x0, y1) +
         a * b * at(x1, y1);
}

LightingEffect::LightingEffect(const LightingSetup& s, const Texture* normal_tex)
    : setup_(s), tex_(normal_tex), normals_(s.normals), terrain_(s.terrain), shader_(s.shader) {
  if (s.normal != LightingSetup::Normal::Flat && !tex_)
    throw std::logic_error("lighting: the normal texture '" + s.normal_texture + "' is not bound");
  if (s.normal == LightingSetup::Normal::HeightMap) hm_ = height_map_of(*tex_);
  if (s.normal == LightingSetup::Normal::Terrain) {
    // The relief's grid (ReliefEffect): heights h·scale texels, node (i, j) = texel (i, j).
    hm_ = height_map_of(*tex_);
    grid_ = TerrainGrid(hm_.width, hm_.height);
    for (size_t i = 0; i < grid_.h.size(); ++i)
      grid_.h[i] = static_cast<float>(hm_.h[i] * s.terrain_scale);
  }
}

Rgba LightingEffect::shade(const Rgba& c, double u, double v, const glm::dvec3& view_ts,
                           const glm::dvec3& light_ts, OpCounts& normal_ops,
                           OpCounts& shader_ops) const {
  glm::vec3 n(0, 0, 1);
  if (setup_.normal == LightingSetup::Normal::NormalMap) {
    // Bilinear read of the map (4 texels, 3 channels): then the unit decodes and normalises.
    normal_ops.mem += 4;
    normal_ops.mul += 9;
    normal_ops.add += 9;
    const glm::vec3 rgb(normal_map_rgb(*tex_, u, v));
    n = normals_.from_map(rgb, normal_ops).n;
    n.y = -n.y;  // green up: towards −v
  } else if (setup_.normal == LightingSetup::Normal::HeightMap) {
    const double x = (u - frac_floor(u)) * hm_.width, y = (v - frac_floor(v)) * hm_.height;
    n = normals_
            .from_height(hm_, static_cast<int32_t>(std::floor(x)),
                         static_cast<int32_t>(std::floor(y)), normal_ops)
            .n;
  } else if (setup_.normal == LightingSetup::Normal::Terrain) {
    // The marched hit's grid position, as the relief's march_terrain placed it (texel centres
    // at integers); the grid frame's y is the tangent frame's z.
    const double x = (u - frac_floor(u)) * hm_.width - 0.5,
                 z = (v - frac_floor(v)) * hm_.height - 0.5;
    const glm::vec3 g = terrain_.normal(grid_, x, z, normal_ops).n;
    n = {g.x, g.z, g.y};
  }
  const glm::vec3 lit =
      shader_
          .shade(glm::vec3(c.r, c.g, c.b), n, glm::vec3(light_ts), glm::vec3(view_ts), shader_ops)
          .rgb;
  return {lit.x, lit.y, lit.z, c.a};
}

TimingSpec LightingEffect::timing(const TechTable& t) const {
  TimingSpec s = shader_.timing(t);
  if (!has_normal_unit() && !has_terrain_normal()) return s;
  const TimingSpec n = has_terrain_normal() ? terrain_.timing(t) : normals_.timing(t);
  s.latency += n.latency;
  s.ii = std::max(s.ii, n.ii);
  s.area += n.area;
  return s;
}

}  // namespace texsim
