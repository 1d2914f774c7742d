// Plots go through gnuplot without a shell and with every string quoted so that neither the
// shell nor gnuplot's own backquote substitution can run what a path, title or label holds.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "pipeline/report/plot.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

namespace fs = std::filesystem;

PlotSpec spec_with(const std::string& text) {
  PlotSpec s;
  s.title = text;
  s.xlabel = text;
  s.ylabel = "y'\"\n" + text;
  PlotSeries a;
  a.label = text;
  a.x = {1, 2, 3};
  a.y = {1, 4, 9};
  a.point_labels = {text, "b\nc", "d"};
  s.series.push_back(a);
  return s;
}

TEST(Plot, NamesAndTextsAreNeverRun) {
  TempDir dir("plot");
  const fs::path marker_shell = fs::path(dir.file("PWNED_SHELL"));
  const fs::path marker_gp = fs::path(dir.file("PWNED_GNUPLOT"));
  // A directory whose name would run a command in a shell line, and texts that would run one
  // through gnuplot's backquotes inside double-quoted strings.
  const fs::path out_dir = dir.file("x$(touch " + marker_shell.string() + ")y");
  fs::create_directories(out_dir);
  const std::string text =
      "t`touch " + marker_gp.string() + "`'\"\\$(touch " + marker_shell.string() + ")";
  const fs::path png = out_dir / "plot.png";
  write_plot_png(png.string(), spec_with(text));
  EXPECT_TRUE(fs::is_regular_file(png));
  EXPECT_GT(fs::file_size(png), 1000u);
  EXPECT_FALSE(fs::exists(marker_shell));
  EXPECT_FALSE(fs::exists(marker_gp));
  // Nothing but the plot is left in the directory (scratch files removed).
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(out_dir)) ++entries;
  EXPECT_EQ(entries, 1);
}

}  // namespace
}  // namespace texsim
