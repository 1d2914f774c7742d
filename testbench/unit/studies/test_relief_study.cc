// study relief on a short run: procedural maps only, 32 × 32, two elevations. Checks the
// orderings the study's tables rest on (more layers: less error; a tight cap: capped rays;
// the refined map: fewer iterations; visibility: more reads, less error than plain EWA).
#include <gtest/gtest.h>

#include <string>

#include "pipeline/studies/study_relief.h"

namespace texsim {
namespace {

ReliefStudyOptions short_run() {
  ReliefStudyOptions o;
  o.size = 32;
  o.fragments = 80;
  o.filter_fragments = 40;
  o.use_files = false;
  o.elevations_deg = {20, 50};
  return o;
}

const ReliefStudyRow& row(const ReliefStudy& st, const std::string& map, double elev,
                          const std::string& method) {
  for (const auto& r : st.rows) {
    if (r.map == map && r.elevation_deg == elev && r.method == method) return r;
  }
  ADD_FAILURE() << "no row " << map << " " << elev << " " << method;
  return st.rows.front();
}

TEST(StudyRelief, ShortRunOrdersMethodsByCostAndError) {
  const ReliefStudy st = measure_relief_study(short_run());
  ASSERT_EQ(st.filter.size(), 4u);  // smooth and sharp maps, two elevations
  ASSERT_EQ(st.rows.size(), 4u * 16u);
  for (const std::string map : {"smooth", "sharp"}) {
    for (const double e : {20.0, 50.0}) {
      const auto& off = row(st, map, e, "offset parallax");
      const auto& rel = row(st, map, e, "relief 8..32 layers + 5 halvings");
      const auto& fine = row(st, map, e, "relief 32..128 layers + 5 halvings");
      EXPECT_EQ(off.fetches, 4);
      EXPECT_GT(rel.cycles, off.cycles);
      EXPECT_GT(fine.fetches, rel.fetches);
      EXPECT_LT(rel.err_texels, off.err_texels) << map << " " << e;
      EXPECT_LT(fine.err_texels, 0.5) << map << " " << e;
      const auto& c4 = row(st, map, e, "sphere, classic map, cap 4");
      const auto& c32 = row(st, map, e, "sphere, classic map, cap 32");
      EXPECT_LE(c4.iterations, 4);
      EXPECT_EQ(c32.capped, 0);
      EXPECT_GE(c32.iterations, c4.iterations);
    }
  }
  // The refined map (45° cone) takes fewer steps than the classic one on the sharp map.
  const auto& c = row(st, "sharp", 50, "sphere, classic map, cap 32");
  const auto& r = row(st, "sharp", 50, "sphere, refined 45° map, cap 32");
  EXPECT_LT(r.iterations, c.iterations);
  EXPECT_LT(r.cycles, c.cycles);
  EXPECT_GT(row(st, "sharp", 20, "sphere, classic map, cap 4").capped, 0);
  for (const auto& f : st.filter) {
    EXPECT_GT(f.reads_rule, f.texels);
    EXPECT_GT(f.cycles_rule, f.cycles_plain);
    EXPECT_LE(f.err_exact, f.err_plain) << f.map << " " << f.elevation_deg;
    // Where the relief hides texels, leaving them out brings the colour nearer the reference.
    if (f.map == "sharp") {
      EXPECT_LT(f.err_exact, f.err_plain) << f.elevation_deg;
    }
  }
}

}  // namespace
}  // namespace texsim
