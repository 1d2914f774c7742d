#include "blocks/texture/coords/ground_point_adder.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<GroundPointAdder>);

GroundPointAdder::Config GroundPointAdder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"form", "datapath"});
  Config c;
  c.form = static_cast<Form>(r.get_choice("form", 0, {"per_pixel", "constant_depth_rows"}));
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

OpCounts GroundPointAdder::ops_per_item() const {
  OpCounts o;
  if (cfg_.form == Form::ConstantDepthRows) {
    o.add = 2;  // x += Δx, z += Δz: no multiply, no division
    return o;
  }
  o.add = 3 + 2;  // N_x, N_z, V_y steps; X_h - ·, Z_h - ·
  o.div = 2;      // N_x/V_y, N_z/V_y (or 1 reciprocal and 2 multiplies)
  o.cmp = 1;      // V_y < 0: the ray goes down
  return o;
}

OpCounts GroundPointAdder::critical_path() const {
  OpCounts p;
  if (cfg_.form == Form::ConstantDepthRows) {
    p.add = 1;
    return p;
  }
  p.div = 1;
  p.add = 1;
  return p;
}

OpCounts GroundPointAdder::row_setup_ops() const {
  // The three linear forms at the row start (2 mul, 2 add each) and Y_h times N_x, N_z and
  // their steps; the constant-depth form then takes 1/V_y and x, z and their steps from it.
  OpCounts o;
  o.mul = 6 + 4;
  o.add = 6;
  if (cfg_.form == Form::ConstantDepthRows) {
    o.rcp = 1;
    o.mul += 4;
    o.add += 2;
    o.cmp = 1;
  }
  return o;
}

TimingSpec GroundPointAdder::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath, 1, row_setup_ops());
}

}  // namespace texsim
