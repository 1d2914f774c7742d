#include "pipeline/render/draw_renderer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "blocks/base/input_error.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/render/colour_stage.h"

namespace texsim {

namespace {

constexpr uint32_t kDepthMax = (1u << 24) - 1;  // a 24-bit depth buffer
// Clip volume: GL's near and far planes, w >= kMinW, and |x|, |y| <= kGuard · w. The guard
// band keeps window coordinates inside the edge rasteriser's ±2^22-pixel range for viewports up
// to 16384 pixels, so only triangles reaching far outside the window are cut in x and y.
constexpr double kMinW = 1e-6;
constexpr double kGuard = 256;
constexpr int kMaxAttrs = 4 + 4 + 2 * kDrawMaxUnits;  // x y z w, r g b a, s t per unit

// A clip-space vertex with its attributes: x y z w, then r g b a, then s t per unit.
using ClipVertex = std::array<double, kMaxAttrs>;

// Signed distance of v to clip plane p (inside: >= 0).
double plane_distance(const ClipVertex& v, int p) {
  switch (p) {
    case 0:
      return v[2] + v[3];  // near: z >= -w
    case 1:
      return v[3] - v[2];  // far: z <= w
    case 2:
      return v[3] - kMinW;
    case 3:
      return kGuard * v[3] - v[0];
    case 4:
      return kGuard * v[3] + v[0];
    case 5:
      return kGuard * v[3] - v[1];
    default:
      return kGuard * v[3] + v[1];
  }
}

// Sutherland–Hodgman against the clip planes; attributes are linear in clip space, so the
// new vertices' attributes are exact blends of the edge's.
void clip_polygon(std::vector<ClipVertex>& poly, std::vector<ClipVertex>& tmp) {
  for (int p = 0; p < 7 && !poly.empty(); ++p) {
    bool all_in = true;
    for (const ClipVertex& v : poly) all_in = all_in && plane_distance(v, p) >= 0;
    if (all_in) continue;
    tmp.clear();
    for (size_t i = 0; i < poly.size(); ++i) {
      const ClipVertex& a = poly[i];
      const ClipVertex& b = poly[(i + 1) % poly.size()];
      const double da = plane_distance(a, p), db = plane_distance(b, p);
      if (da >= 0) tmp.push_back(a);
      if ((da >= 0) != (db >= 0)) {
        const double t = da / (da - db);
        ClipVertex c;
        for (int k = 0; k < kMaxAttrs; ++k) c[k] = a[k] + t * (b[k] - a[k]);
        tmp.push_back(c);
      }
    }
    poly.swap(tmp);
  }
  if (poly.size() < 3) poly.clear();
}

// An attribute's plane over the screen: A(x, y) = a0 + ax (x − x0) + ay (y − y0).
struct Plane {
  double a0 = 0, ax = 0, ay = 0;
  double at(double dx, double dy) const { return a0 + ax * dx + ay * dy; }
};

}  // namespace

void DrawRenderCounts::add(const DrawRenderCounts& o) {
  draws += o.draws;
  draws_refused += o.draws_refused;
  for (const auto& [k, n] : o.refused) refused[k] += n;
  for (const auto& [k, n] : o.approximated) approximated[k] += n;
  triangles += o.triangles;
  clipped_away += o.clipped_away;
  culled += o.culled;
  fragments += o.fragments;
  depth_killed += o.depth_killed;
  alpha_killed += o.alpha_killed;
  blended += o.blended;
  written += o.written;
  lookups += o.lookups;
}

MaterialSetup material_for_sampler(const DrawUnit& u, int texture, std::string& approximation) {
  MaterialSetup m;
  m.texture = texture;
  std::vector<std::string> approx;
  const bool mip = u.min_filter >= 0x2700;
  const bool min_linear = u.min_filter == 0x2601 || u.min_filter == 0x2701 ||
                          u.min_filter == 0x2703;  // the texel filter of min
  const bool mip_linear = u.min_filter == 0x2702 || u.min_filter == 0x2703;
  if (!mip) m.lod.max_lod = 0;  // GL_NEAREST, GL_LINEAR: level 0 only
  if (mip_linear) {
    m.filter.filter = FilterMode::Trilinear;
    if (!min_linear) approx.push_back("NEAREST_MIPMAP_LINEAR as trilinear");
  } else {
    m.filter.filter = min_linear ? FilterMode::Bilinear : FilterMode::Nearest;
  }
  if ((u.mag_filter == 0x2601) != min_linear)
    approx.push_back(std::string("magnification filter ") +
                     (u.mag_filter == 0x2601 ? "LINEAR" : "NEAREST") + " as the min filter's");
  auto wrap = [&](uint32_t w) {
    switch (w) {
      case 0x2901:
        return AddressMode::Wrap;
      case 0x8370:
        return AddressMode::Mirror;
      case 0x2900:
        approx.push_back("GL_CLAMP as CLAMP_TO_EDGE");
        return AddressMode::Clamp;
      case 0x812D:
        approx.push_back("CLAMP_TO_BORDER as CLAMP_TO_EDGE");
        return AddressMode::Clamp;
      default:
        return AddressMode::Clamp;  // CLAMP_TO_EDGE
    }
  };
  m.filter.address_u = wrap(u.wrap_s);
  m.filter.address_v = wrap(u.wrap_t);
  if (u.max_anisotropy > 1) {
    m.lod.aniso = AnisoMode::Vulkan;
    m.lod.max_aniso = std::clamp(static_cast<int>(u.max_anisotropy), 1, 16);
  }
  m.lod.lod_bias = u.lod_bias;
  approximation.clear();
  for (const auto& a : approx) approximation += (approximation.empty() ? "" : "; ") + a;
  return m;
}

struct DrawRenderer::Tri {
  std::array<ClipVertex, 3> v;  // after projection: x y = window (GL, y up), z = depth, w
};

Texture texture_of_draw(const DrawTexture& t) {
  std::vector<int> ws, hs;
  std::vector<std::vector<float>> levels;
  for (size_t l = 0; l < t.levels.size(); ++l) {
    ws.push_back(static_cast<int>(std::max<uint32_t>(1, t.width >> l)));
    hs.push_back(static_cast<int>(std::max<uint32_t>(1, t.height >> l)));
    std::vector<float> f(t.levels[l].size());
    for (size_t i = 0; i < f.size(); ++i) f[i] = static_cast<float>(t.levels[l][i]) / 255.0f;
    levels.push_back(std::move(f));
  }
  // Rows in GL order: texsim's row 0 is at v = 0 too, so no flip.
  return Texture::from_levels("texture " + std::to_string(t.id) + " (" + t.name + ")", ws, hs,
                              levels, TexelFormat::Rgba8);
}

DrawRenderer::SamplerKey DrawRenderer::sampler_key(const DrawUnit& u) {
  return {u.texture,
          u.min_filter,
          u.mag_filter,
          u.wrap_s,
          u.wrap_t,
          std::bit_cast<uint32_t>(u.max_anisotropy),
          std::bit_cast<uint32_t>(u.lod_bias)};
}

DrawRenderer::DrawRenderer(const DrawTrace& trace, const std::vector<size_t>& frames,
                           const PipelineSetup& setup, const TechTable& tech, bool timing,
                           std::string file)
    : trace_(trace), file_(std::move(file)) {
  for (const DrawTexture& t : trace.textures) tex_index_[t.id] = textures_.add(texture_of_draw(t));
  std::vector<MaterialSetup> mats;
  for (size_t fi : frames) {
    if (fi >= trace.frames.size())
      throw InputError(file_, "no frame of index " + std::to_string(fi));
    for (const Draw& d : trace.frames[fi].draws) {
      for (const DrawUnit& u : d.units) {
        const SamplerKey key = sampler_key(u);
        if (materials_.count(key)) continue;
        const auto it = tex_index_.find(u.texture);
        if (it == tex_index_.end())
          throw InputError(file_, "frame " + std::to_string(trace.frames[fi].number) +
                                      ": texture " + std::to_string(u.texture) + " is not defined");
        std::string approx;
        MaterialSetup m = material_for_sampler(u, it->second, approx);
        // "texN", or "texN.K" for the K-th further sampler state on texture N.
        const int same =
            static_cast<int>(std::count_if(materials_.begin(), materials_.end(),
                                           [&](const auto& e) { return e.first[0] == u.texture; }));
        m.name = "tex" + std::to_string(u.texture) + (same ? "." + std::to_string(same) : "");
        notes_.push_back(m.name + ": " + to_string(m.filter.filter) + ", " +
                         to_string(m.filter.address_u) + "/" + to_string(m.filter.address_v) +
                         (m.lod.max_lod == 0 ? ", level 0 only" : "") +
                         (m.lod.aniso == AnisoMode::Vulkan
                              ? ", anisotropic up to " + std::to_string(m.lod.max_aniso)
                              : "") +
                         (approx.empty() ? "" : " (approximated: " + approx + ")"));
        materials_[key] = static_cast<int>(mats.size());
        mats.push_back(std::move(m));
      }
    }
  }
  if (mats.empty()) {  // untextured frames: the unit still needs a material
    MaterialSetup m;
    m.name = "none";
    mats.push_back(m);
  }
  if (setup.units > 1)
    throw InputError(file_, "[pipeline] units = " + std::to_string(setup.units) +
                                ": a draw trace is rendered through one texture unit");
  if (textures_.size() == 0) {
    textures_.add(Texture::from_rgba("white", 1, 1, {1, 1, 1, 1}, TexelFormat::Rgba8, false));
  }
  units_ = std::make_unique<UnitArray>(textures_, mats, setup, tech, timing);
}

DrawRenderer::~DrawRenderer() = default;

std::vector<std::string> DrawRenderer::texture_names() const {
  std::vector<std::string> n;
  for (int i = 0; i < textures_.size(); ++i) {
    const Texture& t = textures_[i];
    n.push_back(t.name() + " " + std::to_string(t.width(0)) + "x" + std::to_string(t.height(0)) +
                ", " + std::to_string(t.levels()) + " levels");
  }
  return n;
}

RenderedFrame DrawRenderer::render(size_t index) {
  const DrawFrame& fr = trace_.frames.at(index);
  RenderedFrame out;
  out.number = fr.number;
  for (const Draw& d : fr.draws) {
    out.width = std::max(out.width, d.state.viewport_x + static_cast<int>(d.state.viewport_w));
    out.height = std::max(out.height, d.state.viewport_y + static_cast<int>(d.state.viewport_h));
  }
  if (out.width <= 0 || out.height <= 0)
    throw InputError(file_, "frame " + std::to_string(fr.number) + ": no draw inside the window");
  const size_t px = static_cast<size_t>(out.width) * static_cast<size_t>(out.height);
  out.rgba.assign(px * 4, 0);
  out.rgba.shrink_to_fit();
  for (size_t i = 3; i < out.rgba.size(); i += 4) out.rgba[i] = 255;
  out.drawn.assign(px, 0);
  depth_.assign(px, kDepthMax);
  if (truth_) {
    out.truth_rgba = out.rgba;
    out.truth_drawn = out.drawn;
  }
  prim_ = 0;
  counts_ = &out.counts;
  accuracy_ = &out.accuracy;
  for (size_t i = 0; i < fr.draws.size(); ++i) render_draw(fr.draws[i], fr.number, i, out);
  counts_ = nullptr;
  accuracy_ = nullptr;
  return out;
}

void DrawRenderer::render_draw(const Draw& d, uint32_t frame, size_t draw_index,
                               RenderedFrame& out) {
  DrawRenderCounts& c = *counts_;
  if (const std::string why = colour_stage_unsupported(d); !why.empty()) {
    ++c.draws_refused;
    ++c.refused[why];
    return;
  }
  ++c.draws;
  for (const DrawUnit& u : d.units) {
    std::string approx;
    material_for_sampler(u, 0, approx);
    if (!approx.empty()) ++c.approximated[approx];
  }
  const DrawState& s = d.state;
  const size_t nu = d.units.size();
  std::vector<ClipVertex> poly, tmp;
  for (size_t t = 0; t + 2 < d.indices.size(); t += 3) {
    ++c.triangles;
    poly.clear();
    for (int k = 0; k < 3; ++k) {
      const uint32_t vi = d.indices[t + static_cast<size_t>(k)];
      if (vi >= d.vertex_count)
        throw InputError(file_, "frame " + std::to_string(frame) + ", draw " +
                                    std::to_string(draw_index) + ": index " + std::to_string(vi) +
                                    " is not below the vertex count");
      ClipVertex v{};
      for (int j = 0; j < 4; ++j) v[j] = d.position[4 * size_t{vi} + static_cast<size_t>(j)];
      for (int j = 0; j < 4; ++j)
        v[4 + j] = d.has_color ? d.color[4 * size_t{vi} + static_cast<size_t>(j)] / 255.0 : 1.0;
      for (size_t u = 0; u < nu; ++u) {
        v[8 + 2 * u] = d.st[u][2 * size_t{vi}];
        v[9 + 2 * u] = d.st[u][2 * size_t{vi} + 1];
      }
      poly.push_back(v);
    }
    clip_polygon(poly, tmp);
    if (poly.empty()) {
      ++c.clipped_away;
      continue;
    }
    // Perspective divide and viewport transform (window coordinates, GL: y up).
    for (ClipVertex& v : poly) {
      const double iw = 1.0 / v[3];
      v[0] = s.viewport_x + (v[0] * iw + 1) * 0.5 * s.viewport_w;
      v[1] = s.viewport_y + (v[1] * iw + 1) * 0.5 * s.viewport_h;
      v[2] = s.depth_near + (v[2] * iw + 1) * 0.5 * (s.depth_far - s.depth_near);
    }
    // Facing from the polygon's signed area (counter-clockwise positive, y up).
    double area = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
      const ClipVertex& a = poly[i];
      const ClipVertex& b = poly[(i + 1) % poly.size()];
      area += a[0] * b[1] - b[0] * a[1];
    }
    const bool front = (area > 0) == (s.front_face == gl::kCcw);
    if (s.cull && (s.cull_face == gl::kFrontAndBack || (s.cull_face == gl::kBack) != front)) {
      ++c.culled;
      continue;
    }
    for (size_t k = 1; k + 1 < poly.size(); ++k) {
      Tri tri{{poly[0], poly[k], poly[k + 1]}};
      raster_triangle(d, tri, frame, out);
    }
  }
}

