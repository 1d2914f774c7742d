#include "pipeline/app/tuner.h"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "blocks/base/printable.h"
#include "pipeline/app/material_override.h"
#include "pipeline/app/run.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/scene_overrides.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

namespace {

struct Budget {
  bool psnr = true;
  double value = 40;
  bool meets(double psnr_db, double nmse) const { return psnr ? psnr_db >= value : nmse <= value; }
};

Budget parse_budget(const std::string& text) {
  const size_t eq = text.find('=');
  Budget b;
  const std::string kind = text.substr(0, eq);
  size_t used = 0;
  try {
    b.value = std::stod(text.substr(eq + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (eq == std::string::npos || (kind != "psnr" && kind != "nmse") || used == 0 ||
      used != text.size() - eq - 1 || !std::isfinite(b.value) || (kind == "nmse" && b.value <= 0))
    throw InputError("--budget " + text, "expected psnr=<dB> or nmse=<positive value>");
  b.psnr = kind == "psnr";
  return b;
}

// The budget of one material: its own `budget = { ... }`, else the command line's.
std::string budget_text(const SceneMaterial& m, const std::string& command_line) {
  if (m.budget.kind.empty()) return command_line;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", m.budget.value);
  return m.budget.kind + "=" + buf;
}

// One knob of a material: a key of its table (dotted path) and the values tried, as TOML, in
// the order they are tried.
struct Knob {
  std::string path;
  std::vector<std::string> values;
};

constexpr const char* kVdKnobs[][2] = {{"evaluator", R"("p1" "p2" "p3" "exact")"},
                                       {"format", R"("fx8" "fx12" "fx16" "float")"}};

std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> w;
  std::istringstream in(s);
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

// The knobs the material's blocks have, in search order (front to back of the unit).
std::vector<Knob> knobs_for(const toml::table& t) {
  std::vector<Knob> k;
  if (t.contains("coords")) {
    k.push_back({"coords.method",
                 words(R"("heckbert" "incremental" "constant-depth" "quadratic-32" "affine-16")")});
    k.push_back({"coords.format", words(R"("float" "s16.16" "s20.28" "double")")});
    if (t.at_path("coords.derivs").value_or<std::string>("analytic") != "none") {
      k.push_back({"coords.derivs", words(R"("analytic" "quad" "accelerated-fd" "iterative")")});
    }
  }
  const bool vd_ewa = t.at_path("ewa.edge").value_or<std::string>("none") == "vd";
  const bool vd_spaf = t.at_path("spaf.coverage").value_or<std::string>("mask") == "vd";
  if (t.contains("ewa")) {
    k.push_back({"ewa.max_aniso", words("4 8 16")});
    k.push_back({"ewa.lut_bits", words("8 12 16")});
    k.push_back({"ewa.mip", words(R"("nearest" "linear")")});
    k.push_back({"ewa.arith", words(R"("fixed" "float")")});
  } else if (t.contains("spaf")) {
    k.push_back({"spaf.arith", words(R"("fixed" "float")")});
  } else if (t.contains("feline")) {
    k.push_back({"feline.max_probes", words("2 4 8 16")});
    k.push_back({"feline.arith", words(R"("fixed" "float")")});
  } else if (t.contains("multi_probe")) {
    k.push_back({"multi_probe.max_probes", words("2 4 8 16")});
  } else {
    k.push_back({"filter.mode", words(R"("nearest" "bilinear" "trilinear")")});
    k.push_back({"lod.aniso", words(R"("isotropic" "vulkan")")});
    k.push_back({"lod.max_aniso", words("2 4 8 16")});
    k.push_back({"filter.sub_texel_bits", words("2 4 6 8")});
    k.push_back({"filter.mipmap_bits", words("1 2 4 8")});
  }
  for (const auto& kv : kVdKnobs) {
    if (vd_ewa) k.push_back({std::string("ewa.vd.") + kv[0], words(kv[1])});
    if (vd_spaf) k.push_back({std::string("spaf.vd.") + kv[0], words(kv[1])});
  }
  return k;
}

// The footprint filters a material can take instead of the classic LOD + filter path.
constexpr const char* kFootprints[] = {"ewa", "spaf", "feline", "multi_probe"};

std::string family_of(const toml::table& t) {
  for (const char* f : kFootprints) {
    if (t.contains(f)) return f;
  }
  return "classic";
}

// `t` switched to filter family `family`: its own table if it is that family already; else the
// footprint table dropped and, for a footprint filter, that filter with its defaults (the lod
// and filter tables stay: checked but unused under a footprint filter).
toml::table with_family(const toml::table& t, const std::string& family) {
  toml::table c = copy_table(t);
  if (family_of(t) == family) return c;
  for (const char* f : kFootprints) c.erase(f);
  if (family != "classic") c.insert(family, toml::table{});
  return c;
}

// The filter families --families tries, in this order.
constexpr const char* kFamilies[] = {"classic", "ewa", "spaf", "feline", "multi_probe"};

// `t` with knob `path` set to `value` (TOML text). A new coordinate method keeps only the
// unit's own keys: the old method's block keys do not belong to it.
toml::table with_knob(const toml::table& t, const std::string& path, const std::string& value) {
  toml::table c = copy_table(t);
  toml::table doc = toml::parse("v = " + value);
  std::vector<std::string> parts;
  for (size_t b = 0, e = 0; e != std::string::npos; b = e + 1) {
    e = path.find('.', b);
    parts.push_back(path.substr(b, e == std::string::npos ? e : e - b));
  }
  if (path == "coords.method") {
    toml::table& co = sub_table(c, "coords");
    toml::table n;
    for (const char* key : {"derivs", "format", "datapath"}) {
      if (co.contains(key)) n.insert(key, *co.get(key));
    }
    co = std::move(n);
  }
  toml::table* at = &c;
  for (size_t i = 0; i + 1 < parts.size(); ++i) at = &sub_table(*at, parts[i]);
  at->insert_or_assign(parts.back(), *doc.get("v"));
  return c;
}

std::string unquoted(std::string s) {
  s.erase(std::remove(s.begin(), s.end(), '"'), s.end());
  return s;
}

// One candidate configuration of a material: its table, the knobs changed and its --set.
struct Candidate {
  toml::table table;
  std::map<std::string, std::string> set;
  std::string override;
};

// What one run of a candidate gave (or why it did not run).
struct Outcome {
  bool ran = false;
  std::string why_not;
  double cycles = 0, area = 0, psnr_db = 0, nmse = 0;
};

class Search {
 public:
  Search(const TuneOptions& opt, TuneResult& res, std::ostream& log)
      : opt_(opt), res_(res), log_(log) {}

  // One run of the scene with `extra` overrides (thread-safe: nothing shared is written).
  RunCapture run(const std::vector<std::string>& extra, const std::string& out = "",
                 bool ledger = false) const {
    RunOptions o;
    o.scene = opt_.scene;
    o.overrides = opt_.overrides;
    o.overrides.insert(o.overrides.end(), extra.begin(), extra.end());
    o.threads = opt_.threads;
    o.truth_cache = opt_.truth_cache;
    o.out = out.empty() ? opt_.out : out;
    o.ledger = ledger;
    o.command = "texsim run " + opt_.scene;
    for (const auto& s : o.overrides) o.command += " --set '" + s + "'";
    if (ledger) o.command += " --ledger";
    RunCapture c;
    c.write_outputs = !out.empty();
    o.capture = &c;
    std::ostringstream quiet;
    run_simulation(o, quiet);
    return c;
  }

  TuneMaterial material(const SceneMaterial& sm) {
    TuneMaterial tm;
    tm.name = sm.name;
    tm.budget = budget_text(sm, opt_.budget);
    budget_ = parse_budget(tm.budget);
    seen_.clear();
    const toml::table start = copy_table(*sm.effects);
    if (!descend(tm, start, {}))
      throw InputError(opt_.scene, "material '" + sm.name + "' does not run");
    // Every other filter family: one more descent from that family's defaults, so the points
    // are a superset of the search without families and the choice is never costlier.
    if (opt_.families) {
      for (const char* f : kFamilies) {
        if (f == family_of(start)) continue;
        if (!descend(tm, with_family(start, f), {{"family", f}}))
          log_ << "texsim tune: " << tm.name << ": family " << f << " does not run\n";
      }
    }
    choose(tm);
    return tm;
  }

 private:
  // Greedy coordinate descent from `from` (the knobs changed so far: `from_set`): each knob in
  // turn takes its best value with the others fixed; at most two passes (a second pass only
  // if the first moved). False if the starting point does not run.
  bool descend(TuneMaterial& tm, const toml::table& from,
               const std::map<std::string, std::string>& from_set) {
    toml::table cur = copy_table(from);
    std::map<std::string, std::string> cur_set = from_set;
    std::vector<Candidate> first;
    first.push_back({copy_table(cur), cur_set, material_override(tm.name, cur)});
    int best = eval(tm, first)[0];
    if (best < 0) return false;
    const std::vector<Knob> knobs = knobs_for(cur);
    for (int pass = 0; pass < 2; ++pass) {
      bool moved = false;
      for (const Knob& k : knobs) {
        std::vector<Candidate> cands;
        for (const std::string& v : k.values) {
          Candidate c{with_knob(cur, k.path, v), cur_set, ""};
          c.set[k.path] = unquoted(v);
          c.override = material_override(tm.name, c.table);
          cands.push_back(std::move(c));
        }
        const std::vector<int> idx = eval(tm, cands);
        int pick = -1;
        for (size_t j = 0; j < cands.size(); ++j) {
          const int i = idx[j];
          if (i >= 0 &&
              better(tm.points[static_cast<size_t>(i)], tm.points[static_cast<size_t>(best)])) {
            best = i;
            pick = static_cast<int>(j);
          }
        }
        if (pick < 0) continue;
        Candidate& c = cands[static_cast<size_t>(pick)];
        if (inline_toml(c.table) != inline_toml(cur)) moved = true;
        cur = std::move(c.table);
        cur_set = std::move(c.set);
      }
      if (!moved) break;
    }
    return true;
  }

  // a before b: meeting the budget first, then cheaper, then more accurate.
  bool better(const TunePoint& a, const TunePoint& b) const {
    if (a.meets != b.meets) return a.meets;
    const double ca = tune_cost(opt_, a), cb = tune_cost(opt_, b);
    if (!a.meets) return a.nmse < b.nmse || (a.nmse == b.nmse && ca < cb);
    return ca < cb || (ca == cb && a.nmse < b.nmse);
  }

  Outcome measure(const std::string& material, const std::string& override) const {
    Outcome o;
    try {
      const RunCapture c = run({override});
      const auto m = std::find(c.material_names.begin(), c.material_names.end(), material);
      const AccuracyMetrics& a = c.materials[static_cast<size_t>(m - c.material_names.begin())];
      o = {true, "", static_cast<double>(c.cycles), c.area, a.psnr_db, a.nmse};
    } catch (const InputError& e) {  // a refused configuration: skipped with a note
      o.why_not = e.what();
    }  // anything else stops the search: the pool rethrows it on the calling thread

    return o;
  }

  // Evaluates each candidate once (a configuration seen before is not run again); returns
  // each candidate's point index, -1 where it does not run. The new ones run as tasks on
  // opt.jobs threads; their points are appended in candidate order, as one after the other.
  std::vector<int> eval(TuneMaterial& tm, const std::vector<Candidate>& cands) {
    std::vector<size_t> todo;
    std::map<std::string, size_t> batch;
    for (size_t j = 0; j < cands.size(); ++j) {
      if (!seen_.contains(cands[j].override) && batch.emplace(cands[j].override, j).second)
        todo.push_back(j);
    }
    std::vector<Outcome> out(todo.size());
    parallel_tasks(todo.size(), opt_.jobs,
                   [&](size_t t) { out[t] = measure(tm.name, cands[todo[t]].override); });
    for (size_t t = 0; t < todo.size(); ++t) {
      const Candidate& c = cands[todo[t]];
      const Outcome& o = out[t];
      int index = -1;
      if (o.ran) {
        ++res_.runs;
        TunePoint p;
        for (const auto& [k, v] : c.set) {
          if (!p.label.empty()) p.label += ' ';
          p.label += k;
          p.label += '=';
          p.label += v;
        }
        if (p.label.empty()) p.label = "as configured";
        p.override = c.override;
        p.cycles = o.cycles;
        p.area = o.area;
        p.psnr_db = o.psnr_db;
        p.nmse = o.nmse;
        p.meets = budget_.meets(o.psnr_db, o.nmse);
        tm.points.push_back(p);
        index = static_cast<int>(tm.points.size()) - 1;
      } else {
        log_ << "texsim tune: " << tm.name << ": skipped (" << o.why_not << ")\n";
      }
      seen_[c.override] = index;
    }
    std::vector<int> idx(cands.size());
    for (size_t j = 0; j < cands.size(); ++j) idx[j] = seen_.at(cands[j].override);
    return idx;
  }

  // The cheapest evaluated point that meets the budget (else the most accurate), and the
  // Pareto front of cost against NMSE.
  void choose(TuneMaterial& tm) const {
    int c = 0;
    for (size_t i = 1; i < tm.points.size(); ++i) {
      if (better(tm.points[i], tm.points[static_cast<size_t>(c)])) c = static_cast<int>(i);
    }
    tm.chosen = c;
    tm.budget_met = tm.points[static_cast<size_t>(c)].meets;
    // On the front: no point is at least as good in both and better in one, and no earlier
    // point has the same cost and error (configurations that differ only in unused knobs).
    for (size_t i = 0; i < tm.points.size(); ++i) {
      TunePoint& p = tm.points[i];
      const double cp = tune_cost(opt_, p);
      p.pareto = true;
      for (size_t j = 0; j < tm.points.size() && p.pareto; ++j) {
        const TunePoint& q = tm.points[j];
        const double cq = tune_cost(opt_, q);
        const bool same = cq == cp && q.nmse == p.nmse;
        if ((same && j < i) || (!same && cq <= cp && q.nmse <= p.nmse)) p.pareto = false;
      }
    }
  }

  const TuneOptions& opt_;
  Budget budget_;
  TuneResult& res_;
  std::ostream& log_;
  std::map<std::string, int> seen_;
};

bool is_default_scene(const std::string& scene) { return scene == "default"; }

std::string num(double v, int prec = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

// The scene file with the chosen material tables; relative texture and mesh paths made
// absolute so the file works from the output directory.
std::string tuned_scene(const TuneOptions& opt, const TuneResult& res) {
  const bool builtin = is_default_scene(opt.scene);
  const std::string text = builtin ? std::string(default_scene_text())
                                   : read_input_file(opt.scene, "scene file", kMaxTextInput);
  toml::table root = toml::parse(
      std::string_view(text), std::string_view(builtin ? "<built-in default scene>" : opt.scene));
  std::vector<std::string> sets = opt.overrides;
  for (const TuneMaterial& m : res.materials)
    sets.push_back(m.points[static_cast<size_t>(m.chosen)].override);
  apply_overrides(root, sets);
  const std::filesystem::path base = std::filesystem::path(opt.scene).parent_path();
  auto absolutize = [&](toml::table& t) {
    auto* src = t.get_as<std::string>("source");
    if (src == nullptr || src->get().rfind("procedural:", 0) == 0) return;
    const std::filesystem::path p(src->get());
    if (p.is_relative() && std::filesystem::exists(base / p))
      *src = std::filesystem::absolute(base / p).lexically_normal().string();
  };
  if (auto* tex = root.get_as<toml::table>("textures")) {
    for (auto& [k, v] : *tex) {
      if (auto* t = v.as_table()) absolutize(*t);
    }
  }
  if (auto* meshes = root.get_as<toml::array>("meshes")) {
    for (auto& v : *meshes) {
      if (auto* t = v.as_table()) absolutize(*t);
    }
  }
  std::ostringstream s;
  s << "# texsim tune " << opt.scene << " --budget " << opt.budget << " --cost " << opt.cost
    << (opt.families ? " --families" : "")
    << ": the cheapest configuration per material that meets the budget (docs/tune.md).\n"
    << toml::toml_formatter(root) << "\n";
  return s.str();
}

void write_tables(const TuneOptions& opt, const TuneResult& res, const StudyFiles& files) {
  StudyTable all(
      {"material", "config", "cycles", "area", "psnr_db", "nmse", "meets", "pareto", "chosen"});
  StudyTable front({"material", "config", "cycles", "area", "psnr_db", "nmse", "meets", "chosen"});
  PlotSpec plot;
  plot.title = "texsim tune " + std::filesystem::path(opt.scene).filename().string() +
               ": Pareto front per material (budget " + opt.budget + ")";
  plot.xlabel = opt.cost == "area" ? "area of the unit (adder-equivalents)" : "cycles of the run";
  plot.ylabel = "material PSNR (dB)";
  std::vector<LabelledPoint> chosen;
  for (const TuneMaterial& m : res.materials) {
    std::vector<LabelledPoint> pts;
    for (size_t i = 0; i < m.points.size(); ++i) {
      const TunePoint& p = m.points[i];
      const bool ch = static_cast<int>(i) == m.chosen;
      std::vector<std::string> row = {
          m.name,         "\"" + p.label + "\"", num(p.cycles, 10),  num(p.area, 8),
          num(p.psnr_db), num(p.nmse),           p.meets ? "1" : "0"};
      std::vector<std::string> r_all = row;
      r_all.push_back(p.pareto ? "1" : "0");
      r_all.push_back(ch ? "1" : "0");
      all.add(r_all);
      if (!p.pareto) continue;
      row.push_back(ch ? "1" : "0");
      front.add(row);
      pts.push_back({tune_cost(opt, p), p.psnr_db, p.label});
    }
    plot.series.push_back(labelled_series(m.name, pts));
    const TunePoint& c = m.points[static_cast<size_t>(m.chosen)];
    chosen.push_back({tune_cost(opt, c), c.psnr_db, m.name + " chosen"});
  }
  plot.series.push_back(labelled_series("chosen", chosen));
  files.csv("points.csv", all);
  files.csv("pareto.csv", front);
  files.plot("pareto.png", plot);
}

void write_summary(const TuneOptions& opt, const TuneResult& res, const StudyFiles& files) {
  std::ostringstream md;
  md << "# texsim tune\n\nScene `" << opt.scene << "`, budget " << opt.budget
     << " per material (a material's own `budget` in the scene instead where it has one), cost: "
     << opt.cost << ". " << res.runs
     << " runs (greedy coordinate descent over each material's knobs"
     << (opt.families ? ", then again from each other filter family's defaults" : "")
     << ", the other materials as configured; docs/tune.md).\n\n";
  StudyTable t({"material", "budget", "choice", "budget met", "PSNR (dB)", "NMSE", "cost",
                "as configured: PSNR (dB)", "cost", "saving", "points"},
               "lllrrrrrrrr");
  for (const TuneMaterial& m : res.materials) {
    const TunePoint& c = m.points[static_cast<size_t>(m.chosen)];
    const TunePoint& d = m.points[0];
    const double cc = tune_cost(opt, c), cd = tune_cost(opt, d);
    t.add({m.name, m.budget, c.label, m.budget_met ? "yes" : "no (most accurate point)",
           num(c.psnr_db, 4), num(c.nmse, 4), num(cc, 8), num(d.psnr_db, 4), num(cd, 8),
           num(cd > 0 ? 100.0 * (cd - cc) / cd : 0, 3) + " %", std::to_string(m.points.size())});
  }
  md << t.markdown() << "\nThe chosen scene (`tuned.toml`) against the scene as configured: "
     << num(res.tuned_cycles, 10) << " cycles vs " << num(res.default_cycles, 10) << " ("
     << num(100.0 * (res.default_cycles - res.tuned_cycles) / std::max(1.0, res.default_cycles), 3)
     << " % saved), area " << num(res.tuned_area, 8) << " vs " << num(res.default_area, 8)
     << ", image PSNR " << num(res.tuned_psnr_db, 4) << " dB vs " << num(res.default_psnr_db, 4)
     << " dB.\n\nFiles: `tuned.toml`, `points.csv` (every evaluated point), `pareto.csv`, "
        "`pareto.png`"
     << (opt.ledger ? ", `tuned/report.md` (the chosen scene's run with its error ledger)" : "")
     << ".\n";
  files.text("tune.md", md.str());
}

}  // namespace

namespace {

// A decimal count in [1, INT_MAX]: digits only (no sign, point, space or suffix).
bool parse_count(std::string_view text, int& v) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string_view::npos) return false;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  return ec == std::errc() && end == text.data() + text.size() && v >= 1;
}

}  // namespace

void parse_tune_shard(const std::string& text, TuneOptions& opt) {
  const size_t slash = text.find('/');
  int k = 0, n = 0;
  if (slash == std::string::npos || !parse_count(std::string_view(text).substr(0, slash), k) ||
      !parse_count(std::string_view(text).substr(slash + 1), n) || k > n)
    throw InputError("--shard " + printable(text),
                     "expected K/N: two whole numbers with 1 <= K <= N (e.g. 1/4)");
  opt.shard = k;
  opt.shards = n;
}

double tune_cost(const TuneOptions& opt, const TunePoint& p) {
  return opt.cost == "area" ? p.area : p.cycles;
}

namespace {

// The shard's file: every field of its materials' points, doubles to the last bit.
constexpr const char* kShardFile = "tune_shard.json";

nlohmann::ordered_json shard_json(const TuneOptions& opt, const TuneResult& res,
                                  const std::vector<size_t>& indices) {
  nlohmann::ordered_json j;
  j["scene"] = opt.scene;
  j["budget"] = opt.budget;
  j["cost"] = opt.cost;
  j["overrides"] = opt.overrides;
  j["families"] = opt.families;
  j["shard"] = opt.shard;
  j["shards"] = opt.shards;
  j["runs"] = res.runs;
  j["materials"] = nlohmann::ordered_json::array();
  for (size_t k = 0; k < res.materials.size(); ++k) {
    const TuneMaterial& m = res.materials[k];
    nlohmann::ordered_json jm = {{"index", indices[k]},
                                 {"name", m.name},
                                 {"budget", m.budget},
                                 {"chosen", m.chosen},
                                 {"budget_met", m.budget_met}};
    jm["points"] = nlohmann::ordered_json::array();
    for (const TunePoint& p : m.points) {
      jm["points"].push_back({{"label", p.label},
                              {"override", p.override},
                              {"cycles", p.cycles},
                              {"area", p.area},
                              {"psnr_db", p.psnr_db},
                              {"nmse", p.nmse},
                              {"meets", p.meets},
                              {"pareto", p.pareto}});
    }
    j["materials"].push_back(std::move(jm));
  }
  return j;
}

// Reads one tune_shard.json field by field: every field's type and range checked, each error
// naming the file and the field (`materials[1].chosen`).
class ShardReader {
 public:
  using Json = nlohmann::ordered_json;
  explicit ShardReader(const std::string& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(path_, field + ": " + what);
  }
  const Json& at(const Json& obj, const std::string& field, const char* key) const {
    if (!obj.is_object()) fail(field.empty() ? "(top level)" : field, "expected an object");
    const auto it = obj.find(key);
    if (it == obj.end()) fail(name(field, key), "missing");
    return *it;
  }
  // A string of printable UTF-8; a `cell` (a CSV or Markdown table cell) also without " or |.
  std::string text(const Json& obj, const std::string& field, const char* key,
                   bool cell = false) const {
    const Json& v = at(obj, field, key);
    if (!v.is_string()) fail(name(field, key), "expected a string");
    const auto& s = v.get_ref<const std::string&>();
    if (!is_printable_utf8(s) || (cell && s.find_first_of("\"|") != std::string::npos))
      fail(name(field, key), shown(v) + " holds a control character" + (cell ? ", \" or |" : ""));
    return s;
  }
  bool flag(const Json& obj, const std::string& field, const char* key) const {
    const Json& v = at(obj, field, key);
    if (!v.is_boolean()) fail(name(field, key), "expected true or false");
    return v.get<bool>();
  }
  int64_t integer(const Json& obj, const std::string& field, const char* key, int64_t lo,
                  int64_t hi) const {
    const Json& v = at(obj, field, key);
    const bool fits = v.is_number_integer() &&
                      (v.is_number_unsigned() ? v.get<uint64_t>() <= static_cast<uint64_t>(hi)
                                              : v.get<int64_t>() <= hi);
    if (!fits || v.get<int64_t>() < lo)
      fail(name(field, key), shown(v) + " is not a whole number in [" + std::to_string(lo) + ", " +
                                 std::to_string(hi) + "]");
    return v.get<int64_t>();
  }
  double number(const Json& obj, const std::string& field, const char* key, double lo) const {
    const Json& v = at(obj, field, key);
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo)
      fail(name(field, key), shown(v) + " is not a finite number" +
                                 (lo > -HUGE_VAL ? " >= " + num(lo) : std::string()));
    return v.get<double>();
  }
  const Json& array(const Json& obj, const std::string& field, const char* key) const {
    const Json& v = at(obj, field, key);
    if (!v.is_array()) fail(name(field, key), "expected an array");
    return v;
  }

 private:
  static std::string name(const std::string& field, const char* key) {
    return field.empty() ? key : field + "." + key;
  }
  // A value as JSON text for a message, whatever bytes it holds, at most 60 characters.
  static std::string shown(const Json& v) {
    std::string t = v.dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
    if (t.size() > 60) t = t.substr(0, 57) + "...";
    return t;
  }
  const std::string& path_;
};

// Parses `text` as JSON; a value nested deeper than kMaxShardDepth is refused while parsing,
// before the parser goes deeper.
nlohmann::ordered_json parse_shard_json(const std::string& path, const std::string& text) {
  const nlohmann::ordered_json::parser_callback_t depth_limit =
      [&path](int depth, nlohmann::ordered_json::parse_event_t event, nlohmann::ordered_json&) {
        if ((event == nlohmann::ordered_json::parse_event_t::object_start ||
             event == nlohmann::ordered_json::parse_event_t::array_start) &&
            depth >= kMaxShardDepth)
          throw InputError(path, "nested deeper than " + std::to_string(kMaxShardDepth) +
                                     " levels: not a tune shard");
        return true;
      };
  try {
    return nlohmann::ordered_json::parse(text, depth_limit);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, std::string("not JSON: ") + e.what());
  }
}

TunePoint read_point(const ShardReader& r, const nlohmann::ordered_json& jp, const std::string& f) {
  TunePoint p;
  p.label = r.text(jp, f, "label", true);
  p.override = r.text(jp, f, "override");
  p.cycles = r.number(jp, f, "cycles", 0);
  p.area = r.number(jp, f, "area", 0);
  p.psnr_db = r.number(jp, f, "psnr_db", -HUGE_VAL);
  p.nmse = r.number(jp, f, "nmse", 0);
  p.meets = r.flag(jp, f, "meets");
  p.pareto = r.flag(jp, f, "pareto");
  return p;
}

TuneMaterial read_material(const ShardReader& r, const nlohmann::ordered_json& jm,
                           const std::string& f) {
  TuneMaterial m;
  m.name = r.text(jm, f, "name");
  m.budget = r.text(jm, f, "budget");
  Budget budget;
  try {
    budget = parse_budget(m.budget);
  } catch (const InputError&) {
    r.fail(f + ".budget", "'" + m.budget + "' is not psnr=<dB> or nmse=<positive value>");
  }
  const nlohmann::ordered_json& points = r.array(jm, f, "points");
  if (points.empty()) r.fail(f + ".points", "empty: a material has at least its own point");
  for (size_t i = 0; i < points.size(); ++i) {
    const std::string fp = f + ".points[" + std::to_string(i) + "]";
    m.points.push_back(read_point(r, points[i], fp));
    const TunePoint& p = m.points.back();
    if (p.override.rfind("materials." + m.name + "=", 0) != 0)
      r.fail(fp + ".override", "does not set materials." + m.name);
    if (p.meets != budget.meets(p.psnr_db, p.nmse))
      r.fail(fp + ".meets", "disagrees with the point's accuracy and the budget " + m.budget);
  }
  m.chosen =
      static_cast<int>(r.integer(jm, f, "chosen", 0, static_cast<int64_t>(points.size()) - 1));
  m.budget_met = r.flag(jm, f, "budget_met");
  if (m.budget_met != m.points[static_cast<size_t>(m.chosen)].meets)
    r.fail(f + ".budget_met", "disagrees with the chosen point's meets");
  return m;
}

}  // namespace

