#include "pipeline/texture/layered_lookup.h"

#include <cmath>

namespace texsim {

LayeredLookup LayeredLookup::from_toml(const ConfigReader& r) {
  r.reject_unknown({"direction", "layer", "r"});
  LayeredLookup l;
  l.direction = static_cast<Direction>(r.get_choice("direction", 0, {"none", "reflect", "view"}));
  l.layer = r.get_double("layer", 0);
  if (!std::isfinite(l.layer) || std::fabs(l.layer) > 1e9)
    r.fail("layer", "must be a finite number of at most 1e9 in magnitude");
  if (const toml::node* n = r.table().get("r")) {
    const toml::array* a = n->as_array();
    if (!a || a->size() != 3) r.fail("r", "expected [a, b, c]: r = a·u + b·v + c");
    for (size_t i = 0; i < 3; ++i) {
      const toml::node& e = *a->get(i);
      const std::optional<double> x = e.value<double>();  // integers too
      if (!x || !std::isfinite(*x) || std::fabs(*x) > 1e9)
        r.fail_at(e, "r: element " + std::to_string(i) + " must be a finite number of at most 1e9");
      l.r[i] = *x;
    }
    l.has_r = true;
  }
  return l;
}

}  // namespace texsim

namespace texsim {

void LayeredLookup::apply_r(Fragment& f) const {
  if (!has_r) return;
  f.w = r[0] * f.u + r[1] * f.v + r[2];
  f.dwdx = r[0] * f.dudx + r[1] * f.dvdx;
  f.dwdy = r[0] * f.dudy + r[1] * f.dvdy;
}

}  // namespace texsim
