#!/usr/bin/env bash
# Functional frame time of scenes/photo.toml with its textures as loaded, as rgba32f, and
# compressed (bc1 by libsquish, astc 4x4 by astcenc): five rounds, each case once per round,
# whole-process wall seconds (docs/performance.md#compressed-textures).
# Usage: scripts/bench-compressed.sh [BUILD_DIR]
cd "$(dirname "$0")/.."
T=${1:-build}/texsim
S=scenes/photo.toml
run() { local t0=$(date +%s.%N); $T run $S --functional --reference none --no-progress --out "${TMPDIR:-/tmp}/texsim-bench-compressed" "$@" >/dev/null 2>&1 || echo FAIL; echo "$(date +%s.%N) - $t0" | bc; }
for i in 1 2 3 4 5; do
  a=$(run); b=$(run --set 'textures.grass.compress={format="bc1_rgb",quality="range"}' --set 'textures.crate.compress={format="bc1_rgb",quality="range"}'); c=$(run --set 'textures.grass.compress={format="astc_4x4",quality="fastest"}' --set 'textures.crate.compress={format="astc_4x4",quality="fastest"}'); d=$(run --set 'textures.grass.format="rgba32f"' --set 'textures.crate.format="rgba32f"')
  echo "rgba8 $a bc1 $b astc4x4 $c rgba32f $d"
done
