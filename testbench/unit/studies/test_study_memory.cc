// study memory --quick: its rows, and the relations between them that follow from how the
// L1s work whatever the scene (true LRU, one tag look-up per distinct line of a fragment).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/app/study_memory.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

const MemoryStudyRow* find(const std::vector<MemoryStudyRow>& rows, const std::string& sweep,
                           int units, uint32_t l1_bytes, uint32_t ways,
                           const std::string& behind = "flat DRAM", const std::string& other = "") {
  for (const MemoryStudyRow& r : rows) {
    if (r.sweep == sweep && r.units == units && r.l1_bytes == l1_bytes && r.l1_ways == ways &&
        r.behind == behind && (other.empty() || r.other == other))
      return &r;
  }
  return nullptr;
}

class StudyMemoryQuick : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("study_memory");
    std::ostringstream log;
    StudyMemoryOptions opt;
    opt.quick = true;
    opt.threads = 2;
    rows_ = new std::vector<MemoryStudyRow>;
    ASSERT_EQ(run_study_memory(dir_->file("out"), log, opt, rows_), 0);
  }
  static void TearDownTestSuite() {
    delete rows_;
    delete dir_;
  }
  static TempDir* dir_;
  static std::vector<MemoryStudyRow>* rows_;
};
TempDir* StudyMemoryQuick::dir_ = nullptr;
std::vector<MemoryStudyRow>* StudyMemoryQuick::rows_ = nullptr;

TEST_F(StudyMemoryQuick, EveryPlannedRowRanAndTheOutputsExist) {
  const std::vector<MemoryStudyRow>& rows = *rows_;
  StudyMemoryOptions opt;
  opt.quick = true;
  ASSERT_EQ(rows.size(), memory_study_plan(opt).size());
  ASSERT_EQ(rows.size(), 9u);
  for (const MemoryStudyRow& r : rows) {
    EXPECT_EQ(r.scene, "default");
    // Every row renders the same scene: the same fragments whatever the memory.
    EXPECT_EQ(r.fragments, rows[0].fragments) << r.sweep << " " << r.units;
    EXPECT_GT(r.fragments, 10000u);
    EXPECT_GT(r.cycles, 0u);
    EXPECT_EQ(r.l1_hits + r.l1_misses, r.l1_accesses);
    EXPECT_GT(r.energy_pj, 0);
    // The scheduler delivered every request to the shared levels in cycle order.
    EXPECT_EQ(r.late_items, 0u) << r.sweep << " " << r.units << " " << r.behind;
  }
  for (const char* f :
       {"memory.csv", "memory.md", "memory_cycles_units.png", "memory_dram_units.png"})
    EXPECT_TRUE(std::filesystem::exists(dir_->file(std::string("out/") + f))) << f;
  EXPECT_FALSE(std::filesystem::exists(dir_->file("out/.runs")));
  std::ifstream in(dir_->file("out/memory.csv"));
  std::string line;
  size_t lines = 0;
  while (std::getline(in, line)) ++lines;
  EXPECT_EQ(lines, rows.size() + 1);
}

