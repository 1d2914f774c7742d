#include "pipeline/app/sweep.h"

#include <toml++/toml.h>

#include <algorithm>
#include <atomic>
#include <charconv>
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
#include "blocks/base/input_file.h"
#include "blocks/base/printable.h"
#include "blocks/base/shell_quote.h"
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

namespace {

// The grid's axes as "KEY=VALUE" strings, one vector per key.
std::vector<std::vector<std::string>> grid_axes(const toml::table& root, const std::string& path) {
  std::vector<std::vector<std::string>> axes;
  const toml::table* g = root["grid"].as_table();
  if (!g) return axes;
  size_t text = 0;
  for (const auto& [k, v] : *g) {
    const toml::array* a = v.as_array();
    if (!a || a->empty())
      throw InputError(ConfigReader(*g, path, "grid").where(&v),
                       "grid." + std::string(k.str()) + ": expected a non-empty array of values");
    // Every value repeats the key: bounded before the strings are made.
    text += (k.length() + 1 + sizeof(std::string)) * std::min(a->size(), kMaxSweepJobs + 1);
    if (a->size() > kMaxSweepJobs || text > kMaxSweepJobText)
      throw InputError(path, "grid." + std::string(k.str()) + ": more than " +
                                 std::to_string(a->size() > kMaxSweepJobs ? kMaxSweepJobs : text) +
                                 (a->size() > kMaxSweepJobs ? " values, the job limit" : " bytes"));
    axes.emplace_back();
    for (const toml::node& e : *a) axes.back().push_back(std::string(k.str()) + "=" + toml_text(e));
  }
  return axes;
}

// Jobs = inputs x every axis's size, computed without overflow: a grid beyond kMaxSweepJobs (or
// whose jobs' text would pass kMaxSweepJobText) is refused before a job is made.
size_t checked_job_count(size_t inputs, const std::vector<std::vector<std::string>>& axes,
                         size_t input_text, const std::string& path) {
  const auto refuse = [&](const std::string& why) {
    throw InputError(path, "the sweep " + why + " (" + std::to_string(inputs) + " input(s) x " +
                               std::to_string(axes.size()) +
                               " grid axes; docs/cli.md#input-limits)");
  };
  size_t jobs = inputs, text = input_text;
  for (const auto& a : axes) {
    if (jobs > kMaxSweepJobs / a.size())
      refuse("has more than " + std::to_string(kMaxSweepJobs) + " jobs, the limit");
    jobs *= a.size();
    size_t longest = 0;
    for (const std::string& v : a) longest = std::max(longest, v.size());
    text += longest + sizeof(std::string);
    if (text > kMaxSweepJobText) refuse("has a job whose overrides are too long");
  }
  if (jobs > kMaxSweepJobs)
    refuse("has more than " + std::to_string(kMaxSweepJobs) + " jobs, the limit");
  if (jobs != 0 && text > kMaxSweepJobText / jobs)
    refuse("would hold more than " + std::to_string(kMaxSweepJobText >> 20) +
           " MiB of job inputs and overrides");
  return jobs;
}

// Inputs: every scene alone, every trace with every scene (or alone); their count is checked
// before they are made.
std::vector<std::pair<std::string, std::string>> sweep_inputs(
    const std::vector<std::string>& scenes, const std::vector<std::string>& traces,
    const std::string& path) {
  const size_t per_trace = std::max<size_t>(scenes.size(), 1);
  if (!traces.empty() && traces.size() > kMaxSweepJobs / per_trace)
    throw InputError(path, "the sweep has more than " + std::to_string(kMaxSweepJobs) +
                               " jobs, the limit (" + std::to_string(traces.size()) + " traces x " +
                               std::to_string(scenes.size()) + " scenes)");
  const size_t count = traces.empty() ? scenes.size() : traces.size() * per_trace;
  size_t longest = 2 * sizeof(std::string);
  for (const auto& list : {&scenes, &traces}) {
    size_t l = 0;
    for (const std::string& p : *list) l = std::max(l, p.size());
    longest += l;
  }
  if (count > kMaxSweepJobText / longest)
    throw InputError(path, "the sweep's inputs would hold more than " +
                               std::to_string(kMaxSweepJobText >> 20) + " MiB of paths");
  std::vector<std::pair<std::string, std::string>> inputs;
  if (traces.empty()) {
    for (const auto& sc : scenes) inputs.emplace_back(sc, "");
  } else {
    for (const auto& tr : traces) {
      if (scenes.empty()) inputs.emplace_back("", tr);
      for (const auto& sc : scenes) inputs.emplace_back(sc, tr);
    }
  }
  return inputs;
}

}  // namespace

