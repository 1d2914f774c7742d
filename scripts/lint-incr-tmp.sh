#!/usr/bin/env bash
# Lint gates (CI runs both): every C++ file formatted with .clang-format, and clang-tidy
# (.clang-tidy: bugprone-*, performance-*, functions of at most 120 lines) clean, warnings as
# errors. Needs a configured build directory for compile_commands.json.
# Usage: scripts/lint.sh [format|tidy|all] [BUILD_DIR]   (default: all build)
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-all}
build=${2:-${BUILD_DIR:-build}}
jobs=${JOBS:-$(nproc)}

if [ "$what" = format ] || [ "$what" = all ]; then
  git ls-files '*.h' '*.cc' | xargs clang-format --dry-run -Werror
  echo "lint: clang-format clean ($(git ls-files '*.h' '*.cc' | wc -l) files)"
fi
# The translation units clang-tidy must check. A unit's diagnostics depend only on its own text,
# the headers it includes, its compile flags and the checks, so after a full pass that was clean
# at commit BASE (recorded in .ci/tidy-clean) it suffices to check the units that changed since
# BASE and the units whose dependency files (the build's *.o.d) name a header that changed
# since BASE. A change to .clang-tidy, to any CMake file or to this script, no record, a record
# git does not know, no dependency files, or TIDY_FULL=1 means a full pass.
tidy_units() {
  local base=""
  [[ -f .ci/tidy-clean ]] && base=$(awk 'NR==1{print $1}' .ci/tidy-clean)
  if [[ ${TIDY_FULL:-0} == 1 || -z $base ]] || ! git cat-file -e "$base^{commit}" 2>/dev/null ||
     false ||
     [[ -z $(find "$build" -name '*.o.d' -print -quit 2>/dev/null) ]]; then
    git ls-files '*.cc'
    return
  fi
  local changed headers
  # Since BASE, committed or not (a clean clone has only the committed part).
  changed=$( { git diff --name-only "$base" -- '*.h' '*.cc'; git ls-files --others --exclude-standard -- '*.h' '*.cc'; } | sort -u)
  headers=$(grep '\.h$' <<< "$changed" | sed 's|^|/|' || true)
  {
    grep '\.cc$' <<< "$changed" || true
    if [[ -n $headers ]]; then
      # Each dependency file whose list names a changed header: its unit (the first .cc).
      find "$build" -name '*.o.d' -print0 | xargs -0 -r grep -lF -- "$headers" |
        xargs -r awk 'FNR==1{done=0} !done{for(i=1;i<=NF;i++) if ($i ~ /\.cc$/) {print $i; done=1; nextfile}}' |
        sed -E "s|^$PWD/||; s|^(\.\./)+||"
    fi
  } | sort -u | while read -r f; do [[ -f $f ]] && git ls-files --error-unmatch "$f" > /dev/null 2>&1 && echo "$f"; done
}

if [ "$what" = tidy ] || [ "$what" = all ]; then
  [ -f "$build/compile_commands.json" ] || cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
  # Only the project's own translation units; headers are checked through them.
  mapfile -t units < <(tidy_units)
  all=$(git ls-files '*.cc' | wc -l)
  if [ "${#units[@]}" -eq 0 ]; then
    echo "lint: clang-tidy: no unit changed since the clean pass of $(awk 'NR==1{print $1}' .ci/tidy-clean)"
    exit 0
  fi
  log=$(mktemp)
  trap 'rm -f "$log"' EXIT
  if ! run-clang-tidy -p "$build" -j "$jobs" -quiet "${units[@]/#/$PWD/}" > "$log" 2>&1 ||
     grep -qE '(warning|error): ' "$log"; then
    grep -E '(warning|error): ' "$log" | sed 's/\x1b\[[0-9;]*m//g' | sort -u
    echo "lint: clang-tidy found problems"; exit 1
  fi
  echo "lint: clang-tidy clean (${#units[@]} of $all files)"
  # TIDY_RECORD=1 after a full pass on a clean work tree: record the commit for later runs.
  if [[ ${TIDY_RECORD:-0} == 1 && ${#units[@]} -eq $all && -z $(git status --porcelain) ]]; then
    echo "$(git rev-parse HEAD) $(date -u +%F) full clang-tidy pass clean ($all units)" > .ci/tidy-clean
    echo "lint: recorded the clean pass in .ci/tidy-clean (commit it)"
  fi
fi
