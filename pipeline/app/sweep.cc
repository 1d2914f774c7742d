#include "pipeline/app/sweep.h"

#include <toml++/toml.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "blocks/base/atomic_file.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "pipeline/app/results_ledger.h"
#include "pipeline/app/run.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/report/plot.h"
#include "pipeline/report/provenance.h"

namespace texsim {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// A list of strings at `key` of `t` (absent: empty), paths made relative to the sweep file.
std::vector<std::string> paths(const toml::table& t, const ConfigReader& r, const char* key) {
  std::vector<std::string> out;
  const toml::node* n = t.get(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a) r.fail(key, "expected an array of strings");
  const fs::path dir = fs::path(r.source()).parent_path();
  for (const toml::node& e : *a) {
    const auto s = e.value<std::string>();
    if (!s) throw InputError(r.where(&e), std::string("sweep.") + key + ": expected a string");
    out.push_back(*s == "default" || fs::path(*s).is_absolute() ? *s : (dir / *s).string());
  }
  return out;
}

std::string toml_text(const toml::node& n) {
  std::ostringstream s;
  n.visit([&](auto&& v) { s << toml::toml_formatter(v); });
  return s.str();
}

}  // namespace

Sweep load_sweep(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open sweep file");
  std::stringstream text;
  text << in.rdbuf();
  const toml::table root = parse_toml(text.str(), path);
  ConfigReader(root, path, "sweep file").reject_unknown({"sweep", "grid"});
  const toml::table* sw = root["sweep"].as_table();
  if (!sw) throw InputError(path, "needs a [sweep] table with scenes = [...] or traces = [...]");
  const ConfigReader sr(*sw, path, "sweep");
  sr.reject_unknown({"scenes", "traces", "out"});
  Sweep s;
  s.path = path;
  s.out = sr.get_string("out", "out/sweep");
  if (sw->contains("out") && !fs::path(s.out).is_absolute())
    s.out = (fs::path(path).parent_path() / s.out).string();
  const std::vector<std::string> scenes = paths(*sw, sr, "scenes"),
                                 traces = paths(*sw, sr, "traces");
  if (scenes.empty() && traces.empty())
    throw InputError(path, "sweep: scenes and traces are both empty");
  // Inputs: every scene alone, every trace with every scene (or alone).
  std::vector<std::pair<std::string, std::string>> inputs;
  if (traces.empty()) {
    for (const auto& sc : scenes) inputs.emplace_back(sc, "");
  } else {
    for (const auto& tr : traces) {
      if (scenes.empty()) inputs.emplace_back("", tr);
      for (const auto& sc : scenes) inputs.emplace_back(sc, tr);
    }
  }
  // Grid axes: "KEY=VALUE" strings per axis.
  std::vector<std::vector<std::string>> axes;
  if (const toml::table* g = root["grid"].as_table()) {
    for (const auto& [k, v] : *g) {
      const toml::array* a = v.as_array();
      if (!a || a->empty())
        throw InputError(ConfigReader(*g, path, "grid").where(&v),
                         "grid." + std::string(k.str()) + ": expected a non-empty array of values");
      axes.emplace_back();
      for (const toml::node& e : *a)
        axes.back().push_back(std::string(k.str()) + "=" + toml_text(e));
    }
  }
  size_t combos = 1;
  for (const auto& a : axes) combos *= a.size();
  if (combos * inputs.size() > 100000)
    throw InputError(path, "the sweep has more than 100000 jobs");
  int id = 0;
  for (const auto& [scene, trace] : inputs) {
    for (size_t c = 0; c < combos; ++c) {
      SweepJob j{id++, scene, trace, {}};
      size_t rest = c;
      std::vector<std::string> sets(axes.size());
      for (size_t a = axes.size(); a-- > 0;) {  // last axis fastest
        sets[a] = axes[a][rest % axes[a].size()];
        rest /= axes[a].size();
      }
      j.overrides = sets;
      s.jobs.push_back(j);
    }
  }
  return s;
}

