// `study vd`: the table, CSV and plot are written, complete and consistent with the
// measurement functions, within the run-time budget.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/studies/study_vd.h"

namespace texsim {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false;
  for (char c : line) {
    if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted) {
      out.push_back(cur);
      cur.clear();
    } else
      cur += c;
  }
  out.push_back(cur);
  return out;
}

TEST(StudyVd, WritesTableCsvAndPlot) {
  // TEXSIM_STUDY_VD_OUT keeps the outputs in that directory (to read them); otherwise a
  // temporary directory is used and removed.
  const char* keep = std::getenv("TEXSIM_STUDY_VD_OUT");
  const std::string dir = keep ? std::string(keep)
                               : (std::filesystem::temp_directory_path() /
                                  ("texsim_study_vd_" + std::to_string(::getpid())))
                                     .string();
  if (!keep) std::filesystem::remove_all(dir);
  std::ostringstream log;
  const std::clock_t c0 = std::clock();
  ASSERT_EQ(run_study_vd(dir, log), 0);
  const double cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  EXPECT_LT(cpu_s, 30.0) << "study vd must stay under ~30 s of one core";

  // CSV: header + evaluator × format rows; the claim column agrees with the numbers.
  std::istringstream csv(slurp(dir + "/vd.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const auto head = split(line);
  ASSERT_EQ(head.front(), "evaluator");
  ASSERT_EQ(head.back(), "claim_holds");
  int rows = 0, p2_double_seen = 0;
  while (std::getline(csv, line)) {
    const auto f = split(line);
    ASSERT_EQ(f.size(), head.size()) << line;
    ++rows;
    const double max_abs = std::stod(f[2]);
    EXPECT_GE(max_abs, 0.0);
    // The signed error at the maximum is the maximum; the mean is at most the maximum.
    EXPECT_NEAR(std::abs(std::stod(f[4])), max_abs, 1e-5 * max_abs) << line;
    EXPECT_LE(std::stod(f[5]), max_abs * (1 + 1e-5)) << line;
    if (!f[14].empty()) {
      const double claim = std::stod(f[14]);
      EXPECT_EQ(f[15], max_abs <= claim ? "yes" : "no") << line;
    }
    if (f[0] == "p2" && f[1] == "double") {
      ++p2_double_seen;
      const auto m = measure_vd_error(VdEvaluatorKind::P2, NumberFormat::Double);
      EXPECT_NEAR(max_abs, m.max_abs, 1e-9);
      EXPECT_EQ(f[15], "no");
      EXPECT_EQ(std::stoi(f[12]), 8);  // 2·mul(3) + 2·add(1) in the default table
    }
  }
  EXPECT_EQ(rows, static_cast<int>(kVdEvaluatorKinds.size() * kVdFormatKinds.size()));
  EXPECT_EQ(p2_double_seen, 1);

  const std::string md = slurp(dir + "/vd.md");
  EXPECT_NE(md.find("| evaluator | format | max abs error"), std::string::npos);
  EXPECT_NE(md.find("best σ"), std::string::npos);
  EXPECT_NE(md.find("Cut-off volume"), std::string::npos);

  const std::string png = slurp(dir + "/vd.png");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // No temporary files left behind.
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  }
  if (!keep) std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace texsim
