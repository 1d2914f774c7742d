#include "pipeline/scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

namespace texsim {

const char* to_string(UvProjection p) {
  switch (p) {
    case UvProjection::None:
      return "none";
    case UvProjection::Planar:
      return "planar";
    case UvProjection::Box:
      return "box";
    case UvProjection::Spherical:
      return "spherical";
  }
  return "?";
}

namespace {

// Two triangles (a, b, c) and (a, c, d) of the quad a b c d with corners' uvs 00 10 11 01.
void add_quad(Mesh& m, int a, int b, int c, int d) {
  const glm::dvec2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles.push_back({{a, b, c}, {uv[0], uv[1], uv[2]}, 0});
  m.triangles.push_back({{a, c, d}, {uv[0], uv[2], uv[3]}, 0});
}

struct Bounds {
  glm::dvec3 lo{0}, hi{0};
  glm::dvec3 size() const { return hi - lo; }
  glm::dvec3 centre() const { return 0.5 * (lo + hi); }
};

Bounds bounds(const Mesh& m) {
  Bounds b;
  if (m.positions.empty()) return b;
  b.lo = b.hi = m.positions[0];
  for (const glm::dvec3& p : m.positions) {
    b.lo = glm::min(b.lo, p);
    b.hi = glm::max(b.hi, p);
  }
  return b;
}

// (p - lo) / extent along `axis`, or 0.5 for a flat extent.
double unit(const glm::dvec3& p, const Bounds& b, int axis) {
  const double e = b.size()[axis];
  return e > 0 ? (p[axis] - b.lo[axis]) / e : 0.5;
}

// u along axis `ua`, v along `va`.
glm::dvec2 planar(const glm::dvec3& p, const Bounds& b, int ua, int va) {
  return {unit(p, b, ua), unit(p, b, va)};
}

}  // namespace

Mesh make_box(const glm::dvec3& size) {
  Mesh m;
  m.source = "procedural:box";
  const glm::dvec3 h = 0.5 * size;
  for (int i = 0; i < 8; ++i) {
    m.positions.emplace_back((i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z);
  }
  // Faces as seen from outside, counter-clockwise: -x, +x, -y, +y, -z, +z.
  add_quad(m, 0, 4, 6, 2);
  add_quad(m, 5, 1, 3, 7);
  add_quad(m, 0, 1, 5, 4);
  add_quad(m, 6, 7, 3, 2);
  add_quad(m, 1, 0, 2, 3);
  add_quad(m, 4, 5, 7, 6);
  m.has_uvs = true;
  return m;
}

Mesh make_grid(int nx, int ny, const glm::dvec2& size) {
  Mesh m;
  m.source = "procedural:grid";
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      m.positions.emplace_back(size.x * (static_cast<double>(i) / nx - 0.5), 0.0,
                               size.y * (static_cast<double>(j) / ny - 0.5));
    }
  }
  const auto at = [nx](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      // Counter-clockwise seen from +y: (i, j+1) → (i+1, j+1) → (i+1, j) in x-z.
      MeshTriangle t0{{at(i, j), at(i, j + 1), at(i + 1, j + 1)}, {}, 0};
      MeshTriangle t1{{at(i, j), at(i + 1, j + 1), at(i + 1, j)}, {}, 0};
      for (MeshTriangle* t : {&t0, &t1}) {
        for (int k = 0; k < 3; ++k) {
          const int col = t->v[k] % (nx + 1), row = t->v[k] / (nx + 1);  // grid position
          t->uv[k] = {static_cast<double>(col) / nx, static_cast<double>(row) / ny};
        }
        m.triangles.push_back(*t);
      }
    }
  }
  m.has_uvs = true;
  return m;
}

void project_uvs(Mesh& mesh, UvProjection p) {
  if (p == UvProjection::None) return;
  const Bounds b = bounds(mesh);
  // Axes by extent, largest first.
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int a, int c) { return b.size()[a] > b.size()[c]; });
  for (MeshTriangle& t : mesh.triangles) {
    const glm::dvec3 a = mesh.positions[t.v[0]], bb = mesh.positions[t.v[1]],
                     c = mesh.positions[t.v[2]];
    int ua = std::min(order[0], order[1]), va = std::max(order[0], order[1]);
    if (p == UvProjection::Box) {
      const glm::dvec3 n = glm::abs(glm::cross(bb - a, c - a));
      const int axis = n.x >= n.y && n.x >= n.z ? 0 : (n.y >= n.z ? 1 : 2);
      ua = axis == 0 ? 1 : 0;
      va = axis == 2 ? 1 : 2;
    }
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3& q = mesh.positions[t.v[k]];
      if (p != UvProjection::Spherical) {
        t.uv[k] = planar(q, b, ua, va);
        continue;
      }
      const glm::dvec3 d = q - b.centre();
      const double r = glm::length(d);
      const double lon = std::atan2(d.z, d.x),
                   lat = r > 0 ? std::acos(std::clamp(d.y / r, -1.0, 1.0)) : 0;
      t.uv[k] = {lon / (2 * std::numbers::pi) + 0.5, lat / std::numbers::pi};
    }
    if (p == UvProjection::Spherical) {
      // A triangle across the seam (u jumping by more than ½) is kept continuous.
      const double umax = std::max({t.uv[0].x, t.uv[1].x, t.uv[2].x});
      for (glm::dvec2& uv : t.uv) {
        if (umax - uv.x > 0.5) uv.x += 1.0;
      }
    }
  }
  mesh.has_uvs = true;
}

}  // namespace texsim
