// The coordinate-method API (pipeline/texture/coord_method) and the coords study on a small set-up:
// op counts, cycles and errors must agree with the blocks' own figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/texture/coords/uv_heckbert_direct.h"
#include "pipeline/studies/study_coords.h"
#include "pipeline/texture/coord_method.h"
#include "testbench/lib/csv_cells.h"

namespace texsim {
namespace {

StudyCoordsOptions small() {
  StudyCoordsOptions o;
  o.width = o.height = 96;
  o.tilts = {0, 60, 89};
  o.tiles = 4;
  o.plane_texels = 512;
  return o;
}

TEST(CoordMethod, UnknownNamesAreInputErrors) {
  EXPECT_THROW(CoordGenerator::create("nope", "float"), InputError);
  EXPECT_THROW(CoordGenerator::create("heckbert", "s3.3"), InputError);
  EXPECT_THROW(DerivGenerator::create("nope", "double"), InputError);
  EXPECT_THROW(EllipseGenerator::create("nope", "double"), InputError);
  for (const auto& m : CoordGenerator::method_names()) {
    for (const auto& f : coord_format_names()) EXPECT_NO_THROW(CoordGenerator::create(m, f));
  }
}

TEST(CoordMethod, MaterialConfigFromToml) {
  const auto t =
      toml::parse("method = 'constant-depth'\nderivs = 'iterative'\nformat = 's24.36'\n");
  const CoordUnitConfig c =
      CoordUnitConfig::from_toml(ConfigReader(t, "scene.toml", "material 'floor'"));
  EXPECT_EQ(c.coords, "constant-depth");
  EXPECT_EQ(c.derivs, "iterative");
  EXPECT_EQ(c.format, "s24.36");
  EXPECT_NO_THROW(CoordUnit{c});
  const auto bad = toml::parse("method = 'heckbert'\nformt = 'float'\n");
  EXPECT_THROW(CoordUnitConfig::from_toml(ConfigReader(bad, "scene.toml", "material 'floor'")),
               InputError);
  const auto bad2 = toml::parse("method = 'fast'\n");
  try {
    CoordUnitConfig::from_toml(ConfigReader(bad2, "scene.toml", "material 'floor'"));
    FAIL() << "unknown method accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("method"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("scene.toml"), std::string::npos);
  }
}

TEST(CoordMethod, RasterizedRowsCoverTheTriangleOnce) {
  const double x[3] = {2.3, 40.7, 10.1}, y[3] = {1.2, 9.9, 30.4};
  const auto rows = triangle_rows(x, y, 64, 64);
  uint64_t n = 0;
  std::set<int32_t> ys;
  for (const auto& r : rows) {
    EXPECT_TRUE(ys.insert(r.y).second);
    n += static_cast<uint64_t>(r.n);
  }
  // Area of the triangle ≈ covered pixel count (pixel centres).
  const double area = std::fabs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])) / 2;
  EXPECT_NEAR(static_cast<double>(n), area, 0.1 * area);
}

TEST(CoordMethod, CoordUnitGivesFragmentsDerivativesAndCosts) {
  const StudyPlane sp = make_study_plane(small(), 60);
  ASSERT_FALSE(sp.tris.empty());
  for (const char* coords : {"incremental", "constant-depth"}) {
    CoordUnitConfig c;
    c.coords = coords;
    c.derivs = "iterative";
    c.format = "double";
    const CoordUnit unit(c);
    const TechTable t = TechTable::defaults();
    EXPECT_EQ(unit.stages(t).size(), 2u);
    std::vector<CoordUnitFragment> frags;
    std::vector<ItemCost> costs;
    OpCounts ops;
    for (const auto& tri : sp.tris) unit.generate(tri, t, frags, costs, ops, ops);
    ASSERT_EQ(costs.size(), 2 * frags.size());
    EXPECT_EQ(frags.size(), sp.pixels);
    double worst = 0;
    for (const auto& f : frags) {
      ASSERT_TRUE(f.d.valid);
      const DerivsL fd = forward_diff_derivs(sp.map, f.x, f.y);
      worst = std::max(worst, std::fabs(f.d.ux - static_cast<double>(fd.ux)));
    }
    EXPECT_LT(worst, 1e-8) << coords;  // derivatives matched to their pixels
  }
}

