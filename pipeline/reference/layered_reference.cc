#include "pipeline/reference/layered_reference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <vector>

#include "blocks/texture/layered/cube_face_select.h"
#include "blocks/texture/layered/cube_seam.h"
#include "blocks/texture/volume/volume_address_gen.h"

namespace texsim {

namespace {

// One step outside a face under an address mode (non-seamless cubes): i in [−1, n].
int face_address(int i, int n, AddressMode m) {
  if (i >= 0 && i < n) return i;
  switch (m) {
    case AddressMode::Wrap:
      return i < 0 ? n - 1 : 0;
    case AddressMode::Border:
      return -1;
    default:  // clamp, mirror and mirror-clamp agree one texel out
      return i < 0 ? 0 : n - 1;
  }
}

glm::dvec4 texel_d(const Texture& tex, int level, int x, int y) {
  return glm::dvec4(tex.texel(level, x, y));
}

}  // namespace

ReferenceFace reference_cube_face(glm::dvec3 r) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(r[k])) r[k] = 0;
  const double ax = std::fabs(r.x), ay = std::fabs(r.y), az = std::fabs(r.z);
  const int axis = az >= ax && az >= ay ? 2 : ay >= ax ? 1 : 0;
  ReferenceFace f;
  f.face = 2 * axis + (std::signbit(r[axis]) ? 1 : 0);
  const double rc = std::fabs(r[axis]);
  if (rc == 0) return f;  // the face the signs give, at its centre (as the unit)
  const CubeFaceAxes& a = cube_face_axes(f.face);
  double sc = 0, tc = 0;
  for (int k = 0; k < 3; ++k) {
    sc += a.s[static_cast<size_t>(k)] * r[k];
    tc += a.t[static_cast<size_t>(k)] * r[k];
  }
  f.s = std::clamp(0.5 * sc / rc + 0.5, 0.0, 1.0);
  f.t = std::clamp(0.5 * tc / rc + 0.5, 0.0, 1.0);
  return f;
}

glm::dvec4 reference_cube_bilinear(const Texture& tex, int cube, glm::dvec3 r, bool seamless,
                                   AddressMode au, AddressMode av, glm::dvec4 border) {
  const ReferenceFace f = reference_cube_face(r);
  const int n = tex.width(0);
  const double x = f.s * n - 0.5, y = f.t * n - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const double a = x - fx, b = y - fy;
  const int i0 = static_cast<int>(fx), j0 = static_cast<int>(fy);
  const double w[4] = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
  glm::dvec4 sum(0.0);
  for (int k = 0; k < 4; ++k) {
    if (w[k] == 0) continue;
    const int i = i0 + (k & 1), j = j0 + (k >> 1);
    glm::dvec4 c(0.0);
    if (seamless) {
      std::array<CubeTexel, 3> t{};
      const int m = CubeSeam::resolve(f.face, i, j, n, t);
      for (int e = 0; e < m; ++e)
        c += texel_d(tex, tex.slice_level(6 * cube + t[static_cast<size_t>(e)].face, 0),
                     t[static_cast<size_t>(e)].x, t[static_cast<size_t>(e)].y);
      c /= static_cast<double>(m);
    } else {
      const int ai = face_address(i, n, au), aj = face_address(j, n, av);
      c = ai < 0 || aj < 0 ? border : texel_d(tex, tex.slice_level(6 * cube + f.face, 0), ai, aj);
    }
    sum += w[k] * c;
  }
  return sum;
}

glm::dvec4 ground_truth_cube(const Texture& tex, int cube, bool seamless, AddressMode au,
                             AddressMode av, glm::dvec4 border, const DirectionMap& map, int px,
                             int py, const PixelIntegrator& integrate, int* samples, int* reach) {
  // The footprint in face texels at the pixel's centre: the direction's change across a pixel
  // relative to its major magnitude, times n/2 (s = ½·sc/|rc| + ½).
  const glm::dvec3 c = map.at(px + 0.5, py + 0.5);
  const double rc = std::max({std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)});
  const double k = rc > 0 ? tex.width(0) / (2 * rc) : 0;
  const auto len = [](glm::dvec3 v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); };
  const glm::dvec2 texels(len(map.ddx) * k, len(map.ddy) * k);
  return integrate(
      [&](double dx, double dy) {
        return reference_cube_bilinear(tex, cube, map.at(px + dx, py + dy), seamless, au, av,
                                       border);
      },
      texels, samples, reach);
}

glm::dvec4 reference_volume_trilinear(const Texture& tex, const AddressMode m[3], glm::dvec4 border,
                                      double u, double v, double r) {
  const int n[3] = {tex.width(0), tex.height(0), tex.volume_depth(0)};
  const double c[3] = {u, v, r};
  int64_t i0[3];
  double f[3];
  for (int k = 0; k < 3; ++k) {
    const double t = std::clamp((std::isfinite(c[k]) ? c[k] : 0.0) * n[k] - 0.5, -0x1p40, 0x1p40);
    i0[k] = static_cast<int64_t>(std::floor(t));
    f[k] = t - std::floor(t);
  }
  glm::dvec4 sum(0);
  for (int corner = 0; corner < 8; ++corner) {
    double w = 1;
    int a[3];
    bool outside = false;
    for (int k = 0; k < 3; ++k) {
      const int hi = (corner >> k) & 1;
      w *= hi ? f[k] : 1 - f[k];
      // The spec's wrap functions on one integer coordinate (−1: the border).
      a[k] = VolumeAddressGen::address(i0[k] + hi, n[k], m[k]);
      outside = outside || a[k] < 0;
    }
    sum += w * (outside ? border : glm::dvec4(tex.texel(tex.volume_level(0, a[2]), a[0], a[1])));
  }
  return sum;
}

