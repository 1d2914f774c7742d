#include "blocks/texture/memory/texture_cache.h"

#include <bit>
#include <limits>
#include <stdexcept>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<TextureCache>);

namespace {
constexpr uint64_t kInvalid = std::numeric_limits<uint64_t>::max();
}

TextureCache::Config TextureCache::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown(
      {"size_bytes", "ways", "line_bytes", "hit_latency", "texels_per_cycle", "miss_queue"});
  Config c;
  c.size_bytes = static_cast<uint32_t>(r.get_int("size_bytes", c.size_bytes, 64, 1 << 26));
  c.ways = static_cast<uint32_t>(r.get_int("ways", c.ways, 1, 64));
  c.line_bytes = static_cast<uint32_t>(r.get_int("line_bytes", c.line_bytes, 16, 4096));
  c.hit_latency = static_cast<uint32_t>(r.get_int("hit_latency", c.hit_latency, 1, 1000));
  c.texels_per_cycle =
      static_cast<uint32_t>(r.get_int("texels_per_cycle", c.texels_per_cycle, 1, 64));
  c.miss_queue = static_cast<uint32_t>(r.get_int("miss_queue", c.miss_queue, 1, 4096));
  if (!std::has_single_bit(c.line_bytes)) r.fail("line_bytes", "must be a power of two");
  if (c.size_bytes % (c.ways * c.line_bytes) != 0 ||
      !std::has_single_bit(c.size_bytes / (c.ways * c.line_bytes))) {
    r.fail("size_bytes", "must be ways x line_bytes x (a power of two) sets");
  }
  return c;
}

TextureCache::TextureCache() : TextureCache(Config{}) {}

TextureCache::TextureCache(const Config& c) : cfg_(c) {
  if (!std::has_single_bit(c.line_bytes) || c.ways == 0 || c.size_bytes < c.ways * c.line_bytes) {
    throw std::invalid_argument("texture cache: bad geometry");
  }
  sets_ = c.size_bytes / (c.ways * c.line_bytes);
  if (!std::has_single_bit(sets_)) throw std::invalid_argument("texture cache: sets must be 2^n");
  line_shift_ = static_cast<uint32_t>(std::countr_zero(c.line_bytes));
  ways_.assign(static_cast<size_t>(sets_) * c.ways, Way{kInvalid, 0});
  mru_.assign(sets_, Mru{kInvalid, 0, 0});
}

bool TextureCache::access_slow(uint64_t line) {
  // A line is in at most one way, and not in the most recent one (touch_mru looked there).
  const size_t s = static_cast<size_t>(line & (sets_ - 1));
  Way* const set = ways_.data() + s * cfg_.ways;
  for (uint32_t w = 0; w < cfg_.ways; ++w) {
    if (set[w].tag == line) {
      ++stats_.hits;
      make_mru(s, w);
      return true;
    }
  }
  // Every stamp in the set current before the LRU way is chosen.
  Mru& m = mru_[s];
  set[m.way].stamp = m.stamp;
  const uint32_t victim = fill(set, line);
  m = {line, clock_, victim};
  return false;
}

uint32_t TextureCache::fill(Way* set, uint64_t line) {
  // The least recently used way (the first of equals; empty ways have stamp 0).
  uint32_t victim = 0;
  for (uint32_t w = 1; w < cfg_.ways; ++w) {
    if (set[w].stamp < set[victim].stamp) victim = w;
  }
  set[victim].tag = line;
  set[victim].stamp = clock_;
  ++stats_.misses;
  stats_.fill_bytes += cfg_.line_bytes;
  return victim;
}

TimingSpec TextureCache::timing(const TechTable& tech) const {
  // Tags and data are SRAM, not operators: a hit's latency and no arithmetic area.
  return derive_timing(tech, OpCounts{}, static_cast<double>(cfg_.hit_latency), Datapath::Spatial);
}

}  // namespace texsim