// coords.csv's coordinate rows against the measured rows: counts as measured, operations per
// pixel = the run's operations ÷ its pixels (9 significant digits).
void check_coords_csv(const std::string& csv, const StudyCoordsResult& r) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  std::map<std::string, size_t> col;
  size_t i = 0;
  for (const std::string& h : csv_cells(line)) col[h] = i++;
  for (const char* c : {"study", "tilt_deg", "method", "format", "pixels", "add_px", "mul_px",
                        "div_px", "rcp_px", "cmp_px", "rows", "triangles", "divisions"})
    ASSERT_TRUE(col.count(c)) << c;
  size_t k = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> v = csv_cells(line);
    if (v[col["study"]] != "coords") continue;
    ASSERT_LT(k, r.coords.size());
    const CoordStudyRow& c = r.coords[k++];  // in the result's order
    EXPECT_EQ(v[col["method"]], c.method);
    EXPECT_EQ(v[col["format"]], c.format);
    EXPECT_NEAR(std::stod(v[col["tilt_deg"]]), c.tilt, 1e-6);
    EXPECT_EQ(std::stoull(v[col["pixels"]]), c.pixels);
    EXPECT_EQ(std::stoull(v[col["rows"]]), c.rows);
    EXPECT_EQ(std::stoull(v[col["triangles"]]), c.triangles);
    EXPECT_EQ(std::stoull(v[col["divisions"]]), c.divisions);
    const std::pair<const char*, uint64_t> ops[] = {{"add_px", c.ops.add},
                                                    {"mul_px", c.ops.mul},
                                                    {"div_px", c.ops.div},
                                                    {"rcp_px", c.ops.rcp},
                                                    {"cmp_px", c.ops.cmp}};
    for (const auto& [name, n] : ops) {
      const double want = c.pixels ? static_cast<double>(n) / static_cast<double>(c.pixels) : 0;
      EXPECT_NEAR(std::stod(v[col[name]]), want, 1e-8 * std::max(1.0, want)) << name << line;
    }
  }
  EXPECT_EQ(k, r.coords.size());
}

TEST(StudyCoords, SmallStudyIsConsistent) {
  const StudyCoordsOptions o = small();
  const StudyCoordsResult r = measure_study_coords(o, nullptr);
  ASSERT_EQ(r.planes.size(), 3u);
  const size_t nm = CoordGenerator::method_names().size(), nf = coord_format_names().size();
  EXPECT_EQ(r.coords.size(), 3 * nm * nf);
  EXPECT_EQ(r.derivs.size(), 3 * DerivGenerator::method_names().size() * nf * 2);
  const UvHeckbertDirect hd;
  for (const auto& c : r.coords) {
    const StudyPlane* p = nullptr;
    for (const auto& q : r.planes) {
      if (q.tilt == c.tilt) p = &q;
    }
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(c.pixels, p->pixels) << c.method;
    if (c.method == "heckbert") {
      EXPECT_EQ(c.ops, hd.ops_per_item() * c.pixels);  // no set-up
      EXPECT_NEAR(c.cpp_spatial.front(), 1.0, 0.2);
      EXPECT_NEAR(c.cpp_shared.front(), 6.0, 0.5);  // 6 mul / 6 add on one unit each
    }
    if (c.format == "double" && (c.method == "heckbert" || c.method.rfind("incremental", 0) == 0)) {
      EXPECT_LT(c.max_err, 1e-8) << c.method << " " << c.tilt;
      EXPECT_EQ(c.rejected, 0u);
    }
    if (c.format == "double" && c.tilt == 0) {
      EXPECT_LT(c.max_err, 1e-6) << c.method;  // screen-parallel: the map is affine
    }
    if (c.method == "constant-depth") {
      EXPECT_EQ(c.divisions, c.rows + c.triangles);  // one rcp per line, one div per triangle
    }
    if (c.method == "heckbert-rcp") {
      EXPECT_EQ(c.divisions, c.pixels);
    }
  }
  const std::string md = study_coords_markdown(o, r), csv = study_coords_csv(o, r);
  EXPECT_NE(md.find("T − q"), std::string::npos);
  EXPECT_NE(md.find("+26 %"), std::string::npos);
  size_t lines = 0;
  for (char ch : csv) lines += ch == '\n';
  EXPECT_EQ(lines, 1 + r.coords.size() + r.derivs.size());
  check_coords_csv(csv, r);
}

