#include "pipeline/app/run_draws.h"

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/output_set.h"
#include "blocks/base/version.h"
#include "pipeline/render/colour_stage.h"
#include "pipeline/report/image_metrics.h"
#include "pipeline/report/number_text.h"
#include "pipeline/report/run_report.h"
#include "pipeline/scene/scene.h"

namespace texsim {

namespace {

using Json = nlohmann::ordered_json;

// The trace's frame `number`, or the first with number < 0.
size_t pick_frame(const DrawTrace& t, int64_t number, const std::string& file) {
  if (t.frames.empty()) throw InputError(file, "no frames to render");
  if (number < 0) return 0;
  std::string have;
  for (size_t i = 0; i < t.frames.size(); ++i) {
    if (t.frames[i].number == number) return i;
    if (have.size() < 60) have += (have.empty() ? "" : ", ") + std::to_string(t.frames[i].number);
  }
  throw InputError(file, "--frame " + std::to_string(number) +
                             ": the trace has no such frame (its frames: " + have + ")");
}

// A frame's RGBA8 pixels where drawn (black elsewhere) as an image file.
void write_frame_image(const std::string& path, const RenderedFrame& f,
                       const std::vector<uint8_t>& rgba, const std::vector<uint8_t>& drawn) {
  ImageRgb img(f.width, f.height, glm::dvec3(0));
  for (int y = 0; y < f.height; ++y) {
    for (int x = 0; x < f.width; ++x) {
      const size_t p =
          static_cast<size_t>(y) * static_cast<size_t>(f.width) + static_cast<size_t>(x);
      if (!drawn[p]) continue;
      const uint8_t* c = rgba.data() + 4 * p;
      img.set(x, y,
              glm::vec4(static_cast<float>(c[0]) / 255.0f, static_cast<float>(c[1]) / 255.0f,
                        static_cast<float>(c[2]) / 255.0f, 1.0f));
    }
  }
  write_image(path, img);
}

Json counts_json(const DrawRenderCounts& c) {
  Json j = {{"draws", c.draws},
            {"draws_refused", c.draws_refused},
            {"triangles", c.triangles},
            {"clipped_away", c.clipped_away},
            {"culled", c.culled},
            {"fragments", c.fragments},
            {"depth_killed", c.depth_killed},
            {"alpha_killed", c.alpha_killed},
            {"blended", c.blended},
            {"written", c.written},
            {"texture_lookups", c.lookups}};
  j["refused"] = Json::object();
  for (const auto& [why, n] : c.refused) j["refused"][why] = n;
  j["approximated"] = Json::object();
  for (const auto& [what, n] : c.approximated) j["approximated"][what] = n;
  return j;
}

Json comparison_json(const FrameComparison& c, const std::string& path) {
  return {{"reference", path},
          {"pixels", c.pixels},
          {"drawn_both", c.drawn_both},
          {"drawn_texsim_only", c.drawn_texsim_only},
          {"drawn_reference_only", c.drawn_reference_only},
          {"drawn_agreement_pct", c.drawn_agreement_pct},
          {"psnr_db", c.psnr_db},
          {"mse", c.mse},
          {"mean_abs_8bit", c.mean_abs},
          {"max_abs_8bit", c.max_abs},
          {"pixels_equal", c.equal},
          {"pixels_off_by_more_than_8", c.off_by_more_than_8}};
}

// The look-ups against their truth, and the frame against the frame shaded with the truth.
Json truth_json(const DrawRunSummary& s) {
  const LookupAccuracy& a = s.frame.accuracy;
  return {{"lookups", a.lookups},
          {"lookup_psnr_db", a.psnr_db()},
          {"lookup_mse", a.mse()},
          {"lookup_max_abs", a.max_abs},
          {"mean_truth_samples",
           a.lookups ? static_cast<double>(a.samples) / static_cast<double>(a.lookups) : 0},
          {"frame", comparison_json(s.truth, "reference.png")}};
}

std::string draws_markdown(const DrawRunSummary& s, const DrawRunOptions& opt,
                           const std::vector<std::string>& notes) {
  const DrawRenderCounts& c = s.frame.counts;
  std::ostringstream md;
  md << "\n## Draws (frame " << s.frame.number << " of `" << opt.draws << "`)\n\n"
     << "Rendered by the draw renderer and the fixed-function colour stage, which are outside "
        "the texture unit (no cycles, operations or area of theirs are counted above).\n\n"
     << "| draws | refused | triangles | clipped away | culled | fragments | depth-killed | "
        "alpha-killed | blended | written | texture look-ups |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|\n"
     << "| " << c.draws << " | " << c.draws_refused << " | " << c.triangles << " | "
     << c.clipped_away << " | " << c.culled << " | " << c.fragments << " | " << c.depth_killed
     << " | " << c.alpha_killed << " | " << c.blended << " | " << c.written << " | " << c.lookups
     << " |\n\n";
  for (const auto& [why, n] : c.refused) md << "- refused: " << why << ": " << n << " draws\n";
  for (const auto& [what, n] : c.approximated)
    md << "- approximated: " << what << ": " << n << " draw units\n";
  md << "\nMaterials (one per texture and sampler state):\n\n";
  for (const auto& n : notes) md << "- " << n << "\n";
  if (s.frame.has_truth()) {
    const LookupAccuracy& a = s.frame.accuracy;
    const FrameComparison& t = s.truth;
    md << "\n## Against the ground truth\n\nEach texture look-up's texel against its truth ("
       << s.truth_text
       << "); `reference.png` is the frame shaded with the truth's texels "
          "(same fragments and depth decisions as `image.png`).\n\n"
       << "| look-ups | look-up PSNR (dB) | look-up max abs | truth samples per look-up | "
          "frame PSNR vs truth (dB) | pixels drawn agree | frame pixels off by > 8 |\n"
          "|---|---|---|---|---|---|---|\n"
       << "| " << a.lookups << " | " << fmt(a.psnr_db(), 4) << " | " << fmt(a.max_abs, 4) << " | "
       << fmt(a.lookups ? static_cast<double>(a.samples) / static_cast<double>(a.lookups) : 0, 4)
       << " | " << fmt(t.psnr_db, 4) << " | " << fmt(t.drawn_agreement_pct, 6) << " % | "
       << t.off_by_more_than_8 << " of " << t.drawn_both << " |\n";
  }
  if (s.compared) {
    const FrameComparison& k = s.comparison;
    md << "\n## Against the application's image\n\n`" << opt.compare
       << "`; a reference pixel counts as drawn when it is not the colour the window was cleared "
          "to "
          "(255, 0, 128: ioquake3's `r_clear 1`). Drawn by texsim only: "
       << k.drawn_texsim_only << " pixels; by the reference only: " << k.drawn_reference_only
       << ".\n\n"
       << "| pixels drawn agree | PSNR over pixels drawn by both (dB) | mean abs (8-bit) | max "
          "abs (8-bit) | pixels off by > 8 |\n|---|---|---|---|---|\n"
       << "| " << k.drawn_agreement_pct << " % | " << k.psnr_db << " | " << k.mean_abs << " | "
       << k.max_abs << " | " << k.off_by_more_than_8 << " of " << k.drawn_both << " |\n\n"
       << "`difference.png`: the largest channel's absolute difference × 8 where both drew, "
          "white where only one drew.\n";
  }
  return md.str();
}

// The run's summary on the terminal.
void log_draw_run(const DrawRunSummary& s, const DrawRunOptions& opt, std::ostream& log) {
  const RunOptions& ro = opt.run;
  const DrawRenderCounts& c = s.frame.counts;
  log << "texsim run: frame " << s.frame.number << " of " << opt.draws << ": " << c.draws
      << " draws (" << c.draws_refused << " refused), " << c.triangles << " triangles, "
      << c.fragments << " fragments (" << c.depth_killed << " depth-killed, " << c.alpha_killed
      << " alpha-killed, " << c.blended << " blended), " << s.unit_fragments
      << " texture look-ups, " << s.cycles << " cycles\n";
  for (const auto& [why, n] : c.refused)
    log << "  refused: " << n << " draws with " << why << " (not reproduced by the colour stage)\n";
  if (s.compared) {
    log << "  against " << opt.compare << ": pixels drawn agree on "
        << s.comparison.drawn_agreement_pct << " %, PSNR " << s.comparison.psnr_db
        << " dB over the " << s.comparison.drawn_both << " pixels both drew\n";
  }
  if (s.frame.has_truth()) {
    log << "  against the ground truth: look-ups PSNR " << fmt(s.frame.accuracy.psnr_db(), 4)
        << " dB; frame PSNR " << fmt(s.truth.psnr_db, 4) << " dB\n";
  }
  log << "  report: " << ro.out << "/report.json, " << ro.out << "/report.md\n  images: " << ro.out
      << "/image.png" << (s.frame.has_truth() ? ", " + ro.out + "/reference.png" : "")
      << (s.compared ? ", " + ro.out + "/difference.png" : "") << "\n";
}

}  // namespace

DrawRunSummary run_draws(const DrawRunOptions& opt, std::ostream& log) {
  const RunOptions& ro = opt.run;
  ensure_dir(ro.out);
  const Scene scene = (ro.scene.empty() || ro.scene == "default")
                          ? default_scene(ro.overrides)
                          : load_scene(ro.scene, ro.overrides);
  static const toml::table kNoPipeline;
  const PipelineSetup setup =
      PipelineSetup::from_toml(scene.pipeline ? *scene.pipeline : kNoPipeline, scene.path);
  if (setup.derivatives != QuadDerivatives::Own) {
    throw InputError(scene.path,
                     "[pipeline] derivatives: a draw trace's fragments carry their exact "
                     "derivatives; quad derivatives are not available with --draws (set "
                     "derivatives = \"fragment\")");
  }
  const DrawTrace trace = read_draw_trace(opt.draws);
  const size_t index = pick_frame(trace, ro.frame, opt.draws);

  DrawRunSummary s;
  const auto t0 = std::chrono::steady_clock::now();
  DrawRenderer renderer(trace, {index}, setup, scene.tech, !ro.functional, opt.draws);
  const PixelIntegrator integrate(scene.reference_pixel, {scene.reference_samples});
  if (ro.reference != "none") renderer.set_truth(integrate, ro.threads);
  WorkloadStats workload(workload_textures(renderer.textures()));
  if (ro.workload) renderer.set_lookup_observer([&](const Fragment& f) { workload.add(f, f.tex); });
  s.frame = renderer.render(index);
  s.truth = compare_with_truth(s.frame);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const UnitArray& units = renderer.units();
  if (units.fragments() > 0) units.check_timing_invariants();
  s.unit_fragments = units.fragments();
  s.cycles = units.cycles();

  Rgb8Image ref;
  if (!opt.compare.empty()) {
    ref = read_rgb8_image(opt.compare);
    s.comparison = compare_frame(s.frame, ref, opt.compare);
    s.compared = true;
  }

  OutputSet outputs(ro.out);
  write_frame_image(outputs.path("image.png"), s.frame, s.frame.rgba, s.frame.drawn);
  if (s.frame.has_truth())
    write_frame_image(outputs.path("reference.png"), s.frame, s.frame.truth_rgba,
                      s.frame.truth_drawn);
  if (s.compared) {
    const std::vector<uint8_t> diff = difference_image(s.frame, ref, 8);
    ImageRgb d(s.frame.width, s.frame.height, glm::dvec3(0));
    for (size_t p = 0; p < diff.size(); ++p) {
      const float g = static_cast<float>(diff[p]) / 255.0f;
      d.set(static_cast<int>(p % static_cast<size_t>(s.frame.width)),
            static_cast<int>(p / static_cast<size_t>(s.frame.width)), glm::vec4(g, g, g, 1));
    }
    write_image(outputs.path("difference.png"), d);
  }

  RunInfo info;
  workload.finish();
  if (ro.workload) info.workload = &workload;
  info.scene = scene.path;
  info.trace = opt.draws;
  // The texture unit's accuracy is that of its look-ups against their exact truth (the
  // "draws" section); RunInfo's per-pixel accuracy is a scene's and is not filled here.
  info.has_truth = false;
  s.truth_text = integrate.sampling().describe(integrate.pixel());
  info.reference =
      ro.reference == "none"
          ? "No ground truth (--reference none). The frame can be compared with the "
            "application's own image (--compare), below."
          : "Ground truth per texture look-up: " + s.truth_text +
                ", through its triangle's exact screen-to-texture map; reference.png is the frame "
                "shaded with the truth's texels (the draws section has the figures).";
  info.width = s.frame.width;
  info.height = s.frame.height;
  info.textures = renderer.texture_names();
  info.provenance.version = kTexsimVersion;
  info.provenance.command = ro.command;
  if (!ro.scene.empty() && ro.scene != "default")
    info.provenance.inputs.push_back(digest_file("scene", ro.scene));
  info.provenance.inputs.push_back(digest_file("draw trace", opt.draws));
  if (s.compared) info.provenance.inputs.push_back(digest_file("reference image", opt.compare));
  info.provenance.setup = setup;
  info.provenance.tech = scene.tech;
  info.provenance.energy = scene.energy;
  write_run_reports(outputs.staging(), info, units, AccuracyMetrics{});
  // The draw-level figures beside the texture unit's.
  const std::string json_path = outputs.staging() + "/report.json";
  Json j = Json::parse(std::ifstream(json_path));
  j["draws"] = counts_json(s.frame.counts);
  j["draws"]["frame"] = s.frame.number;
  j["draws"]["materials"] = renderer.material_notes();
  if (s.compared) j["comparison"] = comparison_json(s.comparison, opt.compare);
  if (s.frame.has_truth()) j["truth"] = truth_json(s);
  write_file_atomic(json_path,
                    j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  const std::string md_path = outputs.staging() + "/report.md";
  std::ostringstream md;
  md << std::ifstream(md_path).rdbuf() << draws_markdown(s, opt, renderer.material_notes());
  write_file_atomic(md_path, md.str());
  outputs.commit();

  log_draw_run(s, opt, log);
  return s;
}

}  // namespace texsim
