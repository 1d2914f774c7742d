// study filters on a small configuration: the files are written, every method has a row per
// texture and view, and the figures hold the relations the study reports (EWA beats the
// trilinear baselines against the Gaussian ground truth; weight maps reproduce the computed
// weights; cycles and texel counts are positive and bounded).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/studies/study_filters.h"

namespace texsim {
namespace {

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"')
      quoted = !quoted;
    else if (ch == ',' && !quoted) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  out.push_back(cur);
  return out;
}

TEST(StudyFilters, SmallRunWritesConsistentTables) {
  const std::string dir = ::testing::TempDir() + "texsim_study_filters";
  std::filesystem::remove_all(dir);
  StudyFiltersOptions opt;
  opt.size = 32;
  opt.anisotropies = {1, 16};
  opt.oiio = false;
  opt.mesa = false;
  opt.threads = 1;
  std::ostringstream log;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(run_study_filters(dir, log, opt), 0) << log.str();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(secs, 30.0);
  for (const char* f :
       {"filters.csv", "filters_timing.csv", "filters.md", "filters.png", "filters_texels.png"}) {
    ASSERT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
    EXPECT_GT(std::filesystem::file_size(dir + "/" + f), 100u) << f;
  }
  std::ifstream in(dir + "/filters.csv");
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> head = split_csv(line);
  std::map<std::string, size_t> col;
  for (size_t i = 0; i < head.size(); ++i) col[head[i]] = i;
  for (const char* c :
       {"texture", "aniso_nominal", "method", "psnr_db", "nmse", "max_abs", "mul_per_frag",
        "texels_per_frag", "cache_misses_per_frag", "cycles_per_frag", "psnr_box_db", "nmse_box"}) {
    ASSERT_TRUE(col.count(c)) << c;
  }
  std::map<std::string, std::vector<std::vector<std::string>>> by_method;
  size_t n = 0;
  while (std::getline(in, line)) {
    const auto cells = split_csv(line);
    ASSERT_EQ(cells.size(), head.size()) << line;
    by_method[cells[col["method"]]].push_back(cells);
    ++n;
  }
  ASSERT_GE(by_method.size(), 10u);
  for (const auto& [m, rows] : by_method) EXPECT_EQ(rows.size(), 3u * 2u) << m;  // textures × views
  auto mean_of = [&](const std::string& m, const std::string& c) {
    double s = 0;
    for (const auto& r : by_method.at(m)) s += std::stod(r[col[c]]);
    return s / static_cast<double>(by_method.at(m).size());
  };
  // EWA against the same pixel model beats both trilinear baselines.
  EXPECT_GT(mean_of("ewa lut256", "psnr_db"), mean_of("trilinear (isotropic)", "psnr_db") + 5.0);
  EXPECT_GT(mean_of("ewa lut256", "psnr_db"),
            mean_of("trilinear aniso 16 (Vulkan probes)", "psnr_db") + 5.0);
  // The ranking flips with the pixel model: against the box pixel the Vulkan probes beat EWA.
  EXPECT_GT(mean_of("trilinear aniso 16 (Vulkan probes)", "psnr_box_db"),
            mean_of("ewa lut256", "psnr_box_db"));
  // Weight maps reproduce the computed power-8 weights closely.
  for (const auto& [m, rows] : by_method) {
    if (m.rfind("ewa map ", 0) != 0 || m.find("jacobian") != std::string::npos) continue;
    for (const auto& r : rows) EXPECT_LT(std::stod(r[col["nmse_vs"]]), 1e-4) << m;
  }
  for (const auto& [m, rows] : by_method) {
    for (const auto& r : rows) {
      const double cyc = std::stod(r[col["cycles_per_frag"]]);
      const double tex = std::stod(r[col["texels_per_frag"]]);
      EXPECT_GE(cyc, 1.0) << m;
      EXPECT_GE(tex, 1.0) << m;
      EXPECT_LE(tex, 8192.0) << m;
      // A pipelined unit with ≥ 1 texel per cycle never needs more cycles than ~texels + latency.
      EXPECT_LT(cyc, tex + 200.0) << m;
    }
  }
  std::ifstream md(dir + "/filters.md");
  std::stringstream ss;
  ss << md.rdbuf();
  EXPECT_NE(ss.str().find("0.000708"), std::string::npos);
  EXPECT_NE(ss.str().find("Computing Gaussian weights"), std::string::npos);
  EXPECT_NE(ss.str().find("Ranking against the Gaussian-pixel truth"), std::string::npos);
  EXPECT_NE(ss.str().find("Ranking against the box-pixel truth"), std::string::npos);
  // The two truths differ (and filters_truths.csv says by how much): a row per view.
  std::ifstream truths(dir + "/filters_truths.csv");
  size_t truth_rows = 0;
  for (std::getline(truths, line); std::getline(truths, line); ++truth_rows) {
    const double db = std::stod(split_csv(line)[2]);
    EXPECT_GT(db, 10.0) << line;
    EXPECT_LT(db, 90.0) << line;
  }
  EXPECT_EQ(truth_rows, 3u * 2u);
  // filters.csv is the same on every run and for every thread count: wall-clock times go to
  // filters_timing.csv.
  const std::string again = dir + "_again";
  std::filesystem::remove_all(again);
  opt.threads = 2;
  ASSERT_EQ(run_study_filters(again, log, opt), 0) << log.str();
  auto slurp = [](const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  };
  for (const char* f : {"filters.csv", "filters.md", "filters_truths.csv"})
    EXPECT_EQ(slurp(dir + "/" + f), slurp(again + "/" + f)) << f;
  EXPECT_EQ(slurp(dir + "/filters.csv").find("functional_ns"), std::string::npos);
  EXPECT_NE(slurp(dir + "/filters_timing.csv").find("functional_ns_per_lookup"), std::string::npos);
  std::filesystem::remove_all(dir);
  std::filesystem::remove_all(again);
}

}  // namespace
}  // namespace texsim
