#include "pipeline/studies/study_rtl.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "blocks/base/input_error.h"
#include "pipeline/studies/study_rtl_params.h"
#include "pipeline/studies/study_table.h"
#include "rtl_model/synth/synth_flow.h"

namespace texsim {

namespace fs = std::filesystem;

namespace {

using Sweep = std::vector<std::pair<std::string, int>>;

std::string fmt(double v, const char* f = "%.1f") {
  char b[32];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// Shared helper modules (texsim_pipe, texsim_round_sat, ...) are named texsim_*: they are
// read with every block but are not blocks of their own. The sampler (texsim_sampler) is named
// like them but is a block of rtl_params.h.
bool is_helper(const fs::path& file) {
  const std::string stem = file.stem().string();
  return stem.rfind("texsim_", 0) == 0 && !rtl_study_known_block(stem);
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
std::vector<Sweep> combinations(const std::string& source, const StudyRtlOptions& opt) {
  std::vector<Sweep> out = {{}};
  for (const auto& [name, values] : opt.params) {
    if (!declares_parameter(source, name)) continue;
    std::vector<Sweep> next;
    for (const Sweep& p : out) {
      for (const int v : values) {
        Sweep q = p;
        q.emplace_back(name, v);
        next.push_back(q);
      }
    }
    out = next;
  }
  return out;
}

std::string params_text(const Sweep& p) {
  std::string s;
  for (const auto& [n, v] : p) s += (s.empty() ? "" : " ") + n + "=" + std::to_string(v);
  return s.empty() ? "defaults" : s;
}

// Stands in for texsim_op_counters when the counters are left out: same ports, outputs 0.
constexpr const char* kCounterStub =
    "// texsim study rtl: texsim_op_counters left out (docs/rtl/study.md); outputs are 0.\n"
    "module texsim_op_counters (\n"
    "    input logic clk, input logic rst, input logic retire,\n"
    "    input logic [15:0] add_n, input logic [15:0] mul_n, input logic [15:0] div_n,\n"
    "    input logic [15:0] cmp_n,\n"
    "    output logic [63:0] ops_add, output logic [63:0] ops_mul, output logic [63:0] ops_div,\n"
    "    output logic [63:0] ops_cmp, output logic [63:0] items);\n"
    "  assign {ops_add, ops_mul, ops_div, ops_cmp, items} = '0;\n"
    "endmodule\n";

// The shared helpers every block is read with (absolute paths), the counter stub in place of
// texsim_op_counters unless the counters are asked for.
std::vector<std::string> helper_files(const std::vector<fs::path>& files,
                                      const std::string& out_dir, const StudyRtlOptions& opt) {
  std::vector<std::string> helpers;
  for (const fs::path& file : files) {
    if (!is_helper(file)) continue;
    if (file.stem() == "texsim_op_counters" && !opt.with_counters) {
      const fs::path stub = fs::absolute(out_dir) / "rtl_work" / "texsim_op_counters_stub.v";
      fs::create_directories(stub.parent_path());
      std::ofstream(stub) << kCounterStub;
      helpers.push_back(stub.string());
    } else {
      helpers.push_back(fs::absolute(file).string());
    }
  }
  // The sampler's log2 table is generated (gen_rtl_params); unused modules are dropped by
  // `hierarchy -top`, so it is read with every block.
  const std::string gen = synth::generated_include_dir();
  std::error_code ec;
  if (!gen.empty() && fs::is_regular_file(fs::path(gen) / "texsim_sampler_log2.v", ec)) {
    helpers.push_back((fs::path(gen) / "texsim_sampler_log2.v").string());
  }
  return helpers;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The other blocks that `block` instantiates (the sampler's bilinear_lerp), read with it.
std::vector<fs::path> blocks_inside(const std::vector<fs::path>& files, const fs::path& block) {
  const std::string source = slurp(block);
  std::vector<fs::path> inside;
  for (const fs::path& f : files) {
    if (f == block || is_helper(f)) continue;
    // An instance: NAME #( or NAME instance_name (.
    const std::regex inst("\\b" + f.stem().string() + "\\s*(#\\s*\\(|[A-Za-z_]\\w*\\s*\\()");
    if (std::regex_search(source, inst)) inside.push_back(fs::absolute(f));
  }
  return inside;
}

struct Row {
  std::string block, params;
  RtlStudyPoint point;
  synth::SynthResult r;
};

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : " ") + x;
  return s.empty() ? "-" : s;
}

std::vector<std::string> cells_of(const Row& row) {
  const synth::SynthResult& r = row.r;
  std::string fallback =
      r.lut_multipliers ? std::to_string(r.lut_multipliers) + " $mul in LUTs" : "no";
  if (r.pnr_without_dsp) fallback += "; placed without DSPs (> 8 SB_MAC16)";
  const RtlStudyPoint& pt = row.point;
  std::vector<std::string> c = {row.block, row.params, pt.max_error.empty() ? "-" : pt.max_error,
                                pt.latency.empty() ? "-" : pt.latency};
  if (!r.error.empty()) {
    c.insert(c.end(), {"-", "-", "-", "-", "-", "-", "-", "-", "-", "-", "-", "-", "0", r.error});
    return c;
  }
  c.push_back(r.generic_cells > 0 ? std::to_string(r.generic_cells) : "-");
  c.push_back(joined(r.multipliers));
  for (const int v : {r.lut4, r.dff, r.carry, r.mac16, r.ram}) c.push_back(std::to_string(v));
  c.push_back(fallback);
  c.push_back(synth::up5k_fit(r));
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

// The measured area fed back to the C++ timing model: a [tech.block_area] table (SB_LUT4 of
// every block built at its generated parameters) for a scene's [tech]; blocks with no report
// block of their own are listed under their module name, which matches no report block.
std::string tech_toml(const std::vector<Row>& rows, bool with_counters) {
  std::string s =
      "# generated by texsim study rtl (docs/rtl/study.md): SB_LUT4 of each RTL block on the\n"
      "# iCE40 UP5K at its generated parameters (rtl_model/params/rtl_params.h), op counters " +
      std::string(with_counters ? "included" : "left out") +
      ".\n"
      "# Copy the table into a scene's [tech]: a report block of that name then shows these LUTs\n"
      "# as its area (in LUT4, not adder-equivalents). Module-name keys match no report block.\n"
      "[tech.block_area]\n";
  for (const Row& row : rows) {
    const synth::SynthResult& r = row.r;
    if (!r.error.empty() || !rtl_study_is_generated(row.block, row.point.params)) continue;
    const std::string name = rtl_report_block(row.block);
    s += "\"" + (name.empty() ? row.block : name) + "\" = " + std::to_string(r.lut4) + "  # " +
         row.block + ": " + std::to_string(r.dff) + " DFF, " + std::to_string(r.carry) +
         " SB_CARRY, " + std::to_string(r.mac16) + " SB_MAC16\n";
  }
  return s;
}

void write_outputs(const std::string& out_dir, const std::vector<Row>& rows,
                   const StudyRtlOptions& opt, const std::string& note) {
  StudyTable t({"block", "parameters", "max error (C++)", "latency", "generic cells", "multipliers",
                "LUT4", "DFF", "carry", "SB_MAC16", "BRAM", "DSP fallback", "fits UP5K",
                "Fmax median MHz", "Fmax min", "Fmax max", "seeds routed", "notes"},
               "llrrrlrrrrrllrrrrl");
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
  files.text("rtl_tech.toml", tech_toml(rows, opt.with_counters));
  files.text(
      "rtl.md",
      "# RTL blocks on the iCE40 UP5K\n\nyosys synth / synth_ice40 -dsp, "
      "nextpnr-ice40 --up5k at seeds 1.." +
          std::to_string(opt.seeds) +
          " (blocks wrapped in shift registers for "
          "place and route; resource counts are the block's alone). " +
          (opt.with_counters ? "Op counters included. "
                             : "Op counters left out (a stub; --with-counters keeps them). ") +
          note + "\n\n" + t.markdown());
  if (series.empty()) return;
  PlotSpec spec;
  spec.title = "RTL blocks on iCE40 UP5K: LUT4 vs median Fmax over " + std::to_string(opt.seeds) +
               " placer seeds";
  spec.xlabel = "SB_LUT4 cells";
  spec.ylabel = "Fmax (MHz, median over seeds)";
  spec.pareto = ParetoFront::higher_y_better;
  for (const auto& [block, points] : series) spec.series.push_back(labelled_series(block, points));
  files.plot("rtl.png", spec);
}

// The sampler's error cell at the point's S and M, computed once per (S, M).
std::string sampler_error_of(const RtlStudyPoint& pt, const StudyRtlOptions& opt,
                             std::map<std::pair<int64_t, int64_t>, std::string>& errors,
                             std::ostream& log) {
  int64_t s = 0, m = 0;
  for (const auto& [n, v] : pt.params) {
    if (n == "S") s = v;
    if (n == "M") m = v;
  }
  const auto key = std::make_pair(s, m);
  if (const auto it = errors.find(key); it != errors.end()) return it->second;
  log << " (C++ error at S=" << s << " M=" << m << ")" << std::flush;
  return errors[key] = opt.sampler_error(static_cast<int>(s), static_cast<int>(m));
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
  for (const std::string& b : opt.blocks) {
    const bool found = std::any_of(files.begin(), files.end(), [&](const fs::path& f) {
      return f.stem() == b && !is_helper(f);
    });
    if (!found) throw InputError("--block " + b, "no block " + b + ".v or .sv in " + opt.rtl_dir);
  }
  std::vector<int> seeds;
  for (int s = 1; s <= opt.seeds; ++s) seeds.push_back(s);
  const std::vector<std::string> helpers = helper_files(files, out_dir, opt);
  std::vector<std::string> includes = {opt.rtl_dir};
  if (!synth::generated_include_dir().empty()) includes.push_back(synth::generated_include_dir());
  std::vector<Row> rows;
  std::map<std::pair<int64_t, int64_t>, std::string> errors;  // sampler (S, M) -> error cell
  for (const fs::path& file : files) {
    const std::string top = file.stem().string();
    if (is_helper(file) || (!opt.blocks.empty() && std::find(opt.blocks.begin(), opt.blocks.end(),
                                                             top) == opt.blocks.end())) {
      continue;
    }
    // The block, and its earlier form when asked for and there is one.
    std::vector<std::pair<std::string, fs::path>> forms = {{top, file}};
    const fs::path earlier =
        file.parent_path() / "ref" / (top + "_comb" + file.extension().string());
    std::error_code ec;
    if (opt.with_earlier && fs::is_regular_file(earlier, ec)) {
      forms.emplace_back(top + "_comb", earlier);
    }
    for (const Sweep& p : combinations(slurp(file), opt)) {
      for (const auto& [module, source] : forms) {
        fs::path work = fs::absolute(out_dir) / "rtl_work" / module;
        for (const auto& [n, v] : p) work += "_" + n + std::to_string(v);
        Row row{module, params_text(p), rtl_study_point(top, p), {}};
        log << "study rtl: " << module << " " << row.params << " ..." << std::flush;
        if (top == "texsim_sampler" && opt.sampler_error) {
          row.point.max_error = sampler_error_of(row.point, opt, errors, log);
        }
        if (!row.point.problem.empty()) {
          row.r.error = row.point.problem;
        } else {
          synth::SynthJob job{{fs::absolute(source).string()},
                              includes,
                              module,
                              row.point.params,
                              work.string(),
                              seeds};
          job.generic_cells = opt.generic_cells;
          job.files.insert(job.files.end(), helpers.begin(), helpers.end());
          for (const fs::path& sub : blocks_inside(files, file)) job.files.push_back(sub.string());
          row.r = synth::run_synth(job, tools);
        }
        log << (row.r.error.empty() ? " " + std::to_string(row.r.lut4) + " LUT4" : " failed")
            << "\n";
        rows.push_back(std::move(row));
      }
    }
  }
  write_outputs(out_dir, rows, opt, note);
  log << "study rtl: wrote " << out_dir << "/rtl.csv, rtl.md, rtl_tech.toml\n";
  return 0;
}

}  // namespace texsim