glm::dvec4 ground_truth_volume(const Texture& tex, const AddressMode m[3], glm::dvec4 border,
                               const Fragment& f, const ProjectiveMap* map, const double* r_of_uv,
                               int px, int py, const PixelIntegrator& integrate, int* samples,
                               int* reach) {
  const glm::dvec2 texels = texels_across(f, tex.width(0), tex.height(0));
  if (map && r_of_uv) {
    const PixelMap pm(*map, px, py);
    return integrate(
        [&](double dx, double dy) {
          double u = 0, v = 0;
          pm.uv(dx, dy, u, v);
          return reference_volume_trilinear(tex, m, border, u, v,
                                            r_of_uv[0] * u + r_of_uv[1] * v + r_of_uv[2]);
        },
        pm.texels_across(tex.width(0), tex.height(0)), samples, reach);
  }
  return integrate(
      [&](double dx, double dy) {
        const double sx = dx - 0.5, sy = dy - 0.5;
        return reference_volume_trilinear(tex, m, border, f.u + sx * f.dudx + sy * f.dudy,
                                          f.v + sx * f.dvdx + sy * f.dvdy,
                                          f.w + sx * f.dwdx + sy * f.dwdy);
      },
      texels, samples, reach);
}

glm::dvec4 ground_truth_volume_operation(const Texture& tex, const AddressMode m[3],
                                         glm::dvec4 border, const OperationSampler& s,
                                         const Fragment& f, const PixelIntegrator& integrate,
                                         int* samples, int* reach) {
  if (reach) *reach = TruthSampling::kTiers - 1;
  const glm::dvec3 size(tex.width(0), tex.height(0), tex.shape().slices);
  const glm::dvec3 c(std::isfinite(f.u) ? f.u : 0.0, std::isfinite(f.v) ? f.v : 0.0,
                     std::isfinite(f.w) ? f.w : 0.0);
  glm::dvec3 a(f.dudx, f.dvdx, f.dwdx), b(f.dudy, f.dvdy, f.dwdy);
  double cube = -1;  // the cube's side in level-0 texels, or < 0: the parallelogram a, b
  if (f.op == static_cast<uint8_t>(SampleOp::kSampleLod)) {
    cube = std::exp2(operation_lod(f.lod, s));
  } else {
    const double rho = std::max(glm::length(a * size), glm::length(b * size));
    if (std::isfinite(rho) && rho > 0) {
      const double lambda = std::log2(rho);
      const double k = std::exp2(operation_lod(lambda, s) - lambda);
      a *= k;
      b *= k;
    } else {
      cube = std::exp2(operation_lod(std::isfinite(rho) ? -std::numeric_limits<double>::infinity()
                                                        : std::numeric_limits<double>::infinity(),
                                     s));
    }
  }
  if (cube < 0) {
    return integrate(
        [&](double dx, double dy) {
          const glm::dvec3 p = c + (dx - 0.5) * a + (dy - 0.5) * b;
          return reference_volume_trilinear(tex, m, border, p.x, p.y, p.z);
        },
        {glm::length(a * size), glm::length(b * size)}, samples, reach);
  }
  // The cube: u and v by the integrator, r by the midpoint rule (the trilinear reconstruction
  // is linear in r between texel centres).
  const double side = std::min(cube, 1e9);
  const int n = static_cast<int>(std::clamp(std::ceil(4 * side), 1.0, 64.0));
  const glm::dvec3 e = side / size;  // the side in normalised coordinates
  const glm::dvec4 sum = integrate(
      [&](double dx, double dy) {
        glm::dvec4 acc(0.0);
        for (int k = 0; k < n; ++k) {
          const double r = c.z + ((k + 0.5) / n - 0.5) * e.z;
          acc += reference_volume_trilinear(tex, m, border, c.x + (dx - 0.5) * e.x,
                                            c.y + (dy - 0.5) * e.y, r);
        }
        return acc / static_cast<double>(n);
      },
      {side, side}, samples, reach);
  if (samples) *samples *= n;
  return sum;
}

int reference_layer(double a, int layers) {
  if (!std::isfinite(a) || layers <= 1) return 0;
  const double r = std::nearbyint(std::clamp(a, -1.0, static_cast<double>(layers)));
  return static_cast<int>(std::clamp(r, 0.0, static_cast<double>(layers - 1)));
}

const Texture& LayerTextures::get(const Texture& tex, int slice) {
  const std::lock_guard<std::mutex> lock(mutex_);
  auto& t = made_[{&tex, slice}];
  if (!t) t = std::make_unique<const Texture>(layer_texture(tex, slice));
  return *t;
}

Texture layer_texture(const Texture& tex, int slice) {
  const int l = tex.slice_level(slice, 0);
  const int w = tex.width(l), h = tex.height(l);
  std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Rgba c = tex.texel(l, x, y);
      float* d =
          &px[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4];
      for (int k = 0; k < 4; ++k) d[k] = c[k];
    }
  return Texture::from_rgba(tex.name(), w, h, px, TexelFormat::Rgba32f, false);
}

}  // namespace texsim
