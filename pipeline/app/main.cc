// texsim command-line entry point (docs/cli.md).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <new>
#include <string>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/printable.h"
#include "blocks/base/temp_registry.h"
#include "blocks/base/version.h"
#include "pipeline/app/cosim.h"
#include "pipeline/app/run.h"
#include "pipeline/app/run_draws.h"
#include "pipeline/app/study_formats.h"
#include "pipeline/app/study_frames.h"
#include "pipeline/app/study_memory.h"
#include "pipeline/app/study_rtl_sampler.h"
#include "pipeline/app/study_workloads.h"
#include "pipeline/app/sweep.h"
#include "pipeline/app/tuner.h"
#include "pipeline/capture/apitrace_import.h"
#include "pipeline/kernel/clocked_pipeline.h"
#include "pipeline/render/draw_fragment_trace.h"
#include "pipeline/report/provenance.h"
#include "pipeline/report/workload_report.h"
#include "pipeline/studies/shipped_scenes.h"
#include "pipeline/studies/study_coords.h"
#include "pipeline/studies/study_filters.h"
#include "pipeline/studies/study_objspace.h"
#include "pipeline/studies/study_raster.h"
#include "pipeline/studies/study_relief.h"
#include "pipeline/studies/study_rtl.h"
#include "pipeline/studies/study_terrain.h"
#include "pipeline/studies/study_thesis.h"
#include "pipeline/studies/study_vd.h"
#include "traces/draw_trace.h"
#include "traces/trace_tools.h"

namespace {

// The first word of the command line that names no subcommand where one is expected
// ("texsim frob", "texsim trace frob"), or "" if there is none. CLI11 alone would report
// "A subcommand is required" without naming it.
std::string unknown_subcommand(const CLI::App& app, int argc, char** argv) {
  const CLI::App* level = &app;
  for (int i = 1; i < argc; ++i) {
    std::string word = argv[i];
    if (word.empty() || word[0] == '-') return "";
    const auto subs = level->get_subcommands([](const CLI::App*) { return true; });
    if (subs.empty()) return "";
    const CLI::App* sub = nullptr;
    for (const CLI::App* s : subs) {
      if (s->get_name() == word) sub = s;
    }
    if (!sub) return word;
    level = sub;
  }
  return "";
}

// Parses the command line. Returns -1 to go on, else the exit status: 0 for --help and
// --version, 2 for a usage error (bad input, as everywhere else).
// "4G", "512M", "65536K", "1000000" (bytes; K, M, G are powers of 1024).
uint64_t parse_byte_size(const std::string& text, const std::string& option) {
  size_t used = 0;
  double v = -1;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string unit = text.substr(used);
  if (unit.size() > 1 && (unit.back() == 'B' || unit.back() == 'b')) unit.pop_back();
  static const std::map<std::string, double> kUnits = {
      {"", 1},        {"K", 1024},    {"k", 1024},  {"M", 1 << 20},  {"m", 1 << 20},
      {"G", 1 << 30}, {"g", 1 << 30}, {"Ki", 1024}, {"Mi", 1 << 20}, {"Gi", 1 << 30}};
  const auto it = kUnits.find(unit);
  if (used == 0 || it == kUnits.end() || !(v > 0) || v * it->second > 1e18) {
    throw texsim::InputError(option, "'" + text + "' is not a size (e.g. 4G, 512M, 1000000)");
  }
  return static_cast<uint64_t>(v * it->second);
}

// "auto" (0) or an error in (0, 1].
double parse_error_scale(const std::string& text) {
  if (text == "auto") return 0;
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(v > 0 && v <= 1)) {
    throw texsim::InputError("--error-scale", "'" + text + "' is not 'auto' or a number in (0, 1]");
  }
  return v;
}

int parse_command_line(CLI::App& app, int argc, char** argv) {
  const std::string unknown = unknown_subcommand(app, argc, argv);
  if (!unknown.empty()) {
    std::cerr << "texsim: error: unknown command '" << texsim::printable(unknown)
              << "' (texsim --help lists the commands)\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "texsim: error: " << texsim::printable(e.what())
              << " (add --help for the usage)\n";
    return 2;
  }
  return -1;
}

// `run` and its options.
struct RunCli {
  texsim::RunOptions opt;
  std::string max_memory = "4G";
  bool no_progress = false;
  std::string error_scale = "auto";
  std::string draws, compare;  // run --draws FILE [--compare PNG]
  CLI::App* cmd = nullptr;
};

