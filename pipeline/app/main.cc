// texsim command-line entry point (docs/cli.md).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <string>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "pipeline/app/run.h"
#include "pipeline/kernel/clocked_pipeline.h"
#include "pipeline/studies/study_coords.h"
#include "pipeline/studies/study_filters.h"
#include "pipeline/studies/study_vd.h"
#include "traces/trace_tools.h"

namespace {

// Parses the command line and runs the subcommand; returns the exit status (docs/cli.md).
int run_cli(int argc, char** argv) {
  using namespace texsim;
  CLI::App app{"texsim: cycle-approximate simulator of a hardware texture unit"};
  app.require_subcommand(1);

  RunOptions run;
  auto* run_cmd = app.add_subcommand("run",
                                     "Simulate a scene (default: the built-in scene) or a trace; "
                                     "write report.json, report.md and images to --out");
  run_cmd->add_option("scene", run.scene,
                      "Scene file (TOML), or 'default' (the built-in scene, also used when both "
                      "scene and --trace are omitted)");
  run_cmd->add_option("--trace", run.trace,
                      "Fragment trace (.trc binary or .csv) to drive the texture unit");
  run_cmd->add_option("--out", run.out, "Output directory")->capture_default_str();
  run_cmd->add_flag("--functional", run.functional,
                    "Functional only: colours and op counts, no cache or clock");
  bool no_progress = false;
  run_cmd->add_flag("--no-progress", no_progress, "Do not show the progress line");

  auto* trace_cmd = app.add_subcommand("trace", "Make, inspect and convert fragment traces");
  trace_cmd->require_subcommand(1);
  std::string gen_scene, gen_out;
  auto* gen = trace_cmd->add_subcommand(
      "gen", "Write a scene's reference fragments (exact double coordinates)");
  gen->add_option("scene", gen_scene, "Scene file; 'default' for the built-in scene")->required();
  gen->add_option("-o,--output", gen_out, "Output trace (.trc binary, .csv text)")->required();
  std::string info_in;
  auto* info =
      trace_cmd->add_subcommand("info", "Print a trace's header, texture table and statistics");
  info->add_option("file", info_in, "Trace file")->required();
  std::string conv_in, conv_out;
  auto* conv =
      trace_cmd->add_subcommand("convert", "Convert between binary and CSV traces (by extension)");
  conv->add_option("input", conv_in, "Input trace")->required();
  conv->add_option("output", conv_out, "Output trace")->required();

  auto* study_cmd = app.add_subcommand(
      "study", "Accuracy-vs-cost studies: tables (CSV, Markdown) and plots (PNG)");
  study_cmd->require_subcommand(1);
  std::string study_out = "out/study";
  auto* vd = study_cmd->add_subcommand(
      "vd", "V(d) evaluators (exact, P3, P2, P1): error over d in each number format");
  auto* coords = study_cmd->add_subcommand(
      "coords",
      "Texture-coordinate and derivative blocks: error in texels vs ops and cycles per pixel");
  auto* filters = study_cmd->add_subcommand(
      "filters",
      "Anisotropic filters vs ground truth and OpenImageIO: error vs cycles and texels fetched");
  for (auto* s : {vd, coords, filters})
    s->add_option("--out", study_out, "Output directory")->capture_default_str();

  CLI11_PARSE(app, argc, argv);
  try {
    if (*run_cmd) {
      run.progress = !no_progress && ::isatty(STDERR_FILENO);
      run_simulation(run, std::cout);
    } else if (*gen) {
      const uint64_t n = generate_scene_trace(gen_scene == "default" ? "" : gen_scene, gen_out);
      std::cout << "texsim trace gen: wrote " << n << " fragments to " << gen_out << "\n";
    } else if (*info) {
      return trace_info(info_in, std::cout);
    } else if (*vd || *coords || *filters) {
      ensure_dir(study_out);
      if (*vd) return run_study_vd(study_out, std::cout);
      if (*coords) return run_study_coords(study_out, std::cout);
      return run_study_filters(study_out, std::cout);
    } else if (*conv) {
      trace_convert(conv_in, conv_out);
      std::cout << "texsim trace convert: wrote " << conv_out << "\n";
    }
  } catch (const InputError& e) {
    std::cerr << "texsim: error: " << e.what() << "\n";
    return 2;
  } catch (const DeadlockError& e) {
    std::cerr << "texsim: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "texsim: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
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
