#include "pipeline/app/study_memory.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "blocks/base/input_error.h"
#include "pipeline/app/run.h"
#include "pipeline/app/study_runs.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/report/number_text.h"
#include "pipeline/scene/scene.h"
#include "pipeline/studies/shipped_scenes.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

namespace {

using Set = StudySet;

std::string kib(uint64_t bytes) {
  return bytes % 1024 == 0 ? std::to_string(bytes / 1024) + "K" : std::to_string(bytes) + "B";
}

// Every row starts from this, so the scenes' own [pipeline] choices (photo's morton layout and
// 32 KB L1) do not mix into the comparison.
const Set& base_set() { return study_base_set(); }

Set l1(uint32_t bytes, uint32_t ways, uint32_t line) {
  return {{"pipeline.cache.size_bytes", std::to_string(bytes)},
          {"pipeline.cache.ways", std::to_string(ways)},
          {"pipeline.cache.line_bytes", std::to_string(line)}};
}

Set tiled(const std::string& curve) {
  return {{"raster.order", "tiled"},
          {"raster.tile", "16"},
          {"raster.tile_order", curve},
          {"raster.quad_order", curve}};
}

Set banked() { return {{"pipeline.dram.model", "banked"}, {"pipeline.dram.preset", "gddr6"}}; }

Set l2(uint32_t bytes, uint32_t slices) {
  return with(banked(), {{"pipeline.l2.size_bytes", std::to_string(bytes)},
                         {"pipeline.l2.slices", std::to_string(slices)}});
}

std::string get(const Set& s, const std::string& k, const std::string& def = "") {
  const auto it = s.find(k);
  return it == s.end() ? def : it->second;
}

// The descriptive columns of a row, from its overrides.
MemoryStudyRow make_row(const std::string& scene, const std::string& path, const std::string& sweep,
                        const Set& row) {
  MemoryStudyRow r;
  r.scene = scene;
  r.scene_path = path;
  r.sweep = sweep;
  r.set = with(base_set(), row);
  const Set& s = r.set;
  r.units = std::stoi(get(s, "pipeline.units"));
  r.l1_bytes = static_cast<uint32_t>(std::stoul(get(s, "pipeline.cache.size_bytes")));
  r.l1_ways = static_cast<uint32_t>(std::stoul(get(s, "pipeline.cache.ways")));
  r.l1_line = static_cast<uint32_t>(std::stoul(get(s, "pipeline.cache.line_bytes")));
  r.layout = get(s, "pipeline.layout");
  r.order = get(s, "raster.order") == "rows"
                ? "rows"
                : "tiled " + get(s, "raster.tile") + " " + get(s, "raster.tile_order") + "/" +
                      get(s, "raster.quad_order");
  const bool is_banked = get(s, "pipeline.dram.model") == "banked";
  r.behind = is_banked ? "banked " + get(s, "pipeline.dram.preset") : "flat DRAM";
  if (s.count("pipeline.l2.size_bytes")) {
    r.behind = "L2 " + kib(std::stoull(get(s, "pipeline.l2.size_bytes"))) + " x" +
               get(s, "pipeline.l2.slices") + " + " + r.behind;
  }
  if (row.count("output.width"))
    r.other = get(s, "output.width") + "x" + get(s, "output.height") + " px";
  if (row.count("materials.floor.lod.max_aniso"))
    r.other = "floor max_aniso=" + get(s, "materials.floor.lod.max_aniso");
  for (const char* k : {"pipeline.unit_tile", "pipeline.quad_merge", "pipeline.cache.miss_queue",
                        "pipeline.l2.prefetch"}) {
    if (row.count(k) || (std::string(k) == "pipeline.unit_tile" && r.units > 1)) {
      const std::string key = std::string(k).substr(std::string(k).rfind('.') + 1);
      r.other += (r.other.empty() ? "" : " ") + key + "=" + get(s, k);
    }
  }
  return r;
}

struct SceneRef {
  std::string name, path;
};

std::vector<SceneRef> scenes_of(const StudyMemoryOptions& opt) {
  std::vector<std::string> paths = opt.scenes;
  if (paths.empty()) {
    paths = {"default"};
    if (!opt.quick) {
      for (const char* s : {"photo", "flight", "bunny"})
        paths.push_back(shipped_scenes_dir() + "/" + s + ".toml");
    }
  }
  std::vector<SceneRef> out;
  out.reserve(paths.size());
  for (const std::string& p : paths) {
    out.push_back({p == "default" ? "default" : std::filesystem::path(p).stem().string(), p});
  }
  return out;
}

const std::vector<std::string> kLayouts = {"linear", "tiled4x4", "morton"};
const std::vector<std::string> kCurves = {"row", "morton", "hilbert"};
const std::vector<uint32_t> kSizes = {1024, 4096, 16384, 65536};
const std::vector<uint32_t> kUnits = {1, 2, 4, 8, 16};

void full_plan(const SceneRef& sc, std::vector<MemoryStudyRow>& rows) {
  auto add = [&](const std::string& sweep, const Set& s) {
    rows.push_back(make_row(sc.name, sc.path, sweep, s));
  };
  // L1 geometry (Hakura & Gupta's size, associativity and line size).
  for (uint32_t line : {32u, 64u, 128u}) {
    for (uint32_t ways : {1u, 2u, 4u, 8u}) {
      for (uint32_t size : kSizes) add("l1", l1(size, ways, line));
    }
  }
  // Texel layout × raster order × L1 size.
  for (const std::string& layout : kLayouts) {
    std::vector<Set> orders = {{{"raster.order", "rows"}}};
    for (const std::string& c : kCurves) orders.push_back(tiled(c));
    for (const Set& o : orders) {
      for (uint32_t size : kSizes)
        add("layout", with(with(o, l1(size, 4, 64)), {{"pipeline.layout", layout}}));
    }
  }
  // Units with the flat DRAM, with banked DRAM and with a shared L2 over banked DRAM.
  for (int mem = 0; mem < 3; ++mem) {
    for (uint32_t u : kUnits) {
      Set s = mem == 0 ? Set{} : mem == 1 ? banked() : l2(262144, 4);
      s["pipeline.units"] = std::to_string(u);
      add("units", s);
    }
  }
  // Screen-tile interleaving granularity (Igehy, Eldridge & Hanrahan 1999), 4 and 16 units.
  for (uint32_t u : {4u, 16u}) {
    for (uint32_t tile : {4u, 8u, 16u, 32u, 64u}) {
      add("unit_tile", with(l2(262144, 4), {{"pipeline.units", std::to_string(u)},
                                            {"pipeline.unit_tile", std::to_string(tile)}}));
    }
  }
  // L2 size × slices at 4 units, and next-line prefetch.
  for (uint32_t size : {65536u, 262144u, 1048576u}) {
    for (uint32_t slices : {1u, 4u, 16u})
      add("l2", with(l2(size, slices), {{"pipeline.units", "4"}}));
  }
  add("l2", with(l2(262144, 4), {{"pipeline.units", "4"}, {"pipeline.l2.prefetch", "next_line"}}));
  // Latency hiding: fragments in flight in the L1 stage (Igehy, Eldridge & Proudfoot 1998).
  for (uint32_t q : {1u, 4u, 16u, 64u, 256u}) {
    add("miss_queue", {{"pipeline.cache.miss_queue", std::to_string(q)}});
    add("miss_queue", with(banked(), {{"pipeline.cache.miss_queue", std::to_string(q)}}));
  }
  // Screen resolution against raster order: a screen row's texels against the L1's size. The
  // built-in scene up to 4x its size, the others 2x (4x is slow and adds little).
  const Scene scene = sc.path == "default" ? default_scene() : load_scene(sc.path);
  for (int scale : {1, 2, 4}) {
    if (scale == 4 && sc.path != "default") continue;
    for (const Set& o : {Set{{"raster.order", "rows"}}, tiled("hilbert")}) {
      for (uint32_t size : {4096u, 16384u}) {
        add("resolution", with(with(o, l1(size, 4, 64)),
                               {{"output.width", std::to_string(scene.width * scale)},
                                {"output.height", std::to_string(scene.height * scale)}}));
      }
    }
  }
  // photo's floor filters anisotropically (up to 16 probes along the footprint's major axis):
  // the same raster orders with the floor isotropic, to tell the footprint's share.
  if (sc.name == "photo") {
    for (const char* aniso : {"1", "16"}) {
      for (const Set& o : {Set{{"raster.order", "rows"}}, tiled("hilbert")}) {
        for (uint32_t size : {4096u, 16384u, 65536u}) {
          add("footprint",
              with(with(o, l1(size, 4, 64)), {{"materials.floor.lod.max_aniso", aniso}}));
        }
      }
    }
  }
  // Quad merging of tag look-ups, in row and in tiled (quad-consecutive) order.
  for (const Set& o : {Set{{"raster.order", "rows"}}, tiled("row")}) {
    for (const char* m : {"false", "true"})
      add("quad_merge", with(o, {{"pipeline.quad_merge", m}}));
  }
}

// A few rows whose relations a test can rely on (test_study_memory.cc).
void quick_plan(const SceneRef& sc, std::vector<MemoryStudyRow>& rows) {
  auto add = [&](const std::string& sweep, const Set& s) {
    rows.push_back(make_row(sc.name, sc.path, sweep, s));
  };
  // 1K/1w and 4K/4w have 16 sets, 4K/1w and 16K/4w 64 sets.
  for (const auto& [size, ways] : {std::pair{1024u, 1u}, {4096u, 1u}, {4096u, 4u}, {16384u, 4u}})
    add("l1", l1(size, ways, 64));
  // An L1 larger than every texture together: only first-touch misses.
  for (uint32_t u : {1u, 4u})
    add("units", {{"pipeline.units", std::to_string(u)}, {"pipeline.cache.size_bytes", "8388608"}});
  add("units", with(l2(262144, 4), {{"pipeline.units", "4"}}));
  for (const char* m : {"false", "true"})
    add("quad_merge", with(tiled("row"), {{"pipeline.quad_merge", m}}));
}

void read_figures(const nlohmann::json& j, MemoryStudyRow& r) {
  r.fragments = j.at("fragments").get<uint64_t>();
  r.cycles = j.at("cycles").get<uint64_t>();
  const auto& c = j.at("cache");
  r.l1_accesses = c.at("accesses").get<uint64_t>();
  r.l1_hits = c.at("hits").get<uint64_t>();
  r.l1_misses = c.at("misses").get<uint64_t>();
  r.l1_hit_rate = c.at("hit_rate").get<double>();
  const auto& d = j.at("dram");
  r.dram_bytes = d.at("bytes").get<uint64_t>();
  r.banked = d.contains("row_hit_rate");
  if (r.banked) r.row_hit_rate = d.at("row_hit_rate").get<double>();
  r.has_l2 = j.contains("l2");
  if (r.has_l2) r.l2_hit_rate = j.at("l2").at("hit_rate").get<double>();
  r.energy_pj = j.at("energy").at("per_fragment_pj").get<double>();
  if (j.contains("scheduler")) {
    r.late_items = j.at("scheduler").at("late_items").get<uint64_t>();
    r.forced_commits = j.at("scheduler").at("forced_commits").get<uint64_t>();
  }
  if (j.contains("quads")) r.quad_merged = j.at("quads").at("merged_lookups").get<uint64_t>();
}

// One row: a timed run without ground truth into its own directory, its report read back and
// the directory removed.
void measure(MemoryStudyRow& r, const std::string& dir) {
  RunOptions o;
  o.scene = r.scene_path;
  o.reference = "none";
  o.overrides = r.overrides();
  run_study_row(o, dir, " --reference none", [&r](const nlohmann::json& j) { read_figures(j, r); });
}

std::string rate(bool present, double v) { return present ? fmt(v, 5) : ""; }

StudyTable table(const std::vector<MemoryStudyRow>& rows, bool csv) {
  std::vector<std::string> head = {"scene",
                                   "sweep",
                                   "units",
                                   "L1 size/ways/line",
                                   "layout",
                                   "raster order",
                                   "behind L1",
                                   "other",
                                   "fragments",
                                   "L1 look-ups/frag",
                                   "L1 hit rate",
                                   "L1 misses",
                                   "DRAM B/frag",
                                   "cycles/frag",
                                   "cycles x units/frag",
                                   "L2 hit rate",
                                   "DRAM row-hit rate",
                                   "energy pJ/frag",
                                   "late items"};
  if (csv) head.push_back("overrides");
  StudyTable t(head, "llrllllllrrrrrrrrrrl");
  for (const MemoryStudyRow& r : rows) {
    std::vector<std::string> c = {
        r.scene,
        r.sweep,
        std::to_string(r.units),
        kib(r.l1_bytes) + "/" + std::to_string(r.l1_ways) + "w/" + std::to_string(r.l1_line),
        r.layout,
        r.order,
        r.behind,
        r.other,
        std::to_string(r.fragments),
        fmt(r.per_fragment(static_cast<double>(r.l1_accesses)), 4),
        fmt(r.l1_hit_rate, 5),
        std::to_string(r.l1_misses),
        fmt(r.per_fragment(static_cast<double>(r.dram_bytes)), 4),
        fmt(r.per_fragment(static_cast<double>(r.cycles)), 4),
        fmt(r.per_fragment(static_cast<double>(r.cycles) * r.units), 4),
        rate(r.has_l2, r.l2_hit_rate),
        rate(r.banked, r.row_hit_rate),
        fmt(r.energy_pj, 4),
        std::to_string(r.late_items)};
    if (csv) {
      std::string o;
      for (const std::string& s : r.overrides()) o += (o.empty() ? "" : " ") + s;
      c.push_back(o);
    }
    t.add(std::move(c));
  }
  return t;
}

std::vector<std::string> scene_names(const std::vector<MemoryStudyRow>& rows) {
  std::vector<std::string> names;
  for (const MemoryStudyRow& r : rows) {
    if (names.empty() || names.back() != r.scene) names.push_back(r.scene);
  }
  return names;
}

// L1 hit rate against L1 size, one series per layout and raster order.
PlotSpec hit_rate_plot(const std::vector<MemoryStudyRow>& rows, const std::string& scene) {
  PlotSpec p;
  p.title = "L1 hit rate vs L1 size (4-way, 64 B lines, one unit): " + scene;
  p.xlabel = "L1 size (bytes)";
  p.ylabel = "L1 hit rate";
  p.logx = true;
  std::map<std::string, std::vector<LabelledPoint>> series;
  std::vector<std::string> order;
  for (const MemoryStudyRow& r : rows) {
    if (r.scene != scene || r.sweep != "layout") continue;
    const std::string name = r.layout + ", " + r.order;
    if (!series.count(name)) order.push_back(name);
    series[name].push_back({static_cast<double>(r.l1_bytes), r.l1_hit_rate, ""});
  }
  for (const std::string& name : order) {
    auto& pts = series[name];
    pts.back().label = name;  // at the largest size, where the series end
    p.series.push_back(labelled_series(name, pts));
  }
  return p;
}

// cycles or DRAM bytes per fragment against units, one series per scene and memory.
PlotSpec units_plot(const std::vector<MemoryStudyRow>& rows, bool dram) {
  PlotSpec p;
  p.title = dram ? "DRAM bytes per fragment vs texture units (16K 4-way L1 per unit)"
                 : "Cycles per fragment vs texture units (16K 4-way L1 per unit)";
  p.xlabel = "texture units";
  p.ylabel = dram ? "DRAM bytes per fragment" : "cycles per fragment";
  p.logx = true;
  p.logy = !dram;
  for (const std::string& scene : scene_names(rows)) {
    for (const std::string& behind : {std::string("flat DRAM"), std::string("banked gddr6"),
                                      std::string("L2 256K x4 + banked gddr6")}) {
      // Without an L2 the DRAM sees exactly the L1 misses, whatever its model.
      if (dram && behind == "banked gddr6") continue;
      std::vector<LabelledPoint> pts;
      for (const MemoryStudyRow& r : rows) {
        if (r.scene != scene || r.sweep != "units" || r.behind != behind) continue;
        const double y = static_cast<double>(dram ? r.dram_bytes : r.cycles);
        std::string label;
        if (!dram) {
          label.append("L1 ").append(fmt(100 * r.l1_hit_rate, 3)).append("%");
        } else if (r.has_l2) {
          label.append("L2 ").append(fmt(100 * r.l2_hit_rate, 3)).append("%");
        }
        pts.push_back({static_cast<double>(r.units), r.per_fragment(y), label});
      }
      if (pts.empty()) continue;
      if (dram && pts.back().label.empty()) pts.back().label = scene;
      std::string name = scene;
      name.append(", ").append(behind);
      p.series.push_back(labelled_series(name, pts));
    }
  }
  return p;
}

std::string markdown(const std::vector<MemoryStudyRow>& rows, const StudyMemoryOptions& opt) {
  std::string s =
      "# Study memory: the texture memory hierarchy on the shipped scenes\n\n"
      "Each row is one timed run (`texsim run SCENE --reference none`) with the `--set` "
      "overrides of its row (memory.csv, last column) on top of a fixed base: ";
  for (const auto& [k, v] : base_set()) s.append("`").append(k).append("=").append(v).append("` ");
  s += "(the scenes' own [pipeline] choices are replaced). Rows of a tiled raster order use "
       "16-pixel tiles with the same curve for tiles and quads. The L2 rows use the L2's defaults "
       "(16 ways, 128-byte lines, 1 port, hit latency 20, 16 MSHRs per slice) and the gddr6 "
       "preset. Per fragment: L1 tag look-ups, DRAM bytes, cycles (the last unit's), cycles × "
       "units (the work of one unit), energy ([tech.energy] defaults). Late items: requests the "
       "unit scheduler delivered out of cycle order (must be 0).\n";
  if (opt.quick) s += "\n`--quick`: a handful of rows on the built-in scene (a CI check).\n";
  const std::vector<std::pair<std::string, std::string>> sweeps = {
      {"l1", "L1 size, ways and line size"},
      {"layout", "Texel layout × raster order × L1 size"},
      {"units", "Texture units and the memory behind the L1s"},
      {"unit_tile", "Screen-tile interleaving over the units"},
      {"l2", "L2 size, slices and next-line prefetch (4 units, banked gddr6)"},
      {"miss_queue", "Latency hiding: fragments in flight in the L1 stage"},
      {"resolution", "Screen resolution × raster order"},
      {"footprint", "Anisotropic footprints × raster order (photo's floor)"},
      {"quad_merge", "Quad merging of tag look-ups"}};
  for (const auto& [key, title] : sweeps) {
    std::vector<MemoryStudyRow> part;
    for (const MemoryStudyRow& r : rows)
      if (r.sweep == key) part.push_back(r);
    if (part.empty()) continue;
    s += "\n## " + title + "\n\n" + table(part, false).markdown();
  }
  return s;
}

}  // namespace