// Rows run on the pool, each in its own slot: one thread writes the same table as two.
TEST_F(StudyMemoryQuick, ThreadCountDoesNotChangeTheTable) {
  std::ostringstream log;
  StudyMemoryOptions opt;
  opt.quick = true;
  opt.threads = 1;
  ASSERT_EQ(run_study_memory(dir_->file("one"), log, opt), 0);
  auto read = [](const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string two = read(dir_->file("out/memory.csv"));
  EXPECT_FALSE(two.empty());
  EXPECT_EQ(read(dir_->file("one/memory.csv")), two);
  EXPECT_EQ(read(dir_->file("one/memory.md")), read(dir_->file("out/memory.md")));
}

// One unit, same line size: every L1 sees the same look-ups in the same order. A cache with
// more sets and the same ways splits each set's stream by a line-address bit, so a line's LRU
// stack distance within its set can only shrink; a cache with the same sets and more ways
// keeps every line the smaller one keeps (LRU's inclusion). Either way, no look-up that hits
// in the smaller cache misses in the larger.
TEST_F(StudyMemoryQuick, LargerLruL1NeverHitsLess) {
  const std::vector<MemoryStudyRow>& rows = *rows_;
  const MemoryStudyRow* a = find(rows, "l1", 1, 1024, 1);   // 16 sets
  const MemoryStudyRow* b = find(rows, "l1", 1, 4096, 1);   // 64 sets
  const MemoryStudyRow* c = find(rows, "l1", 1, 4096, 4);   // 16 sets
  const MemoryStudyRow* d = find(rows, "l1", 1, 16384, 4);  // 64 sets
  ASSERT_TRUE(a && b && c && d);
  for (const MemoryStudyRow* r : {b, c, d}) EXPECT_EQ(r->l1_accesses, a->l1_accesses);
  EXPECT_GE(b->l1_hits, a->l1_hits);  // more sets, 1 way
  EXPECT_GE(d->l1_hits, c->l1_hits);  // more sets, 4 ways
  EXPECT_GE(c->l1_hits, a->l1_hits);  // 16 sets, more ways
  EXPECT_GE(d->l1_hits, b->l1_hits);  // 64 sets, more ways
  // The study would be pointless if the sizes made no difference.
  EXPECT_GT(d->l1_hit_rate, a->l1_hit_rate + 0.1);
}

// With an L1 larger than every texture together only a line's first look-up misses. Split over
// units, every unit misses on its own first look-up of each line it reads, so the units' total
// is at least the one unit's (the lines shared between units' tiles are read more than once).
// The first-touch misses also bound every other L1 of the same line size from below.
TEST_F(StudyMemoryQuick, UnitsNeverMissLessThanOneUnitOnFirstTouch) {
  const std::vector<MemoryStudyRow>& rows = *rows_;
  const MemoryStudyRow* one = find(rows, "units", 1, 8u << 20, 4);
  const MemoryStudyRow* four = find(rows, "units", 4, 8u << 20, 4);
  ASSERT_TRUE(one && four);
  EXPECT_GE(four->l1_misses, one->l1_misses);
  EXPECT_EQ(one->dram_bytes, one->l1_misses * 64);
  for (const MemoryStudyRow& r : rows) {
    if (r.units == 1 && r.l1_line == 64 && r.order == "rows") {
      EXPECT_GE(r.l1_misses, one->l1_misses) << r.l1_bytes << " " << r.l1_ways;
    }
  }
  // Behind an L2 (no prefetch) the DRAM reads whole L2 lines (128 B), at most one per L1 miss.
  const MemoryStudyRow* l2 = find(rows, "units", 4, 16384, 4, "L2 256K x4 + banked gddr6");
  ASSERT_TRUE(l2);
  EXPECT_TRUE(l2->has_l2 && l2->banked);
  EXPECT_GE(l2->l2_hit_rate, 0);
  EXPECT_LE(l2->l2_hit_rate, 1);
  EXPECT_GE(l2->row_hit_rate, 0);
  EXPECT_LE(l2->row_hit_rate, 1);
  EXPECT_GT(l2->dram_bytes, 0u);
  EXPECT_EQ(l2->dram_bytes % 128, 0u);
  EXPECT_LE(l2->dram_bytes, l2->l1_misses * 128);
}

// Quad merging: the quad's later lanes reuse its earlier lanes' look-ups, so fewer look-ups,
// the same fragments.
TEST_F(StudyMemoryQuick, QuadMergingSavesLookUps) {
  const std::vector<MemoryStudyRow>& rows = *rows_;
  const MemoryStudyRow* off =
      find(rows, "quad_merge", 1, 16384, 4, "flat DRAM", "quad_merge=false");
  const MemoryStudyRow* on = find(rows, "quad_merge", 1, 16384, 4, "flat DRAM", "quad_merge=true");
  ASSERT_TRUE(off && on);
  EXPECT_EQ(off->quad_merged, 0u);
  EXPECT_GT(on->quad_merged, 0u);
  EXPECT_EQ(on->l1_accesses + on->quad_merged, off->l1_accesses);
}

}  // namespace
}  // namespace texsim
