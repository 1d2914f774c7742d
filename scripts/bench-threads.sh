#!/usr/bin/env bash
# Wall time of one texsim job with 1 thread and with all threads, interleaved in one session
# (REPEAT rounds, median of each); prints both medians and their ratio, and checks that both
# thread counts wrote byte-identical outputs.
#   run:    `texsim run` on a 1024 x 768 floor (the built-in scene via --set, ~460 k fragments)
#   coords: `texsim study coords` (tasks: tilts x coordinate and derivative methods)
#   filters: `texsim study filters` (tasks: the views' two ground truths, then groups of methods)
# Usage: scripts/bench-threads.sh [run|coords|filters] [BUILD_DIR] [REPEAT]
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-run}
bin=${2:-build}/texsim
repeat=${3:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
case "$what" in
  run) args=(run --no-progress --set output.width=1024 --set output.height=768)
       compare=(image.png reference.png) ;;
  coords) args=(study coords); compare=(coords.csv coords.md) ;;
  filters) args=(study filters); compare=(filters.csv filters.md filters_truths.csv) ;;
  *) echo "usage: $0 [run|coords|filters] [BUILD_DIR] [REPEAT]" >&2; exit 2 ;;
esac
declare -a one all
for ((i = 0; i < repeat; ++i)); do
  for t in 1 0; do
    s=$(date +%s.%N)
    "$bin" "${args[@]}" --out "$out/t$t" --threads "$t" > /dev/null
    e=$(date +%s.%N)
    if [ "$t" = 1 ]; then one+=("$(echo "$e - $s" | bc)"); else all+=("$(echo "$e - $s" | bc)"); fi
  done
done
for f in "${compare[@]}"; do
  cmp -s "$out/t1/$f" "$out/t0/$f" || { echo "bench-threads: $f differs between 1 and all threads"; exit 1; }
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
m1=$(median "${one[@]}")
ma=$(median "${all[@]}")
echo "texsim ${args[*]}: $repeat rounds, $(nproc) hardware threads; outputs identical"
echo "  1 thread:    ${m1} s (median)"
echo "  all threads: ${ma} s (median)"
echo "  speed-up:    $(echo "scale=2; $m1 / $ma" | bc)x"
