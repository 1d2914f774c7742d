#!/usr/bin/env bash
# Builds texsim and runs the whole test suite (unit, stability, conformance, bad-input, CLI).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
JOBS=${JOBS:-$(nproc)}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" -j "$JOBS"
# The tests' truth cache (TEXSIM_CACHE_DIR, set by testbench/CMakeLists.txt) starts empty: the
# first run of a scene computes and stores its truth, later ones read it, and nothing left by
# an earlier run of the suite (or another checkout) is ever read.
rm -rf "$BUILD_DIR/test-cache"
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" -LE '^install$'
# Last, the install from the finished tree (docs/install.md): a prefix and the .deb, one at a time.
ctest --test-dir "$BUILD_DIR" --output-on-failure -L '^install$'