void DrawRenderer::raster_triangle(const Draw& d, const Tri& t, uint32_t frame,
                                   RenderedFrame& out) {
  DrawRenderCounts& c = *counts_;
  const DrawState& s = d.state;
  const size_t nu = d.units.size();
  // Pixel (i, j) has its centre at window (i + 0.5, j + 0.5): the rasteriser's pixel-index
  // coordinates are the window's minus one half. Rows run up as in GL, so the rasteriser's
  // top-left rule is OpenGL's lower-left one.
  ScreenVertex sv[3];
  for (int k = 0; k < 3; ++k) sv[k] = {t.v[k][0] - 0.5, t.v[k][1] - 0.5, t.v[k][3]};
  Scissor sc{std::max(0, s.viewport_x), std::max(0, s.viewport_y),
             std::min(out.width, s.viewport_x + static_cast<int>(s.viewport_w)),
             std::min(out.height, s.viewport_y + static_cast<int>(s.viewport_h))};
  const EdgeRasterizer::Setup st = raster_.setup(sv, sc);
  if (!st.ok() || st.box_empty()) return;
  const uint32_t prim = prim_++;

  // Attribute planes in screen space: 1/w, every attribute / w (perspective-correct), depth
  // (linear in screen space), from the unsnapped vertices.
  const double x0 = sv[0].x, y0 = sv[0].y;
  const double ex1 = sv[1].x - x0, ey1 = sv[1].y - y0, ex2 = sv[2].x - x0, ey2 = sv[2].y - y0;
  const double det = ex1 * ey2 - ex2 * ey1;
  if (det == 0) return;
  auto plane = [&](double a0, double a1, double a2) {
    Plane p;
    p.a0 = a0;
    p.ax = ((a1 - a0) * ey2 - (a2 - a0) * ey1) / det;
    p.ay = ((a2 - a0) * ex1 - (a1 - a0) * ex2) / det;
    return p;
  };
  const double q[3] = {1 / t.v[0][3], 1 / t.v[1][3], 1 / t.v[2][3]};
  const Plane pq = plane(q[0], q[1], q[2]);
  const Plane pz = plane(t.v[0][2], t.v[1][2], t.v[2][2]);
  Plane pa[kMaxAttrs];
  const int na = 8 + 2 * static_cast<int>(nu);
  for (int a = 4; a < na; ++a) pa[a] = plane(t.v[0][a] * q[0], t.v[1][a] * q[1], t.v[2][a] * q[2]);
  if (truth_) {
    // Each unit's s/q, t/q and 1/q planes as one projective map in image pixel coordinates
    // (pixel centres at +0.5, rows down): x = X − 0.5, y = H − Y − 0.5 in the planes' terms.
    const double yt = out.height - 0.5 - y0;
    auto row = [&](const Plane& p, long double& a, long double& b, long double& c0) {
      a = p.ax;
      b = -p.ay;
      c0 = p.a0 - p.ax * (0.5 + x0) + p.ay * yt;
    };
    for (size_t u = 0; u < nu; ++u) {
      ProjectiveMap& m = map_[u];
      row(pa[8 + 2 * u], m.A, m.B, m.C);
      row(pa[9 + 2 * u], m.D, m.E, m.F);
      row(pq, m.G, m.H, m.I);
    }
  }
  // Polygon offset: factor · max |∂z/∂x|, |∂z/∂y| + units · the 24-bit buffer's resolution.
  double offset = 0;
  if (s.polygon_offset) {
    offset = s.offset_factor * std::max(std::fabs(pz.ax), std::fabs(pz.ay)) +
             s.offset_units / static_cast<double>(kDepthMax);
  }

  frags_.clear();
  for (size_t u = 0; u < nu; ++u) look_[u].clear();
  raster_.scan(st, [&](int32_t x, int32_t y, const std::array<int64_t, 3>&) {
    ++c.fragments;
    const double dx = x - x0, dy = y - y0;
    const double z = std::clamp(pz.at(dx, dy) + offset, 0.0, 1.0);
    const auto z24 = static_cast<uint32_t>(std::lround(z * kDepthMax));
    const size_t pix = static_cast<size_t>(y) * static_cast<size_t>(out.width) + x;
    if (s.depth_test && !gl_compare(s.depth_func, z24, depth_[pix])) {
      ++c.depth_killed;
      return;
    }
    const double w = 1 / pq.at(dx, dy);
    Frag f{x, y, z24, {}};
    for (int k = 0; k < 4; ++k) f.colour[k] = static_cast<float>(pa[4 + k].at(dx, dy) * w);
    frags_.push_back(f);
    for (size_t u = 0; u < nu; ++u) {
      const Plane& ps = pa[8 + 2 * u];
      const Plane& pt = pa[9 + 2 * u];
      Fragment g;
      g.frame = frame;
      g.prim = prim;
      g.x = static_cast<uint32_t>(x);
      g.y = static_cast<uint32_t>(out.height - 1 - y);  // image rows run down
      g.u = ps.at(dx, dy) * w;
      g.v = pt.at(dx, dy) * w;
      // Exact derivatives of u = S/Q: ∂u/∂x = (S_x − u Q_x) / Q; image y runs down.
      g.dudx = (ps.ax - g.u * pq.ax) * w;
      g.dvdx = (pt.ax - g.v * pq.ax) * w;
      g.dudy = -(ps.ay - g.u * pq.ay) * w;
      g.dvdy = -(pt.ay - g.v * pq.ay) * w;
      look_[u].push_back(g);
    }
  });
  if (frags_.empty()) return;

  texture_fragments(d);
  shade_fragments(d, out);
}

