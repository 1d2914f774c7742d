#pragma once
// The walk over a frame's pixels in a scene's raster order (RasterOrder, `[raster]`,
// docs/scenes.md). Tiled: the screen is cut into tile × tile squares anchored at its origin
// (0, 0), visited in the tile order; inside a tile its 2×2 quads, anchored at even x and y,
// in the quad order; inside a quad its pixels in Vulkan's order (0,0), (1,0), (0,1), (1,1).
// Tiles and quads cut by the walked rectangle are walked over their pixels inside it only.
#include <cstdint>
#include <vector>

#include "pipeline/geometry/screen_extent.h"
#include "pipeline/scene/raster_order_config.h"

namespace texsim {

// Position of cell (x, y) along `c` over a 2^bits × 2^bits grid (x, y < 2^bits, bits <= 15):
// Row y·2^bits + x; Morton the bits of x and y interleaved, x's in the even places; Hilbert the
// distance along the curve from (0, 0), which ends at (2^bits − 1, 0).
uint32_t curve_index(CurveOrder c, uint32_t x, uint32_t y, int bits);

class RasterWalk {
 public:
  // Walks the pixels of `r` (a rectangle of a width × height screen) in `o`'s order. The tile
  // order's curve spans the screen's tile grid, so a pixel's place in it does not depend on r.
  RasterWalk(const RasterOrder& o, int width, int height, const PixelRect& r);

  // Calls visit(x, y) once for every pixel of r.
  template <class Visit>
  void for_each(Visit&& visit) const;

 private:
  PixelRect r_;
  bool tiled_ = false;
  int tile_ = 16;
  std::vector<uint32_t> tiles_;  // tiles meeting r in walking order: ty << 16 | tx
  std::vector<uint16_t> quads_;  // a tile's quads in walking order: qy << 8 | qx
};

template <class Visit>
void RasterWalk::for_each(Visit&& visit) const {
  if (!tiled_) {
    for (int y = r_.y0; y < r_.y1; ++y) {
      for (int x = r_.x0; x < r_.x1; ++x) visit(x, y);
    }
    return;
  }
  for (const uint32_t t : tiles_) {
    const int tx = static_cast<int>(t & 0xffffu) * tile_, ty = static_cast<int>(t >> 16) * tile_;
    const bool whole = tx >= r_.x0 && ty >= r_.y0 && tx + tile_ <= r_.x1 && ty + tile_ <= r_.y1;
    for (const uint16_t q : quads_) {
      const int x = tx + 2 * (q & 0xff), y = ty + 2 * (q >> 8);
      if (whole) {
        visit(x, y);
        visit(x + 1, y);
        visit(x, y + 1);
        visit(x + 1, y + 1);
        continue;
      }
      // A tile on r's border: its quads (or lanes of them) outside r are skipped.
      if (x + 1 < r_.x0 || y + 1 < r_.y0 || x >= r_.x1 || y >= r_.y1) continue;
      for (int lane = 0; lane < 4; ++lane) {
        const int px = x + (lane & 1), py = y + (lane >> 1);
        if (px >= r_.x0 && py >= r_.y0 && px < r_.x1 && py < r_.y1) visit(px, py);
      }
    }
  }
}

}  // namespace texsim
