#include "pipeline/texture/pipeline_setup.h"

#include <bit>

#include "blocks/base/config_reader.h"

namespace texsim {

PipelineSetup PipelineSetup::from_toml(const toml::table& t, const std::string& source) {
  PipelineSetup p;
  ConfigReader r(t, source, "pipeline");
  r.reject_unknown({"fifo_depth", "layout", "units", "unit_tile", "derivatives", "quad_merge",
                    "cache", "l2", "dram", "blend", "decompress", "srgb_decode"});
  p.fifo_depth = static_cast<uint32_t>(r.get_int("fifo_depth", p.fifo_depth, 1, 1 << 16));
  p.layout = static_cast<TexelLayout>(
      r.get_choice("layout", static_cast<int>(p.layout), {"linear", "tiled4x4", "morton"}));
  p.units = static_cast<uint32_t>(r.get_int("units", p.units, 1, kMaxUnits));
  p.unit_tile = static_cast<uint32_t>(r.get_int("unit_tile", p.unit_tile, 2, 1024));
  if (!std::has_single_bit(p.unit_tile))
    r.fail("unit_tile",
           "must be a power of two (tiles are whole quads and align with the raster's)");
  p.derivatives = static_cast<QuadDerivatives>(
      r.get_choice("derivatives", static_cast<int>(p.derivatives), {"fragment", "coarse", "fine"}));
  p.quad_merge = r.get_bool("quad_merge", p.quad_merge);
  p.cache = TextureCache::Config::from_toml(r.sub("cache"));
  uint32_t line = p.cache.line_bytes;  // what the level behind the L1s is asked for
  if (r.subtable("l2")) {
    const ConfigReader l2 = r.sub("l2");
    p.has_l2 = true;
    p.l2 = L2Cache::Config::from_toml(l2);
    const std::string e = p.l2.line_error(line);
    if (!e.empty()) l2.fail("line_bytes", e);
    line = p.l2.line_bytes;
  }
  const ConfigReader dram = r.sub("dram");
  p.dram_kind = static_cast<DramKind>(dram.get_choice("model", 0, {"flat", "banked"}));
  const ConfigReader keys = dram.for_block("dram", {"model"});
  if (p.dram_kind == DramKind::Flat) {
    p.dram = DramModel::Config::from_toml(keys);
  } else {
    p.banked = BankedDram::Config::from_toml(keys);
    const std::string e = p.banked.line_error(line);
    if (!e.empty()) dram.fail("row_bytes", e);
  }
  p.blend = TexelBlend::Config::from_toml(r.sub("blend"));
  p.decompress = static_cast<Decompress>(r.get_choice("decompress", static_cast<int>(p.decompress),
                                                      {"before_l1", "after_l1", "after_l2"}));
  if (p.decompress == Decompress::AfterL2 && !p.has_l2)
    r.fail("decompress", "\"after_l2\" needs an L2 ([pipeline.l2])");
  p.srgb_decode = static_cast<SrgbDecode>(r.get_choice(
      "srgb_decode", static_cast<int>(p.srgb_decode), {"before_filter", "after_filter"}));
  return p;
}

}  // namespace texsim
