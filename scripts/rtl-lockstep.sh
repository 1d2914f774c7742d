#!/usr/bin/env bash
# Long lockstep run of the Verilog blocks against their C++ cores (docs/rtl/blocks.md): each
# block's lockstep test with 10^6 seeded random vectors (CI runs 10^5), printing per block the
# transactions compared and the mismatches. Exit status non-zero on any mismatch.
# Usage: scripts/rtl-lockstep.sh [BUILD_DIR] [VECTORS]   (default: build 1000000)
# Waveforms: TEXSIM_RTL_TRACE=DIR writes DIR/<block>.vcd (large at 10^6 vectors).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
vectors=${2:-1000000}
tests=(test_rtl_vd test_rtl_lerp test_rtl_uv test_rtl_rect_scan test_rtl_rect_control test_rtl_sampler)
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
fi
if ! cmake --build "$build" -j"${JOBS:-2}" --target "${tests[@]}" > /dev/null; then
  echo "rtl-lockstep: Verilator or the RTL targets are not available in $build"; exit 1
fi
status=0
for t in "${tests[@]}"; do
  start=$(date +%s.%N)
  # The sampler runs every fragment of the shipped scenes' covered materials.
  if ! out=$(TEXSIM_RTL_VECTORS=$vectors TEXSIM_RTL_SAMPLER_FRAGMENTS=0 "$build/$t" \
    --gtest_filter='*MatchesCpp*' 2>&1); then
    status=1
  fi
  end=$(date +%s.%N)
  grep -E 'transactions|mismatch|^\S+: transaction' <<< "$out" || true
  grep -E '^\[  (PASSED|FAILED)' <<< "$out" | sed "s/^/$t: /"
  printf '%s: %.1f s\n' "$t" "$(echo "$end - $start" | bc)"
done
[ "$status" -eq 0 ] && echo "rtl-lockstep: every block bit-exact over $vectors random vectors" ||
  echo "rtl-lockstep: MISMATCHES (see above)"
exit "$status"
