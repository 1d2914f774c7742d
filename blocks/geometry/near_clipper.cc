#include "blocks/geometry/near_clipper.h"

namespace texsim {

std::vector<Vec3L> clip_polygon_z(const std::vector<Vec3L>& poly, long double z, bool keep_above) {
  std::vector<Vec3L> out;
  const size_t n = poly.size();
  auto inside = [&](const Vec3L& p) { return keep_above ? p.z >= z : p.z <= z; };
  for (size_t i = 0; i < n; ++i) {
    const Vec3L& a = poly[i];
    const Vec3L& b = poly[(i + 1) % n];
    const bool ia = inside(a), ib = inside(b);
    if (ia) out.push_back(a);
    if (ia != ib) {
      const long double t = (z - a.z) / (b.z - a.z);
      out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), z});
    }
  }
  return out;
}

}  // namespace texsim
