// study formats --quick: its rows, and the relations between them that follow from what the
// formats store and where the decoder sits, whatever the scene: fewer bytes per texel never
// help the truth, a compressed texture moves fewer bytes than rgba8 when the caches hold
// blocks, and the decoder's place changes the traffic but never the decoded values.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/app/study_formats.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

const FormatsStudyRow* find(const std::vector<FormatsStudyRow>& rows, const std::string& sweep,
                            const std::string& variant, const std::string& placement = "") {
  for (const FormatsStudyRow& r : rows) {
    if (r.sweep == sweep && r.variant == variant && r.placement == placement) return &r;
  }
  return nullptr;
}

class StudyFormatsQuick : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("study_formats");
    std::ostringstream log;
    StudyFormatsOptions opt;
    opt.quick = true;
    opt.threads = 2;
    rows_ = new std::vector<FormatsStudyRow>;
    ASSERT_EQ(run_study_formats(dir_->file("out"), log, opt, rows_), 0);
  }
  static void TearDownTestSuite() {
    delete rows_;
    delete dir_;
  }
  static TempDir* dir_;
  static std::vector<FormatsStudyRow>* rows_;
};
TempDir* StudyFormatsQuick::dir_ = nullptr;
std::vector<FormatsStudyRow>* StudyFormatsQuick::rows_ = nullptr;

constexpr const char* kBc1 = "bc1_rgb squish range";
constexpr const char* kAstc = "astc_6x6 astcenc fast";

TEST_F(StudyFormatsQuick, EveryPlannedRowRanAndTheOutputsExist) {
  const std::vector<FormatsStudyRow>& rows = *rows_;
  StudyFormatsOptions opt;
  opt.quick = true;
  ASSERT_EQ(rows.size(), formats_study_plan(opt).size());
  ASSERT_EQ(rows.size(), 8u);
  for (const FormatsStudyRow& r : rows) {
    EXPECT_EQ(r.scene, "photo");
    // Every row renders the same scene at the same size: the same fragments whatever the
    // format.
    EXPECT_EQ(r.fragments, rows[0].fragments) << r.variant;
    EXPECT_GT(r.fragments, 1000u);
    EXPECT_GT(r.cycles, 0u);
    EXPECT_GT(r.psnr_db, 10) << r.variant;
    EXPECT_LE(r.l1_hits, r.l1_accesses);
    EXPECT_GT(r.energy_pj, 0);
    EXPECT_EQ(r.has_l2, r.sweep == "placement") << r.variant;
    // Without an L2 the DRAM sees exactly the L1's fills; behind one, the L2's (no prefetch).
    EXPECT_EQ(r.dram_bytes, r.has_l2 ? r.l2_fill_bytes : r.l1_fill_bytes) << r.variant;
    EXPECT_EQ(r.compressed, !r.placement.empty());
    if (r.compressed) {
      EXPECT_GT(r.blocks_decoded, 0u) << r.variant << " " << r.placement;
      EXPECT_GT(r.decoder_ops_per_block, 0);
      EXPECT_GT(r.decoder_area, 0);
      EXPECT_GT(r.decoder_pj, 0);
      EXPECT_GE(r.decoder_latency, 1);
      EXPECT_GE(r.decoder_ii, 1);
    }
  }
  for (const char* f : {"formats.csv", "formats.md", "formats_pareto.png", "formats_placement.png"})
    EXPECT_TRUE(std::filesystem::exists(dir_->file(std::string("out/") + f))) << f;
  EXPECT_FALSE(std::filesystem::exists(dir_->file("out/.runs")));
  std::ifstream in(dir_->file("out/formats.csv"));
  std::string line;
  size_t lines = 0;
  while (std::getline(in, line)) ++lines;
  EXPECT_EQ(lines, rows.size() + 1);
}

// The truth samples the texture as loaded: a format that loses bits, or an encoder that
// approximates blocks, can only add error; and fewer bytes per texel mean fewer bytes moved
// when the caches hold them.
TEST_F(StudyFormatsQuick, SmallerFormatsLoseAccuracyAndMoveFewerBytes) {
  const std::vector<FormatsStudyRow>& rows = *rows_;
  const FormatsStudyRow* rgba8 = find(rows, "variants", "rgba8");
  const FormatsStudyRow* rgb565 = find(rows, "variants", "rgb565");
  const FormatsStudyRow* bc1 = find(rows, "variants", kBc1, "after_l1");
  const FormatsStudyRow* astc = find(rows, "variants", kAstc, "after_l1");
  ASSERT_TRUE(rgba8 && rgb565 && bc1 && astc);
  EXPECT_LT(rgb565->psnr_db, rgba8->psnr_db);
  EXPECT_LT(bc1->psnr_db, rgba8->psnr_db);
  EXPECT_LT(astc->psnr_db, rgba8->psnr_db);
  EXPECT_LT(rgb565->dram_bytes, rgba8->dram_bytes);
  // BC1 stores 0.5 bytes per texel against rgba8's 4: far fewer DRAM bytes with the L1
  // holding blocks.
  EXPECT_LT(2 * bc1->dram_bytes, rgba8->dram_bytes);
  EXPECT_LT(2 * astc->dram_bytes, rgba8->dram_bytes);
  // The ASTC decoder (weights, partitions, colour endpoint modes) is larger than BC1's.
  EXPECT_GT(astc->decoder_area, bc1->decoder_area);
}

// The decoder's place changes the traffic, never the decoded values.
TEST_F(StudyFormatsQuick, PlacementChangesTrafficNotValues) {
  const std::vector<FormatsStudyRow>& rows = *rows_;
  const FormatsStudyRow* rgba8 = find(rows, "placement", "rgba8");
  const FormatsStudyRow* before = find(rows, "placement", kBc1, "before_l1");
  const FormatsStudyRow* after = find(rows, "placement", kBc1, "after_l1");
  const FormatsStudyRow* after_l2 = find(rows, "placement", kBc1, "after_l2");
  const FormatsStudyRow* variant = find(rows, "variants", kBc1, "after_l1");
  ASSERT_TRUE(rgba8 && before && after && after_l2 && variant);
  for (const FormatsStudyRow* r : {before, after, after_l2})
    EXPECT_EQ(r->psnr_db, variant->psnr_db) << r->placement;
  // Before the L1 and after the L2 the L1 holds decoded texels (4 bytes each, laid out as
  // rgba8's): the same look-ups and hits as rgba8. After the L1 it holds blocks and hits more.
  for (const FormatsStudyRow* r : {before, after_l2}) {
    EXPECT_EQ(r->l1_accesses, rgba8->l1_accesses) << r->placement;
    EXPECT_EQ(r->l1_hits, rgba8->l1_hits) << r->placement;
  }
  EXPECT_GT(after->l1_hit_rate, rgba8->l1_hit_rate);
  EXPECT_LT(after->l1_fill_bytes, before->l1_fill_bytes);
  // With the L2 holding blocks DRAM moves fewer bytes than with it holding decoded texels.
  EXPECT_LT(after_l2->dram_bytes, before->dram_bytes);
  EXPECT_LT(after->dram_bytes, rgba8->dram_bytes);
  // After the L1 every fragment decodes its blocks; elsewhere only a missing line does.
  EXPECT_GT(after->blocks_decoded, before->blocks_decoded);
  EXPECT_GT(after->blocks_decoded, after_l2->blocks_decoded);
}

}  // namespace
}  // namespace texsim
