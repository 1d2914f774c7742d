#pragma once
// PNG plots for studies, drawn by gnuplot (Debian gnuplot-nox, pngcairo terminal).
#include <string>
#include <vector>

namespace texsim {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  bool lines = false;  // a line without markers (e.g. error over d); otherwise points only
  // Text drawn next to each point (e.g. the method it measures); empty: no labels.
  std::vector<std::string> point_labels;
};

struct PlotSpec {
  std::string title, xlabel, ylabel;
  bool logx = false, logy = false;
  int width = 1200, height = 800;
  std::vector<PlotSeries> series;
};

// Writes `spec` as a PNG at `path` (atomically); throws InputError if gnuplot fails.
// Non-finite or (on a log axis) non-positive points are dropped, never plotted as garbage.
void write_plot_png(const std::string& path, const PlotSpec& spec);

}  // namespace texsim
