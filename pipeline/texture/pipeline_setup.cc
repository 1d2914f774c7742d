#include "pipeline/texture/pipeline_setup.h"

#include <bit>

#include "blocks/base/config_reader.h"

namespace texsim {

PipelineSetup PipelineSetup::from_toml(const toml::table& t, const std::string& source) {
  PipelineSetup p;
  ConfigReader r(t, source, "pipeline");
  r.reject_unknown({"fifo_depth", "layout", "units", "unit_tile", "cache", "dram", "blend"});
  p.fifo_depth = static_cast<uint32_t>(r.get_int("fifo_depth", p.fifo_depth, 1, 1 << 16));
  p.layout = static_cast<TexelLayout>(
      r.get_choice("layout", static_cast<int>(p.layout), {"linear", "tiled4x4", "morton"}));
  p.units = static_cast<uint32_t>(r.get_int("units", p.units, 1, kMaxUnits));
  p.unit_tile = static_cast<uint32_t>(r.get_int("unit_tile", p.unit_tile, 2, 1024));
  if (!std::has_single_bit(p.unit_tile))
    r.fail("unit_tile",
           "must be a power of two (tiles are whole quads and align with the raster's)");
  p.cache = TextureCache::Config::from_toml(r.sub("cache"));
  p.dram = DramModel::Config::from_toml(r.sub("dram"));
  p.blend = TexelBlend::Config::from_toml(r.sub("blend"));
  return p;
}

}  // namespace texsim
