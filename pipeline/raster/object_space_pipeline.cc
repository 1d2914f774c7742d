#include "pipeline/raster/object_space_pipeline.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "blocks/base/input_error.h"
#include "pipeline/geometry/plane_projection.h"

namespace texsim {

namespace {

// The camera's view space (X right, Y down the screen, Z forward) and its imaging.
struct ViewFrame {
  glm::dvec3 eye, right, down, fwd;
  double f = 1, cx = 0, cy = 0, near = 0.01;
  // Half extents of the clip frustum (X/Z, Y/Z; orthographic: X, Y), one pixel of guard.
  double tx = 1, ty = 1;
  bool ortho = false;  // parallel projection: f pixels per world unit

  explicit ViewFrame(const Camera& c) {
    eye = c.position;
    fwd = glm::normalize(c.look_at - c.position);
    right = glm::normalize(glm::cross(fwd, c.up));
    down = -glm::cross(right, fwd);
    f = static_cast<double>(c.focal_px());
    cx = static_cast<double>(c.cx());
    cy = static_cast<double>(c.cy());
    near = c.near;
    ortho = c.orthographic;
    tx = (cx + 1) / f;
    ty = (cy + 1) / f;
  }
  glm::dvec3 to_view(const glm::dvec3& p) const {
    const glm::dvec3 d = p - eye;
    return {glm::dot(d, right), glm::dot(d, down), glm::dot(d, fwd)};
  }
  glm::dvec2 to_screen(const glm::dvec3& v) const {
    if (ortho) return {cx + f * v.x, cy + f * v.y};
    return {cx + f * v.x / v.z, cy + f * v.y / v.z};
  }
};

// Sutherland–Hodgman against the half space n·p >= c. Counts 1 div and a few ops per cut.
std::vector<glm::dvec3> clip_half(const std::vector<glm::dvec3>& poly, const glm::dvec3& n,
                                  double c, OpCounts& ops) {
  std::vector<glm::dvec3> out;
  const size_t m = poly.size();
  for (size_t i = 0; i < m; ++i) {
    const glm::dvec3& a = poly[i];
    const glm::dvec3& b = poly[(i + 1) % m];
    const double da = glm::dot(n, a) - c, db = glm::dot(n, b) - c;
    ops.mul += 3;
    ops.add += 3;
    ops.cmp += 1;
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) {
      const double t = da / (da - db);
      ops.div += 1;
      ops.mul += 3;
      ops.add += 4;
      out.push_back(a + t * (b - a));
    }
  }
  return out;
}

std::vector<glm::dvec3> clip_frustum(std::vector<glm::dvec3> poly, const ViewFrame& vf,
                                     OpCounts& ops) {
  poly = clip_half(poly, {0, 0, 1}, vf.near, ops);
  if (vf.ortho) {  // the box |X| <= tx, |Y| <= ty
    poly = clip_half(poly, {-1, 0, 0}, -vf.tx, ops);
    poly = clip_half(poly, {1, 0, 0}, -vf.tx, ops);
    poly = clip_half(poly, {0, -1, 0}, -vf.ty, ops);
    return clip_half(poly, {0, 1, 0}, -vf.ty, ops);
  }
  poly = clip_half(poly, {-1, 0, vf.tx}, 0, ops);
  poly = clip_half(poly, {1, 0, vf.tx}, 0, ops);
  poly = clip_half(poly, {0, -1, vf.ty}, 0, ops);
  poly = clip_half(poly, {0, 1, vf.ty}, 0, ops);
  return poly;
}

// Marks the pixel centres inside a convex screen polygon (a check for holes, not hardware).
void mark_covered(const std::vector<glm::dvec2>& sp, int w, int h, std::vector<uint8_t>& covered) {
  if (sp.size() < 3) return;
  double x0 = sp[0].x, x1 = x0, y0 = sp[0].y, y1 = y0;
  for (const glm::dvec2& p : sp) {
    x0 = std::min(x0, p.x);
    x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  const int i0 = std::max(0, static_cast<int>(std::floor(x0))),
            i1 = std::min(w - 1, static_cast<int>(std::ceil(x1)));
  const int j0 = std::max(0, static_cast<int>(std::floor(y0))),
            j1 = std::min(h - 1, static_cast<int>(std::ceil(y1)));
  const size_t n = sp.size();
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const double px = i + 0.5, py = j + 0.5;
      int pos = 0, neg = 0;
      for (size_t e = 0; e < n; ++e) {
        const glm::dvec2 a = sp[e], b = sp[(e + 1) % n];
        const double c = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
        pos += c > 0;
        neg += c < 0;
      }
      if (pos == 0 || neg == 0) covered[static_cast<size_t>(j) * static_cast<size_t>(w) + i] = 1;
    }
  }
}

