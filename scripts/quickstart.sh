#!/usr/bin/env bash
# One command for a fresh Debian machine: install the packages, build, and run the built-in
# default scene and the sample trace. Prints where the reports and images went.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup-debian.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)" --target texsim
echo
echo "== built-in default scene =="
build/texsim run --out out/default
echo
echo "== sample trace (traces/samples/basic.trc) =="
build/texsim run --trace traces/samples/basic.trc --out out/sample-trace
