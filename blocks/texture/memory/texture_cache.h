#pragma once
// Texture cache: set-associative, LRU replacement, read-only (texels are never written back).
// Cycle costs are charged by the pipeline's cache stage (docs/timing-model.md#memory).
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class TextureCache {
 public:
  struct Config {
    uint32_t size_bytes = 16 * 1024;
    uint32_t ways = 4;
    uint32_t line_bytes = 64;
    uint32_t hit_latency = 4;       // tag check + data read, cycles
    uint32_t texels_per_cycle = 4;  // tag look-ups per cycle (one bilinear quad)
    uint32_t miss_queue = 32;       // fragments in flight (latency-hiding FIFO depth)
    static Config from_toml(const ConfigReader& r);  // validates: powers of two, sizes fit
  };
  struct Stats {
    uint64_t accesses = 0;  // line look-ups (one per distinct line per fragment)
    uint64_t hits = 0;
    uint64_t misses = 0;
    uint64_t texel_reads = 0;  // texels delivered to the filter
    uint64_t fill_bytes = 0;   // bytes brought in from DRAM
  };

  TextureCache();
  explicit TextureCache(const Config& c);
  // Looks up the line holding byte address `addr`; on a miss the LRU way is refilled.
  // Returns true on a hit.
  bool access(uint64_t addr) { return access_line(line_of(addr)); }
  // The same for a line number (addr >> log2(line_bytes)). Inline: a hit is the common case
  // and costs a few compares.
  bool access_line(uint64_t line) {
    ++stats_.accesses;
    ++clock_;
    if (touch_mru(line, clock_)) {
      ++stats_.hits;
      return true;
    }
    return access_slow(line);
  }
  // A run of look-ups made together (the batched datapath): access_line() for each line in
  // order, the counters added once at the end. Lines that hit their set's most recent way
  // cost a compare and a store; the others take access_line()'s search and fill.
  class Run {
   public:
    explicit Run(TextureCache& c) : c_(c), start_(c.clock_), clock_(c.clock_) {}
    Run(const Run&) = delete;
    Run& operator=(const Run&) = delete;
    ~Run() {
      c_.stats_.accesses += clock_ - start_;
      c_.stats_.hits += hits_;
      c_.clock_ = clock_;
    }
    [[gnu::always_inline]] bool access(uint64_t line) {
      ++clock_;
      if (c_.touch_mru(line, clock_)) {
        ++hits_;
        return true;
      }
      // The slow way (which counts its hits and misses) sees the clock access_line() would.
      c_.clock_ = clock_;
      return c_.access_slow(line);
    }

   private:
    TextureCache& c_;
    const uint64_t start_;
    uint64_t clock_;
    uint64_t hits_ = 0;
  };
  // Where the line is cached: its way's index in the cache (set · ways + way), or -1. No
  // look-up is made: nothing changes, nothing is counted.
  int64_t find(uint64_t line) const {
    const size_t set_index = static_cast<size_t>(line & (sets_ - 1));
    const size_t first = set_index * cfg_.ways;
    const Mru& m = mru_[set_index];  // the likely way first, as access_line()
    if (m.tag == line) return static_cast<int64_t>(first + m.way);
    for (uint32_t w = 0; w < cfg_.ways; ++w) {
      if (ways_[first + w].tag == line) return static_cast<int64_t>(first + w);
    }
    return -1;
  }
  bool contains(uint64_t line) const { return find(line) >= 0; }
  // The look-up of a line find() placed at `way`: the hit access_line() would make (the same
  // stamp, counters and most recent way), without searching the set again.
  void hit_at(int64_t way) {
    ++stats_.accesses;
    ++clock_;
    ++stats_.hits;
    const auto w = static_cast<size_t>(way);
    make_mru(w / cfg_.ways, static_cast<uint32_t>(w % cfg_.ways));
  }
  uint32_t line_shift() const { return line_shift_; }
  uint64_t line_of(uint64_t addr) const { return addr >> line_shift_; }
  const Config& config() const { return cfg_; }
  const Stats& stats() const { return stats_; }
  Stats& stats() { return stats_; }
  uint32_t sets() const { return sets_; }
  void count_texels(uint64_t n) { stats_.texel_reads += n; }

  // Item: one texel read through the cache (the tag look-up is charged in cycles, not ops).
  static OpCounts ops_per_item() {
    OpCounts o;
    o.mem = 1;
    return o;
  }
  // A hit: hit_latency cycles, texels_per_cycle look-ups per cycle; no arithmetic area.
  TimingSpec timing(const TechTable& tech) const;
  static std::string name() { return "cache"; }
  static std::string arithmetic() { return "tag compare"; }

 private:
  struct Way;
  // A hit on the set's most recent way: its stamp now `clock`.
  [[gnu::always_inline]] bool touch_mru(uint64_t line, uint64_t clock) {
    Mru& m = mru_[static_cast<size_t>(line & (sets_ - 1))];
    if (m.tag != line) return false;
    m.stamp = clock;
    return true;
  }
  // The rest of a look-up that missed the most recent way: the set searched, the LRU way
  // refilled on a miss (counted), and the way that served made the most recent.
  bool access_slow(uint64_t line);
  // Way w of set s becomes the set's most recent, stamped now; the way it replaces keeps its
  // stamp in the set.
  void make_mru(size_t s, uint32_t w) {
    Mru& m = mru_[s];
    Way* const set = ways_.data() + s * cfg_.ways;
    set[m.way].stamp = m.stamp;
    m = {set[w].tag, clock_, w};
  }
  uint32_t fill(Way* set, uint64_t line);  // miss: refill the LRU way of `set`; returns it

  Config cfg_;
  uint32_t sets_ = 1;
  uint32_t line_shift_ = 6;
  uint64_t clock_ = 0;
  // One set's ways side by side: a look-up reads one contiguous block.
  struct Way {
    uint64_t tag;    // line number; kInvalid = empty
    uint64_t stamp;  // last use, for LRU (0 = never used); not kept for the set's most recent
  };
  // Per set, the way that hit or was filled last, with its tag and stamp: a hit there (the
  // common case: neighbouring fragments read the same lines, each in its own set) reads and
  // writes this record only. Its way's stamp in ways_ is written back when another way
  // becomes the most recent, before any replacement reads the set's stamps.
  struct Mru {
    uint64_t tag;
    uint64_t stamp;
    uint32_t way;
  };
  std::vector<Way> ways_;  // sets_ * ways
  std::vector<Mru> mru_;   // sets_
  Stats stats_;
};

}  // namespace texsim
