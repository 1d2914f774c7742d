#include "pipeline/app/study_workloads.h"

#include <bit>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "blocks/base/input_error.h"
#include "pipeline/app/run.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/render/draw_renderer.h"
#include "pipeline/report/number_text.h"
#include "pipeline/report/workload_report.h"
#include "pipeline/studies/shipped_scenes.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

namespace {

using Json = nlohmann::json;

const char* const kScenes[] = {"photo",       "flight",          "bunny",
                               "relief_wall", "terrain_flyover", "cube"};

template <size_t N>
void read_array(const Json& j, std::array<uint64_t, N>& a) {
  for (size_t i = 0; i < N && i < j.size(); ++i) a[i] = j[i].get<uint64_t>();
}

FrameWorkload from_json(const Json& j) {
  FrameWorkload f;
  f.frame = j.at("frame").get<uint32_t>();
  for (auto [k, p] : {std::pair{"fragments", &f.fragments},
                      {"quads", &f.quads},
                      {"textures", &f.textures},
                      {"texels_level0", &f.texels_level0},
                      {"texels_lod", &f.texels_lod},
                      {"lod_under", &f.lod_under},
                      {"lod_over", &f.lod_over},
                      {"magnified", &f.magnified},
                      {"minified", &f.minified},
                      {"line_uses", &f.line_uses},
                      {"first_uses", &f.first_uses},
                      {"untracked_uses", &f.untracked_uses}})
    *p = j.at(k).get<uint64_t>();
  read_array(j.at("lines"), f.lines);
  read_array(j.at("lod"), f.lod);
  read_array(j.at("aniso"), f.aniso);
  read_array(j.at("reuse"), f.reuse);
  f.footprint_texels =
      j.at("footprint_texels_per_fragment").get<double>() * static_cast<double>(f.fragments);
  return f;
}

// A scene row: a functional run without ground truth at tiled4x4 addresses, its report's
// characterisation read back and the run's directory removed.
void measure_scene(WorkloadStudyRow& r, const std::string& dir, bool quick) {
  RunOptions o;
  o.scene = r.source;
  o.reference = "none";
  o.functional = true;
  o.threads = 1;
  o.out = dir;
  o.overrides = {"pipeline.layout=tiled4x4"};
  if (quick) o.overrides.insert(o.overrides.end(), {"output.width=160", "output.height=120"});
  std::ostringstream quiet;
  run_simulation(o, quiet);
  std::ifstream in(dir + "/report.json");
  try {
    const Json j = Json::parse(in).at("workload");
    r.frames = j.at("frames").size();
    r.total = from_json(j.at("total"));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(dir + "/report.json", std::string("unexpected report: ") + e.what());
  }
  std::filesystem::remove_all(dir);
}

// A draw trace's row: every frame rendered by the draw renderer (functional, default pipeline
// with tiled4x4 textures), the look-ups it sends to the unit characterised.
void measure_draws(WorkloadStudyRow& r) {
  const DrawTrace trace = read_draw_trace(r.source);
  std::vector<size_t> frames(trace.frames.size());
  for (size_t i = 0; i < frames.size(); ++i) frames[i] = i;
  static const toml::table kNoPipeline;
  PipelineSetup setup = PipelineSetup::from_toml(kNoPipeline, r.source);
  setup.layout = TexelLayout::Tiled4x4;
  DrawRenderer renderer(trace, frames, setup, TechTable::defaults(), false, r.source);
  WorkloadStats w(workload_textures(renderer.textures()));
  renderer.set_lookup_observer([&](const Fragment& f) { w.add(f, f.tex); });
  for (size_t i : frames) renderer.render(i);
  w.finish();
  r.frames = w.frames().size();
  r.total = w.total();
}

// The λ of the histogram's median fragment (the bin's centre); the under/overflow bins give
// their edge.
double median_lod(const FrameWorkload& f) {
  uint64_t seen = f.lod_under;
  if (2 * seen >= f.fragments) return FrameWorkload::kLodLo;
  for (size_t b = 0; b < f.lod.size(); ++b) {
    seen += f.lod[b];
    if (2 * seen >= f.fragments)
      return FrameWorkload::kLodLo + FrameWorkload::kLodStep * (static_cast<double>(b) + 0.5);
  }
  return FrameWorkload::kLodLo + FrameWorkload::kLodStep * FrameWorkload::kLodBins;
}

StudyTable table(const std::vector<WorkloadStudyRow>& rows) {
  StudyTable t({"workload", "kind", "frames", "fragments/frame", "quads/frame", "textures/frame",
                "texels/fragment (λ level)", "texels/fragment (level 0)",
                "footprint texels/fragment", "working set KiB 32 B", "working set KiB 64 B",
                "working set KiB 128 B", "median λ", "magnified %", "η ≥ 2 %", "reuse < 16 lines %",
                "reuse < 256 lines %", "reuse < 4096 lines %", "first uses %"},
               "llrrrrrrrrrrrrrrrrr");
  for (const WorkloadStudyRow& r : rows) {
    const FrameWorkload& f = r.total;
    const auto fr = static_cast<double>(f.fragments);
    auto share = [&](double v, double of) { return fmt(of > 0 ? 100 * v / of : 0); };
    std::vector<std::string> c = {r.name,
                                  r.kind,
                                  std::to_string(r.frames),
                                  fmt(r.per_frame(fr), 6),
                                  fmt(r.per_frame(static_cast<double>(f.quads)), 6),
                                  fmt(r.per_frame(static_cast<double>(f.textures))),
                                  fmt(f.per_fragment(static_cast<double>(f.texels_lod))),
                                  fmt(f.per_fragment(static_cast<double>(f.texels_level0))),
                                  fmt(f.per_fragment(f.footprint_texels))};
    for (size_t k = 0; k < 3; ++k) {
      c.push_back(fmt(
          r.per_frame(static_cast<double>(f.lines[k]) * FrameWorkload::kLineBytes[k] / 1024.0)));
    }
    uint64_t aniso2 = 0;
    for (size_t k = 1; k < f.aniso.size(); ++k) aniso2 += f.aniso[k];
    c.push_back(fmt(median_lod(f)));
    c.push_back(share(static_cast<double>(f.magnified), fr));
    c.push_back(share(static_cast<double>(aniso2), fr));
    for (uint64_t d : {16u, 256u, 4096u}) c.push_back(fmt(100 * reuse_within(f, d)));
    c.push_back(share(static_cast<double>(f.first_uses), static_cast<double>(f.line_uses)));
    t.add(c);
  }
  return t;
}

PlotSpec lod_plot(const std::vector<WorkloadStudyRow>& rows) {
  PlotSpec p;
  p.title = "LOD of the fragments (isotropic λ, bins of 0.5)";
  p.xlabel = "λ (bin centre; ends: below -4, from 12)";
  p.ylabel = "share of fragments";
  for (const WorkloadStudyRow& r : rows) {
    PlotSeries s;
    s.label = r.name;
    s.lines = true;
    const auto fr = static_cast<double>(std::max<uint64_t>(r.total.fragments, 1));
    s.x.push_back(FrameWorkload::kLodLo - FrameWorkload::kLodStep / 2);
    s.y.push_back(static_cast<double>(r.total.lod_under) / fr);
    for (size_t b = 0; b < r.total.lod.size(); ++b) {
      s.x.push_back(FrameWorkload::kLodLo +
                    FrameWorkload::kLodStep * (static_cast<double>(b) + 0.5));
      s.y.push_back(static_cast<double>(r.total.lod[b]) / fr);
    }
    s.x.push_back(FrameWorkload::kLodLo +
                  FrameWorkload::kLodStep * (FrameWorkload::kLodBins + 0.5));
    s.y.push_back(static_cast<double>(r.total.lod_over) / fr);
    p.series.push_back(s);
  }
  return p;
}

PlotSpec reuse_plot(const std::vector<WorkloadStudyRow>& rows) {
  PlotSpec p;
  p.title = "Reuse distance of 64-byte lines within a frame (cumulative)";
  p.xlabel = "distance below (distinct lines)";
  p.ylabel = "share of line reuses";
  p.logx = true;
  for (const WorkloadStudyRow& r : rows) {
    PlotSeries s;
    s.label = r.name;
    s.lines = true;
    for (int b = 0; b < ReuseDistance::kBins; ++b) {
      const uint64_t d = uint64_t{1} << b;
      s.x.push_back(static_cast<double>(d));
      s.y.push_back(reuse_within(r.total, d));
    }
    p.series.push_back(s);
  }
  return p;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown";
}

}  // namespace

