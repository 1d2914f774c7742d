#include "blocks/texture/relief/distance_map_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "blocks/base/config_reader.h"
#include "blocks/texture/relief/voxel_walk.h"

namespace texsim {

DistanceMapBuilder::Config DistanceMapBuilder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"depth", "cone_deg", "polar_steps", "azimuth_steps", "penetration"});
  Config c;
  c.depth = static_cast<int32_t>(r.get_int("depth", c.depth, 1, 1024));
  c.cone_deg = r.get_double("cone_deg", c.cone_deg);
  c.polar_steps = static_cast<int32_t>(r.get_int("polar_steps", c.polar_steps, 0, 64));
  c.azimuth_steps = static_cast<int32_t>(r.get_int("azimuth_steps", c.azimuth_steps, 1, 256));
  c.penetration = r.get_double("penetration", c.penetration);
  if (!(c.cone_deg >= 0 && c.cone_deg < 90)) r.fail("cone_deg", "must be in [0, 90)");
  if (!(c.penetration > 0 && c.penetration <= 1)) r.fail("penetration", "must be in (0, 1]");
  return c;
}

DistanceMap DistanceMapBuilder::classic(const ReliefHeightMap& hm) const {
  const int32_t w = hm.width, h = hm.height, depth = cfg_.depth;
  DistanceMap m(w, h, depth);
  // Highest solid layer of each column (-1: only the base).
  std::vector<int32_t> top(static_cast<size_t>(w) * static_cast<size_t>(h));
  for (int32_t y = 0; y < h; ++y) {
    for (int32_t x = 0; x < w; ++x) {
      top[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] =
          static_cast<int32_t>(std::ceil(solid_layers(hm, x, y))) - 1;
    }
  }
  for (int32_t z = 0; z < depth; ++z) {
    const int32_t r = z + 1;  // the base is z + 1 below: nothing nearer lies farther out
    for (int32_t y = 0; y < h; ++y) {
      for (int32_t x = 0; x < w; ++x) {
        double best = r;
        for (int32_t yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy) {
          for (int32_t xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx) {
            const int32_t t =
                top[static_cast<size_t>(yy) * static_cast<size_t>(w) + static_cast<size_t>(xx)];
            const double dz = std::max(0, z - t), dx = xx - x, dy = yy - y;
            best = std::min(best, std::sqrt(dx * dx + dy * dy + dz * dz));
          }
        }
        m.at(x, y, z) = static_cast<float>(best);
      }
    }
  }
  return m;
}

double DistanceMapBuilder::refined_voxel(const ReliefHeightMap& hm, int32_t x, int32_t y, int32_t z,
                                         double classic_value) const {
  const int32_t w = hm.width, h = hm.height, depth = cfg_.depth;
  auto solid = [&](int32_t cx, int32_t cy, int32_t cz) {
    return cz < 0 || cz < solid_layers(hm, cx, cy);
  };
  if (solid(x, y, z)) return 0.0;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kTouch = 1e-9;
  const glm::dvec3 p(x, y, z);
  double best = kInf;
  const double cone = cfg_.cone_deg * std::numbers::pi / 180;
  for (int32_t k = 0; k <= cfg_.polar_steps; ++k) {
    const double theta = cfg_.polar_steps == 0 ? 0.0 : cone * k / cfg_.polar_steps;
    const int32_t n_az = k == 0 ? 1 : cfg_.azimuth_steps;
    for (int32_t j = 0; j < n_az; ++j) {
      const double phi = 2 * std::numbers::pi * j / n_az;
      const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         -std::cos(theta));
      // Blocked: a solid voxel between the ray's entry into the volume and p.
      bool blocked = false;
      // Cells the ray only touches at an edge or corner (zero length) are not crossed.
      walk_voxels(p, -d, w, h, depth,
                  [&](int32_t cx, int32_t cy, int32_t cz, double t_in, double t_out) {
                    blocked = t_out - t_in > kTouch && solid(cx, cy, cz);
                    return !blocked;
                  });
      if (blocked) continue;
      // First solid run along the ray: entry and exit (the base is unbounded below).
      double t_enter = kInf, t_exit = kInf;
      walk_voxels(p, d, w, h, depth,
                  [&](int32_t cx, int32_t cy, int32_t cz, double t_in, double t_out) {
                    if (t_out - t_in <= kTouch) return true;
                    if (!solid(cx, cy, cz)) return t_enter == kInf;  // a gap ends the run
                    if (t_enter == kInf) t_enter = t_in;
                    // The base is unbounded below.
                    t_exit = cz < 0 ? std::numeric_limits<double>::infinity() : t_out;
                    return cz >= 0;
                  });
      if (t_enter == kInf) continue;  // leaves the volume without a hit: no constraint
      best = std::min(best, t_enter + std::min(cfg_.penetration, 0.5 * (t_exit - t_enter)));
    }
  }
  return best < kInf ? best : classic_value;
}

DistanceMap DistanceMapBuilder::refined(const ReliefHeightMap& hm) const {
  DistanceMap m = classic(hm);
  for (int32_t z = 0; z < m.depth; ++z) {
    for (int32_t y = 0; y < m.height; ++y) {
      for (int32_t x = 0; x < m.width; ++x) {
        m.at(x, y, z) = static_cast<float>(refined_voxel(hm, x, y, z, m.at(x, y, z)));
      }
    }
  }
  return m;
}

}  // namespace texsim
