#!/usr/bin/env bash
# End-to-end `texsim run` time with 1 thread and with all threads, interleaved in one session
# (REPEAT rounds, median of each), on a 1024 x 768 floor scene (about 460 k fragments) made from
# the built-in scene with --set; prints both medians and their ratio.
# Usage: scripts/bench-run-threads.sh [BUILD_DIR] [REPEAT]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build}/texsim
repeat=${2:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
args=(run --no-progress --out "$out/o" --set output.width=1024 --set output.height=768)
declare -a one all
for ((i = 0; i < repeat; ++i)); do
  for t in 1 0; do
    s=$(date +%s.%N)
    "$bin" "${args[@]}" --threads "$t" > /dev/null
    e=$(date +%s.%N)
    if [ "$t" = 1 ]; then one+=("$(echo "$e - $s" | bc)"); else all+=("$(echo "$e - $s" | bc)"); fi
  done
done
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
m1=$(median "${one[@]}")
ma=$(median "${all[@]}")
echo "texsim run, 1024x768 default scene, $repeat rounds, $(nproc) hardware threads"
echo "  1 thread:    ${m1} s (median)"
echo "  all threads: ${ma} s (median)"
echo "  speed-up:    $(echo "scale=2; $m1 / $ma" | bc)x"
