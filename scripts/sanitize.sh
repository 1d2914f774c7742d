#!/usr/bin/env bash
# Builds the whole tree with clang, AddressSanitizer and UndefinedBehaviorSanitizer (including
# float-cast-overflow and integer overflow checks that are not UB but are bugs here), any
# finding fatal, and runs the test suite under them.
# Usage: scripts/sanitize.sh   (build directory: build-asan, or SAN_BUILD_DIR)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${SAN_BUILD_DIR:-build-asan}
flags="-fsanitize=address,undefined,float-cast-overflow,float-divide-by-zero -fno-sanitize-recover=all -fno-omit-frame-pointer"
CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTEXSIM_BUILD_BENCH=OFF -DTEXSIM_WERROR=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" > /dev/null
cmake --build "$build" -j "$(nproc)"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
