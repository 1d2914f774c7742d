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
if [ "$what" = tidy ] || [ "$what" = all ]; then
  [ -f "$build/compile_commands.json" ] || cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
  # Only the project's own translation units; headers are checked through them.
  mapfile -t units < <(git ls-files '*.cc')
  log=$(mktemp)
  trap 'rm -f "$log"' EXIT
  if ! run-clang-tidy -p "$build" -j "$jobs" -quiet "${units[@]/#/$PWD/}" > "$log" 2>&1 ||
     grep -qE '(warning|error): ' "$log"; then
    grep -E '(warning|error): ' "$log" | sed 's/\x1b\[[0-9;]*m//g' | sort -u
    echo "lint: clang-tidy found problems"; exit 1
  fi
  echo "lint: clang-tidy clean ($(git ls-files '*.cc' | wc -l) files)"
fi
