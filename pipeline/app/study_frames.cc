#include "pipeline/app/study_frames.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "blocks/base/input_error.h"
#include "pipeline/capture/apitrace_import.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/report/number_text.h"
#include "pipeline/studies/shipped_scenes.h"
#include "pipeline/studies/study_table.h"
#include "traces/draw_trace.h"

namespace texsim {

namespace {

std::string default_draws() {
  return shipped_scenes_dir() + "/../traces/samples/openarena-aggressor.draws";
}

// The application's image of frame `number`, or "" when the folder has none.
std::string image_of(const std::string& dir, uint32_t number) {
  if (dir.empty()) return "";
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04u.png", number);
  const std::filesystem::path p = std::filesystem::path(dir) / name;
  return std::filesystem::is_regular_file(p) ? p.string() : "";
}

// Indices of the trace's frames in [first, last] (capture numbers); every frame without a range.
std::vector<size_t> pick_frames(const DrawTrace& t, const StudyFramesOptions& opt,
                                const std::string& file) {
  uint32_t first = 0, last = UINT32_MAX;
  if (!opt.frames.empty()) parse_frame_range(opt.frames, first, last);
  std::vector<size_t> out;
  for (size_t i = 0; i < t.frames.size(); ++i)
    if (t.frames[i].number >= first && t.frames[i].number <= last) out.push_back(i);
  if (out.empty())
    throw InputError(file, "no frame of the trace is in --frames " +
                               (opt.frames.empty() ? std::string("(all)") : opt.frames));
  return out;
}

// One frame through the clocked unit (default [pipeline]) with its truth, on one thread.
FrameStudyRow measure_frame(const DrawTrace& trace, size_t index, const std::string& file,
                            const std::string& images, bool truth) {
  const auto t0 = std::chrono::steady_clock::now();
  static const toml::table kNoPipeline;
  const PipelineSetup setup = PipelineSetup::from_toml(kNoPipeline, file);
  DrawRenderer renderer(trace, {index}, setup, TechTable::defaults(), true, file);
  if (truth) renderer.set_truth(PixelIntegrator(TruthPixel::Box, TruthSampling{}), 1);
  const RenderedFrame f = renderer.render(index);
  FrameStudyRow r;
  r.frame = f.number;
  r.counts = f.counts;
  const UnitArray& units = renderer.units();
  if (units.fragments() > 0) units.check_timing_invariants();
  r.lookups = units.fragments();
  r.cycles = units.cycles();
  const TextureCache::Stats l1 = units.l1_totals();
  r.l1_accesses = l1.accesses;
  r.l1_hits = l1.hits;
  r.dram_bytes = units.memory().dram_totals().bytes;
  r.accuracy = f.accuracy;
  r.truth = compare_with_truth(f);
  if (const std::string img = image_of(images, f.number); !img.empty()) {
    r.image = compare_frame(f, read_rgb8_image(img), img);
    r.has_image = true;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

double ratio(double a, double b) { return b > 0 ? a / b : 0; }

StudyTable table(const std::vector<FrameStudyRow>& rows) {
  StudyTable t({"frame", "draws", "triangles", "fragments", "look-ups", "written", "cycles",
                "cycles/look-up", "L1 hit %", "DRAM bytes/look-up", "look-up PSNR vs truth (dB)",
                "frame PSNR vs truth (dB)", "drawn agree vs app %", "PSNR vs app (dB)", "s"},
               "rrrrrrrrrrrrrrr");
  for (const FrameStudyRow& r : rows) {
    const double n = static_cast<double>(r.lookups);
    const bool truth = r.accuracy.lookups > 0;
    t.add({std::to_string(r.frame), std::to_string(r.counts.draws),
           std::to_string(r.counts.triangles), std::to_string(r.counts.fragments),
           std::to_string(r.lookups), std::to_string(r.counts.written), std::to_string(r.cycles),
           fmt(ratio(static_cast<double>(r.cycles), n), 4),
           fmt(100 * ratio(static_cast<double>(r.l1_hits), static_cast<double>(r.l1_accesses)), 5),
           fmt(ratio(static_cast<double>(r.dram_bytes), n), 4),
           truth ? fmt(r.accuracy.psnr_db(), 4) : "", truth ? fmt(r.truth.psnr_db, 4) : "",
           r.has_image ? fmt(r.image.drawn_agreement_pct, 6) : "",
           r.has_image ? fmt(r.image.psnr_db, 4) : "", fmt(r.seconds, 3)});
  }
  return t;
}

PlotSpec psnr_plot(const std::vector<FrameStudyRow>& rows) {
  PlotSpec p{"Frames of a real application: PSNR per frame",
             "frame (capture number)",
             "PSNR (dB)",
             false,
             false,
             1200,
             800,
             {}};
  PlotSeries lookups{"texture look-ups vs ground truth", {}, {}, true, {}};
  PlotSeries frame{"frame vs frame shaded with the truth", {}, {}, true, {}};
  PlotSeries app{"frame vs the application's image", {}, {}, false, {}};
  for (const FrameStudyRow& r : rows) {
    const double x = r.frame;
    if (r.accuracy.lookups > 0) {
      lookups.x.push_back(x);
      lookups.y.push_back(r.accuracy.psnr_db());
      frame.x.push_back(x);
      frame.y.push_back(r.truth.psnr_db);
    }
    if (r.has_image) {
      app.x.push_back(x);
      app.y.push_back(r.image.psnr_db);
    }
  }
  for (PlotSeries* s : {&lookups, &frame, &app})
    if (!s->x.empty()) p.series.push_back(*s);
  return p;
}

PlotSpec cycles_plot(const std::vector<FrameStudyRow>& rows) {
  PlotSpec p{"Frames of a real application: texture-unit cycles per look-up and L1 hit rate",
             "frame (capture number)",
             "cycles per look-up; L1 hit rate (%) / 10",
             false,
             false,
             1200,
             800,
             {}};
  PlotSeries cyc{"cycles per look-up", {}, {}, true, {}};
  PlotSeries hit{"L1 hit rate (%) / 10", {}, {}, true, {}};
  for (const FrameStudyRow& r : rows) {
    cyc.x.push_back(r.frame);
    cyc.y.push_back(ratio(static_cast<double>(r.cycles), static_cast<double>(r.lookups)));
    hit.x.push_back(r.frame);
    hit.y.push_back(10 * ratio(static_cast<double>(r.l1_hits), static_cast<double>(r.l1_accesses)));
  }
  p.series = {cyc, hit};
  return p;
}

std::string markdown(const std::vector<FrameStudyRow>& rows, const std::string& draws,
                     const std::string& images, bool truth, double seconds, int threads) {
  std::string s = "# Study: frames of a real application\n\n";
  s += "Every frame of `" + draws +
       "` rendered by `texsim study frames`: the draw renderer, the "
       "clocked texture unit (default `[pipeline]`, one unit; its caches start cold in every "
       "frame, as each frame is a task of its own) and the fixed-function colour stage. ";
  s += truth ? "Ground truth per look-up: the level-0 texture, bilinear in double, integrated "
               "over the pixel (adaptive box) through the triangle's exact map; the frame PSNR "
               "is against the frame shaded with the truth's texels. "
             : "No ground truth (--reference none). ";
  s += images.empty() ? "No application images were given.\n"
                      : "Application images from `" + images +
                            "` (frame_NNNN.png), where present; a pixel counts as drawn there "
                            "when it is not the clear colour.\n";
  s.append("\n").append(std::to_string(rows.size())).append(" frames in ");
  s.append(fmt(seconds, 3)).append(" s on ").append(std::to_string(threads));
  s.append(" worker threads (the `s` column: each frame's task).\n\n");
  return s + table(rows).markdown();
}

}  // namespace

int run_study_frames(const std::string& out_dir, std::ostream& log, const StudyFramesOptions& opt,
                     std::vector<FrameStudyRow>* out_rows) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string draws = opt.draws.empty() ? default_draws() : opt.draws;
  std::string images = opt.images;
  if (images.empty()) {
    const std::filesystem::path d = std::filesystem::path(draws).replace_extension();
    if (std::filesystem::is_directory(d)) images = d.string();
  } else if (!std::filesystem::is_directory(images)) {
    throw InputError(images, "--images: not a folder");
  }
  const DrawTrace trace = read_draw_trace(draws);
  const std::vector<size_t> frames = pick_frames(trace, opt, draws);
  const StudyFiles files(out_dir);
  const int threads = std::min(resolve_threads(opt.threads), static_cast<int>(frames.size()));
  log << "study frames: " << frames.size() << " frames of " << draws << " on " << threads
      << " threads\n";
  std::vector<FrameStudyRow> rows(frames.size());
  parallel_tasks(frames.size(), threads, [&](size_t k) {
    rows[k] = measure_frame(trace, frames[k], draws, images, opt.truth);
  });
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  files.csv("frames.csv", table(rows));
  files.text("frames.md", markdown(rows, draws, images, opt.truth, secs, threads));
  files.plot("frames_psnr.png", psnr_plot(rows));
  files.plot("frames_cycles.png", cycles_plot(rows));
  log << "study frames: wrote " << out_dir
      << "/frames.csv, frames.md, frames_psnr.png, frames_cycles.png in " << fmt(secs, 3) << " s\n";
  if (out_rows) *out_rows = std::move(rows);
  return 0;
}

}  // namespace texsim