// Splits a convex view-space polygon into bands of far/near depth ratio at most `ratio`.
std::vector<std::vector<glm::dvec3>> depth_bands(const std::vector<glm::dvec3>& poly, double ratio,
                                                 OpCounts& ops) {
  double z0 = poly[0].z, z1 = z0;
  for (const glm::dvec3& p : poly) {
    z0 = std::min(z0, p.z);
    z1 = std::max(z1, p.z);
  }
  if (!(ratio > 1) || z1 <= z0 * ratio) return {poly};
  std::vector<std::vector<glm::dvec3>> bands;
  for (double lo = z0; lo < z1; lo *= ratio) {
    std::vector<glm::dvec3> b = clip_half(poly, {0, 0, 1}, lo, ops);
    b = clip_half(b, {0, 0, -1}, -lo * ratio, ops);
    if (b.size() >= 3) bands.push_back(std::move(b));
  }
  return bands;
}

// Everything one primitive needs while its bands are walked.
struct PrimitiveWork {
  int material = 0;
  uint32_t prim = 0, tex = 0;
  int tw = 1, th = 1;
  Rotation rot;
  PlaneUvMap uv;
  // Depth change per pixel of screen travel: perspective, divided by Z² (1/Z = (nx (xs − cx) +
  // ny (ys − cy)) / (f k) + nz / k, k = n·V0: slope (|nx| + |ny|) / (f |k|)); orthographic,
  // exact (Z = (k − nx X − ny Y) / nz: slope (|nx| + |ny|) / (f nz)).
  double depth_slope = 0;
};

class Renderer {
 public:
  Renderer(const Scene& scene, TextureSet& textures, const std::vector<MaterialSetup>& mats,
           const PipelineSetup& setup, const ObjectSpaceConfig& cfg, int material)
      : scene_(scene),
        material_(material),
        vf_(scene.camera),
        cfg_(cfg),
        raster_(cfg.raster),
        splat_(cfg.splat),
        rotation_(cfg.rotation),
        projection_(cfg.projection),
        unit_(textures, object_space_materials(mats), setup, scene.tech, true),
        buffer_(scene.width, scene.height) {
    r_.width = scene.width;
    r_.height = scene.height;
    r_.covered.assign(static_cast<size_t>(scene.width) * static_cast<size_t>(scene.height), 0);
  }
  ObjectSpaceResult run();

 private:
  void primitive(uint32_t index);
  void band(const PrimitiveWork& w, const std::vector<glm::dvec3>& poly);
  // Texture and splat the waiting samples of one band (material, projection kind, depth slope).
  void splat_batch(int material, bool ortho, double slope);

  const Scene& scene_;
  int material_;  // -1: every primitive
  ViewFrame vf_;
  ObjectSpaceConfig cfg_;
  ObjectSpaceRaster raster_;
  SplatResolve splat_;
  PolygonRotation rotation_;
  SampleProjection projection_;
  TextureUnit unit_;
  SplatBuffer buffer_;
  ObjectSpaceResult r_;
  // Samples waiting for the texture unit, their projections, and their colours.
  std::vector<Fragment> batch_;
  std::vector<ProjectedSample> projected_;
  std::vector<Rgba> colours_;
};