// Texturing through the texsim unit: each enabled unit's fragments of the triangle, in turn.
void DrawRenderer::texture_fragments(const Draw& d) {
  DrawRenderCounts& c = *counts_;
  const size_t nu = d.units.size();
  TextureUnit& unit = units_->unit(0);
  for (size_t u = 0; u < nu; ++u) {
    const DrawUnit& du = d.units[u];
    const int m = materials_.at(sampler_key(du));
    const uint32_t tex = static_cast<uint32_t>(tex_index_.at(du.texture));
    for (Fragment& g : look_[u]) g.tex = tex;
    if (observer_)
      for (const Fragment& g : look_[u]) observer_(g);
    texel_[u].resize(look_[u].size());
    for (size_t i = 0; i < look_[u].size(); i += LinearBatch::kMax) {
      const size_t n = std::min<size_t>(LinearBatch::kMax, look_[u].size() - i);
      unit.process_batch(look_[u].data() + i, n, m, texel_[u].data() + i);
    }
    if (truth_) truth_lookups(u, m);
    c.lookups += look_[u].size();
  }
}

// The colour stage, fragment by fragment in rasterisation order: the truth's frame first (it
// writes no depth), then the unit's.
void DrawRenderer::shade_fragments(const Draw& d, RenderedFrame& out) {
  if (out.has_truth())
    shade_into(d, truth_texel_, out.width, out.height, out.truth_rgba, out.truth_drawn, nullptr);
  shade_into(d, texel_, out.width, out.height, out.rgba, out.drawn, counts_);
}