// The lane sweep: more lanes make the coordinate unit itself faster (until the row set-ups
// bound it) and never slower than one fragment per cycle behind a filter of II 1; the k-lane
// form's float error falls with its lanes (shorter chains), the direct-n form's does not depend
// on them; its first row equals the plain incremental form's cost.
TEST(StudyCoords, LaneSweepScalesTheUnitAndTheKLaneError) {
  StudyCoordsOptions o = small();
  o.coord_methods = {"incremental"};
  o.formats = {"float"};
  const StudyCoordsResult r = measure_study_coords(o, nullptr);
  ASSERT_EQ(r.lanes.size(), 2 * o.lane_counts.size());
  const LaneSweepRow &k1 = r.lanes[0], &k4 = r.lanes[2], &d1 = r.lanes[5], &d8 = r.lanes[8];
  EXPECT_EQ(k1.method, "incremental-k4");
  EXPECT_EQ(k1.lanes, 1);
  EXPECT_EQ(d8.method, "incremental-direct");
  EXPECT_EQ(d8.lanes, 8);
  EXPECT_LT(k4.cpp_unit_spatial, 0.6 * k1.cpp_unit_spatial);
  EXPECT_LT(d8.cpp_unit_spatial, 0.3 * d1.cpp_unit_spatial);
  EXPECT_GT(k4.area, k1.area);
  for (const LaneSweepRow& l : r.lanes) EXPECT_GE(l.cpp_spatial, 1.0) << l.method << l.lanes;
  EXPECT_LT(k4.max_err_float, k1.max_err_float);
  EXPECT_EQ(d1.max_err_float, d8.max_err_float);
  const CoordStudyRow* inc = nullptr;
  for (const auto& c : r.coords) {
    if (c.tilt == 60) inc = &c;
  }
  ASSERT_NE(inc, nullptr);
  EXPECT_NEAR(k1.cpp_spatial, inc->cpp_spatial.front(), 1e-9);
  EXPECT_NE(study_coords_markdown(o, r).find("Parallel lanes"), std::string::npos);
}

// Tasks run on any number of threads give the same tables, byte for byte.
TEST(StudyCoords, ThreadCountDoesNotChangeTheTables) {
  StudyCoordsOptions o = small();
  o.threads = 1;
  const StudyCoordsResult one = measure_study_coords(o, nullptr);
  o.threads = 3;
  const StudyCoordsResult three = measure_study_coords(o, nullptr);
  EXPECT_EQ(study_coords_csv(o, one), study_coords_csv(o, three));
  EXPECT_EQ(study_coords_markdown(o, one), study_coords_markdown(o, three));
  EXPECT_GT(one.derivs.size(), 0u);
}

// The full study (about 20 s), run on request (one command line):
//   TEXSIM_STUDY_OUT=/tmp/coords build/testbench/test_coords_study
//   --gtest_also_run_disabled_tests --gtest_filter='*FullStudy*'
// (the same as `texsim study coords --out /tmp/coords` once the CLI carries it).
TEST(StudyCoords, DISABLED_FullStudy) {
  const char* out = std::getenv("TEXSIM_STUDY_OUT");
  ASSERT_NE(out, nullptr) << "set TEXSIM_STUDY_OUT to the output directory";
  EXPECT_EQ(run_study_coords(out, std::cerr), 0);
}

}  // namespace
}  // namespace texsim
