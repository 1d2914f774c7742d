#include "blocks/texture/sampler/bilinear_lerp.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<BilinearLerp>);

BilinearLerp::Config BilinearLerp::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"texel_bits", "sub_bits"});
  Config c;
  c.texel_bits = static_cast<int>(r.get_int("texel_bits", c.texel_bits, 1, 16));
  c.sub_bits = static_cast<int>(r.get_int("sub_bits", c.sub_bits, 1, 16));
  return c;
}

TimingSpec BilinearLerp::timing(const TechTable& tech) const {
  return derive_timing(tech, ops_per_item(), critical_path(), Datapath::Spatial);
}

std::string BilinearLerp::arithmetic() const {
  std::string s = "u";
  s += std::to_string(cfg_.texel_bits);
  s += " texels, u0.";
  s += std::to_string(cfg_.sub_bits);
  s += " weights, exact products, one HalfUp rounding";
  return s;
}

}  // namespace texsim