void Renderer::primitive(uint32_t index) {
  const ScenePrimitive& p = scene_.primitives[index];
  const PlaneProjection map(scene_, p);
  if (map.degenerate()) {
    ++r_.degenerate;
    return;
  }
  if (map.culled()) {
    ++r_.culled;
    return;
  }
  const bool tri = p.shape == ScenePrimitive::Shape::Triangle;
  const glm::dvec3 corners[4] = {p.origin, p.origin + p.edge_u,
                                 tri ? p.origin + p.edge_v : p.origin + p.edge_u + p.edge_v,
                                 p.origin + p.edge_v};
  std::vector<glm::dvec3> view;
  view.reserve(4);
  for (int i = 0; i < (tri ? 3 : 4); ++i) view.push_back(vf_.to_view(corners[i]));
  r_.rotation_ops.mul += 9 * view.size();  // the view transform of the corners
  r_.rotation_ops.add += 9 * view.size();
  PrimitiveWork w;
  w.material = p.material;
  w.prim = index;
  const MaterialSetup& ms = unit_.material(p.material);
  w.tex = static_cast<uint32_t>(ms.texture);
  w.tw = unit_.texture_of(p.material).width(0);
  w.th = unit_.texture_of(p.material).height(0);
  const glm::dvec3 n = PolygonRotation::unit_normal(view[0], view[1], view[2], r_.rotation_ops);
  w.rot = PolygonRotation::setup(n, r_.rotation_ops);
  if (w.rot.kind == RotationCase::Degenerate) {
    ++r_.degenerate;
    return;
  }
  // Edge-on: the plane passes through the eye (orthographic: contains the view direction), so
  // its projection has no area: nothing to draw.
  const glm::dvec3& n1 = w.rot.normal;
  const double k = glm::dot(n1, view[0]);
  if (vf_.ortho ? n1.z <= 1e-12 : std::fabs(k) <= 1e-12 * glm::length(view[0])) {
    ++r_.edge_on;
    return;
  }
  w.depth_slope = vf_.ortho ? (std::fabs(n1.x) + std::fabs(n1.y)) / (vf_.f * n1.z)
                            : (std::fabs(n1.x) + std::fabs(n1.y)) * std::fabs(1.0 / k) / vf_.f;
  const std::vector<glm::dvec3> clipped = clip_frustum(view, vf_, r_.rotation_ops);
  if (clipped.size() < 3) {
    ++r_.clipped_away;
    return;
  }
  ++r_.primitives;
  std::vector<glm::dvec2> sp;
  sp.reserve(clipped.size());
  for (const glm::dvec3& v : clipped) sp.push_back(vf_.to_screen(v));
  mark_covered(sp, r_.width, r_.height, r_.covered);
  // The affine texture map from three unclipped corners (texture coordinates of a, b = 0/1).
  const glm::dvec2 uv[3] = {
      p.uv_origin, p.uv_origin + p.uv_edge_u,
      tri ? p.uv_origin + p.uv_edge_v : p.uv_origin + p.uv_edge_u + p.uv_edge_v};
  const glm::dvec2 xy[3] = {PolygonRotation::rotate_xy(w.rot, view[0], r_.rotation_ops),
                            PolygonRotation::rotate_xy(w.rot, view[1], r_.rotation_ops),
                            PolygonRotation::rotate_xy(w.rot, view[2], r_.rotation_ops)};
  w.uv = ObjectSpaceRaster::uv_map(xy, uv, r_.raster_ops);
  // Orthographic: the screen scale is the same everywhere, so one band is enough.
  for (const auto& b : depth_bands(clipped, vf_.ortho ? 0.0 : cfg_.band_ratio, r_.rotation_ops))
    band(w, b);
}

void Renderer::band(const PrimitiveWork& w, const std::vector<glm::dvec3>& poly) {
  ++r_.bands;
  const RotatedPolygon rp = PolygonRotation::rotate_polygon(w.rot, poly, r_.rotation_ops);
  // Orthographic: a unit step in the plane spans at most f pixels (the projection drops Z).
  const double jmax =
      vf_.ortho ? vf_.f : ObjectSpaceRaster::max_screen_scale(poly, vf_.f, r_.raster_ops);
  const double h = raster_.step(jmax, r_.raster_ops);
  if (!(h > 0)) return;
  const double bound = ObjectSpaceRaster::sample_bound(rp, h);
  if (static_cast<double>(r_.samples) + bound > cfg_.max_samples) {
    throw InputError(scene_.path, "object space: primitive " + std::to_string(w.prim) +
                                      " needs about " + std::to_string(bound) +
                                      " samples, beyond max_samples");
  }
  const double lod = ObjectSpaceRaster::lod(w.uv, h, w.tw, w.th, r_.raster_ops);
  r_.lod_sum += lod;
  const SampleProjection::Setup ps =
      vf_.ortho ? SampleProjection::setup_orthographic(w.rot, rp.z, vf_.f, vf_.cx, vf_.cy,
                                                       r_.projection_ops)
                : SampleProjection::setup(w.rot, rp.z, vf_.f, vf_.cx, vf_.cy, r_.projection_ops);
  r_.setup_cycles +=
      rotation_.timing(scene_.tech).latency + projection_.timing(scene_.tech).latency;
  // Depth tolerance: 1/Z is affine on the screen with slopes a = nx/(f k), b = ny/(f k), so a
  // step of δ pixels changes Z by about Z² (|a| + |b|) δ (orthographic: Z is affine, exactly
  // (|a| + |b|) δ); a sample and the pixel it lands on are within one pixel, two samples of the
  // same pixel within two.
  const bool ortho = vf_.ortho;
  const double slope = w.depth_slope;
  Fragment f;
  f.prim = w.prim;
  f.tex = w.tex;
  f.dudx = w.uv.ux * h;
  f.dvdx = w.uv.vx * h;
  f.dudy = w.uv.uy * h;
  f.dvdy = w.uv.vy * h;
  raster_.rasterize(
      rp, h, w.uv,
      [&](const PlaneSample& s) {
        ++r_.samples;
        const ProjectedSample q = SampleProjection::project(ps, s.x, s.y, r_.projection_ops);
        if (!q.valid) return;
        f.x = static_cast<uint32_t>(std::clamp(q.x, 0.0, r_.width - 1.0));
        f.y = static_cast<uint32_t>(std::clamp(q.y, 0.0, r_.height - 1.0));
        f.u = s.u;
        f.v = s.v;
        batch_.push_back(f);
        projected_.push_back(q);
        if (batch_.size() == LinearBatch::kMax) splat_batch(w.material, ortho, slope);
      },
      r_.raster, r_.raster_ops);
  splat_batch(w.material, ortho, slope);
}

