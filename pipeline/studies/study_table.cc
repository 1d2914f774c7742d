#include "pipeline/studies/study_table.h"

#include <utility>

#include "blocks/base/atomic_file.h"

namespace texsim {

StudyTable::StudyTable(std::vector<std::string> header, std::string align)
    : header_(std::move(header)), align_(std::move(align)) {}

namespace {
std::string joined(const std::vector<std::string>& cells, const char* sep) {
  std::string s;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (i) s += sep;
    s += cells[i];
  }
  return s;
}

// A CSV cell: one holding a comma, quote or line break is quoted (RFC 4180, inner quotes
// doubled) unless the study quoted it already.
std::string csv_cell(const std::string& c) {
  const bool quoted = c.size() >= 2 && c.front() == '"' && c.back() == '"';
  if (quoted || c.find_first_of(",\"\r\n") == std::string::npos) return c;
  std::string q = "\"";
  for (char ch : c) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

std::string csv_line(const std::vector<std::string>& cells) {
  std::string s;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (i) s += ",";
    s += csv_cell(cells[i]);
  }
  return s + "\n";
}
}  // namespace

std::string StudyTable::csv() const {
  std::string s = csv_line(header_);
  for (const auto& r : rows_) s += csv_line(r);
  return s;
}

std::string StudyTable::markdown() const {
  std::string s = "| " + joined(header_, " | ") + " |\n|";
  for (size_t i = 0; i < header_.size(); ++i)
    s += (i < align_.size() && align_[i] == 'r') ? "---:|" : "---|";
  s += "\n";
  for (const auto& r : rows_) s += "| " + joined(r, " | ") + " |\n";
  return s;
}

PlotSeries labelled_series(std::string name, const std::vector<LabelledPoint>& points) {
  PlotSeries s;
  s.label = std::move(name);
  for (const LabelledPoint& p : points) {
    s.x.push_back(p.x);
    s.y.push_back(p.y);
    s.point_labels.push_back(p.label);
  }
  return s;
}

StudyFiles::StudyFiles(std::string dir) : dir_(std::move(dir)) { ensure_dir(dir_); }

void StudyFiles::text(const std::string& file, const std::string& content) const {
  write_file_atomic(path(file), content);
}

void StudyFiles::plot(const std::string& file, const PlotSpec& spec) const {
  write_plot_png(path(file), spec);
}

}  // namespace texsim
