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
# The pre-compressed textures: every MIP level down to 1x1, each level from the one above.
ktx() {
  local src=$1 out=$2 w h k=0 files=()
  read -r w h < <(oiiotool --info "$src" | sed -n 's/.*: *\([0-9]*\) x *\([0-9]*\),.*/\1 \2/p')
  oiiotool "$src" --ch R,G,B,A=1.0 -d uint8 -o "$cache/l0.png" >/dev/null
  while :; do
    astcenc -cl "$cache/l$k.png" "$cache/l$k.astc" 4x4 -fastest -silent >/dev/null || exit 1
    files+=("$cache/l$k.astc")
    [ "$w" -le 1 ] && [ "$h" -le 1 ] && break
    w=$(( w > 1 ? w / 2 : 1 )); h=$(( h > 1 ? h / 2 : 1 ))
    oiiotool "$cache/l$k.png" --resize:filter=box "${w}x${h}" -d uint8 -o "$cache/l$((k + 1)).png" >/dev/null
    k=$((k + 1))
  done
  scripts/astc-ktx.py "$out" "${files[@]}" || exit 1
}
ktx /usr/share/glmark2/textures/terrain-grasslight-512.jpg "$cache/grass.ktx"
ktx /usr/share/glmark2/textures/crate-base.png "$cache/crate.ktx"
file=(--set "textures.grass.source=\"$cache/grass.ktx\"" --set "textures.crate.source=\"$cache/crate.ktx\"")
run() { local t0=$(date +%s.%N); $T run $S --functional --reference none --no-progress --out "$cache/out" "$@" >/dev/null 2>&1 || echo FAIL; echo "$(date +%s.%N) - $t0" | bc; }
cold() { TEXSIM_ENCODED_CACHE_MAX=0 run "$@"; }
for i in 1 2 3 4 5; do
  a=$(run); b=$(cold "${bc1[@]}"); c=$(cold "${astc[@]}"); d=$(run --set 'textures.grass.format="rgba32f"' --set 'textures.crate.format="rgba32f"')
  e=$(run "${bc1[@]}"); f=$(run "${astc[@]}"); g=$(run "${file[@]}")
  echo "rgba8 $a bc1-cold $b astc4x4-cold $c rgba32f $d bc1-warm $e astc4x4-warm $f astc4x4-ktx $g"
done
