#include "pipeline/scene/object_space_config.h"

#include "blocks/base/config_reader.h"

namespace texsim {

ObjectSpaceConfig ObjectSpaceConfig::from_toml(const ConfigReader& r) {
  r.reject_unknown({"max_step_px", "band_ratio", "max_samples", "lanes"});
  ObjectSpaceConfig c;
  c.raster.max_step_px = r.get_double("max_step_px", c.raster.max_step_px);
  if (!(c.raster.max_step_px > 0 && c.raster.max_step_px <= 4))
    r.fail("max_step_px", "must be in (0, 4] (hole-free up to 0.76)");
  c.band_ratio = r.get_double("band_ratio", c.band_ratio);
  if (!(c.band_ratio == 0 || (c.band_ratio > 1 && c.band_ratio <= 1e6)))
    r.fail("band_ratio", "must be 0 (never split) or in (1, 1e6]");
  c.max_samples = r.get_double("max_samples", c.max_samples);
  if (!(c.max_samples >= 1 && c.max_samples <= 1e12)) r.fail("max_samples", "must be in [1, 1e12]");
  const int lanes = static_cast<int>(r.get_int("lanes", 1, 1, 64));
  c.raster.lanes = c.splat.lanes = c.rotation.lanes = c.projection.lanes = lanes;
  return c;
}

}  // namespace texsim