TuneShard read_tune_shard(const std::string& path) {
  const std::string text = read_input_file(path, "tune shard", kMaxJsonInput);
  const nlohmann::ordered_json j = parse_shard_json(path, text);
  const ShardReader r(path);
  TuneShard s;
  s.scene = r.text(j, "", "scene");
  s.budget = r.text(j, "", "budget");
  s.cost = r.text(j, "", "cost");
  const nlohmann::ordered_json& overrides = r.array(j, "", "overrides");
  for (size_t i = 0; i < overrides.size(); ++i) {
    if (!overrides[i].is_string())
      r.fail("overrides[" + std::to_string(i) + "]", "expected a string");
    s.overrides.push_back(overrides[i].get<std::string>());
  }
  s.families = r.flag(j, "", "families");
  s.shards = static_cast<int>(r.integer(j, "", "shards", 1, INT_MAX));
  s.shard = static_cast<int>(r.integer(j, "", "shard", 1, s.shards));
  s.runs = static_cast<int>(r.integer(j, "", "runs", 0, kMaxShardRuns));
  const nlohmann::ordered_json& materials = r.array(j, "", "materials");
  for (size_t k = 0; k < materials.size(); ++k) {
    const std::string f = "materials[" + std::to_string(k) + "]";
    const auto index = static_cast<size_t>(r.integer(materials[k], f, "index", 0, INT_MAX));
    if (static_cast<int>(index % static_cast<size_t>(s.shards)) != s.shard - 1)
      r.fail(f + ".index", std::to_string(index) + " is not in shard " + std::to_string(s.shard) +
                               "/" + std::to_string(s.shards));
    if (std::find(s.indices.begin(), s.indices.end(), index) != s.indices.end())
      r.fail(f + ".index", "material " + std::to_string(index) + " appears twice");
    s.indices.push_back(index);
    s.materials.push_back(read_material(r, materials[k], f));
  }
  return s;
}