std::vector<std::string> MemoryStudyRow::overrides() const { return overrides_of(set); }

std::vector<MemoryStudyRow> memory_study_plan(const StudyMemoryOptions& opt) {
  std::vector<MemoryStudyRow> rows;
  for (const SceneRef& sc : scenes_of(opt)) (opt.quick ? quick_plan : full_plan)(sc, rows);
  return rows;
}

int run_study_memory(const std::string& out_dir, std::ostream& log, const StudyMemoryOptions& opt,
                     std::vector<MemoryStudyRow>* out_rows) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudyFiles files(out_dir);
  std::vector<MemoryStudyRow> rows = memory_study_plan(opt);
  // Rows that repeat an earlier row's scene and overrides (a point shared by two sweeps) are
  // run once.
  std::map<std::string, size_t> first;
  std::vector<size_t> unique, same(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    std::string key = rows[i].scene_path;
    for (const std::string& o : rows[i].overrides()) key += "\n" + o;
    const auto [it, fresh] = first.emplace(key, i);
    same[i] = it->second;
    if (fresh) unique.push_back(i);
  }
  log << "study memory: " << rows.size() << " rows, " << unique.size() << " runs\n";
  const std::string work = files.path(".runs");
  parallel_tasks(unique.size(), opt.threads, [&](size_t k) {
    measure(rows[unique[k]], work + "/" + std::to_string(unique[k]));
  });
  std::filesystem::remove_all(work);
  for (size_t i = 0; i < rows.size(); ++i) {
    if (same[i] == i) continue;
    MemoryStudyRow r = rows[same[i]];
    r.sweep = rows[i].sweep;
    rows[i] = std::move(r);
  }
  files.csv("memory.csv", table(rows, true));
  files.text("memory.md", markdown(rows, opt));
  std::string plots;
  for (const std::string& scene : scene_names(rows)) {
    if (hit_rate_plot(rows, scene).series.empty()) continue;
    files.plot("memory_l1_" + scene + ".png", hit_rate_plot(rows, scene));
    plots += ", memory_l1_" + scene + ".png";
  }
  files.plot("memory_cycles_units.png", units_plot(rows, false));
  files.plot("memory_dram_units.png", units_plot(rows, true));
  uint64_t late = 0;
  for (const MemoryStudyRow& r : rows) late += r.late_items;
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study memory: wrote " << out_dir << "/memory.csv, memory.md" << plots
      << ", memory_cycles_units.png, memory_dram_units.png in " << fmt(secs, 3)
      << " s (late items: " << late << ")\n";
  if (out_rows) *out_rows = std::move(rows);
  return 0;
}

}  // namespace texsim