namespace {

std::string job_dir(const std::string& out, int id) {
  std::ostringstream s;
  s << out << "/job-" << std::setw(5) << std::setfill('0') << id;
  return s.str();
}

Json job_json(const SweepJob& j) {
  return {{"job", j.id}, {"scene", j.scene}, {"trace", j.trace}, {"overrides", j.overrides}};
}

// One job into its own directory; its log lines go to `log` (a string per job).
bool run_job(const SweepJob& j, const std::string& out, int threads, std::string& log) {
  RunOptions r;
  r.scene = j.scene;
  r.trace = j.trace;
  r.overrides = j.overrides;
  r.out = job_dir(out, j.id);
  r.threads = threads;
  r.command = "texsim sweep (job " + std::to_string(j.id) + ")";
  std::ostringstream s;
  try {
    run_simulation(r, s);
    write_file_atomic(r.out + "/job.json", job_json(j).dump(2) + "\n");
    log = "job " + std::to_string(j.id) + ": " + s.str();
    return true;
  } catch (const InputError& e) {
    log = "job " + std::to_string(j.id) + ": error: " + e.what() + "\n";
    return false;
  }
}

void write_slurm(const Sweep& sw, const SweepOptions& opt, const std::string& out,
                 std::ostream& log) {
  ensure_dir(out);
  std::ostringstream s;
  s << "#!/bin/bash\n# texsim sweep " << sw.path << ": one array task per job (docs/sweeps.md).\n"
    << "#SBATCH --job-name=texsim-sweep\n#SBATCH --array=0-" << sw.jobs.size() - 1 << "\n"
    << "#SBATCH --cpus-per-task=1\n#SBATCH --output=" << out << "/slurm-%A_%a.log\n"
    << "exec '" << opt.command << "' sweep '" << sw.path << "' --out '" << out
    << "' --job \"$SLURM_ARRAY_TASK_ID\"\n";
  write_file_atomic(out + "/sweep.sbatch", s.str());
  log << "texsim sweep: wrote " << out << "/sweep.sbatch (" << sw.jobs.size()
      << " array tasks); submit with: sbatch " << out << "/sweep.sbatch\n";
}

}  // namespace

int run_sweep(const std::string& sweep_path, const SweepOptions& opt, std::ostream& log) {
  const Sweep sw = load_sweep(sweep_path);
  const std::string out = opt.out.empty() ? sw.out : opt.out;
  if (opt.list) {
    for (const SweepJob& j : sw.jobs) log << job_json(j).dump() << "\n";
    return 0;
  }
  if (opt.slurm) {
    write_slurm(sw, opt, out, log);
    return 0;
  }
  std::vector<SweepJob> todo;
  for (const SweepJob& j : sw.jobs) {
    const bool in_shard = opt.shards == 0 || j.id % opt.shards == opt.shard - 1;
    if ((opt.job < 0 && in_shard) || j.id == opt.job) todo.push_back(j);
  }
  if (opt.job >= static_cast<int>(sw.jobs.size())) {
    throw InputError(sweep_path, "--job " + std::to_string(opt.job) + ": the sweep has " +
                                     std::to_string(sw.jobs.size()) + " jobs");
  }
  ensure_dir(out);
  // Jobs in parallel, each on one thread; logs printed in job order.
  std::vector<std::string> logs(todo.size());
  std::vector<char> ok(todo.size(), 0);
  const int pool =
      std::min<int>(resolve_threads(opt.jobs), static_cast<int>(std::max<size_t>(todo.size(), 1)));
  std::atomic<size_t> next{0};
  parallel_range(static_cast<size_t>(pool), pool, [&](size_t, size_t) {
    for (size_t i = next++; i < todo.size(); i = next++)
      ok[i] = run_job(todo[i], out, 1, logs[i]) ? 1 : 0;
  });
  int failed = 0;
  for (size_t i = 0; i < todo.size(); ++i) {
    log << logs[i];
    failed += ok[i] ? 0 : 1;
  }
  log << "texsim sweep: " << todo.size() - failed << " of " << todo.size() << " jobs done in "
      << out << (failed ? ", " + std::to_string(failed) + " failed" : "") << "\n";
  return failed ? 2 : 0;
}

