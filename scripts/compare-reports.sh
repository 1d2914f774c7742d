#!/usr/bin/env bash
# Runs every shipped scene with two texsim binaries and compares their report.json byte for
# byte: the check that a change keeps every figure. Extra arguments go to both runs (e.g.
# --functional, or --set pipeline.units=4); without a --reference among them the runs take
# --reference none (add --reference scene to compare the ground truths too). Exit 1 if any
# scene differs or fails in one binary only.
# Usage: scripts/compare-reports.sh OLD_TEXSIM NEW_TEXSIM [ARGS...]
set -uo pipefail
[[ $# -ge 2 ]] || { echo "usage: $0 OLD_TEXSIM NEW_TEXSIM [ARGS...]" >&2; exit 2; }
old=$(realpath "$1") new=$(realpath "$2")
shift 2
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
reference=(--reference none)
for a in "$@"; do [[ $a == --reference* ]] && reference=(); done
for scene in scenes/*.toml; do
  name=$(basename "$scene" .toml)
  # One output directory name for both, so the command line in the provenance is the same.
  "$old" run "$scene" "${reference[@]}" --no-progress --out "$work/out" "$@" > "$work/old.log" 2>&1
  old_rc=$?
  [[ -f $work/out/report.json ]] && mv "$work/out/report.json" "$work/old.json"
  rm -rf "$work/out"
  "$new" run "$scene" "${reference[@]}" --no-progress --out "$work/out" "$@" > "$work/new.log" 2>&1
  new_rc=$?
  if [[ $old_rc -ne 0 || $new_rc -ne 0 ]]; then
    if [[ $old_rc -ne 0 && $new_rc -ne 0 ]] && cmp -s "$work/old.log" "$work/new.log"; then
      echo "both refuse: $name"
    else
      echo "DIFFERS: $name (exit $old_rc old, $new_rc new)"; status=1
    fi
  elif cmp -s "$work/old.json" "$work/out/report.json"; then
    echo "same: $name"
  else
    echo "DIFFERS: $name"; status=1
    diff <(python3 -m json.tool "$work/old.json") <(python3 -m json.tool "$work/out/report.json") | head -20
  fi
  rm -rf "$work/out" "$work/old.json"
done
exit $status
