#pragma once
// Shared L2 between the texture units' L1s and the next level
// (docs/timing-model.md#memory-hierarchy): set-associative, true LRU, read-only, split into
// address-interleaved slices, each with its own ports and miss status holding registers (MSHRs).
//
// A request for an L1 line at `now` goes to the slice of the L2 line holding it
// (slice = L2 line number mod slices) and is accepted at the first cycle >= now with a free
// port of that slice, in call order (a later acceptance is a bank conflict, counted with its
// cycles). Then, with accept + hit_latency the end of the tag check:
//   hit                          ready at accept + hit_latency
//   hit on a line still filling  merged with its MSHR: ready at max(accept + hit_latency, fill)
//   miss                         needs a free MSHR of the slice at the end of the tag check (an
//                                MSHR is held from its request until its fill arrives; if none
//                                is free it waits for the earliest, counted as MSHR stall
//                                cycles), sends the L2 line's read to the next level then and
//                                is ready when the fill arrives (forwarded as it arrives).
// The line is allocated (LRU victim) when its miss is sent. next_line prefetch: a demand miss
// also reads L2 line + 1 if no way holds it and its slice has an MSHR free at that cycle; the
// prefetch takes no port. A demand access to a prefetched line counts it useful once.
//
// Limits: no write-backs (read-only, like the L1), no coherence, no bank conflicts inside a
// slice beyond its ports, an evicted line that is still filling is simply dropped from the
// tags (its MSHR stays held until its fill arrives).
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/line_memory.h"

namespace texsim {

class L2Cache : public LineMemory {
 public:
  enum class Prefetch { None, NextLine };
  struct Config {
    uint32_t size_bytes = 512 * 1024;  // all slices together
    uint32_t ways = 16;
    uint32_t line_bytes = 128;  // a multiple of the L1 line it serves
    uint32_t slices = 4;        // power of two, interleaved by L2 line
    uint32_t ports = 1;         // requests one slice accepts per cycle
    uint32_t hit_latency = 20;  // cycles: tag check and data read
    uint32_t mshrs = 16;        // per slice
    Prefetch prefetch = Prefetch::None;
    static Config from_toml(const ConfigReader& r);  // validates: powers of two, sizes fit
    // Empty when L1 lines of `l1_line_bytes` can be served, else what is wrong, naming the key.
    std::string line_error(uint32_t l1_line_bytes) const;
  };
  struct Stats {
    uint64_t accesses = 0;  // = hits + misses + mshr_merges
    uint64_t hits = 0;
    uint64_t misses = 0;
    uint64_t mshr_merges = 0;  // hits on a line whose fill was still in flight
    uint64_t mshr_stalls = 0;  // misses that waited for an MSHR
    uint64_t mshr_stall_cycles = 0;
    uint64_t bank_conflicts = 0;  // requests accepted after their cycle (no free port)
    uint64_t bank_conflict_cycles = 0;
    uint64_t prefetches_issued = 0;
    uint64_t prefetches_useful = 0;  // prefetched lines a demand access used
    uint64_t fill_bytes = 0;         // bytes read from the next level
    std::vector<uint64_t> slice_accesses;
  };

  // `next` must outlive the cache. Throws std::invalid_argument on a bad geometry.
  L2Cache(const Config& c, LineMemory& next);
  // Throws std::invalid_argument (naming the key) unless L1 lines of `l1_line_bytes` fit.
  void validate(uint32_t l1_line_bytes) const;
  uint64_t read_line(uint64_t now, uint64_t addr, uint32_t bytes, int unit) override;
  uint32_t slice_of(uint64_t addr) const {
    return static_cast<uint32_t>((addr >> line_shift_) & (cfg_.slices - 1));
  }
  uint32_t sets_per_slice() const { return sets_; }

  const Config& config() const { return cfg_; }
  const Stats& stats() const { return stats_; }

  // Item: one line request (one tag look-up and data read).
  static OpCounts ops_per_item() {
    OpCounts o;
    o.mem = 1;
    return o;
  }
  // A hit: hit_latency cycles; slices x ports look-ups per cycle; tags and data are SRAM, no
  // arithmetic area.
  TimingSpec timing(const TechTable& tech) const;
  static std::string name() { return "l2"; }
  static std::string arithmetic() { return "tag compare"; }

 private:
  struct Way {
    uint64_t tag;         // L2 line number; kInvalid = empty
    uint64_t stamp;       // last use, for LRU (0 = never used)
    uint64_t fill_ready;  // cycle its fill arrives (in flight while later than a request)
    bool prefetched;      // filled by a prefetch and not yet used by a demand access
  };
  struct Slice {
    uint64_t port_cycle = 0;             // the latest cycle a request was accepted
    uint32_t port_used = 0;              // requests accepted at port_cycle
    std::vector<uint64_t> mshr_release;  // per MSHR: the cycle its fill arrives
  };
  uint64_t accept(Slice& s, uint64_t now);
  // The MSHR free soonest at or after `t`; sets `issue` to the cycle it is free.
  size_t take_mshr(Slice& s, uint64_t t, uint64_t& issue);
  Way* find(uint64_t line);
  Way* victim(uint64_t line);
  void prefetch(uint64_t line, uint64_t issue, int unit);

  Config cfg_;
  LineMemory* next_;
  uint32_t sets_ = 1;
  uint32_t line_shift_ = 7;
  uint32_t slice_bits_ = 0;
  uint64_t clock_ = 0;
  std::vector<Way> ways_;  // slices * sets * ways, one set's ways side by side
  std::vector<Slice> slices_;
  Stats stats_;
};

}  // namespace texsim
