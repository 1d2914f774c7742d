#include "pipeline/report/plot.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"

namespace texsim {

namespace {
std::string quote(const std::string& s) {
  std::string r = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') r += '\\';
    r += c;
  }
  return r + "\"";
}

// A point label as a gnuplot data column: double-quoted, inner double quotes made single.
std::string data_label(std::string s) {
  for (char& c : s) {
    if (c == '"') c = '\'';
  }
  return "\"" + s + "\"";
}
}  // namespace

void write_plot_png(const std::string& path, const PlotSpec& spec) {
  const std::string tmp_png = temp_path_for(path) + ".png";
  const std::string script_path = temp_path_for(path) + ".gp";
  const std::string data_path = temp_path_for(path) + ".dat";
  {
    std::ofstream data(data_path);
    std::ofstream gp(script_path);
    if (!data || !gp) throw InputError(path, "cannot write plot scratch files");
    gp << "set terminal pngcairo size " << spec.width << "," << spec.height
       << " enhanced font 'sans,11'\n";
    gp << "set output " << quote(tmp_png) << "\n";
    gp << "set title " << quote(spec.title) << " noenhanced\n";
    gp << "set xlabel " << quote(spec.xlabel) << " noenhanced\n";
    gp << "set ylabel " << quote(spec.ylabel) << " noenhanced\n";
    gp << "set grid\nset key outside right top noenhanced\n";
    if (spec.logx) gp << "set logscale x\n";
    if (spec.logy) gp << "set logscale y\n";
    gp << "plot ";
    int block = 0;
    for (size_t s = 0; s < spec.series.size(); ++s) {
      const auto& ser = spec.series[s];
      data << "# " << ser.label << "\n";
      int n = 0;
      for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i) {
        const double x = ser.x[i], y = ser.y[i];
        if (!std::isfinite(x) || !std::isfinite(y)) continue;
        if ((spec.logx && x <= 0) || (spec.logy && y <= 0)) continue;
        data << x << " " << y;
        if (i < ser.point_labels.size()) data << " " << data_label(ser.point_labels[i]);
        data << "\n";
        ++n;
      }
      if (n == 0) data << "nan nan\n";
      data << "\n\n";
      if (s) gp << ", ";
      gp << quote(data_path) << " index " << block << " using 1:2 with "
         << (ser.lines ? "lines lw 2" : "points pt 7 ps 1.2") << " lt " << s + 1 << " title "
         << quote(ser.label);
      if (!ser.point_labels.empty() && n > 0) {
        gp << ", " << quote(data_path) << " index " << block
           << " using 1:2:3 with labels left offset char 0.6,0.3 font ',7' tc lt " << s + 1
           << " noenhanced notitle";
      }
      ++block;
    }
    if (spec.series.empty()) gp << "0 notitle";
    gp << "\n";
  }
  const std::string cmd = "gnuplot " + quote(script_path) + " 2>" + quote(script_path + ".err");
  const int rc = std::system(cmd.c_str());
  std::string err;
  {
    std::ifstream e(script_path + ".err");
    std::stringstream ss;
    ss << e.rdbuf();
    err = ss.str();
  }
  std::remove(script_path.c_str());
  std::remove(data_path.c_str());
  std::remove((script_path + ".err").c_str());
  if (rc != 0 || !std::filesystem::exists(tmp_png)) {
    std::remove(tmp_png.c_str());
    throw InputError(path, "gnuplot failed (is gnuplot-nox installed?): " + err);
  }
  commit_temp(tmp_png, path);
}

}  // namespace texsim
