#!/usr/bin/env bash
# Peak resident memory (GNU time's maximum RSS) of `texsim run`: a trace of about 10^6 and one
# of about 10^7 fragments from the built-in floor (made with `trace gen --set`), each run with
# its trace alone (images sized by the pixels the fragments cover) and a 5000 x 3750 scene run.
# Prints fragments, image size, wall time and peak RSS per case. Takes a few minutes.
# Usage: scripts/bench-memory.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-build}")/texsim
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
measure() {  # label, texsim arguments...
  local label=$1
  shift
  /usr/bin/time -f "%e %M" -o "$out/time" "$bin" "$@" --no-progress --out "$out/o" > "$out/log"
  read -r secs kb < "$out/time"
  local frags
  frags=$(sed -n 's/^texsim run: \([0-9]*\) fragments.*/\1/p' "$out/log")
  printf '| %s | %s | %s s | %s MiB |\n' "$label" "$frags" "$secs" "$((kb / 1024))"
}
echo "| case | fragments | wall time | peak RSS |"
echo "|---|---:|---:|---:|"
for size in 1420x1060 4480x3360; do
  w=${size%x*}
  h=${size#*x}
  "$bin" trace gen default -o "$out/t.trc" --set output.width="$w" --set output.height="$h" > /dev/null
  measure "trace of the ${size} floor, no scene" run --trace "$out/t.trc"
done
measure "scene run, 5000x3750" run --set output.width=5000 --set output.height=3750
