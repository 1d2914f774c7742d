#include "pipeline/texture/layered_lookup.h"

#include <cmath>

namespace texsim {

LayeredLookup LayeredLookup::from_toml(const ConfigReader& r) {
  r.reject_unknown({"direction", "layer"});
  LayeredLookup l;
  l.direction = static_cast<Direction>(r.get_choice("direction", 0, {"none", "reflect", "view"}));
  l.layer = r.get_double("layer", 0);
  if (!std::isfinite(l.layer) || std::fabs(l.layer) > 1e9)
    r.fail("layer", "must be a finite number of at most 1e9 in magnitude");
  return l;
}

}  // namespace texsim
