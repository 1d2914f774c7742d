// Plots go through gnuplot without a shell and with every string quoted so that neither the
// shell nor gnuplot's own backquote substitution can run what a path, title or label holds.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "pipeline/report/label_placer.h"
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

// Isolated points get their label at the preferred place (right of the point); a dense cluster
// gets as many as fit, and no placed label overlaps another label or any point.
TEST(Plot, LabelsNeverOverlap) {
  const LabelBox area{0, 0, 1000, 600};
  std::vector<LabelRequest> req = {{100, 100, 40, 12}, {500, 300, 40, 12}};
  for (int k = 0; k < 40; ++k) {
    const int col = k % 5, row = k / 5;  // a 5 x 8 cluster of points 3 px apart
    req.push_back({700.0 + col * 3, 300.0 + row * 3, 60, 12});
  }
  const std::vector<PlacedLabel> out = place_labels(req, area, 8);
  ASSERT_EQ(out.size(), req.size());
  ASSERT_TRUE(out[0].placed && out[1].placed);
  EXPECT_DOUBLE_EQ(out[0].box.x0, 100 + 4 + 2);  // right of the point, centred on it
  EXPECT_DOUBLE_EQ(out[0].box.y0, 100 - 6);
  int placed = 0;
  for (size_t i = 0; i < out.size(); ++i) {
    if (!out[i].placed) continue;
    ++placed;
    const LabelBox& b = out[i].box;
    EXPECT_TRUE(b.x0 >= area.x0 && b.x1 <= area.x1 && b.y0 >= area.y0 && b.y1 <= area.y1);
    for (size_t j = 0; j < out.size(); ++j) {
      const LabelBox point{req[j].px - 4, req[j].py - 4, req[j].px + 4, req[j].py + 4};
      EXPECT_FALSE(b.overlaps(point, 0)) << i << " covers point " << j;
      if (j != i && out[j].placed) {
        EXPECT_FALSE(b.overlaps(out[j].box, 0)) << i << " " << j;
      }
    }
  }
  EXPECT_GT(placed, 2 + 8);                         // the cluster keeps a ring of labels around it
  EXPECT_LT(placed, static_cast<int>(req.size()));  // but not all 40 fit
  // A label at the area's right edge goes to the left of its point instead.
  const auto edge = place_labels({{990, 300, 40, 12}}, area, 8);
  ASSERT_TRUE(edge[0].placed);
  EXPECT_DOUBLE_EQ(edge[0].box.x1, 990 - 6);
}

TEST(Plot, ParetoFrontOverAllSeries) {
  PlotSpec s;
  PlotSeries a, b;
  a.x = {1, 2, 4, 8};
  a.y = {10, 30, 20, 40};  // higher better: (1,10), (2,30), (8,40); (4,20) is dominated
  b.x = {2, 3, std::nan("")};
  b.y = {35, 38, 99};  // (2,35) beats (2,30); (3,38) on the front; NaN ignored
  s.series = {a, b};
  EXPECT_TRUE(pareto_points(s).empty());
  s.pareto = ParetoFront::higher_y_better;
  const std::vector<std::pair<double, double>> hi = {{1, 10}, {2, 35}, {3, 38}, {8, 40}};
  EXPECT_EQ(pareto_points(s), hi);
  s.pareto = ParetoFront::lower_y_better;
  const std::vector<std::pair<double, double>> lo = {{1, 10}};
  EXPECT_EQ(pareto_points(s), lo);
  s.logy = true;
  s.series[0].y[0] = -1;  // not on a log axis: (2, 30) is then the cheapest lowest
  const std::vector<std::pair<double, double>> lo_log = {{2, 30}, {4, 20}};
  EXPECT_EQ(pareto_points(s), lo_log);
  // Drawn: the plot still writes.
  TempDir dir("plot");
  s.series[0].point_labels = {"a", "b", "c", "d"};
  write_plot_png(dir.file("p.png"), s);
  EXPECT_TRUE(fs::is_regular_file(dir.file("p.png")));
}

}  // namespace
}  // namespace texsim
