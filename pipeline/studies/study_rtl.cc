#include "pipeline/studies/study_rtl.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "blocks/base/input_error.h"
#include "pipeline/studies/study_table.h"
#include "pipeline/studies/study_vd.h"
#include "rtl_model/synth/synth_flow.h"

namespace texsim {

namespace fs = std::filesystem;

namespace {

using Params = std::vector<std::pair<std::string, int>>;

std::string fmt(double v, const char* f = "%.1f") {
  char b[32];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::vector<fs::path> verilog_files(const std::string& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return files;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".v" || ext == ".sv")) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool declares_parameter(const std::string& source, const std::string& name) {
  const std::regex re("\\bparameter\\b[^;)]*\\b" + name + "\\b");
  return std::regex_search(source, re);
}

// Every combination of the swept parameters the file declares.
std::vector<Params> combinations(const std::string& source, const StudyRtlOptions& opt) {
  std::vector<Params> out = {{}};
  for (const auto& [name, values] : opt.params) {
    if (!declares_parameter(source, name)) continue;
    std::vector<Params> next;
    for (const Params& p : out) {
      for (const int v : values) {
        Params q = p;
        q.emplace_back(name, v);
        next.push_back(q);
      }
    }
    out = next;
  }
  return out;
}

std::string params_text(const Params& p) {
  std::string s;
  for (const auto& [n, v] : p) s += (s.empty() ? "" : " ") + n + "=" + std::to_string(v);
  return s.empty() ? "defaults" : s;
}

// The exhaustive C++ error of a V(d) evaluator block (top vd_p2*/vd_p1*) whose width parameter
// is one of the fixed formats' input widths; "" for any other block.
std::string vd_max_error(const std::string& top, const Params& p) {
  VdEvaluatorKind kind;
  if (top.rfind("vd_p2", 0) == 0) {
    kind = VdEvaluatorKind::P2;
  } else if (top.rfind("vd_p1", 0) == 0) {
    kind = VdEvaluatorKind::P1;
  } else {
    return "";
  }
  for (const auto& [name, v] : p) {
    const NumberFormat f = v == 16   ? NumberFormat::Fx16
                           : v == 12 ? NumberFormat::Fx12
                           : v == 8  ? NumberFormat::Fx8
                                     : NumberFormat::Double;
    if (f != NumberFormat::Double) return fmt(measure_vd_error(kind, f).max_abs, "%.2e");
  }
  return "";
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Row {
  std::string block, params, error;
  synth::SynthResult r;
};

std::vector<std::string> cells_of(const Row& row) {
  const synth::SynthResult& r = row.r;
  const std::string fallback = r.multipliers > r.mac16
                                   ? std::to_string(r.multipliers - r.mac16) + " of " +
                                         std::to_string(r.multipliers) + " in LUTs"
                                   : "no";
  std::vector<std::string> c = {row.block, row.params, row.error.empty() ? "-" : row.error};
  if (!r.error.empty()) {
    c.insert(c.end(), {"-", "-", "-", "-", "-", "-", "-", "-", "-", "-", "0", r.error});
    return c;
  }
  for (const int v : {r.generic_cells, r.multipliers, r.lut4, r.dff, r.carry, r.mac16}) {
    c.push_back(std::to_string(v));
  }
  c.push_back(fallback);
  if (r.fmax_mhz.empty()) {
    c.insert(c.end(), {"-", "-", "-"});
  } else {
    const auto [lo, hi] = std::minmax_element(r.fmax_mhz.begin(), r.fmax_mhz.end());
    c.insert(c.end(), {fmt(median_of(r.fmax_mhz)), fmt(*lo), fmt(*hi)});
  }
  c.push_back(std::to_string(r.fmax_mhz.size()));
  c.push_back(r.pnr_error.empty() ? "" : r.pnr_error);
  return c;
}

void write_outputs(const std::string& out_dir, const std::vector<Row>& rows,
                   const StudyRtlOptions& opt, const std::string& note) {
  StudyTable t({"block", "parameters", "max error (C++)", "generic cells", "multipliers", "LUT4",
                "DFF", "carry", "SB_MAC16", "DSP fallback", "Fmax median MHz", "Fmax min",
                "Fmax max", "seeds routed", "notes"},
               "llrrrrrrrlrrrrl");
  // One plot series per block, a point per parameter set.
  std::vector<std::pair<std::string, std::vector<LabelledPoint>>> series;
  for (const Row& row : rows) {
    t.add(cells_of(row));
    if (row.r.fmax_mhz.empty()) continue;
    if (series.empty() || series.back().first != row.block) series.push_back({row.block, {}});
    series.back().second.push_back(
        {static_cast<double>(row.r.lut4), median_of(row.r.fmax_mhz), row.params});
  }
  const StudyFiles files(out_dir);
  files.csv("rtl.csv", t);
  files.text("rtl.md",
             "# RTL blocks on the iCE40 UP5K\n\nyosys synth / synth_ice40 -dsp, "
             "nextpnr-ice40 --up5k at seeds 1.." +
                 std::to_string(opt.seeds) +
                 " (blocks wrapped in shift registers for "
                 "place and route; resource counts are the block's alone). " +
                 note + "\n\n" + t.markdown());
  if (series.empty()) return;
  PlotSpec spec;
  spec.title = "RTL blocks on iCE40 UP5K: LUT4 vs median Fmax over " + std::to_string(opt.seeds) +
               " placer seeds";
  spec.xlabel = "SB_LUT4 cells";
  spec.ylabel = "Fmax (MHz, median over seeds)";
  for (const auto& [block, points] : series) spec.series.push_back(labelled_series(block, points));
  files.plot("rtl.png", spec);
}

}  // namespace

std::pair<std::string, std::vector<int>> parse_rtl_param(const std::string& text) {
  static const std::regex re("([A-Za-z_][A-Za-z0-9_]*)=([0-9]+(,[0-9]+)*)");
  std::smatch m;
  if (!std::regex_match(text, m, re)) {
    throw InputError("--param " + text, "expected NAME=v1,v2,... (e.g. W=8,12,16)");
  }
  std::vector<int> values;
  std::stringstream s(m[2].str());
  for (std::string v; std::getline(s, v, ',');) {
    if (v.size() > 6) throw InputError("--param " + text, "value " + v + " is too large");
    values.push_back(std::stoi(v));
  }
  return {m[1].str(), values};
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

int run_study_rtl(const std::string& out_dir, const StudyRtlOptions& opt, std::ostream& log) {
  const synth::Tools tools = synth::find_tools();
  if (tools.yosys.empty()) {
    log << "study rtl: skipped: " << tools.missing()
        << " (scripts/setup-debian.sh installs yosys, nextpnr-ice40 and fpga-icestorm)\n";
    return 0;
  }
  const std::vector<fs::path> files = verilog_files(opt.rtl_dir);
  if (files.empty()) {
    log << "study rtl: no RTL blocks in " << opt.rtl_dir << " (no .v or .sv files)\n";
    return 0;
  }
  std::string note;
  if (tools.nextpnr.empty()) {
    note = "nextpnr-ice40 not found: no Fmax.";
    log << "study rtl: " << tools.missing() << ": synthesis only, no Fmax\n";
  }
  std::vector<int> seeds;
  for (int s = 1; s <= opt.seeds; ++s) seeds.push_back(s);
  std::vector<Row> rows;
  for (const fs::path& file : files) {
    const std::string top = file.stem().string();
    for (const Params& p : combinations(slurp(file), opt)) {
      fs::path work = fs::absolute(out_dir) / "rtl_work" / top;
      for (const auto& [n, v] : p) work += "_" + n + std::to_string(v);
      const synth::SynthJob job{fs::absolute(file).string(), top, p, work.string(), seeds};
      log << "study rtl: " << top << " " << params_text(p) << " ..." << std::flush;
      Row row{top, params_text(p), vd_max_error(top, p), synth::run_synth(job, tools)};
      log << (row.r.error.empty() ? " " + std::to_string(row.r.lut4) + " LUT4" : " failed") << "\n";
      rows.push_back(std::move(row));
    }
  }
  write_outputs(out_dir, rows, opt, note);
  log << "study rtl: wrote " << out_dir << "/rtl.csv, rtl.md"
      << "\n";
  return 0;
}

}  // namespace texsim
