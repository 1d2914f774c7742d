#pragma once
// PNG plots for studies, drawn by gnuplot (Debian gnuplot-nox, pngcairo terminal).
#include <string>
#include <utility>
#include <vector>

namespace texsim {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;
  bool lines = false;  // a line without markers (e.g. error over d); otherwise points only
  // Text drawn next to each point (e.g. the method it measures); empty: no labels.
  std::vector<std::string> point_labels;
};

// Which points of a trade-off plot are Pareto-optimal: lower x (a cost) is always better; y is
// better lower (an error) or higher (PSNR, Fmax).
enum class ParetoFront { none, lower_y_better, higher_y_better };

struct PlotSpec {
  std::string title, xlabel, ylabel;
  bool logx = false, logy = false;
  int width = 1200, height = 800;
  std::vector<PlotSeries> series;
  // Draws the front over all series' points as a dashed line titled "Pareto front".
  ParetoFront pareto = ParetoFront::none;
};

// The points of `spec` (all series) on its Pareto front, sorted by x; empty for
// ParetoFront::none. Non-finite and (on a log axis) non-positive points take no part.
std::vector<std::pair<double, double>> pareto_points(const PlotSpec& spec);

// Writes `spec` as a PNG at `path` (atomically); throws InputError if gnuplot fails.
// Non-finite or (on a log axis) non-positive points are dropped, never plotted as garbage.
// Point labels are placed by place_labels (label_placer.h) so that none overlaps another or a
// point; those left out are counted in a note at the bottom left ("k of n point labels left
// out where they would overlap").
void write_plot_png(const std::string& path, const PlotSpec& spec);

}  // namespace texsim