namespace {

// One merged row: the job and its report's headline figures.
struct MergedRow {
  Json job, report;
  std::string report_sha1;
};

std::string csv_field(std::string v) {
  if (v.find_first_of(",\"\n") == std::string::npos) return v;
  std::string q = "\"";
  for (char c : v) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

Json read_json(const fs::path& p) {
  std::ifstream in(p);
  try {
    return Json::parse(in);
  } catch (const Json::exception& e) {
    throw InputError(p.string(), std::string("not a valid JSON file: ") + e.what());
  }
}

// The columns of merged.csv: a label and how to read it from the job and report.
struct Column {
  const char* name;
  const char* where;  // "job" or "report"
  const char* key;    // JSON pointer
};
const Column kColumns[] = {
    {"job", "job", "/job"},
    {"scene", "job", "/scene"},
    {"trace", "job", "/trace"},
    {"overrides", "job", "/overrides"},
    {"fragments", "report", "/fragments"},
    {"cycles", "report", "/cycles"},
    {"cycles_per_fragment", "report", "/cycles_per_fragment"},
    {"psnr_db", "report", "/accuracy/psnr_db"},
    {"nmse", "report", "/accuracy/nmse"},
    {"max_abs", "report", "/accuracy/max_abs"},
    {"area_total", "report", "/area_total"},
    {"time_us", "report", "/physical/time_us"},
    {"cache_hit_rate", "report", "/cache/hit_rate"},
};

std::string cell(const MergedRow& r, const Column& c) {
  const Json& j = std::string(c.where) == "job" ? r.job : r.report;
  const Json::json_pointer ptr(c.key);
  if (!j.contains(ptr)) return "";
  const Json& v = j.at(ptr);
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::string s;
    for (const auto& e : v) s += (s.empty() ? "" : "; ") + e.get<std::string>();
    return s;
  }
  return v.dump();
}

// merged.png: PSNR against cycles per fragment, a point per job labelled with its number, a
// series per input (scene or trace) in order of first appearance.
void write_merged_plot(const std::vector<MergedRow>& rows, const std::string& path) {
  PlotSpec spec;
  spec.title = "Sweep: image error against cost, one point per job";
  spec.xlabel = "cycles per fragment";
  spec.ylabel = "PSNR (dB)";
  for (const MergedRow& r : rows) {
    const Json::json_pointer cpf("/cycles_per_fragment"), psnr("/accuracy/psnr_db");
    if (!r.report.contains(cpf) || !r.report.contains(psnr) || !r.report.at(psnr).is_number())
      continue;
    const std::string input =
        cell(r, kColumns[2]).empty() ? cell(r, kColumns[1]) : cell(r, kColumns[2]);
    const std::string name = fs::path(input).filename().string();
    auto it = std::find_if(spec.series.begin(), spec.series.end(),
                           [&](const PlotSeries& s) { return s.label == name; });
    if (it == spec.series.end()) {
      spec.series.push_back({name, {}, {}, false, {}});
      it = spec.series.end() - 1;
    }
    it->x.push_back(r.report.at(cpf).get<double>());
    it->y.push_back(r.report.at(psnr).get<double>());
    it->point_labels.push_back("job " + cell(r, kColumns[0]));
  }
  write_plot_png(path, spec);
}

}  // namespace

int merge_sweeps(const std::vector<std::string>& dirs, const std::string& out, std::ostream& log) {
  std::vector<MergedRow> rows;
  for (const std::string& d : dirs) {
    if (!fs::is_directory(d)) throw InputError(d, "not a directory");
    std::vector<fs::path> jobs;
    for (const auto& e : fs::directory_iterator(d)) {
      if (e.is_directory() && e.path().filename().string().rfind("job-", 0) == 0)
        jobs.push_back(e.path());
    }
    std::sort(jobs.begin(), jobs.end());
    for (const fs::path& j : jobs) {
      if (!fs::exists(j / "job.json") || !fs::exists(j / "report.json")) {
        throw InputError(j.string(),
                         "has no job.json and report.json (a job that did not finish?)");
      }
      rows.push_back({read_json(j / "job.json"), read_json(j / "report.json"),
                      digest_file("report", (j / "report.json").string()).sha1});
    }
  }
  if (rows.empty())
    throw InputError(dirs.empty() ? out : dirs.front(), "no job-* directories to merge");
  std::ostringstream csv, md;
  md << "# Sweep results\n\n|";
  for (const Column& c : kColumns) {
    csv << (&c == kColumns ? "" : ",") << c.name;
    md << " " << c.name << " |";
  }
  csv << "\n";
  md << "\n|";
  for (size_t i = 0; i < std::size(kColumns); ++i) md << "---|";
  md << "\n";
  for (const MergedRow& r : rows) {
    md << "|";
    for (const Column& c : kColumns) {
      csv << (&c == kColumns ? "" : ",") << csv_field(cell(r, c));
      md << " " << cell(r, c) << " |";
    }
    csv << "\n";
    md << "\n";
  }
  ensure_dir(out);
  write_file_atomic(out + "/merged.csv", csv.str());
  write_file_atomic(out + "/merged.md", md.str());
  write_merged_plot(rows, out + "/merged.png");
  ResultsLedger ledger(out + "/ledger.sqlite");
  int added = 0;
  for (const MergedRow& r : rows) added += ledger.add(r.job, r.report, r.report_sha1) ? 1 : 0;
  log << "texsim merge: " << rows.size() << " jobs -> " << out << "/merged.csv, " << out
      << "/merged.md, " << out << "/merged.png; ledger " << out << "/ledger.sqlite: " << added
      << " new, " << ledger.rows() << " in all\n";
  return static_cast<int>(rows.size());
}

}  // namespace texsim