int run_study_workloads(const std::string& out_dir, std::ostream& log,
                        const StudyWorkloadsOptions& opt, std::vector<WorkloadStudyRow>* out_rows) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudyFiles files(out_dir);
  std::vector<WorkloadStudyRow> rows;
  std::vector<std::string> scenes = opt.scenes;
  if (scenes.empty()) {
    scenes = {"default"};
    if (!opt.quick)
      for (const char* s : kScenes) scenes.push_back(shipped_scenes_dir() + "/" + s + ".toml");
  }
  rows.reserve(rows.size() + scenes.size() + opt.traces.size() + opt.draws.size());
  for (const std::string& s : scenes) {
    rows.push_back(
        {s == "default" ? "default" : std::filesystem::path(s).stem().string(), s, "scene", 0, {}});
  }
  for (const std::string& t : opt.traces)
    rows.push_back({std::filesystem::path(t).filename().string(), t, "trace", 0, {}});
  std::vector<std::string> draws = opt.draws;
  const std::string sample = shipped_scenes_dir() + "/../traces/samples/openarena-aggressor.draws";
  if (draws.empty() && !opt.quick && std::filesystem::exists(sample)) draws.push_back(sample);
  for (const std::string& t : draws)
    rows.push_back({std::filesystem::path(t).stem().string(), t, "draws", 0, {}});
  log << "study workloads: " << rows.size() << " workloads\n";
  const std::string work = files.path(".runs");
  parallel_tasks(rows.size(), opt.threads, [&](size_t k) {
    WorkloadStudyRow& r = rows[k];
    if (r.kind == "scene") {
      measure_scene(r, work + "/" + std::to_string(k), opt.quick);
    } else if (r.kind == "draws") {
      measure_draws(r);
    } else {
      const WorkloadStats w = trace_workload(r.source);
      r.frames = w.frames().size();
      r.total = w.total();
    }
  });
  std::filesystem::remove_all(work);
  const StudyTable t = table(rows);
  files.csv("workloads.csv", t);
  std::string md =
      "# Workloads side by side\n\n`texsim study workloads" +
      std::string(opt.quick ? " --quick" : "") + "` on " + cpu_model() +
      ". Per frame means; distinct texels and lines counted per frame "
      "(docs/reports.md \"workload\"). Scenes: functional runs, tiled4x4 "
      "addresses; traces: full RGBA8 mip chains, tiled4x4; draw traces: every frame rendered, "
      "the texture look-ups at tiled4x4 addresses.\n\n" +
      t.markdown();
  files.text("workloads.md", md);
  files.plot("workloads_lod.png", lod_plot(rows));
  files.plot("workloads_reuse.png", reuse_plot(rows));
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study workloads: wrote " << out_dir
      << "/workloads.csv, workloads.md, workloads_lod.png, workloads_reuse.png in " << fmt(secs, 3)
      << " s\n";
  if (out_rows) *out_rows = std::move(rows);
  return 0;
}

}  // namespace texsim