Sweep load_sweep(const std::string& path) {
  const toml::table root = parse_toml(read_input_file(path, "sweep file", kMaxTextInput), path);
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
  const std::vector<std::pair<std::string, std::string>> inputs =
      sweep_inputs(scenes, traces, path);
  const std::vector<std::vector<std::string>> axes = grid_axes(root, path);
  size_t input_text = 0;
  for (const auto& [scene, trace] : inputs)
    input_text = std::max(input_text, scene.size() + trace.size());
  const size_t jobs = checked_job_count(inputs.size(), axes, input_text, path);
  const size_t combos = jobs / inputs.size();
  s.jobs.reserve(jobs);
  int id = 0;
  for (const auto& [scene, trace] : inputs) {
    for (size_t c = 0; c < combos; ++c) {
      SweepJob j{id++, scene, trace, {}};
      size_t rest = c;
      j.overrides.resize(axes.size());
      for (size_t a = axes.size(); a-- > 0;) {  // last axis fastest
        j.overrides[a] = axes[a][rest % axes[a].size()];
        rest /= axes[a].size();
      }
      s.jobs.push_back(std::move(j));
    }
  }
  return s;
}

namespace {

// A whole number in [0, INT_MAX]: digits only (no sign, space or fraction), nothing after.
bool whole_number(std::string_view s, int& v) {
  if (s.empty() || s.front() < '0' || s.front() > '9') return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && end == s.data() + s.size();
}

}  // namespace

void parse_sweep_shard(std::string_view text, int& shard, int& shards) {
  const size_t slash = text.find('/');
  int k = 0, n = 0;
  if (slash == std::string_view::npos || !whole_number(text.substr(0, slash), k) ||
      !whole_number(text.substr(slash + 1), n) || k < 1 || n < 1 || k > n)
    throw InputError("--shard " + printable(text),
                     "expected K/N, two whole numbers with 1 <= K <= N (for example 2/4)");
  shard = k;
  shards = n;
}

int parse_sweep_job(std::string_view text) {
  int j = 0;
  if (!whole_number(text, j))
    throw InputError("--job " + printable(text),
                     "expected a job number, a whole number from 0 (`texsim sweep FILE --list` "
                     "prints the jobs)");
  return j;
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
bool run_job(const SweepJob& j, const std::string& out, int threads, bool truth_cache,
             std::string& log) {
  RunOptions r;
  r.truth_cache = truth_cache;
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

// The --output value of the #SBATCH line: the task logs in directory `dir`. sbatch reads those
// lines itself, not the shell: the value goes in double quotes (spaces, quotes and '#' stay in the
// path), '%' starts a filename pattern ('%%' is one '%'). A line break would end the directive and
// start another, and sbatch gives '\\' and '"' meanings of their own: such a path is refused.
std::string sbatch_output(const std::string& dir) {
  for (const char c : dir) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f || c == '"' || c == '\\')
      throw InputError(printable(dir),
                       "the sweep's output directory holds a control character, '\"' or '\\', "
                       "which cannot be written into the #SBATCH --output line of a Slurm "
                       "script; choose another --out");
  }
  std::string q = "\"";
  for (const char c : dir) q += c == '%' ? std::string("%%") : std::string(1, c);
  return q + "/slurm-%A_%a.log\"";
}

