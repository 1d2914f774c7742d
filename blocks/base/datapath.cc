#include "blocks/base/datapath.h"

#include "blocks/base/config_reader.h"

namespace texsim {

Datapath parse_datapath(const ConfigReader& r, Datapath def) {
  return static_cast<Datapath>(
      r.get_choice("datapath", static_cast<int>(def), {"spatial", "shared"}));
}

const char* datapath_name(Datapath d) { return d == Datapath::Spatial ? "spatial" : "shared"; }

}  // namespace texsim
