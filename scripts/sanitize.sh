#!/usr/bin/env bash
# Builds with clang, AddressSanitizer and UndefinedBehaviorSanitizer (clang's `undefined` group,
# which includes float-cast-overflow, plus float-divide-by-zero in the full mode), any finding
# fatal, and runs tests under them.
# Usage:
#   scripts/sanitize.sh          the whole suite (build directory build-asan, or SAN_BUILD_DIR);
#                                run before each release note
#   scripts/sanitize.sh subset   the tests of every parser, reader and writer and the CLI tests,
#                                in the fuzz build (build-fuzz, or FUZZ_BUILD_DIR: the same
#                                sanitizers, so CI compiles the tree once for both); CI runs this
set -euo pipefail
cd "$(dirname "$0")/.."
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
if [[ ${1:-} == subset ]]; then
  build=${FUZZ_BUILD_DIR:-build-fuzz}
  # Readers, parsers and writers: every test of these executables.
  tests=(test_input_file test_output_set test_shell_quote test_trace_file test_trace_csv
    test_trace_tools test_prefetch_reader test_mesh test_obj_inputs test_npz_height_field
    test_scene_overrides test_texture_loader test_sweep_inputs test_tune_inputs test_models
    test_model_isolation test_link_protocol test_link_hostile test_png_file test_oiio_plugin
    test_truth_cache test_dds_file test_astc_file)
  # The CLI's bad-input tests (test_cli_run); its rendering tests take minutes under ASan.
  cli='UsageErrors|HelpAndVersion|TraceWritersKeep|SceneSyntax|SceneType|TimingParameters|NonUtf8'
  cli+='|SceneUnknown|MissingTexture|RunRefuses|TracePixelBeyond|TraceConvertOnto|SceneThatIsAFifo'
  cli+='|BadProcedural|UnreadableTexture|NanCoordinate|CorruptedAndTruncated|UnknownTraceVersion'
  cli+='|UnwritableOutput'
  # The configuration of scripts/fuzz.sh, so that its build serves here.
  CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTEXSIM_FUZZ=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DTEXSIM_BUILD_BENCH=OFF -DTEXSIM_WERROR=OFF > /dev/null
  cmake --build "$build" -j "$(nproc)" --target texsim test_cli_run "${tests[@]}"
  regex=$(printf '%s|' "${tests[@]}")
  rm -rf "$build/test-cache"  # the tests' truth cache starts empty (scripts/test.sh)
  # Tests are labelled by their executable (testbench/CMakeLists.txt). A commit test that runs
  # a whole render is left to the full mode. Loading models from several threads at once is
  # left out here: it forks from a multi-threaded process, and this clang's ASan allocator is
  # not fork-safe (a child forked while another thread holds its lock can hang; the test runs
  # in the normal suite, and the children's deadline and parent-death signal end such hangs).
  ctest --test-dir "$build" --output-on-failure -j "$(nproc)" --timeout 600 \
    -L "^(${regex%|})\$" -E '^(OutputSet\.RunThatCannotCommit|ModelIsolation\.ModelsLoadFromThreadsAtOnce)'
  ctest --test-dir "$build" --output-on-failure -j "$(nproc)" -L '^test_cli_run$' -R "^Cli\.($cli)"
  exit 0
fi
build=${SAN_BUILD_DIR:-build-asan}
flags="-fsanitize=address,undefined,float-cast-overflow,float-divide-by-zero -fno-sanitize-recover=all -fno-omit-frame-pointer"
CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTEXSIM_BUILD_BENCH=OFF -DTEXSIM_WERROR=OFF -DTEXSIM_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
cmake --build "$build" -j "$(nproc)"
rm -rf "$build/test-cache"
# The install's tests (label install) link the instrumented libraries into a project of their own.
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" -LE '^install$'
