// study filters on a small configuration: the files are written, every method has a row per
// texture and view, and the figures hold the relations the study reports (EWA beats the
// trilinear baselines against the Gaussian ground truth; weight maps reproduce the computed
// weights; cycles and texel counts are positive and bounded).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
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

using Rows = std::map<std::string, std::vector<std::vector<std::string>>>;

// The cells of the Markdown table that follows `heading` in `md`, header row first.
std::vector<std::vector<std::string>> md_table(const std::string& md, const std::string& heading) {
  std::vector<std::vector<std::string>> rows;
  size_t at = md.find(heading);
  if (at == std::string::npos) return rows;
  at = md.find("\n|", at);
  while (at != std::string::npos && md.compare(at, 2, "\n|") == 0) {
    const size_t end = md.find('\n', at + 1);
    const std::string line = md.substr(at + 2, end - at - 2);
    std::vector<std::string> cells(1);
    for (char ch : line) {
      if (ch == '|') {
        cells.emplace_back();
      } else {
        cells.back() += ch;
      }
    }
    cells.pop_back();  // after the closing '|'
    for (std::string& c : cells) {
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
    }
    if (cells.front().find("---") == std::string::npos) rows.push_back(cells);
    at = end;
  }
  return rows;
}

// Pooled PSNR (Σ err² over every compared pixel, from each row's PSNR and pixels) and the
// largest error of a method's rows.
struct PooledFromRows {
  double psnr = 0, psnr_box = 0, max_abs = 0;
};
PooledFromRows pooled(const std::vector<std::vector<std::string>>& rows,
                      std::map<std::string, size_t>& col) {
  double px = 0, se = 0, se_box = 0, mx = 0;
  for (const auto& r : rows) {
    const double n = std::stod(r[col["pixels"]]);
    px += n;
    se += n * std::pow(10.0, -std::stod(r[col["psnr_db"]]) / 10);
    se_box += n * std::pow(10.0, -std::stod(r[col["psnr_box_db"]]) / 10);
    mx = std::max(mx, std::stod(r[col["max_abs"]]));
  }
  return {10 * std::log10(px / se), 10 * std::log10(px / se_box), mx};
}

// filters.md's pooled table and rankings against filters.csv's rows (printed to 4 or 3
// significant digits).
void check_pooled_tables(const std::string& md, const Rows& by_method,
                         std::map<std::string, size_t>& col) {
  const auto all = md_table(md, "## All views pooled");
  ASSERT_GT(all.size(), 1u);
  ASSERT_EQ(all[0][2], "PSNR dB");
  ASSERT_EQ(all[0][4], "max err");
  for (size_t i = 1; i < all.size(); ++i) {
    ASSERT_TRUE(by_method.count(all[i][0])) << all[i][0];
    const PooledFromRows p = pooled(by_method.at(all[i][0]), col);
    EXPECT_NEAR(std::stod(all[i][2]), p.psnr, 0.006 + 5e-4 * p.psnr) << all[i][0];
    EXPECT_NEAR(std::stod(all[i][4]), p.max_abs, 5e-3 * p.max_abs + 1e-9) << all[i][0];
  }
  for (const bool box : {false, true}) {
    const auto rank = md_table(md, box ? "## Ranking against the box-pixel truth"
                                       : "## Ranking against the Gaussian-pixel truth");
    ASSERT_EQ(rank.size(), by_method.size() + 1) << box;
    double prev = 1e9;
    for (size_t i = 1; i < rank.size(); ++i) {
      EXPECT_EQ(rank[i][0], std::to_string(i));
      const PooledFromRows p = pooled(by_method.at(rank[i][1]), col);
      const double own = box ? p.psnr_box : p.psnr, other = box ? p.psnr : p.psnr_box;
      EXPECT_NEAR(std::stod(rank[i][3]), own, 0.006 + 5e-4 * own) << rank[i][1];
      EXPECT_NEAR(std::stod(rank[i][5]), other, 0.006 + 5e-4 * other) << rank[i][1];
      EXPECT_LE(own, prev + 0.01) << "ranked by PSNR: " << rank[i][1];  // CSV: 5 digits
      prev = own;
    }
  }
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
  check_pooled_tables(ss.str(), by_method, col);
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
