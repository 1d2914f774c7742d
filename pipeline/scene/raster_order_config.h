#pragma once
// The order in which the fragment generator emits a frame's kept pixels: a scene's top-level
// `[raster]` table (docs/scenes.md). The order decides which texels a texture cache sees
// close together in time (Hakura & Gupta, ISCA 1997). The scene reads the table; the walk
// itself is pipeline/raster/raster_order.h.
//   [raster]
//   order = "tiled"        # "rows" (default) or "tiled"
//   tile = 16              # tile side in pixels, a power of two 4..256
//   tile_order = "morton"  # tiles on the screen: "row", "morton" or "hilbert"
//   quad_order = "hilbert" # 2x2 quads inside a tile: "row", "morton" or "hilbert"
#include <cstdint>

namespace texsim {

class ConfigReader;

// Order of the cells of a square grid: row by row, Morton (Z: x in the low bit) or Hilbert
// (starting at the top-left cell and ending at the top-right one).
enum class CurveOrder : uint8_t { Row, Morton, Hilbert };
const char* to_string(CurveOrder c);

struct RasterOrder {
  enum class Kind : uint8_t { Rows, Tiled };
  Kind kind = Kind::Rows;  // Rows: top to bottom, each row left to right (no tiles, no quads)
  int tile = 16;
  CurveOrder tile_order = CurveOrder::Row;
  CurveOrder quad_order = CurveOrder::Row;

  // Reads `[raster]` (an empty table gives the defaults); a bad key or value is an InputError
  // naming file:line:column and the key.
  static RasterOrder from_toml(const ConfigReader& r);
};

}  // namespace texsim
