// study relief on a short run: procedural maps only, 32 × 32, two elevations. Checks the
// orderings the study's tables rest on (more layers: less error; a tight cap: capped rays;
// the refined map: fewer iterations; visibility: more reads, less error than plain EWA).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/studies/study_relief.h"
#include "testbench/lib/csv_cells.h"
#include "testbench/lib/temp_dir.h"

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

// The short run, measured once for the tests that read it.
const ReliefStudy& short_study() {
  static const ReliefStudy st = measure_relief_study(short_run());
  return st;
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
  const ReliefStudy& st = short_study();
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

// The footprint after the shift against the reference's (centred differences of the true hit
// across one pixel); the analytic one costs a gradient read and a reciprocal, the quad one four
// subtractions.
TEST(StudyRelief, DeformedFootprintBeatsTheUnshiftedOne) {
  const ReliefStudy& st = short_study();
  ASSERT_EQ(st.footprint.size(), 4u * 2u * 3u);
  for (size_t i = 0; i < st.footprint.size(); i += 3) {
    const ReliefFootprintRow &un = st.footprint[i], &an = st.footprint[i + 1],
                             &q = st.footprint[i + 2];
    ASSERT_EQ(un.footprint, "unshifted");
    ASSERT_EQ(an.footprint, "analytic");
    ASSERT_EQ(q.footprint, "quad");
    const std::string what = un.map + " " + un.method + " " + std::to_string(un.elevation_deg);
    for (const ReliefFootprintRow* r : {&un, &an, &q}) {
      std::printf("%s %g %s %s: LOD error %.3f, > 0.5 level %.3f, axis error %.3f\n",
                  r->map.c_str(), r->elevation_deg, r->method.c_str(), r->footprint.c_str(),
                  r->lod_err, r->lod_far, r->axis_err);
    }
    // Relief mapping on the smooth map: the deformed footprint gives the reference's LOD far
    // better. (Offset parallax's shift is not the ray's hit, and on the sharp map one pixel
    // spans occlusion steps that no derivative sees: there the study shows them worse.)
    if (un.map == "smooth" && un.method.rfind("relief", 0) == 0) {
      EXPECT_LT(an.lod_err, 0.6 * un.lod_err) << what;
      EXPECT_LT(q.lod_err, 0.75 * un.lod_err) << what;
      EXPECT_LT(an.axis_err, 0.5 * un.axis_err) << what;
    }
    EXPECT_EQ(un.ops, 0);
    EXPECT_EQ(q.ops, 4);
    EXPECT_GT(an.ops, q.ops);
    EXPECT_GT(an.latency, q.latency);
  }
}

// "now (p %)": the percentage must be 100 (a / b − 1) of the figures it compares (printed to
// 4 significant digits, the percentage to 3).
void expect_pct(const std::string& cell, double a, double b, const std::string& what) {
  const size_t open = cell.find(" (");
  ASSERT_NE(open, std::string::npos) << what << ": " << cell;
  const double p = std::stod(cell.substr(open + 2)), want = 100 * (a / b - 1);
  EXPECT_NEAR(p, want, 5e-3 * std::abs(want) + 0.2 * (1 + std::abs(want) / 100)) << what << cell;
}

// relief.csv and relief_filter.csv keep one cell per column (method names and headers hold
// commas), and the speed columns are the percentages of the cycles beside them.
TEST(StudyRelief, TablesKeepTheirColumnsAndDerivedCells) {
  const TempDir dir("relief_study");
  std::ostringstream log;
  ASSERT_EQ(run_study_relief(dir.file("out"), log, short_run()), 0);
  for (const char* f : {"relief.csv", "relief_filter.csv", "relief_footprint.csv"}) {
    std::ifstream in(dir.file(std::string("out/") + f));
    std::string line;
    std::getline(in, line);
    const size_t n = csv_cells(line).size();
    const std::string name(f);
    EXPECT_EQ(n, name == "relief.csv" ? 11u : name == "relief_filter.csv" ? 12u : 9u) << line;
    int rows = 0;
    while (std::getline(in, line)) {
      const std::vector<std::string> c = csv_cells(line);
      ASSERT_EQ(c.size(), n) << f << ": " << line;
      if (std::string(f) == "relief_filter.csv") {
        const double plain = std::stod(c[5]);
        expect_pct(c[6], plain, std::stod(c[6]), "row rule");
        expect_pct(c[7], plain, std::stod(c[7]), "exact");
      }
      ++rows;
    }
    EXPECT_GT(rows, 0) << f;
  }
}

}  // namespace
}  // namespace texsim