namespace {

// The shards' materials in scene order: each material exactly once, from a shard of this
// scene, budget, cost and overrides; no shard (or directory) given twice.
void read_shards(const TuneOptions& opt, const std::vector<SceneMaterial>& materials,
                 TuneResult& res) {
  std::vector<std::optional<TuneMaterial>> slots(materials.size());
  std::vector<std::string> from(materials.size());  // the shard file of each material
  std::map<std::string, std::string> dirs;          // canonical directory -> as given
  std::map<int, std::string> shard_files;           // shard k -> its file
  int shards = 0;
  for (const std::string& dir : opt.merge) {
    std::error_code ec;
    const std::string canon = std::filesystem::weakly_canonical(dir, ec).string();
    if (!dirs.emplace(ec ? dir : canon, dir).second)
      throw InputError("texsim tune --merge " + dir, "this shard directory is given twice");
    const std::string path = (std::filesystem::path(dir) / kShardFile).string();
    if (!std::filesystem::exists(path, ec))
      throw InputError(path, "no tune shard here (run `texsim tune … --shard k/n` first)");
    const TuneShard s = read_tune_shard(path);
    const std::pair<const char*, std::pair<std::string, std::string>> same[] = {
        {"scene", {s.scene, opt.scene}},
        {"budget", {s.budget, opt.budget}},
        {"cost", {s.cost, opt.cost}}};
    for (const auto& [key, v] : same) {
      if (v.first != v.second)
        throw InputError(path, std::string(key) + " differs: '" + v.first + "', this merge has '" +
                                   v.second + "'");
    }
    if (s.overrides != opt.overrides)
      throw InputError(path, "the --set overrides differ from this merge's");
    if (s.families != opt.families) throw InputError(path, "--families differs from this merge's");
    if (shards != 0 && s.shards != shards)
      throw InputError(path, "shard " + std::to_string(s.shard) + "/" + std::to_string(s.shards) +
                                 " is of another split than " + std::to_string(shards));
    shards = s.shards;
    if (const auto [it, fresh] = shard_files.emplace(s.shard, path); !fresh)
      throw InputError(path, "shard " + std::to_string(s.shard) + "/" + std::to_string(s.shards) +
                                 " is also " + it->second);
    res.runs += s.runs;
    for (size_t k = 0; k < s.materials.size(); ++k) {
      const size_t i = s.indices[k];
      const std::string f = "materials[" + std::to_string(k) + "]";
      if (i >= materials.size())
        throw InputError(path, f + ".index: " + std::to_string(i) +
                                   " is out of range (the scene has " +
                                   std::to_string(materials.size()) + " materials)");
      if (slots[i])
        throw InputError(path, f + ": material " + std::to_string(i) + " is also in " + from[i]);
      if (s.materials[k].name != materials[i].name)
        throw InputError(path, f + ".name: '" + s.materials[k].name + "', the scene's material " +
                                   std::to_string(i) + " is '" + materials[i].name + "'");
      if (s.materials[k].budget != budget_text(materials[i], opt.budget))
        throw InputError(path, f + ".budget: '" + s.materials[k].budget + "', this merge has '" +
                                   budget_text(materials[i], opt.budget) + "'");
      slots[i] = s.materials[k];
      from[i] = path;
    }
  }
  for (size_t i = 0; i < materials.size(); ++i) {
    if (!slots[i])
      throw InputError("texsim tune --merge", "no shard has material " + std::to_string(i));
    res.materials.push_back(std::move(*slots[i]));
  }
}

void log_material(const TuneMaterial& tm, std::ostream& log) {
  log << "texsim tune: " << tm.name << ": " << tm.points[static_cast<size_t>(tm.chosen)].label
      << (tm.budget_met ? "" : " (budget not met: the most accurate point)") << ", "
      << tm.points.size() << " points\n";
}

}  // namespace

