#include "pipeline/raster/scene_front_end.h"

#include <cmath>
#include <limits>

namespace texsim {

namespace {

// Translation by whole periods of an address mode (0: none) that brings c near [0, period).
long double rebase(long double c, int size, AddressMode m) {
  // Clamp, border and mirror-clamp are not periodic: no translation keeps their texels.
  if (m == AddressMode::Clamp || m == AddressMode::Border || m == AddressMode::MirrorClamp ||
      !std::isfinite(c))
    return 0;
  const long double period = static_cast<long double>(size) * (m == AddressMode::Mirror ? 2 : 1);
  return std::floor(c / period) * period;
}

}  // namespace

PlaneTriangles plane_triangles(const PlaneProjection& proj, int width, int height, int tw, int th,
                               AddressMode au, AddressMode av) {
  PlaneTriangles pt;
  const std::vector<glm::dvec2> poly = proj.screen_polygon();
  ProjectiveMap m = proj.texel_map(tw, th);
  if (proj.culled() || poly.size() < 3 || !m.finite()) return pt;
  std::vector<long double> xs, ys;
  for (const auto& p : poly) {
    xs.push_back(p.x);
    ys.push_back(p.y);
  }
  m = m.normalised(xs.data(), ys.data(), static_cast<int>(xs.size()));
  pt.rebase_u = rebase(m.u(xs[0], ys[0]), tw, au);
  pt.rebase_v = rebase(m.v(xs[0], ys[0]), th, av);
  pt.map = m.translated(pt.rebase_u, pt.rebase_v);
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    CoordTriangle t;
    t.map = pt.map;
    const size_t idx[3] = {0, i, i + 1};
    for (int k = 0; k < 3; ++k) {
      t.x[k] = poly[idx[k]].x;
      t.y[k] = poly[idx[k]].y;
    }
    t.rows = triangle_rows(t.x, t.y, width, height);
    if (!t.rows.empty()) pt.tris.push_back(std::move(t));
  }
  return pt;
}

void draw_scene_front_end(const Scene& scene, const std::vector<PlaneProjection>& maps,
                          TextureUnit& unit,
                          const std::function<void(const Fragment&, int, const Rgba*)>& emit) {
  FrontEndTarget t;
  t.texture = [&](const Fragment& f, int m, const ItemCost* front) {
    const Rgba c = unit.process(f, m, front);
    emit(f, m, &c);
  };
  t.drop = [&](int m, const ItemCost* front, bool rejected, int32_t, int32_t) {
    unit.drop(m, front, rejected);
  };
  t.untextured = [&](const Fragment& f, int m) { emit(f, m, nullptr); };
  draw_scene_front_end(scene, maps, unit, t);
}

void draw_scene_front_end(const Scene& scene, const std::vector<PlaneProjection>& maps,
                          TextureUnit& unit, const FrontEndTarget& target) {
  const int w = scene.width, h = scene.height;
  const auto pixel = [w](int32_t x, int32_t y) {
    return static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
  };
  std::vector<PlaneTriangles> planes;
  for (size_t p = 0; p < scene.primitives.size(); ++p) {
    const int m = scene.primitives[p].material;
    const Texture& tex = unit.texture_of(m);
    const MaterialSetup& ms = unit.material(m);
    planes.push_back(plane_triangles(maps[p], w, h, tex.width(0), tex.height(0), ms.address_u(),
                                     ms.address_v()));
  }
  // Depth test: the nearest plane whose triangles cover a pixel (the first one on a tie, as in
  // the reference generator).
  std::vector<int32_t> owner(static_cast<size_t>(w) * static_cast<size_t>(h), -1);
  std::vector<double> depth(owner.size(), std::numeric_limits<double>::infinity());
  for (size_t p = 0; p < planes.size(); ++p) {
    for (const CoordTriangle& t : planes[p].tris) {
      for (const RowSpan& r : t.rows) {
        for (int32_t x = r.x0; x < r.x0 + r.n; ++x) {
          const double d = maps[p].at(x + 0.5, r.y + 0.5).depth;
          if (!(d > 0)) continue;  // on the horizon line: nothing of the plane is seen there
          const size_t k = pixel(x, r.y);
          if (d < depth[k]) {
            depth[k] = d;
            owner[k] = static_cast<int32_t>(p);
          }
        }
      }
    }
  }
  std::vector<uint8_t> done(owner.size(), 0);
  std::vector<CoordUnitFragment> frags;
  std::vector<ItemCost> costs;
  for (size_t p = 0; p < planes.size(); ++p) {
    const int m = scene.primitives[p].material;
    const Texture& tex = unit.texture_of(m);
    const double tw = tex.width(0), th = tex.height(0);
    Fragment f;
    f.prim = static_cast<uint32_t>(p);
    f.tex = static_cast<uint32_t>(scene.materials[static_cast<size_t>(m)].texture);
    const bool own_coords = unit.material(m).coords != nullptr;
    for (const CoordTriangle& t : planes[p].tris) {
      if (!own_coords) {
        for (const RowSpan& r : t.rows) {
          for (int32_t x = r.x0; x < r.x0 + r.n; ++x) {
            const size_t k = pixel(x, r.y);
            if (owner[k] != static_cast<int32_t>(p) || done[k]) continue;
            done[k] = 1;
            Fragment e = maps[p]
                             .at(x + 0.5, r.y + 0.5)
                             .fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(r.y));
            e.prim = f.prim;
            e.tex = f.tex;
            target.texture(e, m, nullptr);
          }
        }
        continue;
      }
      frags.clear();
      costs.clear();
      unit.generate_coords(m, t, frags, costs);
      const size_t stride = frags.empty() ? 0 : costs.size() / frags.size();
      for (size_t i = 0; i < frags.size(); ++i) {
        const CoordUnitFragment& g = frags[i];
        const ItemCost* front = &costs[i * stride];
        const bool on_image = g.x >= 0 && g.y >= 0 && g.x < w && g.y < h;
        const size_t k = on_image ? pixel(g.x, g.y) : 0;
        if (!on_image || owner[k] != static_cast<int32_t>(p) || done[k]) {
          target.drop(m, front, false, on_image ? g.x : -1, on_image ? g.y : -1);
          continue;
        }
        done[k] = 1;
        f.x = static_cast<uint32_t>(g.x);
        f.y = static_cast<uint32_t>(g.y);
        if (!g.uv.valid) {
          f.u = f.v = f.dudx = f.dvdx = f.dudy = f.dvdy = 0;  // none: the pixel is not textured
          target.drop(m, front, true, g.x, g.y);
          target.untextured(f, m);
          continue;
        }
        // Texels to normalised coordinates; no derivatives (derivs = "none", or rejected by
        // the derivative block) read as zero: level 0.
        f.u = g.uv.u / tw;
        f.v = g.uv.v / th;
        f.dudx = g.d.valid ? g.d.ux / tw : 0;
        f.dvdx = g.d.valid ? g.d.vx / th : 0;
        f.dudy = g.d.valid ? g.d.uy / tw : 0;
        f.dvdy = g.d.valid ? g.d.vy / th : 0;
        target.texture(f, m, front);
      }
    }
  }
}

}  // namespace texsim
