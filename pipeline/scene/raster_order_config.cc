#include "pipeline/scene/raster_order_config.h"

#include "blocks/base/config_reader.h"

namespace texsim {

const char* to_string(CurveOrder c) {
  switch (c) {
    case CurveOrder::Row:
      return "row";
    case CurveOrder::Morton:
      return "morton";
    case CurveOrder::Hilbert:
      return "hilbert";
  }
  return "?";
}

RasterOrder RasterOrder::from_toml(const ConfigReader& r) {
  r.reject_unknown({"order", "tile", "tile_order", "quad_order"});
  RasterOrder o;
  o.kind = static_cast<Kind>(r.get_choice("order", 0, {"rows", "tiled"}));
  o.tile = static_cast<int>(r.get_int("tile", o.tile, 4, 256));
  // Quads and curves need whole halvings: a quad grid of a power-of-two side.
  if ((o.tile & (o.tile - 1)) != 0) r.fail("tile", "must be a power of two (4, 8, ..., 256)");
  const std::vector<std::string_view> curves = {"row", "morton", "hilbert"};
  o.tile_order = static_cast<CurveOrder>(r.get_choice("tile_order", 0, curves));
  o.quad_order = static_cast<CurveOrder>(r.get_choice("quad_order", 0, curves));
  return o;
}

}  // namespace texsim