void Renderer::splat_batch(int material, bool ortho, double slope) {
  // The samples through the texture unit a batch at a time (its batched datapath), then
  // splatted in sample order.
  colours_.resize(batch_.size());
  unit_.process_batch(batch_.data(), batch_.size(), material, colours_.data());
  for (size_t i = 0; i < batch_.size(); ++i) {
    const ProjectedSample& q = projected_[i];
    const double tol = ortho ? 2 * slope + 1e-9 * std::fabs(q.depth)
                             : 2 * q.depth * q.depth * slope + 1e-9 * q.depth;
    r_.splat_ops.mul += 3;
    r_.splat_ops.add += 1;
    splat_.splat(buffer_, q.x, q.y, q.depth, tol, colours_[i], r_.splat, r_.splat_ops);
  }
  batch_.clear();
  projected_.clear();
}

ObjectSpaceResult Renderer::run() {
  for (uint32_t i = 0; i < scene_.primitives.size(); ++i) {
    if (material_ < 0 || scene_.primitives[i].material == material_) primitive(i);
  }
  const glm::dvec3& bg = scene_.background;
  r_.resolve = splat_.resolve(
      buffer_, r_.covered,
      Rgba(static_cast<float>(bg.x), static_cast<float>(bg.y), static_cast<float>(bg.z), 1.0f),
      r_.image, r_.splat_ops);
  r_.drawn.resize(buffer_.weight.size());
  for (size_t i = 0; i < buffer_.weight.size(); ++i) r_.drawn[i] = buffer_.weight[i] > 0;
  unit_.check_timing_invariants();
  if (material_ >= 0) {
    for (const BlockUse& b : unit_.material_blocks(material_)) r_.texture_blocks.push_back(b.name);
  }
  for (const BlockUse& b : unit_.blocks()) {
    if (b.name == "cache") continue;
    if (material_ < 0) r_.texture_blocks.push_back(b.name);
    r_.texture_ops += b.ops;
    r_.texels += b.texels;
  }
  r_.cache = unit_.cache().stats();
  r_.dram_bytes = unit_.memory().dram_totals().bytes;
  const TechTable& t = scene_.tech;
  auto stage = [&](const TimingSpec& ts, uint64_t items) {
    return items * ts.ii / std::max<uint32_t>(1, ts.lanes);
  };
  r_.texture_cycles = unit_.cycles();
  r_.raster_cycles = stage(raster_.timing(t), r_.samples) + r_.raster.rows;
  r_.projection_cycles = stage(projection_.timing(t), r_.samples);
  r_.splat_cycles = stage(splat_.timing(t), r_.samples);
  // The resolve reads one pixel of each of the buffer's four banks per cycle and lane.
  r_.resolve_cycles = stage(splat_.timing(t), buffer_.weight.size()) / 4;
  r_.cycles =
      std::max({r_.texture_cycles, r_.raster_cycles, r_.projection_cycles, r_.splat_cycles}) +
      r_.setup_cycles + r_.resolve_cycles;
  return std::move(r_);
}

}  // namespace

std::vector<MaterialSetup> object_space_materials(const std::vector<MaterialSetup>& mats) {
  std::vector<MaterialSetup> out;
  for (const MaterialSetup& m : mats) {
    MaterialSetup o;
    o.name = m.name;
    o.texture = m.texture;
    o.filter.filter = FilterMode::Trilinear;
    o.filter.address_u = m.address_u();
    o.filter.address_v = m.address_v();
    out.push_back(std::move(o));
  }
  return out;
}

ObjectSpaceResult render_object_space(const Scene& scene, TextureSet& textures,
                                      const std::vector<MaterialSetup>& mats,
                                      const PipelineSetup& setup, const ObjectSpaceConfig& cfg,
                                      int material) {
  Renderer r(scene, textures, mats, setup, cfg, material);
  return r.run();
}

}  // namespace texsim
