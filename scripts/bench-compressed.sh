#!/usr/bin/env bash
# Functional frame time of scenes/photo.toml with its textures as loaded, as rgba32f, and
# compressed (bc1 by libsquish, astc 4x4 by astcenc), the compressed cases with the encoded-level
# cache off (every run encodes: a first run) and warm (docs/compressed-files.md): five rounds,
# each case once per round, whole-process wall seconds (docs/performance.md#compressed-textures).
# Usage: scripts/bench-compressed.sh [BUILD_DIR]
cd "$(dirname "$0")/.."
T=${1:-build}/texsim
S=scenes/photo.toml
cache=$(mktemp -d)
trap 'rm -rf "$cache"' EXIT
export TEXSIM_CACHE_DIR=$cache
bc1=(--set 'textures.grass.compress={format="bc1_rgb",quality="range"}' --set 'textures.crate.compress={format="bc1_rgb",quality="range"}')
astc=(--set 'textures.grass.compress={format="astc_4x4",quality="fastest"}' --set 'textures.crate.compress={format="astc_4x4",quality="fastest"}')
run() { local t0=$(date +%s.%N); $T run $S --functional --reference none --no-progress --out "$cache/out" "$@" >/dev/null 2>&1 || echo FAIL; echo "$(date +%s.%N) - $t0" | bc; }
cold() { TEXSIM_ENCODED_CACHE_MAX=0 run "$@"; }
for i in 1 2 3 4 5; do
  a=$(run); b=$(cold "${bc1[@]}"); c=$(cold "${astc[@]}"); d=$(run --set 'textures.grass.format="rgba32f"' --set 'textures.crate.format="rgba32f"')
  e=$(run "${bc1[@]}"); f=$(run "${astc[@]}")
  echo "rgba8 $a bc1-cold $b astc4x4-cold $c rgba32f $d bc1-warm $e astc4x4-warm $f"
done