// OUT/sweep.sbatch: a job array whose task J runs `texsim sweep FILE --out OUT --job J`. Every
// value is quoted by shell_quote and every path is absolute, so a task started in any
// directory runs exactly that command and nothing else.
void write_slurm(const Sweep& sw, const SweepOptions& opt, const std::string& out,
                 std::ostream& log) {
  const std::string abs_out = fs::absolute(out).lexically_normal().string();
  const std::string abs_sweep = fs::absolute(sw.path).lexically_normal().string();
  const std::string command = fs::absolute(opt.command).lexically_normal().string();
  std::ostringstream s;
  s << "#!/bin/bash\n# texsim sweep: one array task per job (docs/sweeps.md).\n"
    << "#SBATCH --job-name=texsim-sweep\n#SBATCH --array=0-" << sw.jobs.size() - 1 << "\n"
    << "#SBATCH --cpus-per-task=1\n#SBATCH --output=" << sbatch_output(abs_out) << "\n"
    << "exec " << shell_quote(command, "texsim command") << " sweep "
    << shell_quote(abs_sweep, "sweep file") << " --out " << shell_quote(abs_out, "--out")
    << (opt.truth_cache ? "" : " --no-truth-cache") << " --job \"$SLURM_ARRAY_TASK_ID\"\n";
  ensure_dir(out);
  write_file_atomic(out + "/sweep.sbatch", s.str());
  log << "texsim sweep: wrote " << printable(abs_out) << "/sweep.sbatch (" << sw.jobs.size()
      << " array tasks); submit with: sbatch "
      << printable(shell_quote(abs_out + "/sweep.sbatch", "--out")) << "\n";
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
      ok[i] = run_job(todo[i], out, 1, opt.truth_cache, logs[i]) ? 1 : 0;
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
  if (v.find_first_of(",\"\n\r") == std::string::npos) return v;
  std::string q = "\"";
  for (char c : v) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// A Markdown table cell: line breaks and tabs as spaces, other control characters shown as
// \xNN, and '|' and '\' escaped so the text cannot end the cell.
std::string md_cell(std::string v) {
  std::replace_if(
      v.begin(), v.end(), [](char c) { return c == '\n' || c == '\r' || c == '\t'; }, ' ');
  std::string out;
  for (const char c : printable(v)) {
    if (c == '|' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

// Refuses JSON nested deeper than kMaxMergeJsonDepth before it is parsed (the parser and the
// values it builds recurse once per level): brackets outside strings are counted.
void check_json_depth(const std::string& text, const std::string& path) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxMergeJsonDepth)
        throw InputError(path, "JSON nested deeper than " + std::to_string(kMaxMergeJsonDepth) +
                                   " levels (byte " + std::to_string(i) + ")");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

Json read_json(const fs::path& p, const char* what) {
  const std::string text = read_input_file(p.string(), what, kMaxJsonInput);
  check_json_depth(text, p.string());
  try {
    return Json::parse(text);
  } catch (const Json::exception& e) {
    throw InputError(p.string(), std::string("not a valid JSON file: ") + e.what());
  }
}

// The columns of merged.csv: a label and how to read it from the job and report.
struct Column {
  const char* name;
  const char* where;  // "job" or "report"
  const char* key;    // path of object keys
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

// The value at `path` ("/a/b": object keys) in `j`, or null when a key is absent; a value on
// the way that is not an object is an InputError naming `file`.
const Json* lookup(const Json& j, std::string_view path, const std::string& file) {
  const Json* v = &j;
  for (size_t i = 1; i <= path.size();) {
    const size_t end = std::min(path.find('/', i), path.size());
    if (!v->is_object())
      throw InputError(file, std::string(i > 1 ? path.substr(0, i - 1) : "the file") +
                                 ": expected a JSON object");
    const auto it = v->find(std::string(path.substr(i, end - i)));
    if (it == v->end()) return nullptr;
    v = &*it;
    i = end + 1;
  }
  return v;
}

// What merge and the ledger read from a job.json and a report.json, checked for type: the job
// number an integer, scene and trace strings, overrides an array of strings; the report's
// figures numbers (or null), its provenance strings.
void check_merge_inputs(const Json& job, const Json& report, const fs::path& dir) {
  const std::string jf = (dir / "job.json").string(), rf = (dir / "report.json").string();
  const auto fail = [](const std::string& f, const std::string& key, const char* want) {
    throw InputError(f, key + ": expected " + want);
  };
  if (!job.is_object()) fail(jf, "the file", "a JSON object");
  if (const Json* v = lookup(job, "/job", jf); v && !v->is_number_integer())
    fail(jf, "job", "an integer");
  for (const char* k : {"/scene", "/trace"}) {
    if (const Json* v = lookup(job, k, jf); v && !v->is_string()) fail(jf, k + 1, "a string");
  }
  if (const Json* v = lookup(job, "/overrides", jf)) {
    if (!v->is_array()) fail(jf, "overrides", "an array of strings");
    for (const Json& e : *v) {
      if (!e.is_string()) fail(jf, "overrides", "an array of strings");
    }
  }
  if (!report.is_object()) fail(rf, "the file", "a JSON object");
  for (const Column& c : kColumns) {
    if (std::string(c.where) != "report") continue;
    if (const Json* v = lookup(report, c.key, rf); v && !v->is_number() && !v->is_null())
      fail(rf, c.key + 1, "a number");
  }
  for (const char* k : {"/provenance/texsim_version", "/provenance/command"}) {
    if (const Json* v = lookup(report, k, rf); v && !v->is_string()) fail(rf, k + 1, "a string");
  }
}

std::string cell(const MergedRow& r, const Column& c) {
  const Json* v = lookup(std::string(c.where) == "job" ? r.job : r.report, c.key, "");
  if (v == nullptr) return "";
  if (v->is_string()) return v->get<std::string>();
  if (v->is_array()) {
    std::string s;
    for (const auto& e : *v) s += (s.empty() ? "" : "; ") + e.get<std::string>();
    return s;
  }
  return v->dump();
}

// merged.png: PSNR against cycles per fragment, a point per job labelled with its number, a
// series per input (scene or trace) in order of first appearance.
void write_merged_plot(const std::vector<MergedRow>& rows, const std::string& path) {
  PlotSpec spec;
  spec.title = "Sweep: image error against cost, one point per job";
  spec.xlabel = "cycles per fragment";
  spec.ylabel = "PSNR (dB)";
  spec.pareto = ParetoFront::higher_y_better;
  for (const MergedRow& r : rows) {
    const Json* cpf = lookup(r.report, "/cycles_per_fragment", "");
    const Json* psnr = lookup(r.report, "/accuracy/psnr_db", "");
    if (!cpf || !psnr || !cpf->is_number() || !psnr->is_number()) continue;
    const std::string input =
        cell(r, kColumns[2]).empty() ? cell(r, kColumns[1]) : cell(r, kColumns[2]);
    const std::string name = fs::path(input).filename().string();
    auto it = std::find_if(spec.series.begin(), spec.series.end(),
                           [&](const PlotSeries& s) { return s.label == name; });
    if (it == spec.series.end()) {
      spec.series.push_back({name, {}, {}, false, {}});
      it = spec.series.end() - 1;
    }
    it->x.push_back(cpf->get<double>());
    it->y.push_back(psnr->get<double>());
    it->point_labels.push_back("job " + cell(r, kColumns[0]));
  }
  write_plot_png(path, spec);
}

// The rows of the job-* directories of `dir`, in job order.
void read_merge_dir(const std::string& dir, std::vector<MergedRow>& rows) {
  std::vector<fs::path> jobs;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_directory() && e.path().filename().string().rfind("job-", 0) == 0)
      jobs.push_back(e.path());
  }
  std::sort(jobs.begin(), jobs.end());
  for (const fs::path& j : jobs) {
    if (!fs::exists(j / "job.json") || !fs::exists(j / "report.json")) {
      throw InputError(j.string(), "has no job.json and report.json (a job that did not finish?)");
    }
    MergedRow row{read_json(j / "job.json", "job.json"),
                  read_json(j / "report.json", "report.json"), ""};
    check_merge_inputs(row.job, row.report, j);
    row.report_sha1 = digest_file("report", (j / "report.json").string()).sha1;
    rows.push_back(std::move(row));
  }
}

// The rows of every directory of `dirs`, in order; a directory given twice (by any name) is
// refused, as it would repeat each of its rows.
std::vector<MergedRow> read_merge_rows(const std::vector<std::string>& dirs) {
  std::vector<MergedRow> rows;
  std::vector<std::pair<fs::path, std::string>> seen;
  for (const std::string& d : dirs) {
    try {
      if (!fs::is_directory(d)) throw InputError(d, "not a directory");
      const fs::path canon = fs::canonical(d);
      for (const auto& [c, name] : seen) {
        if (c == canon) throw InputError(d, "given twice (the same directory as " + name + ")");
      }
      seen.emplace_back(canon, d);
      read_merge_dir(d, rows);
    } catch (const fs::filesystem_error& e) {  // an unreadable directory
      throw InputError(e.path1().empty() ? d : e.path1().string(), e.code().message());
    }
  }
  return rows;
}

}  // namespace

int merge_sweeps(const std::vector<std::string>& dirs, const std::string& out, std::ostream& log,
                 bool plot) {
  const std::vector<MergedRow> rows = read_merge_rows(dirs);
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
      md << " " << md_cell(cell(r, c)) << " |";
    }
    csv << "\n";
    md << "\n";
  }
  ensure_dir(out);
  write_file_atomic(out + "/merged.csv", csv.str());
  write_file_atomic(out + "/merged.md", md.str());
  if (plot) write_merged_plot(rows, out + "/merged.png");
  ResultsLedger ledger(out + "/ledger.sqlite");
  int added = 0;
  for (const MergedRow& r : rows) added += ledger.add(r.job, r.report, r.report_sha1) ? 1 : 0;
  log << "texsim merge: " << rows.size() << " jobs -> " << printable(out) << "/merged.csv, "
      << printable(out) << "/merged.md" << (plot ? ", " + printable(out) + "/merged.png" : "")
      << "; ledger " << printable(out) << "/ledger.sqlite: " << added << " new, " << ledger.rows()
      << " in all\n";
  return static_cast<int>(rows.size());
}

}  // namespace texsim
