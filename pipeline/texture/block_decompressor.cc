#include "pipeline/texture/block_decompressor.h"

#include <algorithm>
#include <bit>
#include <vector>

namespace texsim {

uint64_t BlockDecompressor::read_line(uint64_t now, uint64_t addr, uint32_t bytes, int unit) {
  const Texture* t = textures_->holding(addr);
  if (!t || !t->compressed()) {
    ++stats_.passed;
    return next_->read_line(now, addr, bytes, unit);
  }
  // The blocks the line's texels come from, and the compressed lines holding them (lines of
  // the request's size), each in order of first use.
  const auto bpt = static_cast<uint64_t>(t->bytes_per_texel());
  const uint32_t shift = static_cast<uint32_t>(std::countr_zero(bytes));
  std::vector<uint64_t> blocks, lines;
  for (uint64_t a = addr; a < addr + bytes; a += bpt) {
    int level = 0, x = 0, y = 0;
    if (!t->texel_at(a, level, x, y)) continue;  // padding of a tiled or Morton level
    const uint64_t b = t->block_address(level, x, y);
    if (std::find(blocks.begin(), blocks.end(), b) != blocks.end()) continue;
    blocks.push_back(b);
    if (std::find(lines.begin(), lines.end(), b >> shift) == lines.end())
      lines.push_back(b >> shift);
  }
  ++stats_.lines;
  if (blocks.empty()) return next_->read_line(now, addr, bytes, unit);  // all padding
  uint64_t ready = now + 1;
  for (const uint64_t l : lines)
    ready = std::max(ready, next_->read_line(now, l << shift, bytes, unit));
  stats_.compressed_reads += lines.size();
  stats_.blocks += blocks.size();
  stats_.blocks_by_format[static_cast<size_t>(t->blocks()->format)] += blocks.size();
  const Timing tm = timing_(t->blocks()->format);
  return ready + tm.latency + static_cast<uint64_t>(tm.ii) * (blocks.size() - 1);
}

}  // namespace texsim
