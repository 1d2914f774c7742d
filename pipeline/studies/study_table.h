#pragma once
// The one writer every study uses for its outputs: a table of formatted cells written as CSV
// or as a Markdown table, and the files of a study (<stem>.csv, <stem>.md, plots) written
// atomically into its directory. Plots go through gnuplot (pipeline/report/plot.h); their
// points carry labels (the method each point measures), so a plot reads without the table.
#include <ostream>
#include <string>
#include <vector>

#include "pipeline/report/plot.h"

namespace texsim {

class StudyTable {
 public:
  // `align` gives each column's Markdown alignment, 'l' or 'r' (left when missing).
  explicit StudyTable(std::vector<std::string> header, std::string align = "");
  // One row of already formatted cells. In CSV a cell with a comma, quote or line break is
  // quoted (one already in quotes is written as given).
  void add(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }
  size_t size() const { return rows_.size(); }

  std::string csv() const;       // header line, then one line per row, cells joined by ','
  std::string markdown() const;  // | header |, the alignment row, then | cell | … | per row

 private:
  std::vector<std::string> header_;
  std::string align_;
  std::vector<std::vector<std::string>> rows_;
};

// A point of a study plot with the label drawn next to it.
struct LabelledPoint {
  double x = 0, y = 0;
  std::string label;
};
PlotSeries labelled_series(std::string name, const std::vector<LabelledPoint>& points);

// The output directory of one study (created on construction).
class StudyFiles {
 public:
  explicit StudyFiles(std::string dir);
  const std::string& dir() const { return dir_; }
  std::string path(const std::string& file) const { return dir_ + "/" + file; }
  void text(const std::string& file, const std::string& content) const;
  void csv(const std::string& file, const StudyTable& table) const { text(file, table.csv()); }
  void plot(const std::string& file, const PlotSpec& spec) const;

 private:
  std::string dir_;
};

}  // namespace texsim
