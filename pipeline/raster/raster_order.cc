#include "pipeline/raster/raster_order.h"

#include <algorithm>
#include <bit>
#include <utility>

namespace texsim {

namespace {

// Smallest bits with 2^bits >= n (n >= 1).
int bits_for(uint32_t n) { return static_cast<int>(std::bit_width(std::max(n, 1u) - 1)); }

uint32_t morton(uint32_t x, uint32_t y, int bits) {
  uint32_t d = 0;
  for (int b = 0; b < bits; ++b) d |= ((x >> b & 1u) << (2 * b)) | ((y >> b & 1u) << (2 * b + 1));
  return d;
}

// The usual xy-to-distance conversion: at each level the quadrant's place along the curve, then
// the point rotated or reflected into that quadrant's own frame.
uint32_t hilbert(uint32_t x, uint32_t y, int bits) {
  const uint32_t n = 1u << bits;
  uint32_t d = 0;
  for (uint32_t s = n >> 1; s > 0; s >>= 1) {
    const uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    d += s * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = n - 1 - x;
        y = n - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

}  // namespace

uint32_t curve_index(CurveOrder c, uint32_t x, uint32_t y, int bits) {
  switch (c) {
    case CurveOrder::Row:
      return (y << bits) | x;
    case CurveOrder::Morton:
      return morton(x, y, bits);
    case CurveOrder::Hilbert:
      return hilbert(x, y, bits);
  }
  return 0;
}

RasterWalk::RasterWalk(const RasterOrder& o, int width, int height, const PixelRect& r)
    : r_(r), tiled_(o.kind == RasterOrder::Kind::Tiled), tile_(o.tile) {
  if (!tiled_ || r.empty()) return;
  // The quads of one tile, once: a lookup table every tile reuses.
  const auto side = static_cast<uint32_t>(tile_ / 2);
  const int qbits = bits_for(side);
  std::vector<std::pair<uint32_t, uint16_t>> q;
  q.reserve(static_cast<size_t>(side) * side);
  for (uint32_t y = 0; y < side; ++y) {
    for (uint32_t x = 0; x < side; ++x)
      q.emplace_back(curve_index(o.quad_order, x, y, qbits), static_cast<uint16_t>(y << 8 | x));
  }
  std::sort(q.begin(), q.end());
  for (const auto& e : q) quads_.push_back(e.second);
  // The tiles meeting r, sorted by their place on the screen's tile curve.
  const auto tiles_x = static_cast<uint32_t>((width + tile_ - 1) / tile_);
  const auto tiles_y = static_cast<uint32_t>((height + tile_ - 1) / tile_);
  const int tbits = bits_for(std::max(tiles_x, tiles_y));
  const auto tx0 = static_cast<uint32_t>(r.x0 / tile_), ty0 = static_cast<uint32_t>(r.y0 / tile_);
  const auto tx1 = static_cast<uint32_t>((r.x1 + tile_ - 1) / tile_);
  const auto ty1 = static_cast<uint32_t>((r.y1 + tile_ - 1) / tile_);
  std::vector<uint64_t> keyed;
  keyed.reserve(static_cast<size_t>(tx1 - tx0) * (ty1 - ty0));
  for (uint32_t ty = ty0; ty < ty1; ++ty) {
    for (uint32_t tx = tx0; tx < tx1; ++tx) {
      const uint64_t key = curve_index(o.tile_order, tx, ty, tbits);
      keyed.push_back(key << 32 | (ty << 16 | tx));
    }
  }
  if (o.tile_order != CurveOrder::Row) std::sort(keyed.begin(), keyed.end());
  tiles_.reserve(keyed.size());
  for (const uint64_t k : keyed) tiles_.push_back(static_cast<uint32_t>(k));
}

}  // namespace texsim