void add_run_command(CLI::App& app, RunCli& r) {
  texsim::RunOptions& run = r.opt;
  r.cmd = app.add_subcommand("run",
                             "Simulate a scene (default: the built-in scene) or a trace; "
                             "write report.json, report.md and images to --out");
  CLI::App* run_cmd = r.cmd;
  run_cmd->add_option("scene", run.scene,
                      "Scene file (TOML), or 'default' (the built-in scene, also used when both "
                      "scene and --trace are omitted)");
  run_cmd->add_option("--trace", run.trace,
                      "Fragment trace (.trc binary or .csv) to drive the texture unit");
  run_cmd
      ->add_option("--draws", r.draws,
                   "Draw trace (.draws, traces/DRAWS.md): render one frame (--frame, "
                   "default the first) through the texture unit and the fixed-function "
                   "colour stage")
      ->excludes("--trace");
  run_cmd
      ->add_option("--compare", r.compare,
                   "With --draws: the application's own image of the frame (PNG) to compare "
                   "with (pixels drawn, PSNR, difference.png)")
      ->needs("--draws");
  run_cmd->add_option("--out", run.out, "Output directory")->capture_default_str();
  run_cmd->add_flag("--functional", run.functional,
                    "Functional only: colours and op counts, no cache or clock");
  run_cmd
      ->add_option("--frame", run.frame,
                   "Frame whose images are written (default: the first); every frame's "
                   "accuracy is in the report")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_option("--set", run.overrides,
                      "KEY=VALUE: change one scene key before the scene is read, e.g. "
                      "pipeline.fifo_depth=8 or materials.floor.filter.mode=ewa (repeatable)");
  run_cmd
      ->add_option("--threads", run.threads,
                   "Threads for the ground truth (0: one per hardware thread); results are "
                   "identical for any count")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  run_cmd
      ->add_option("--reference", run.reference,
                   "'scene' (the ground truth as the scene's [reference] says) or 'none' (no "
                   "ground truth: faster, and the report has no meaningful accuracy figures)")
      ->check(CLI::IsMember({"scene", "none"}))
      ->capture_default_str();
  run_cmd
      ->add_option("--max-memory", r.max_memory,
                   "Refuse a run estimated to need more memory (bytes, or with K/M/G suffix)")
      ->capture_default_str();
  run_cmd
      ->add_option("--error-scale", r.error_scale,
                   "Error drawn white in error.png: 'auto' (the largest error of the imaged "
                   "frame) or a fixed value in (0, 1], e.g. 0.05, to compare runs")
      ->capture_default_str();
  run_cmd->add_flag("--no-progress", r.no_progress, "Do not show the progress line");
  run_cmd->add_flag("--no-workload{false}", run.workload,
                    "Leave the workload characterisation out of the report (it costs about "
                    "0.15 µs per fragment)");
  run_cmd
      ->add_option("--timeline", run.timeline,
                   "Write the clocked pipeline's stage activity: FILE.json as Chrome trace "
                   "events (Perfetto, chrome://tracing), any other name as a VCD (GTKWave); "
                   "per stage busy, items issued and items in flight; one time unit = one cycle")
      ->excludes("--functional");
  run_cmd
      ->add_option("--timeline-limit", run.timeline_limit,
                   "Fragments recorded in the --timeline (the first ones)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{100000000}))
      ->capture_default_str();
  run_cmd->add_flag("--no-truth-cache{false}", run.truth_cache,
                    "Compute the ground truth without the truth cache (docs/truth-cache.md): "
                    "neither read nor written");
  run_cmd->add_flag("--ledger", run.ledger,
                    "Per-block error ledger in the report: each block made exact in turn, its "
                    "share of the error next to its cost (docs/ledger.md; repeats the run)");
  run_cmd->add_flag("--ledger-maps", run.ledger_maps,
                    "With --ledger: ledger_<block>.png, the pixels each exact block changes");
  run_cmd
      ->add_option("--board", run.board,
                   "virtual|hid: the materials with filter.arithmetic = \"fixed\" sampled by the "
                   "RTL sampler on a board over the link (docs/rtl/link.md)")
      ->check(CLI::IsMember({"virtual", "hid"}));
}

// `sweep` and `merge` and their options.
struct SweepCli {
  texsim::SweepOptions opt;
  std::string file, shard, job;
  std::vector<std::string> merge_dirs;
  std::string merge_out = "out/merged";
  CLI::App* cmd = nullptr;
  CLI::App* merge = nullptr;
};

void add_sweep_commands(CLI::App& app, SweepCli& s) {
  s.cmd = app.add_subcommand(
      "sweep",
      "Run a grid of scenes/traces x scene-key overrides as numbered jobs (docs/sweeps.md)");
  s.cmd->add_option("file", s.file, "Sweep file (TOML: [sweep] and [grid])")->required();
  s.cmd->add_option("--out", s.opt.out, "Output directory (default: the sweep's out)");
  s.cmd->add_option("--jobs", s.opt.jobs, "Jobs at a time (0: one per hardware thread)")
      ->check(CLI::Range(0, 1024));
  s.cmd->add_option("--shard", s.shard, "K/N: run only jobs with id % N == K-1 (GNU parallel)");
  s.cmd->add_option("--job", s.job, "Run one job (a Slurm array task)");
  s.cmd->add_flag("--slurm", s.opt.slurm, "Write OUT/sweep.sbatch (a job array) instead");
  s.cmd->add_flag("--list", s.opt.list, "Print the jobs (JSON lines) and exit");
  s.cmd->add_flag("--no-truth-cache{false}", s.opt.truth_cache,
                  "Jobs compute their ground truths without the truth cache");
  s.merge = app.add_subcommand("merge", "Combine sweep outputs into merged.csv and merged.md");
  s.merge->add_option("dirs", s.merge_dirs, "Sweep output directories")->required();
  s.merge->add_option("--out", s.merge_out, "Output directory")->capture_default_str();
}

int run_sweep_command(SweepCli& s, const char* argv0) {
  // Parsed strictly here (CLI11 would take "1/2/3", wrap "-1" or answer with its own message).
  if (s.cmd->count("--shard") > 0) texsim::parse_sweep_shard(s.shard, s.opt.shard, s.opt.shards);
  if (s.cmd->count("--job") > 0) s.opt.job = texsim::parse_sweep_job(s.job);
  s.opt.command = std::filesystem::absolute(argv0).string();
  return texsim::run_sweep(s.file, s.opt, std::cout);
}

// `tune` and its options.
// `--shard` goes to `shard` and is parsed with the other inputs (an InputError, exit 2).
CLI::App* add_tune_command(CLI::App& app, texsim::TuneOptions& t, std::string& shard) {
  CLI::App* cmd = app.add_subcommand(
      "tune",
      "Cheapest configuration per material that meets an error budget; Pareto front "
      "(docs/tune.md)");
  cmd->add_option("scene", t.scene, "Scene file (TOML), or 'default' for the built-in scene")
      ->required();
  cmd->add_option("--budget", t.budget,
                  "psnr=<dB> (at least) or nmse=<value> (at most), per "
                  "material")
      ->capture_default_str();
  cmd->add_option("--cost", t.cost, "What to minimise: cycles or area")->capture_default_str();
  cmd->add_option("--out", t.out, "Output directory")->capture_default_str();
  cmd->add_option("--set", t.overrides, "KEY=VALUE: change one scene key first (repeatable)");
  cmd->add_option("--threads", t.threads,
                  "Threads for the ground truth (0: one per hardware "
                  "thread)")
      ->check(CLI::Range(0, 1024));
  cmd->add_flag("!--no-ledger", t.ledger, "Do not run the chosen scene with the error ledger");
  cmd->add_option("--jobs", t.jobs,
                  "Candidate runs at a time (0: one per hardware thread); the outputs do not "
                  "depend on it")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_option(
      "--shard", shard,
      "K/N: search only materials with index % N == K-1; writes tune_shard.json (GNU parallel)");
  cmd->add_flag("--no-truth-cache{false}", t.truth_cache,
                "Compute every candidate's ground truth without the truth cache (in memory or "
                "on disk)");
  cmd->add_flag("--families", t.families,
                "Also switch each material's filter family (classic, ewa, spaf, feline, "
                "multi_probe)");
  cmd->add_option("--merge", t.merge,
                  "Shard output directories: assemble their points into the outputs of one run");
  return cmd;
}

// `trace gen` and its options.
struct GenCli {
  std::string scene, out, draws, frames;
  std::vector<std::string> overrides;
  CLI::App* cmd = nullptr;
};

void add_gen_command(CLI::App& trace_cmd, GenCli& g) {
  g.cmd = trace_cmd.add_subcommand(
      "gen", "Write a scene's reference fragments (exact double coordinates)");
  g.cmd->add_option("scene", g.scene, "Scene file; 'default' for the built-in scene");
  g.cmd
      ->add_option("--draws", g.draws,
                   "Instead of a scene: a draw trace (traces/DRAWS.md), whose texture look-ups "
                   "are written")
      ->excludes("scene");
  g.cmd
      ->add_option("--frames", g.frames,
                   "With --draws: frames A-B or A (the capture's numbers; default: all)")
      ->needs("--draws");
  g.cmd->add_option("-o,--output", g.out, "Output trace (.trc binary, .csv text)")->required();
  g.cmd->add_option("--set", g.overrides,
                    "KEY=VALUE: change one scene key before the scene is read, as for run "
                    "(repeatable)");
}

void run_gen_command(const GenCli& g) {
  using namespace texsim;  // NOLINT(google-build-using-namespace)
  if (g.scene.empty() && g.draws.empty())
    throw InputError("trace gen", "give a scene file (or 'default') or --draws FILE");
  uint32_t first = 0, last = UINT32_MAX;
  if (!g.frames.empty()) parse_frame_range(g.frames, first, last);
  const uint64_t n = g.draws.empty() ? generate_scene_trace(g.scene == "default" ? "" : g.scene,
                                                            g.out, g.overrides)
                                     : generate_draws_trace(g.draws, first, last, g.out);
  // With -o - the trace itself is on standard output: the summary goes to stderr.
  (g.out == "-" ? std::cerr : std::cout)
      << "texsim trace gen: wrote " << n << " fragments to " << g.out << "\n";
}

// `texsim study …`: every study subcommand and its options.
struct StudyCli {
  CLI::App *cmd = nullptr, *vd = nullptr, *coords = nullptr, *filters = nullptr, *raster = nullptr,
           *objspace = nullptr, *rtl = nullptr, *thesis = nullptr, *relief = nullptr,
           *terrain = nullptr, *memory = nullptr, *workloads = nullptr, *frames = nullptr,
           *formats = nullptr;
  std::string out = "out/study";
  int threads = 0;
  texsim::StudyRtlOptions rtl_opt;
  std::vector<std::string> rtl_params;
  std::string rtl_sampler_scene = texsim::shipped_scenes_dir() + "/bunny.toml";
  std::string rtl_sampler_material = "fur";
  bool rtl_no_generic = false;
  texsim::StudyThesisOptions thesis_opt;
  texsim::StudyMemoryOptions memory_opt;
  texsim::StudyFormatsOptions formats_opt;
  texsim::StudyWorkloadsOptions workloads_opt;
  texsim::StudyFramesOptions frames_opt;
  std::string frames_reference = "scene";
};

void add_study_commands(CLI::App& app, StudyCli& s) {
  s.cmd = app.add_subcommand("study",
                             "Accuracy-vs-cost studies: tables (CSV, Markdown) and plots (PNG)");
  s.cmd->require_subcommand(1);
  CLI::App& c = *s.cmd;
  s.vd = c.add_subcommand(
      "vd", "V(d) evaluators (exact, P3, P2, P1): error over d in each number format");
  s.coords = c.add_subcommand(
      "coords",
      "Texture-coordinate and derivative blocks: error in texels vs ops and cycles per pixel");
  s.filters = c.add_subcommand(
      "filters",
      "Anisotropic filters vs ground truth and OpenImageIO: error vs cycles and texels fetched");
  s.raster = c.add_subcommand(
      "raster",
      "Rectangle-scan digital rows vs edge rasteriser + Heckbert: coordinate error vs divisions");
  s.objspace = c.add_subcommand(
      "objspace",
      "Object-space texturing vs screen space + trilinear/anisotropic: cycles, ops, error");
  s.rtl = c.add_subcommand(
      "rtl", "RTL blocks on an iCE40 FPGA: yosys cells, LUTs, DSPs and nextpnr Fmax over seeds");
  s.thesis = c.add_subcommand(
      "thesis",
      "The thesis configuration (seed transform, theta/L/d weights) vs texsim's on scenes");
  s.relief = c.add_subcommand(
      "relief",
      "Relief methods (parallax, steep/relief, sphere tracing): iterations, fetches, cycles vs "
      "image error");
  s.terrain = c.add_subcommand(
      "terrain",
      "Finite-function terrain: evaluator costs, slope jumps, flat ripple, terrace measure");
  s.memory = c.add_subcommand(
      "memory",
      "Memory hierarchy on the shipped scenes: L1 size/ways/line, layout, raster order, units, "
      "L2, DRAM: hit rates, DRAM bytes, cycles and energy per fragment");
  s.formats = c.add_subcommand(
      "formats",
      "Texel formats and block compression (BC1, BC3, ASTC) on photo and cube: PSNR vs bytes "
      "per fragment at L1, L2 and DRAM, cycles, decoder area and energy, decoder placement");
  s.formats->add_flag("--quick", s.formats_opt.quick, "A few rows on photo at 96x64 (seconds)");
  s.formats->add_option("--scene", s.formats_opt.scenes,
                        "Scene file (repeatable; default: photo and cube)");
  s.formats->add_option("--width", s.formats_opt.width, "Output width (default 240)");
  s.formats->add_option("--height", s.formats_opt.height, "Output height (default 160)");
  s.workloads = c.add_subcommand(
      "workloads",
      "Workload characterisation of the shipped scenes and of fragment traces side by side: "
      "texels and lines per frame, LOD, anisotropy, magnification, line reuse distance");
  s.workloads->add_flag("--quick", s.workloads_opt.quick,
                        "The built-in scene at 160x120 only (seconds)");
  s.workloads->add_option("--scene", s.workloads_opt.scenes,
                          "Scene file or 'default' (repeatable; default: the built-in scene and "
                          "the shipped scenes)");
  s.workloads->add_option("--trace", s.workloads_opt.traces,
                          "Fragment trace to put beside the scenes (repeatable)");
  s.workloads->add_option("--draws", s.workloads_opt.draws,
                          "Draw trace of real frames to put beside the scenes (repeatable; "
                          "default: traces/samples/openarena-aggressor.draws)");
  s.frames = c.add_subcommand(
      "frames",
      "Every frame of a draw trace (a real application's capture) through the clocked unit, "
      "one frame per worker: cycles, L1 and DRAM, error vs the ground truth and vs the "
      "application's own images");
  s.frames->add_option("--draws", s.frames_opt.draws,
                       "Draw trace (default: traces/samples/openarena-aggressor.draws)");
  s.frames->add_option("--frames", s.frames_opt.frames,
                       "Frames to render, A-B or A (the capture's numbers; default: all)");
  s.frames->add_option("--images", s.frames_opt.images,
                       "Folder of the application's images frame_NNNN.png (default: the folder "
                       "named like the trace, if any)");
  s.frames
      ->add_option("--reference", s.frames_reference,
                   "'scene' (ground truth per look-up) or 'none' (faster, no accuracy figures)")
      ->check(CLI::IsMember({"scene", "none"}))
      ->capture_default_str();
  for (auto* sub : {s.vd, s.coords, s.filters, s.raster, s.objspace, s.rtl, s.thesis, s.relief,
                    s.terrain, s.memory, s.workloads, s.frames, s.formats})
    sub->add_option("--out", s.out, "Output directory")->capture_default_str();
  s.memory->add_flag("--quick", s.memory_opt.quick, "A few rows on the built-in scene (seconds)");
  s.memory->add_option("--scene", s.memory_opt.scenes,
                       "Scene file or 'default' (repeatable; default: the built-in scene, "
                       "photo, flight and bunny)");
  for (auto* sub : {s.vd, s.coords, s.filters, s.memory, s.workloads, s.frames, s.formats}) {
    sub->add_option("--threads", s.threads,
                    "Worker threads (0: one per core); the outputs do not depend on it")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
  }
  s.thesis->add_option("--scene", s.thesis_opt.scenes, "Scene files (repeatable)")
      ->capture_default_str();
  s.rtl->add_option("--rtl", s.rtl_opt.rtl_dir, "Folder of Verilog blocks (one module per file)")
      ->capture_default_str();
  s.rtl->add_option("--param", s.rtl_params,
                    "NAME=v1,v2,...: build each block that has parameter "
                    "NAME at these values (repeatable)");
  s.rtl->add_option("--seeds", s.rtl_opt.seeds, "Placer seeds per build")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  s.rtl->add_option("--block", s.rtl_opt.blocks, "Only this block (module name; repeatable)");
  s.rtl->add_flag("--with-counters", s.rtl_opt.with_counters,
                  "Synthesise the blocks' op counters too (default: a stub replaces them)");
  s.rtl->add_flag("--with-earlier", s.rtl_opt.with_earlier,
                  "Also build each block's earlier form (ref/BLOCK_comb.v) at the same "
                  "parameters: Fmax before and after retiming");
  s.rtl->add_flag("--no-generic", s.rtl_no_generic,
                  "Leave out yosys' generic synthesis (the generic cell count)");
  s.rtl
      ->add_option("--sampler-scene", s.rtl_sampler_scene,
                   "Scene whose fragments give the sampler's error (C++ FixedSampler vs truth)")
      ->capture_default_str();
  s.rtl
      ->add_option("--sampler-material", s.rtl_sampler_material,
                   "Material of --sampler-scene run with filter.arithmetic = \"fixed\"")
      ->capture_default_str();
}

int run_study_command(StudyCli& s) {
  using namespace texsim;  // NOLINT(google-build-using-namespace)
  if (*s.rtl) {
    for (const std::string& p : s.rtl_params) s.rtl_opt.params.push_back(parse_rtl_param(p));
    s.rtl_opt.generic_cells = !s.rtl_no_generic;
    auto errors = std::make_shared<SamplerSceneErrors>(s.rtl_sampler_scene, s.rtl_sampler_material);
    s.rtl_opt.sampler_error = [errors](int sub_bits, int mip_bits) {
      return errors->cell(sub_bits, mip_bits);
    };
    return run_study_rtl(s.out, s.rtl_opt, std::cout);
  }
  ensure_dir(s.out);
  if (*s.thesis) return run_study_thesis(s.out, std::cout, s.thesis_opt);
  if (*s.objspace) return run_study_objspace(s.out, std::cout);
  if (*s.relief) return run_study_relief(s.out, std::cout);
  if (*s.terrain) return run_study_terrain(s.out, std::cout);
  if (*s.vd) return run_study_vd(s.out, std::cout, s.threads);
  if (*s.coords) return run_study_coords(s.out, std::cout, s.threads);
  if (*s.raster) return run_study_raster(s.out, std::cout);
  if (*s.workloads) {
    s.workloads_opt.threads = s.threads;
    return run_study_workloads(s.out, std::cout, s.workloads_opt);
  }
  if (*s.frames) {
    s.frames_opt.threads = s.threads;
    s.frames_opt.truth = s.frames_reference != "none";
    return run_study_frames(s.out, std::cout, s.frames_opt);
  }
  if (*s.memory) {
    s.memory_opt.threads = s.threads;
    return run_study_memory(s.out, std::cout, s.memory_opt);
  }
  if (*s.formats) {
    s.formats_opt.threads = s.threads;
    return run_study_formats(s.out, std::cout, s.formats_opt);
  }
  StudyFiltersOptions fo;
  fo.threads = s.threads;
  return run_study_filters(s.out, std::cout, fo);
}

// Parses the command line and runs the subcommand; returns the exit status (docs/cli.md).
// `texsim run`: a scene or trace run, or a draw trace's frame with --draws.
void run_run_command(RunCli& run, int argc, char** argv) {
  using namespace texsim;  // NOLINT(google-build-using-namespace)
  run.opt.progress = !run.no_progress && ::isatty(STDERR_FILENO);
  run.opt.command = command_line(argc, argv);
  run.opt.max_memory = parse_byte_size(run.max_memory, "--max-memory");
  run.opt.error_scale = parse_error_scale(run.error_scale);
  run.opt.ledger = run.opt.ledger || run.opt.ledger_maps;
  if (run.opt.ledger && run.opt.reference == "none")
    throw InputError("--ledger", "the error ledger needs the ground truth: drop --reference none");
  if (!run.draws.empty()) {
    for (const char* o : {"--ledger", "--ledger-maps", "--timeline"})
      if (run.cmd->count(o) > 0) throw InputError(o, "not available with --draws");
    run_draws({run.opt, run.draws, run.compare}, std::cout);
  } else {
    run_simulation(run.opt, std::cout);
  }
}

int run_cli(int argc, char** argv) {
  using namespace texsim;
  CLI::App app{"texsim: cycle-approximate simulator of a hardware texture unit"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("texsim ") + kTexsimVersion);

  RunCli run;
  add_run_command(app, run);

  auto* trace_cmd = app.add_subcommand("trace", "Make, inspect and convert fragment traces");
  trace_cmd->require_subcommand(1);
  GenCli gen;
  add_gen_command(*trace_cmd, gen);
  std::string info_in;
  auto* info =
      trace_cmd->add_subcommand("info", "Print a trace's header, texture table and statistics");
  info->add_option("file", info_in, "Trace file")->required();
  std::string conv_in, conv_out;
  auto* conv =
      trace_cmd->add_subcommand("convert", "Convert between binary and CSV traces (by extension)");
  conv->add_option("input", conv_in, "Input trace")->required();
  conv->add_option("output", conv_out, "Output trace")->required();

  auto* import_cmd =
      app.add_subcommand("import", "Turn captures of real applications into draw traces");
  import_cmd->require_subcommand(1);
  std::string imp_capture, imp_frames, imp_out;
  auto* imp = import_cmd->add_subcommand(
      "apitrace",
      "Interpret the fixed-function OpenGL of an apitrace capture into a draw trace "
      "(traces/DRAWS.md)");
  imp->add_option("capture", imp_capture, "apitrace capture (.trace)")->required();
  imp->add_option("--frames", imp_frames, "Frames to import, A-B or A (0-based)")->required();
  imp->add_option("-o,--output", imp_out, "Output draw trace (.draws)")->required();

  StudyCli study;
  add_study_commands(app, study);

  SweepCli sweep;
  add_sweep_commands(app, sweep);

  CosimOptions cosim;
  CLI::App* cosim_cmd = add_cosim_command(app, cosim);

  TuneOptions tune;
  std::string tune_shard;
  CLI::App* tune_cmd = add_tune_command(app, tune, tune_shard);

  if (const int status = parse_command_line(app, argc, argv); status >= 0) return status;
  try {
    if (*run.cmd) {
      run_run_command(run, argc, argv);
    } else if (*gen.cmd) {
      run_gen_command(gen);
    } else if (*imp) {
      uint32_t first = 0, last = 0;
      parse_frame_range(imp_frames, first, last);
      const ImportSummary s = import_apitrace(imp_capture, first, last, imp_out);
      print_import_summary(s, imp_out, std::cout);
    } else if (*info) {
      const int rc = trace_info(info_in, std::cout);
      // A fragment trace in a file: its workload too (a second pass).
      if (rc == 0 && !is_draw_trace(info_in) && std::filesystem::is_regular_file(info_in))
        print_trace_workload(info_in, std::cout);
      return rc;
    } else if (*study.cmd) {
      return run_study_command(study);
    } else if (*tune_cmd) {
      if (tune_cmd->count("--shard") > 0) parse_tune_shard(tune_shard, tune);
      run_tune(tune, std::cout);
    } else if (*cosim_cmd) {
      return run_cosim(cosim, std::cout, std::cerr);
    } else if (*sweep.cmd) {
      return run_sweep_command(sweep, argv[0]);
    } else if (*sweep.merge) {
      merge_sweeps(sweep.merge_dirs, sweep.merge_out, std::cout);
    } else if (*conv) {
      trace_convert(conv_in, conv_out);
      (conv_out == "-" ? std::cerr : std::cout)
          << "texsim trace convert: wrote " << conv_out << "\n";
    }
  } catch (const InputError& e) {
    std::cerr << "texsim: error: " << printable(e.what()) << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "texsim: error: out of memory: this machine could not give the run the memory "
                 "it needed; lower the image size, the textures or the trace's pixel extent "
                 "(docs/usage.md, --max-memory)\n";
    return 2;
  } catch (const DeadlockError& e) {
    std::cerr << "texsim: " << printable(e.what()) << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "texsim: internal error: " << printable(e.what()) << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  texsim::install_temp_cleanup();  // SIGINT/SIGTERM/SIGHUP remove unfinished outputs
  // Whatever escapes the subcommands (or the command-line set-up itself) is an internal error.
  try {
    return run_cli(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "texsim: internal error: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "texsim: internal error: unknown exception\n";
  }
  return 1;
}