void DrawRenderer::shade_into(const Draw& d, const std::vector<Rgba>* texels, int width, int height,
                              std::vector<uint8_t>& rgba, std::vector<uint8_t>& drawn,
                              DrawRenderCounts* counts) {
  const DrawState& s = d.state;
  const size_t nu = d.units.size();
  for (size_t i = 0; i < frags_.size(); ++i) {
    const Frag& f = frags_[i];
    Rgba col = f.colour;
    for (size_t u = 0; u < nu; ++u) col = texture_env(d.units[u].env_mode, col, texels[u][i]);
    if (s.alpha_test && !gl_compare(s.alpha_func, col.a, s.alpha_ref)) {
      if (counts) ++counts->alpha_killed;
      continue;
    }
    const size_t pix = static_cast<size_t>(f.y) * static_cast<size_t>(width) + f.x;
    if (counts && s.depth_test && s.depth_write) depth_[pix] = f.z;
    // Framebuffer rows run down (image order).
    const size_t img = (static_cast<size_t>(height - 1 - f.y) * static_cast<size_t>(width) +
                        static_cast<size_t>(f.x)) *
                       4;
    uint8_t* p = rgba.data() + img;
    if (s.blend) {
      const Rgba dst(static_cast<float>(p[0]) / 255.0f, static_cast<float>(p[1]) / 255.0f,
                     static_cast<float>(p[2]) / 255.0f, static_cast<float>(p[3]) / 255.0f);
      col = blend(s.blend_src, s.blend_dst, col, dst);
      if (counts) ++counts->blended;
    }
    for (int k = 0; k < 4; ++k) p[k] = to_unorm8(col[k]);
    drawn[img / 4] = 1;
    if (counts) ++counts->written;
  }
}

