// Shared L2: directed cases against a next level of fixed latency. Every expected cycle is
// written from the timing rules (l2_cache.h): accept + hit_latency for a hit, the next level's
// answer to a read sent at accept + hit_latency (or when an MSHR frees) for a miss.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/texture/memory/l2_cache.h"

namespace texsim {
namespace {

constexpr uint64_t kHit = 10;    // hit_latency
constexpr uint64_t kNext = 100;  // the next level's latency

// A next level that answers every read kNext cycles after it is sent, and records it.
class FixedLatency : public LineMemory {
 public:
  struct Read {
    uint64_t now, addr;
    uint32_t bytes;
  };
  uint64_t read_line(uint64_t now, uint64_t addr, uint32_t bytes, int /*unit*/) override {
    reads.push_back({now, addr, bytes});
    return now + kNext;
  }
  std::vector<Read> reads;
};

// Two slices of four sets of two 128-byte ways: line = addr >> 7, slice = line bit 0, set =
// line bits 1-2, so lines 8 apart (1024 bytes) share a slice and a set.
L2Cache::Config small() {
  L2Cache::Config c;
  c.slices = 2;
  c.ways = 2;
  c.line_bytes = 128;
  c.size_bytes = 2 * 4 * 2 * 128;
  c.ports = 1;
  c.hit_latency = kHit;
  c.mshrs = 2;
  return c;
}

std::string error_of(const std::string& text) {
  try {
    const toml::table t = parse_toml(text, "t.toml");
    L2Cache::Config::from_toml(ConfigReader(t, "t.toml", "l2"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(L2Cache, MissThenHitLatency) {
  FixedLatency next;
  L2Cache l2(small(), next);
  EXPECT_EQ(l2.sets_per_slice(), 4u);
  EXPECT_EQ(l2.read_line(0, 0, 64, 0), kHit + kNext);  // miss: sent after the tag check
  ASSERT_EQ(next.reads.size(), 1u);
  EXPECT_EQ(next.reads[0].now, kHit);
  EXPECT_EQ(next.reads[0].addr, 0u);
  EXPECT_EQ(next.reads[0].bytes, 128u);  // the whole L2 line
  // The other half of the same L2 line, after the fill: a hit.
  EXPECT_EQ(l2.read_line(500, 64, 64, 0), 500 + kHit);
  EXPECT_EQ(l2.stats().hits, 1u);
  EXPECT_EQ(l2.stats().misses, 1u);
  EXPECT_EQ(l2.stats().fill_bytes, 128u);
  EXPECT_EQ(next.reads.size(), 1u);
}

TEST(L2Cache, LruEviction) {
  FixedLatency next;
  L2Cache l2(small(), next);
  const uint64_t a = 0, b = 1024, c = 2048;  // one slice, one set
  uint64_t t = 0;
  const auto at = [&](uint64_t addr) {
    t += 1000;  // far apart: no fill in flight, no port or MSHR waits
    return l2.read_line(t, addr, 64, 0) - t;
  };
  EXPECT_EQ(at(a), kHit + kNext);
  EXPECT_EQ(at(b), kHit + kNext);
  EXPECT_EQ(at(a), kHit);          // b is now least recently used
  EXPECT_EQ(at(c), kHit + kNext);  // evicts b
  EXPECT_EQ(at(a), kHit);
  EXPECT_EQ(at(b), kHit + kNext);  // b was evicted (and now c is)
  EXPECT_EQ(at(c), kHit + kNext);
  EXPECT_EQ(l2.stats().hits, 2u);
  EXPECT_EQ(l2.stats().misses, 5u);
}

TEST(L2Cache, SlicesInterleaveByLine) {
  FixedLatency next;
  L2Cache l2(small(), next);
  EXPECT_EQ(l2.slice_of(0), 0u);
  EXPECT_EQ(l2.slice_of(64), 0u);
  EXPECT_EQ(l2.slice_of(128), 1u);
  EXPECT_EQ(l2.slice_of(256), 0u);
  // Two slices accept one request each in the same cycle: no conflict.
  EXPECT_EQ(l2.read_line(0, 0, 64, 0), kHit + kNext);
  EXPECT_EQ(l2.read_line(0, 128, 64, 1), kHit + kNext);
  EXPECT_EQ(l2.read_line(1000, 384, 64, 1), 1000 + kHit + kNext);
  EXPECT_EQ(l2.stats().slice_accesses, (std::vector<uint64_t>{1, 2}));
  EXPECT_EQ(l2.stats().bank_conflicts, 0u);
}

TEST(L2Cache, PortConflictWaits) {
  FixedLatency next;
  L2Cache::Config c = small();
  c.mshrs = 4;  // three misses in flight in one slice, no MSHR stall
  L2Cache l2(c, next);
  EXPECT_EQ(l2.read_line(0, 0, 64, 0), kHit + kNext);
  // Slice 0 again in cycle 0: one port, so accepted at 1.
  EXPECT_EQ(l2.read_line(0, 256, 64, 1), 1 + kHit + kNext);
  EXPECT_EQ(l2.read_line(0, 512, 64, 1), 2 + kHit + kNext);
  EXPECT_EQ(l2.stats().bank_conflicts, 2u);
  EXPECT_EQ(l2.stats().bank_conflict_cycles, 1u + 2u);
  // With two ports the first two go in cycle 0.
  FixedLatency next2;
  c.ports = 2;
  L2Cache two(c, next2);
  EXPECT_EQ(two.read_line(0, 0, 64, 0), kHit + kNext);
  EXPECT_EQ(two.read_line(0, 256, 64, 0), kHit + kNext);
  EXPECT_EQ(two.read_line(0, 512, 64, 0), 1 + kHit + kNext);
  EXPECT_EQ(two.stats().bank_conflicts, 1u);
}

TEST(L2Cache, HitOnAFillingLineMergesWithItsMshr) {
  FixedLatency next;
  L2Cache l2(small(), next);
  const uint64_t fill = kHit + kNext;
  EXPECT_EQ(l2.read_line(0, 0, 64, 0), fill);
  EXPECT_EQ(l2.read_line(50, 64, 64, 1), fill);  // waits for the fill, sends nothing
  // Accepted before the fill, but its own tag check ends later.
  EXPECT_EQ(l2.read_line(105, 0, 64, 1), 105 + kHit);
  EXPECT_EQ(next.reads.size(), 1u);
  EXPECT_EQ(l2.stats().mshr_merges, 2u);
  EXPECT_EQ(l2.stats().hits, 0u);
  EXPECT_EQ(l2.stats().misses, 1u);
  EXPECT_EQ(l2.stats().accesses, 3u);
}

TEST(L2Cache, MshrExhaustionStalls) {
  FixedLatency next;
  L2Cache::Config c = small();
  c.ports = 4;  // all three accepted in cycle 0
  L2Cache l2(c, next);
  EXPECT_EQ(l2.read_line(0, 0, 64, 0), kHit + kNext);
  EXPECT_EQ(l2.read_line(0, 256, 64, 0), kHit + kNext);
  // Both MSHRs of slice 0 are held until kHit + kNext: the third miss is sent then.
  const uint64_t free_at = kHit + kNext;
  EXPECT_EQ(l2.read_line(0, 512, 64, 0), free_at + kNext);
  ASSERT_EQ(next.reads.size(), 3u);
  EXPECT_EQ(next.reads[2].now, free_at);
  EXPECT_EQ(l2.stats().mshr_stalls, 1u);
  EXPECT_EQ(l2.stats().mshr_stall_cycles, free_at - kHit);
  // Slice 1 has its own MSHRs.
  EXPECT_EQ(l2.read_line(0, 128, 64, 0), kHit + kNext);
}

TEST(L2Cache, NextLinePrefetchIsUseful) {
  FixedLatency next;
  L2Cache::Config c = small();
  c.prefetch = L2Cache::Prefetch::NextLine;
  L2Cache l2(c, next);
  EXPECT_EQ(l2.read_line(0, 0, 64, 0), kHit + kNext);
  ASSERT_EQ(next.reads.size(), 2u);
  EXPECT_EQ(next.reads[1].now, kHit);  // line 1 with the demand miss
  EXPECT_EQ(next.reads[1].addr, 128u);
  EXPECT_EQ(l2.stats().prefetches_issued, 1u);
  EXPECT_EQ(l2.stats().fill_bytes, 256u);
  EXPECT_EQ(l2.read_line(500, 128, 64, 0), 500 + kHit);  // a hit thanks to the prefetch
  EXPECT_EQ(l2.read_line(600, 192, 64, 0), 600 + kHit);  // the same line: useful only once
  EXPECT_EQ(l2.stats().prefetches_useful, 1u);
  EXPECT_EQ(l2.stats().hits, 2u);
  // Line 2 misses; line 3 is prefetched; line 1 (present) is not read again.
  l2.read_line(700, 256, 64, 0);
  EXPECT_EQ(l2.stats().prefetches_issued, 2u);
  EXPECT_EQ(next.reads.back().addr, 384u);
  EXPECT_EQ(next.reads.size(), 4u);
}

TEST(L2Cache, PrefetchNeedsAFreeMshr) {
  FixedLatency next;
  L2Cache::Config c = small();
  c.slices = 1;
  c.size_bytes = 4 * 2 * 128;
  c.mshrs = 1;
  c.prefetch = L2Cache::Prefetch::NextLine;
  L2Cache l2(c, next);
  l2.read_line(0, 0, 64, 0);  // the demand miss holds the only MSHR
  EXPECT_EQ(l2.stats().prefetches_issued, 0u);
  EXPECT_EQ(next.reads.size(), 1u);
  EXPECT_EQ(l2.read_line(1000, 128, 64, 0), 1000 + kHit + kNext);  // line 1 was not fetched
}

TEST(L2Cache, ConfigErrorsNameTheKey) {
  auto e = error_of("slices = 3\n");
  EXPECT_NE(e.find("t.toml:1:10"), std::string::npos) << e;
  EXPECT_NE(e.find("l2.slices: must be a power of two"), std::string::npos) << e;
  e = error_of("line_bytes = 96\n");
  EXPECT_NE(e.find("l2.line_bytes: must be a power of two"), std::string::npos) << e;
  e = error_of("size_bytes = 3000\n");
  EXPECT_NE(e.find("l2.size_bytes: must be slices x ways x line_bytes"), std::string::npos) << e;
  e = error_of("mshrs = 0\n");
  EXPECT_NE(e.find("l2.mshrs: value 0 out of range [1, 4096]"), std::string::npos) << e;
  e = error_of("ways = 0\n");
  EXPECT_NE(e.find("l2.ways: value 0 out of range"), std::string::npos) << e;
  e = error_of("prefetch = \"stride\"\n");
  EXPECT_NE(e.find("l2.prefetch: unknown value 'stride'"), std::string::npos) << e;
  e = error_of("hit_latency = 0\n");
  EXPECT_NE(e.find("l2.hit_latency: value 0 out of range [1, 1000]"), std::string::npos) << e;
  e = error_of("size = 4096\n");
  EXPECT_NE(e.find("l2: unknown key 'size'"), std::string::npos) << e;
  EXPECT_EQ(error_of("size_bytes = 8192\nslices = 2\nways = 4\nline_bytes = 256\n"), "(no error)");
}

TEST(L2Cache, L1LineMustFitTheL2Line) {
  FixedLatency next;
  L2Cache l2(small(), next);
  EXPECT_NO_THROW(l2.validate(64));
  EXPECT_NO_THROW(l2.validate(128));
  try {
    l2.validate(256);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("l2.line_bytes (128) must be a multiple of the 256-byte"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(l2.read_line(0, 0, 256, 0), std::invalid_argument);
  EXPECT_THROW(l2.read_line(0, 32, 64, 0), std::invalid_argument);
}

}  // namespace
}  // namespace texsim
