#include "pipeline/report/plot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

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

// A point label as a gnuplot data column: double-quoted, inner double quotes made single.
std::string data_label(std::string s) {
  for (char& c : s) {
    if (c == '"') c = '\'';
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  }
  return "\"" + s + "\"";
}
}  // namespace

void write_plot_png(const std::string& path, const PlotSpec& spec) {
  const std::string tmp_png = temp_path_for(path, ".png");
  const std::string err_path = scratch_path_for(path, ".err");
  const std::string data_path = scratch_path_for(path, ".dat");
  std::ostringstream gp;
  {
    std::ofstream data(data_path);
    if (!data) throw InputError(path, "cannot write plot scratch files");
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
