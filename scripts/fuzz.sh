#!/usr/bin/env bash
# Builds the libFuzzer harnesses (testbench/fuzz/) with clang, ASan and UBSan, and runs each
# for SECONDS (default 60) on its seed corpus: fuzz_trace_reader (binary traces, with the
# version-5 sampler table among the seeds; also in the mode that recomputes CRCs so mutations
# reach the parser), fuzz_draw_trace (draw traces, also
# with the CRCs recomputed), fuzz_apitrace_dump (apitrace dump text, and blobs, through the
# importer of `texsim import apitrace`), fuzz_csv_reader (CSV traces with their texture and
# sampler directives, and their round trip through both writers), fuzz_scene (scene TOML through the materials, the
# texture unit and a tiny render), fuzz_obj (OBJ text and an MTL through the mesh loader),
# fuzz_model (OBJ, 3DS, glTF, MD3, PLY and STL bytes through Assimp and texsim's model
# conversion, in the import's child process and then in-process; also the child's stream through
# the parent's reader; seeded with Assimp's known crash too), fuzz_npz (.npz archives and .npy arrays through the DEM reader), fuzz_png (PNG bytes
# through the libpng reader of reference frames, and what it decodes back through the writer),
# fuzz_dds, fuzz_astc_file and fuzz_ktx (DDS, .astc and KTX bytes through the strict
# compressed-texture readers, and what they read back through the writers), fuzz_sweep (sweep files
# through the grid's expansion, the job list and the Slurm script), fuzz_merge_json (job.json
# and report.json through merge), fuzz_tune_shard (tune_shard.json as `tune --merge` reads it)
# and fuzz_link_host (the input plays the board behind LinkHost; -timeout=5 catches a host
# that loops), fuzz_cache_entry (truth cache and encoded-level cache entries, also with the payload's size and CRC
# made to match). New inputs go to build-fuzz/corpus/.
# Exit 1 if any harness finds a crash, a leak, undefined behaviour or a non-InputError
# exception (the reproducer is left in build-fuzz/).
# Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
build=${FUZZ_BUILD_DIR:-build-fuzz}
# -O1 with line tables only: ASan's usual setting, and quicker to compile than -O2 -g.
CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTEXSIM_FUZZ=ON \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
  -DTEXSIM_BUILD_BENCH=OFF -DTEXSIM_WERROR=OFF > /dev/null
cmake --build "$build" -j "$(nproc)" --target fuzz_trace_reader fuzz_draw_trace fuzz_apitrace_dump fuzz_csv_reader fuzz_scene \
  fuzz_obj fuzz_model fuzz_npz fuzz_png fuzz_dds fuzz_astc_file fuzz_ktx fuzz_sweep fuzz_merge_json fuzz_tune_shard fuzz_link_host fuzz_sampler_link fuzz_cache_entry
run() {  # run NAME CORPUS [ENV=VALUE]
  local name=$1 seeds=$2; shift 2
  local work="$build/corpus/$name${1:+-crc}"
  mkdir -p "$work"
  echo "== $name ${1:-} ($secs s)"
  local dict=()  # testbench/fuzz/NAME.dict: the format's keywords, when the harness has one
  [[ -f testbench/fuzz/${name#fuzz_}.dict ]] && dict=(-dict="../testbench/fuzz/${name#fuzz_}.dict")
  local limits=()  # the link host must end every input quickly, whatever the board sends
  [[ $name == fuzz_link_host ]] && limits=(-timeout=5)
  local extra=()  # inputs that crash Assimp: the model import must survive them every run
  [[ $name == fuzz_model ]] && extra=(../testbench/fuzz/known-crashes)
  (cd "$build" && env "$@" "./testbench/$name" -max_total_time="$secs" -rss_limit_mb=2048 \
     -max_len=65536 -print_final_stats=1 "${dict[@]}" "${limits[@]}" "../$work" "../$seeds" \
     "${extra[@]}" 2>&1 | tail -n 12)
}
run fuzz_trace_reader testbench/fuzz/corpus/trace
run fuzz_trace_reader testbench/fuzz/corpus/trace TEXSIM_FUZZ_FIX_CRC=1
run fuzz_draw_trace testbench/fuzz/corpus/draws
run fuzz_draw_trace testbench/fuzz/corpus/draws TEXSIM_FUZZ_FIX_CRC=1
run fuzz_apitrace_dump testbench/fuzz/corpus/apitrace_dump
run fuzz_csv_reader testbench/fuzz/corpus/csv
run fuzz_scene testbench/fuzz/corpus/scene
run fuzz_sweep testbench/fuzz/corpus/sweep
run fuzz_merge_json testbench/fuzz/corpus/merge_json
run fuzz_tune_shard testbench/fuzz/corpus/tune_shard
run fuzz_link_host testbench/fuzz/corpus/link_host
run fuzz_sampler_link testbench/fuzz/corpus/sampler_link
run fuzz_obj testbench/fuzz/corpus/obj
run fuzz_model testbench/fuzz/corpus/model
run fuzz_npz testbench/fuzz/corpus/npz
run fuzz_png testbench/fuzz/corpus/png
run fuzz_dds testbench/fuzz/corpus/dds
run fuzz_astc_file testbench/fuzz/corpus/astc_file
run fuzz_ktx testbench/fuzz/corpus/ktx
run fuzz_cache_entry testbench/fuzz/corpus/cache_entry
echo "fuzz: no findings in ${secs} s per harness"
