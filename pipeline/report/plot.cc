#include "pipeline/report/plot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/temp_registry.h"
#include "pipeline/report/label_placer.h"

namespace texsim {

namespace {
// A gnuplot string literal. Single quotes, because gnuplot substitutes `command` inside
// double-quoted strings; control characters become spaces so a string cannot end the command.
std::string quote(const std::string& s) {
  std::string r = "'";
  for (char c : s) {
    if (c == '\'') {
      r += "''";
    } else {
      r += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? ' ' : c;
    }
  }
  return r + "'";
}

// Runs gnuplot with `script` on its standard input, never through a shell; its standard error
// goes to `err_path`. Returns gnuplot's exit status, or -1 if it could not be started.
int run_gnuplot(const std::string& script, const std::string& err_path) {
  // A socket pair rather than a pipe: send() with MSG_NOSIGNAL reports a gnuplot that exited
  // early as an error instead of killing the process with SIGPIPE.
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) return -1;
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, fds[0], STDIN_FILENO);
  posix_spawn_file_actions_addclose(&fa, fds[0]);
  posix_spawn_file_actions_addclose(&fa, fds[1]);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, err_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  char arg0[] = "gnuplot";
  char* argv[] = {arg0, nullptr};
  pid_t pid = 0;
  const int rc = ::posix_spawnp(&pid, "gnuplot", &fa, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(fds[0]);
  if (rc != 0) {
    ::close(fds[1]);
    return -1;
  }
  size_t done = 0;
  while (done < script.size()) {
    const ssize_t n = ::send(fds[1], script.data() + done, script.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // gnuplot exited early; its status and stderr say why
    done += static_cast<size_t>(n);
  }
  ::close(fds[1]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

bool usable(const PlotSpec& spec, double x, double y) {
  if (!std::isfinite(x) || !std::isfinite(y)) return false;
  return !((spec.logx && x <= 0) || (spec.logy && y <= 0));
}

// The plot area's edges as fractions of the image (fixed, so that labels can be placed in
// pixels before gnuplot draws): the key sits right of it.
constexpr double kLeft = 0.09, kRight = 0.74, kBottom = 0.10, kTop = 0.90;
// Point labels: gnuplot's 7-point font on pngcairo; generous so that a placed label never
// touches its neighbour.
constexpr double kLabelCharW = 6.0, kLabelH = 12.0;

struct Axis {
  double lo = 0, hi = 1;
  bool log = false;
  double t(double v) const { return log ? std::log10(v) : v; }
  double fraction(double v) const { return (t(v) - t(lo)) / (t(hi) - t(lo)); }
};

// The range of the usable values, padded by 5 % (in log space on a log axis).
Axis axis_of(const std::vector<double>& v, bool log) {
  Axis a;
  a.log = log;
  if (v.empty()) return log ? Axis{1, 10, true} : a;
  double lo = v.front(), hi = v.front();
  for (const double x : v) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  double tl = log ? std::log10(lo) : lo, th = log ? std::log10(hi) : hi;
  if (th - tl < 1e-12 * std::max(1.0, std::abs(tl))) {
    tl -= 0.5;
    th += 0.5;
  }
  const double pad = 0.05 * (th - tl);
  tl -= pad;
  th += pad;
  a.lo = log ? std::pow(10.0, tl) : tl;
  a.hi = log ? std::pow(10.0, th) : th;
  return a;
}

}  // namespace

std::vector<std::pair<double, double>> pareto_points(const PlotSpec& spec) {
  std::vector<std::pair<double, double>> pts, front;
  if (spec.pareto == ParetoFront::none) return front;
  const double sign = spec.pareto == ParetoFront::higher_y_better ? -1 : 1;  // lower is better
  for (const PlotSeries& ser : spec.series)
    for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i)
      if (usable(spec, ser.x[i], ser.y[i])) pts.emplace_back(ser.x[i], ser.y[i]);
  std::sort(pts.begin(), pts.end(), [sign](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : sign * a.second < sign * b.second;
  });
  for (const auto& p : pts)
    if (front.empty() || sign * p.second < sign * front.back().second) front.push_back(p);
  return front;
}

void write_plot_png(const std::string& path, const PlotSpec& spec) {
  const std::string tmp_png = temp_path_for(path, ".png");
  const std::string err_path = scratch_path_for(path, ".err");
  const std::string data_path = scratch_path_for(path, ".dat");
  std::vector<double> xs, ys;
  for (const PlotSeries& ser : spec.series)
    for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i)
      if (usable(spec, ser.x[i], ser.y[i])) {
        xs.push_back(ser.x[i]);
        ys.push_back(ser.y[i]);
      }
  const Axis ax = axis_of(xs, spec.logx), ay = axis_of(ys, spec.logy);
  // Point labels placed in pixels, in series order.
  const double w = spec.width, h = spec.height;
  std::vector<LabelRequest> req;
  std::vector<std::pair<size_t, std::string>> text;  // series, label
  for (size_t s = 0; s < spec.series.size(); ++s) {
    const PlotSeries& ser = spec.series[s];
    for (size_t i = 0; i < ser.x.size() && i < ser.y.size() && i < ser.point_labels.size(); ++i) {
      if (!usable(spec, ser.x[i], ser.y[i]) || ser.point_labels[i].empty()) continue;
      req.push_back({(kLeft + ax.fraction(ser.x[i]) * (kRight - kLeft)) * w,
                     (1 - kBottom - ay.fraction(ser.y[i]) * (kTop - kBottom)) * h,
                     kLabelCharW * static_cast<double>(ser.point_labels[i].size()), kLabelH});
      text.emplace_back(s, ser.point_labels[i]);
    }
  }
  const std::vector<PlacedLabel> placed =
      place_labels(req, {kLeft * w, (1 - kTop) * h, kRight * w, (1 - kBottom) * h});
  size_t left_out = 0;
  for (const PlacedLabel& p : placed) left_out += p.placed ? 0 : 1;
  std::ostringstream gp;
  {
    std::ofstream data(data_path);
    if (!data) throw InputError(path, "cannot write plot scratch files");
    gp << "set terminal pngcairo size " << spec.width << "," << spec.height
       << " enhanced font 'sans,11'\n";
    gp << "set output " << quote(tmp_png) << "\n";
    gp << "set title " << quote(spec.title) << " noenhanced\n";
    if (left_out > 0) {
      gp << "set label "
         << quote(std::to_string(left_out) + " of " + std::to_string(placed.size()) +
                  " point labels left out where they would overlap")
         << " at screen 0.01,0.02 left font ',9' noenhanced\n";
    }
    gp << "set xlabel " << quote(spec.xlabel) << " noenhanced\n";
    gp << "set ylabel " << quote(spec.ylabel) << " noenhanced\n";
    gp << "set grid\nset key outside right top noenhanced\n";
    gp << "set lmargin at screen " << kLeft << "\nset rmargin at screen " << kRight
       << "\nset bmargin at screen " << kBottom << "\nset tmargin at screen " << kTop << "\n";
    gp << "set xrange [" << ax.lo << ":" << ax.hi << "]\nset yrange [" << ay.lo << ":" << ay.hi
       << "]\n";
    if (spec.logx) gp << "set logscale x\n";
    if (spec.logy) gp << "set logscale y\n";
    for (size_t k = 0; k < placed.size(); ++k) {
      if (!placed[k].placed) continue;
      const LabelBox& b = placed[k].box;
      gp << "set label " << quote(text[k].second) << " at screen " << b.x0 / w << ","
         << 1 - (b.y0 + b.y1) / 2 / h << " left font ',7' tc lt " << text[k].first + 1
         << " noenhanced front\n";
    }
    gp << "plot ";
    int block = 0;
    for (size_t s = 0; s < spec.series.size(); ++s) {
      const auto& ser = spec.series[s];
      data << "# " << ser.label << "\n";
      int n = 0;
      for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i) {
        if (!usable(spec, ser.x[i], ser.y[i])) continue;
        data << ser.x[i] << " " << ser.y[i] << "\n";
        ++n;
      }
      if (n == 0) data << "nan nan\n";
      data << "\n\n";
      if (s) gp << ", ";
      gp << quote(data_path) << " index " << block << " using 1:2 with "
         << (ser.lines ? "lines lw 2" : "points pt 7 ps 1.2") << " lt " << s + 1 << " title "
         << quote(ser.label);
      ++block;
    }
    const auto front = pareto_points(spec);
    if (!front.empty()) {
      data << "# Pareto front\n";
      for (const auto& [x, y] : front) data << x << " " << y << "\n";
      data << "\n\n";
      gp << (spec.series.empty() ? "" : ", ") << quote(data_path) << " index " << block
         << " using 1:2 with lines dt 2 lw 1.5 lc rgb 'black' title 'Pareto front'";
    } else if (spec.series.empty()) {
      gp << "0 notitle";
    }
    gp << "\n";
  }
  const int rc = run_gnuplot(gp.str(), err_path);
  std::string err;
  {
    std::ifstream e(err_path);
    std::stringstream ss;
    ss << e.rdbuf();
    err = ss.str();
  }
  remove_temp(data_path);
  remove_temp(err_path);
  if (rc != 0 || !std::filesystem::exists(tmp_png)) {
    discard_temp(tmp_png, path);
    throw InputError(path, "gnuplot failed (is gnuplot-nox installed?): " + err);
  }
  commit_temp(tmp_png, path);
}

}  // namespace texsim