TuneResult run_tune(const TuneOptions& opt, std::ostream& log) {
  parse_budget(opt.budget);
  if (opt.cost != "cycles" && opt.cost != "area")
    throw InputError("--cost " + opt.cost, "expected cycles or area");
  if (opt.shards < 0 || opt.shard < 0 || (opt.shards > 0 && opt.shard > opt.shards) ||
      (opt.shard > 0) != (opt.shards > 0))
    throw InputError("--shard", "expected k/n with 1 <= k <= n");
  if (opt.shards > 0 && !opt.merge.empty())
    throw InputError("--merge", "merges shards; it does not take --shard");
  // "default" is the built-in scene, as for `texsim run default`.
  const Scene scene = is_default_scene(opt.scene) ? default_scene(opt.overrides)
                                                  : load_scene(opt.scene, opt.overrides);
  const StudyFiles files(opt.out);
  TuneResult res;
  Search search(opt, res, log);
  if (!opt.merge.empty()) {
    read_shards(opt, scene.materials, res);
    for (const TuneMaterial& tm : res.materials) log_material(tm, log);
  } else {
    std::vector<size_t> mine;
    for (size_t i = 0; i < scene.materials.size(); ++i) {
      if (opt.shards > 0 && static_cast<int>(i % static_cast<size_t>(opt.shards)) != opt.shard - 1)
        continue;
      mine.push_back(i);
      res.materials.push_back(search.material(scene.materials[i]));
      log_material(res.materials.back(), log);
    }
    if (opt.shards > 0) {
      files.text(kShardFile, shard_json(opt, res, mine).dump(1) + "\n");
      log << "texsim tune: shard " << opt.shard << "/" << opt.shards << ": " << res.runs
          << " runs; " << opt.out << "/" << kShardFile << " (assemble with --merge)\n";
      return res;
    }
  }
  const RunCapture def = search.run({});
  res.default_cycles = static_cast<double>(def.cycles);
  res.default_area = def.area;
  res.default_psnr_db = def.total.psnr_db;
  std::vector<std::string> chosen;
  for (const TuneMaterial& m : res.materials)
    chosen.push_back(m.points[static_cast<size_t>(m.chosen)].override);
  const RunCapture tuned = search.run(chosen, opt.out + "/tuned", opt.ledger);
  res.runs += 2;
  res.tuned_cycles = static_cast<double>(tuned.cycles);
  res.tuned_area = tuned.area;
  res.tuned_psnr_db = tuned.total.psnr_db;
  files.text("tuned.toml", tuned_scene(opt, res));
  write_tables(opt, res, files);
  write_summary(opt, res, files);
  log << "texsim tune: " << res.runs << " runs; tuned " << num(res.tuned_cycles, 10)
      << " cycles vs " << num(res.default_cycles, 10) << " as configured, PSNR "
      << num(res.tuned_psnr_db, 4) << " dB vs " << num(res.default_psnr_db, 4) << " dB\n  "
      << opt.out << "/tune.md, tuned.toml, points.csv, pareto.csv, pareto.png\n";
  return res;
}

}  // namespace texsim