// Each look-up's truth through the triangle's exact map, and its error against the unit's
// texel.
void DrawRenderer::truth_lookups(size_t u, int m) {
  const std::vector<Fragment>& look = look_[u];
  std::vector<Rgba>& out = truth_texel_[u];
  out.resize(look.size());
  truth_samples_.resize(look.size());
  if (look.empty()) return;
  const MaterialSetup& ms = units_->unit(0).material(m);
  const Texture& tex = textures_[static_cast<int>(look.front().tex)];
  // Each truth depends on its look-up alone: computed on the threads, then summed in order, so
  // every thread count gives the same figures. A triangle's look-ups are split only when there
  // are enough of them to pay for starting threads.
  constexpr size_t kPerThread = 64;
  const int threads = look.size() >= 2 * kPerThread ? truth_threads_ : 1;
  parallel_range(look.size(), threads, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      int samples = 0;
      const glm::dvec4 t = ground_truth_exact(tex, ms.address_u(), ms.address_v(), map_[u],
                                              static_cast<int>(look[i].x),
                                              static_cast<int>(look[i].y), *truth_, &samples);
      out[i] = Rgba(static_cast<float>(t.r), static_cast<float>(t.g), static_cast<float>(t.b),
                    static_cast<float>(t.a));
      truth_samples_[i] = samples;
    }
  });
  LookupAccuracy& acc = *accuracy_;
  for (size_t i = 0; i < look.size(); ++i) {
    const Rgba& c = texel_[u][i];
    for (int k = 0; k < 4; ++k) {
      // Against the truth as the colour stage takes it (rounded to float).
      const double e = static_cast<double>(c[k]) - static_cast<double>(out[i][k]);
      acc.sum_sq += e * e;
      acc.max_abs = std::max(acc.max_abs, std::fabs(e));
    }
    acc.samples += static_cast<uint64_t>(truth_samples_[i]);
    ++acc.lookups;
  }
}

double LookupAccuracy::psnr_db() const {
  const double e = mse();
  return e > 0 ? 10 * std::log10(1 / e) : 999;
}

void LookupAccuracy::add(const LookupAccuracy& o) {
  lookups += o.lookups;
  samples += o.samples;
  sum_sq += o.sum_sq;
  max_abs = std::max(max_abs, o.max_abs);
}

}  // namespace texsim
